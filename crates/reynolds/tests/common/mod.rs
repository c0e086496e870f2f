//! The reference cases of the Reynolds tests (and of the `m20` probe).
#![allow(dead_code)] // each test file uses what it needs

use ehl_core::{Moes, SEED_CONTACT, SEED_LUBRICANT};
use ehl_reynolds::*;

/// The classic moderate case `M = 20, L = 10`.
pub fn m20() -> ReynoldsParams {
    moes(20.0, 10.0)
}

/// Roelands `η0 = 40 mPa s`, `p0 = 1.96e8 Pa`, Dowson–Higginson on the seed's ball and load:
/// velocity and `α` follow from `M`, `L`.
pub fn moes(m: f64, l: f64) -> ReynoldsParams {
    ReynoldsParams::from_moes(
        &Moes { m, l },
        &SEED_CONTACT,
        40e-3,
        1.96e8,
        ViscosityLaw::Roelands,
        DensityLaw::DowsonHigginson,
    )
}

/// Seed Table 1: `M ≈ 2223, L ≈ 2.49`, pure rolling at `u1 = 0.01 m/s` (sum velocity 0.02 m/s).
pub fn seed() -> ReynoldsParams {
    ReynoldsParams::from_si(
        &SEED_CONTACT,
        &SEED_LUBRICANT,
        0.02,
        ViscosityLaw::Roelands,
        DensityLaw::DowsonHigginson,
    )
}
