//! What a march through the surfaces' relief gives per passage: its films and pressure over
//! the last passage, the film-to-roughness ratio `λ`, and the amplitude a wave keeps inside the
//! contact (the deformed amplitude `A_d` of Venner & Lubrecht's amplitude reduction).

use crate::observe::Observables;
use serde::{Deserialize, Serialize};

/// Statistics over the last passage of a march whose surfaces carry a relief (SI).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Passage {
    /// The passage's travel [m] (a periodic pattern's period, else the domain's length).
    pub travel_m: f64,
    /// Its duration [s].
    pub duration_s: f64,
    /// Records (steps) the statistics are over.
    pub records: usize,
    /// Central film over the passage: mean [m] …
    pub central_film_mean_m: f64,
    /// … least [m] …
    pub central_film_min_m: f64,
    /// … and largest [m].
    pub central_film_max_m: f64,
    /// The least minimum film over the passage [m] (0: the solids touched).
    pub minimum_film_m: f64,
    /// The largest pressure over the passage [Pa].
    pub max_pressure_pa: f64,
    /// `λ`: the mean central film over the relief's RMS height (`None`: a relief without one,
    /// dents alone).
    pub lambda: Option<f64>,
    /// The share of the load the solids carry, over the passage: mean … (`None`: a model
    /// that does not tell contact from a film)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_load_share_mean: Option<f64>,
    /// … and largest [-].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_load_share_max: Option<f64>,
    /// The area where the solids touch, mean over the passage [m²].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_area_mean_m2: Option<f64>,
    /// A single wave's amplitude in the final film at the contact's centre [m] (`None`: not a
    /// single wave, or one longer than the centre holds).
    pub deformed_amplitude_m: Option<f64>,
    /// `A_d / A_i`: the deformed amplitude over the surfaces' own.
    pub amplitude_ratio: Option<f64>,
}

impl Passage {
    /// The statistics of the records of `history` (time [s], observables) in its last
    /// `duration_s` [s], a passage of `travel_m` [m] of a relief of RMS height `rms_m` [m];
    /// `None` when the history does not span a passage.
    pub fn over(
        history: &[(f64, Observables)],
        duration_s: f64,
        travel_m: f64,
        rms_m: Option<f64>,
    ) -> Option<Self> {
        let (t_end, first) = (history.last()?.0, history.first()?.0);
        if !(duration_s > 0.0 && t_end - first >= duration_s * (1.0 - 1e-9)) {
            return None;
        }
        // The passage's records, its first instant left out: the one before is its last
        // instant's twin in a periodic state, and counting both would weigh that phase twice.
        let last: Vec<&Observables> = history
            .iter()
            .filter(|(t, _)| in_passage(*t, t_end, duration_s))
            .map(|(_, o)| o)
            .collect();
        let n = last.len() as f64;
        let fold = |f: fn(&Observables) -> f64, g: fn(f64, f64) -> f64, z: f64| {
            last.iter().map(|o| f(o)).fold(z, g)
        };
        let mean = last.iter().map(|o| o.central_film_m).sum::<f64>() / n;
        Some(Passage {
            travel_m,
            duration_s,
            records: last.len(),
            central_film_mean_m: mean,
            central_film_min_m: fold(|o| o.central_film_m, f64::min, f64::INFINITY),
            central_film_max_m: fold(|o| o.central_film_m, f64::max, 0.0),
            minimum_film_m: fold(|o| o.minimum_film_m, f64::min, f64::INFINITY),
            max_pressure_pa: fold(|o| o.max_pressure_pa, f64::max, 0.0),
            lambda: rms_m.filter(|r| *r > 0.0).map(|r| mean / r),
            contact_load_share_mean: None,
            contact_load_share_max: None,
            contact_area_mean_m2: None,
            deformed_amplitude_m: None,
            amplitude_ratio: None,
        })
    }

    /// With the solids' contact over the same records: `contact` holds the load share and the
    /// area [m²] of each record of `history` (the history [`Passage::over`] read); unchanged
    /// when the two do not line up.
    pub fn with_contact(
        self,
        history: &[(f64, Observables)],
        contact: &[(f64, f64)],
        duration_s: f64,
    ) -> Self {
        let Some(t_end) = history.last().map(|h| h.0) else { return self };
        if contact.len() != history.len() {
            return self;
        }
        let last: Vec<(f64, f64)> = history
            .iter()
            .zip(contact)
            .filter(|((t, _), _)| in_passage(*t, t_end, duration_s))
            .map(|(_, c)| *c)
            .collect();
        if last.is_empty() {
            return self;
        }
        let n = last.len() as f64;
        Self {
            contact_load_share_mean: Some(last.iter().map(|c| c.0).sum::<f64>() / n),
            contact_load_share_max: Some(last.iter().map(|c| c.0).fold(0.0, f64::max)),
            contact_area_mean_m2: Some(last.iter().map(|c| c.1).sum::<f64>() / n),
            ..self
        }
    }

    /// With a wave's deformed amplitude `a_d` [m] against its own `a_i` [m].
    pub fn with_amplitude(self, a_d: f64, a_i: f64) -> Self {
        Self {
            deformed_amplitude_m: Some(a_d),
            amplitude_ratio: (a_i > 0.0).then(|| a_d / a_i),
            ..self
        }
    }
}

/// Whether a record at `t` [s] is in the passage of `duration_s` [s] that ends at `t_end`: its
/// first instant left out, the twin of its last in a periodic state.
fn in_passage(t: f64, t_end: f64, duration_s: f64) -> bool {
    t > t_end - duration_s * (1.0 - 1e-9)
}

/// Terms of the smooth trend fitted beside a harmonic along a line: a quartic, which holds a
/// contact's central film (flat, rising to its side lobes) across a Hertz width without leaking
/// into the harmonic.
const LINE_TREND: usize = 5;
/// Unknowns of the largest fit: the trend, then the harmonic's cosine and sine.
const MAX_TERMS: usize = LINE_TREND + 2;

/// The amplitude of the harmonic of wavenumber `k` [1/unit of `xs`] in `h(xs)`, fitted by least
/// squares together with a polynomial trend (the smooth film's own shape across the window):
/// `h ≈ Σ c_n xⁿ (n < 5) + A cos kx + B sin kx`, amplitude `√(A² + B²)`. `None` when the
/// samples cannot separate the terms.
pub fn harmonic_amplitude(xs: &[f64], h: &[f64], k: f64) -> Option<f64> {
    harmonic_fit(xs, h, k, LINE_TREND)
}

/// The amplitude of the centre's film oscillating at angular frequency `omega` [rad/s] over the
/// last `duration_s` [s] of `history` (the records [`Passage::over`] reads, its first instant
/// left out): the deformed amplitude `A_d` as Venner and co-workers define it, the film's
/// amplitude at the contact's centre as the pattern passes. Fitted over a constant alone: a
/// periodic state has no trend, and a polynomial over one period would take part of the wave.
/// `None` with fewer than four records in the passage.
pub fn centre_amplitude(
    history: &[(f64, Observables)],
    duration_s: f64,
    omega: f64,
) -> Option<f64> {
    let t_end = history.last()?.0;
    let (ts, h): (Vec<f64>, Vec<f64>) = history
        .iter()
        .filter(|(t, _)| in_passage(*t, t_end, duration_s))
        .map(|(t, o)| (*t, o.central_film_m))
        .unzip();
    (ts.len() >= 4).then(|| harmonic_fit(&ts, &h, omega, 1)).flatten()
}

/// [`harmonic_amplitude`] over a trend of `trend` terms (1: a constant; at most a quartic).
fn harmonic_fit(xs: &[f64], h: &[f64], k: f64, trend: usize) -> Option<f64> {
    let terms = trend + 2;
    // x scaled to [−1, 1] keeps the normal equations' columns of one size.
    let (lo, hi) =
        xs.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    if !(1..=LINE_TREND).contains(&trend)
        || xs.len() < terms
        || xs.len() != h.len()
        || !(half > 0.0)
    {
        return None;
    }
    let basis = |x: f64| {
        let s = (x - mid) / half;
        let mut b = [0.0; MAX_TERMS];
        b[0] = 1.0;
        for n in 1..trend {
            b[n] = b[n - 1] * s;
        }
        (b[trend], b[trend + 1]) = ((k * x).cos(), (k * x).sin());
        b
    };
    let mut m = [[0.0; MAX_TERMS + 1]; MAX_TERMS];
    for (&x, &v) in xs.iter().zip(h) {
        let b = basis(x);
        for r in 0..terms {
            for c in 0..terms {
                m[r][c] += b[r] * b[c];
            }
            m[r][terms] += b[r] * v;
        }
    }
    // Gaussian elimination with partial pivoting on the normal equations.
    let scale = (0..terms).map(|r| m[r][r]).fold(0.0, f64::max);
    for col in 0..terms {
        let p = (col..terms).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if !(m[p][col].abs() > 1e-12 * scale) {
            return None;
        }
        m.swap(col, p);
        for r in col + 1..terms {
            let f = m[r][col] / m[col][col];
            for c in col..=terms {
                m[r][c] -= f * m[col][c];
            }
        }
    }
    let mut c = [0.0; MAX_TERMS];
    for r in (0..terms).rev() {
        let tail: f64 = (r + 1..terms).map(|j| m[r][j] * c[j]).sum();
        c[r] = (m[r][terms] - tail) / m[r][r];
    }
    Some(c[trend].hypot(c[trend + 1]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn observed(t: f64, hc: f64) -> (f64, Observables) {
        let o = Observables {
            central_film_m: hc,
            minimum_film_m: 0.5 * hc,
            minimum_film_at_m: (0.0, 0.0),
            film_overlap_m: 0.0,
            max_pressure_pa: 1e9 * hc / 1e-8,
            max_pressure_at_m: (0.0, 0.0),
            contact_extent_x_m: 0.0,
            contact_extent_y_m: 0.0,
            load_error: 0.0,
        };
        (t, o)
    }

    #[test]
    fn a_passage_averages_its_last_period_once_over_each_phase() {
        // A film of 10 nm ± 2 nm oscillating with period 1 s, sampled 8 times a period for 3 s:
        // the last period's eight records average to 10 nm exactly (the discrete cosine sums to
        // zero over whole periods), its extremes are the samples' 8 and 12 nm.
        let h: Vec<_> = (0..=24)
            .map(|k| {
                let t = k as f64 / 8.0;
                observed(t, 1e-8 + 2e-9 * (std::f64::consts::TAU * t).cos())
            })
            .collect();
        let p = Passage::over(&h, 1.0, 2e-5, Some(5e-9)).unwrap();
        assert_eq!(p.records, 8);
        assert!((p.central_film_mean_m - 1e-8).abs() < 1e-20, "{}", p.central_film_mean_m);
        assert!(
            (p.central_film_min_m - 8e-9).abs() < 1e-20
                && (p.central_film_max_m - 1.2e-8).abs() < 1e-20
        );
        assert!(
            (p.minimum_film_m - 4e-9).abs() < 1e-20 && (p.max_pressure_pa - 1.2e9).abs() < 1e-3
        );
        assert!((p.lambda.unwrap() - 2.0).abs() < 1e-12);
        assert!(Passage::over(&h[..5], 1.0, 2e-5, None).is_none(), "half a passage is none");
        // The centre's oscillation over the same records: 2 nm, to rounding (eight samples of a
        // whole period separate the constant from the harmonic exactly).
        let a_d = centre_amplitude(&h, 1.0, std::f64::consts::TAU).unwrap();
        assert!((a_d - 2e-9).abs() < 1e-20, "{a_d}");
        assert!(centre_amplitude(&h[..3], 0.2, std::f64::consts::TAU).is_none(), "2 records");
        let p = p.with_amplitude(2e-9, 5e-9);
        assert!((p.amplitude_ratio.unwrap() - 0.4).abs() < 1e-15);
        // The solids' share over the same eight records: 0 before the last period, then k/100
        // at its k-th record (k = 1 … 8): mean 4.5 %, largest 8 %, and the first instant (the
        // twin of the last) left out as the films' is. Off by a record, the mean is 4 or 5 %.
        let contact: Vec<(f64, f64)> = (0..=24)
            .map(|k| if k > 16 { ((k - 16) as f64 / 100.0, 1e-10) } else { (0.5, 1.0) })
            .collect();
        let q = p.with_contact(&h, &contact, 1.0);
        assert!((q.contact_load_share_mean.unwrap() - 0.045).abs() < 1e-15, "{q:?}");
        assert_eq!(q.contact_load_share_max, Some(0.08));
        assert!((q.contact_area_mean_m2.unwrap() - 1e-10).abs() < 1e-24);
        // A contact history that does not line up with the films' is not read.
        assert_eq!(p.with_contact(&h, &contact[1..], 1.0).contact_load_share_mean, None);
    }

    #[test]
    fn the_harmonic_is_found_beneath_a_quartic_and_only_it() {
        // A film shaped like a contact's (a quartic and a tilt) with a wave of 3 nm at phase
        // 0.7 rad: the fit recovers the 3 nm to rounding (the model holds the signal exactly).
        let k = std::f64::consts::TAU / 0.25;
        let xs: Vec<f64> = (0..=60).map(|i| -0.375 + 0.75 * i as f64 / 60.0).collect();
        let h: Vec<f64> = xs
            .iter()
            .map(|&x| {
                1e-8 + 4e-9 * x + 2e-8 * x * x - 5e-8 * x.powi(4) + 3e-9 * (k * x + 0.7).cos()
            })
            .collect();
        let a = harmonic_amplitude(&xs, &h, k).unwrap();
        assert!((a - 3e-9).abs() < 1e-18, "{a}");
        let smooth: Vec<f64> = xs.iter().map(|&x| 1e-8 + 2e-8 * x * x).collect();
        assert!(harmonic_amplitude(&xs, &smooth, k).unwrap() < 1e-20);
        assert!(harmonic_amplitude(&xs[..6], &h[..6], k).is_none(), "six samples, seven terms");
    }
}
