//! The features of a run as a scene gives them: the surfaces' relief (dents, waviness,
//! roughness) in SI, resolved on a model's contact into the core's [`ehl_core::Relief`].

use ehl_core::{Dent, HeightMap, Hole, Roughness, Waviness};
use serde::{Deserialize, Serialize};

/// A feature of the run: the surfaces' relief. A hole is in the oil supply (`supply.holes`) and
/// is refused here with that said.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Feature {
    /// A dent (or bump) in the ball.
    Dent(DentSpec),
    /// Harmonic waviness of the surfaces.
    Waviness(WavinessSpec),
    /// Random roughness of the surfaces.
    Roughness(RoughnessSpec),
    /// A measured surface: a height map read from an `.npy` file, placed and tiled.
    HeightMap(HeightMapSpec),
    /// Refused: holes are in `supply.holes`.
    Hole(Hole),
}

/// A dent as a scene gives it: the depth in metres, or as the seed's factor `A` in units of the
/// supply's thickness (exactly one of the two).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DentSpec {
    /// Height factor `A` [-]: depth in units of `supply.thickness_m` …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f64>,
    /// … or the depth at the centre [m].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth_m: Option<f64>,
    /// Width factor `W` [a].
    pub width_a: f64,
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    /// Centre across the rolling direction [a].
    #[serde(default)]
    pub y_a: f64,
}

impl DentSpec {
    /// The dent with its depth in metres, an amplitude resolved with the supply's thickness
    /// `l0_m` [m]; `None` when an amplitude has no supply to refer to.
    pub fn resolved(&self, l0_m: Option<f64>) -> Option<Dent> {
        let depth_m = match (self.depth_m, self.amplitude, l0_m) {
            (Some(d), _, _) => d,
            (None, Some(a), Some(l0)) => a * l0,
            _ => return None,
        };
        Some(Dent { depth_m, width_a: self.width_a, x_start_a: self.x_start_a, y_a: self.y_a })
    }
    /// Radius beyond which the dent is below 1e-6 of its depth [a].
    pub fn reach_a(&self) -> f64 {
        Dent { depth_m: 0.0, width_a: self.width_a, x_start_a: 0.0, y_a: 0.0 }.reach_a()
    }
}

/// Harmonic waviness as a scene gives it (SI): a gap added of `A cos(2π s/λ + φ)`, `s` the
/// distance along the wave's direction on the moving surfaces (pure rolling: a pattern on the
/// ball and one on the disc pass alike).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WavinessSpec {
    /// Amplitude `A` [m].
    pub amplitude_m: f64,
    /// Wavelength `λ` [m].
    pub wavelength_m: f64,
    /// Direction of the wave from the rolling direction [deg]: 0 transverse (ridges across the
    /// track, passing through the contact), 90 longitudinal (ridges along it, standing).
    #[serde(default)]
    pub angle_deg: f64,
    /// Phase `φ` at the origin at `t = 0` [deg].
    #[serde(default)]
    pub phase_deg: f64,
    /// Where the wavy surface ends downstream at the start, `x` [m] (absent: wavy everywhere):
    /// a wavy patch rolling in over a smooth surface, its edge blended over half a wavelength,
    /// so that a march starts from the smooth contact's steady state (crests that close the
    /// film need the time steps' contact, which a steady solve with them in place lacks).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub enters_at_x_m: Option<f64>,
}

impl WavinessSpec {
    /// The waviness on a contact of half-width `a_m` [m].
    pub fn resolved(&self, a_m: f64) -> Waviness {
        let w = Waviness {
            amplitude_m: self.amplitude_m,
            wavelength_a: self.wavelength_m / a_m,
            angle_rad: self.angle_deg.to_radians(),
            phase_rad: self.phase_deg.to_radians(),
            edge_a: None,
        };
        match self.enters_at_x_m {
            Some(x) => w.entering_at(x / a_m),
            None => w,
        }
    }
}

/// Random roughness as a scene gives it (SI): Gaussian heights of RMS `rq_m`, a Gaussian
/// autocorrelation falling to `1/e` over the correlation lengths, drawn from `seed`
/// ([`ehl_core::Roughness`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoughnessSpec {
    /// RMS height `Rq` [m].
    pub rq_m: f64,
    /// Correlation length `β` along the rolling direction [m] (across it too, unless given).
    pub correlation_length_m: f64,
    /// Correlation length across the rolling direction [m] (absent: isotropic).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation_length_y_m: Option<f64>,
    /// The random stream's seed: one seed, one surface, on every grid and machine.
    #[serde(default)]
    pub seed: u64,
    /// Where the rough surface ends downstream at the start, `x` [m] (absent: rough
    /// everywhere): a rough patch rolling in over a smooth surface, its edge blended over the
    /// correlation length, so that a march starts from the smooth contact's steady state
    /// (a film that closes over the roughness needs the time steps' contact, which a steady
    /// solve does not have).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub enters_at_x_m: Option<f64>,
}

impl RoughnessSpec {
    /// The surface on a contact of half-width `a_m` [m].
    pub fn resolved(&self, a_m: f64) -> Roughness {
        let beta_y = self.correlation_length_y_m.unwrap_or(self.correlation_length_m);
        let r = Roughness::new(self.rq_m, self.correlation_length_m / a_m, beta_y / a_m, self.seed);
        match self.enters_at_x_m {
            Some(x) => r.entering_at(x / a_m),
            None => r,
        }
    }
    /// The shortest correlation length [m].
    pub fn shortest_m(&self) -> f64 {
        self.correlation_length_m.min(self.correlation_length_y_m.unwrap_or(f64::INFINITY))
    }
}

/// A measured surface as a scene gives it (SI): an `.npy` file of heights [m] with the spacing
/// of its samples, placed on the track and tiled along and across it ([`ehl_core::HeightMap`]:
/// its mean removed, a peak narrowing the gap).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HeightMapSpec {
    /// The `.npy` file: a 2-D array of float64 heights [m], rows across the rolling direction
    /// (`y`), columns along it (`x`). A relative path is taken from the scene file's folder.
    pub path: String,
    /// The samples' spacing along the rolling direction [m] (across it too, unless given).
    pub spacing_m: f64,
    /// The samples' spacing across the rolling direction [m] (absent: `spacing_m`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing_y_m: Option<f64>,
    /// Where the map's first sample is at the start, `[x, y]` [m].
    #[serde(default)]
    pub origin_m: [f64; 2],
}

impl HeightMapSpec {
    /// The file's heights [m], rows along `y`; why not, in words (the file, its shape, its type).
    pub fn read(&self) -> Result<ndarray::Array2<f64>, String> {
        ndarray_npy::read_npy::<_, ndarray::Array2<f64>>(&self.path).map_err(|e| {
            format!("{}: not a readable 2-D float64 .npy array of heights in m ({e})", self.path)
        })
    }
    /// The spacing across the rolling direction [m].
    pub fn spacing_y(&self) -> f64 {
        self.spacing_y_m.unwrap_or(self.spacing_m)
    }
    /// The surface on a contact of half-width `a_m` [m], read from its file.
    pub fn resolved(&self, a_m: f64) -> Result<HeightMap, String> {
        let h = self.read()?;
        let (ny, nx) = h.dim();
        HeightMap::new(
            h,
            (self.spacing_m / a_m, self.spacing_y() / a_m),
            (self.origin_m[0] / a_m, self.origin_m[1] / a_m),
        )
        .ok_or_else(|| format!("{}: {ny} × {nx} samples, at least 2 × 2 are needed", self.path))
    }
}
