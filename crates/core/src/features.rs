//! What passes through the contact, shared by every model: the surfaces' relief (dents or
//! bumps, harmonic waviness, random roughness: [`Relief`]) and the oil supply with its holes.
//! All travel with the surfaces (pure rolling, both surfaces at one speed, so a pattern on the
//! ball and one on the disc pass alike): a feature's centre at time `t` is `x_start + travel(t)/a`
//! ([`crate::Kinematics::travel`]). Heights and thicknesses in m (SI, as the scene gives them),
//! positions and lengths in units of `a`.

use crate::grid::{Grid, dent_profile};
use ndarray::{Array2, Zip};
use serde::{Deserialize, Serialize};

/// A dent in the ball (seed Eq. 14, reconstructed): a gap added of
/// `depth · 10^(−10 ((x − x_c)² + (y − y_c)²) / W²)`; a negative depth is a bump.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dent {
    /// Depth at the centre [m].
    pub depth_m: f64,
    /// Width factor `W` [a].
    pub width_a: f64,
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    /// Centre across the rolling direction [a].
    #[serde(default)]
    pub y_a: f64,
}

impl Dent {
    /// Gap added at `(x, y)` [a] with the centre at `x_c` [a], in units of `delta` [m] (the
    /// solvers' `a²/R`).
    #[inline]
    pub fn gap(&self, x: f64, y: f64, x_c: f64, delta: f64) -> f64 {
        let r2 = (x - x_c).powi(2) + (y - self.y_a).powi(2);
        self.depth_m / delta * dent_profile(r2, self.width_a)
    }
    /// Radius beyond which the dent is below 1e-6 of its depth [a].
    pub fn reach_a(&self) -> f64 {
        self.width_a * (0.6f64).sqrt()
    }

    /// How steep its walls are on a grid of cells `cell_a` [a] over a film `h_m` [m] (the gap
    /// beside it): the largest ratio of the gap between two neighbouring points along a line
    /// through its centre, over a few placements of the points; infinite where a bump closes
    /// the gap. A march's diagnosis reads it: a Reynolds step carries the oil across a wall
    /// cell by cell, and a gap that jumps tenfold in one cell is no thin film.
    pub fn steepest_cell_ratio(&self, cell_a: f64, h_m: f64) -> f64 {
        let cells = (self.reach_a() / cell_a).ceil() as i64 + 1;
        let mut worst = 1.0f64;
        for offset in [0.0, 0.25, 0.5, 0.75] {
            let gap = |k: i64| {
                let x = (k as f64 + offset) * cell_a;
                h_m + self.depth_m * dent_profile(x * x, self.width_a)
            };
            for k in -cells..cells {
                let (a, b) = (gap(k), gap(k + 1));
                if a.min(b) <= 0.0 {
                    return f64::INFINITY;
                }
                worst = worst.max(a.max(b) / a.min(b));
            }
        }
        worst
    }
}

/// Harmonic waviness: a gap added of `A cos(2π s / λ + φ)`, `s` the distance along the wave's
/// direction on the moving surface. The direction is at `angle` from the rolling direction:
/// 0 is transverse waviness (ridges across the track, passing through the contact), π/2
/// longitudinal (ridges along the track, standing in the contact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Waviness {
    /// Amplitude `A` [m].
    pub amplitude_m: f64,
    /// Wavelength `λ` [a].
    pub wavelength_a: f64,
    /// Direction of the wave vector from the rolling direction [rad].
    pub angle_rad: f64,
    /// Phase `φ` at the origin at `t = 0` [rad].
    pub phase_rad: f64,
    /// Where the wavy surface ends downstream at the start [a] (`None`: wavy everywhere): a
    /// wavy patch rolling in over a smooth surface ([`Self::entering_at`]).
    pub edge_a: Option<f64>,
}

impl Waviness {
    /// Gap added at `(x, y)` [a] after the surfaces travelled `travel_a` [a], in units of
    /// `delta` [m].
    #[inline]
    pub fn gap(&self, x: f64, y: f64, travel_a: f64, delta: f64) -> f64 {
        let xs = x - travel_a;
        let s = xs * self.angle_rad.cos() + y * self.angle_rad.sin();
        self.amplitude_m / delta
            * (std::f64::consts::TAU * s / self.wavelength_a + self.phase_rad).cos()
            * self.taper(xs)
    }

    /// The same wave only upstream of `x_a` [a] at the start, the edge moving with the
    /// surfaces and blended over half a wavelength (`½ (1 − tanh((x' − x_a)/(λ/2)))` of the
    /// heights, `x'` on the moving surface), so that a march starts from the smooth contact's
    /// steady state: a wave whose crests close the film needs the time steps' contact, and a
    /// steady solve with the crests already in the contact has none to start from.
    pub fn entering_at(self, x_a: f64) -> Self {
        Self { edge_a: Some(x_a), ..self }
    }

    /// The share of the amplitude kept at `x'` [a] on the moving surface (1 without an edge).
    #[inline]
    fn taper(&self, xs: f64) -> f64 {
        self.edge_a.map_or(1.0, |e| 0.5 * (1.0 - ((xs - e) / (0.5 * self.wavelength_a)).tanh()))
    }
}

/// How many cosines make a random surface: enough for Gaussian heights (the sum's kurtosis is
/// `3 − 3/(2N)`) and a smooth spectrum, few enough that evaluating it costs less than a solve.
pub const ROUGHNESS_MODES: usize = 256;

/// Random roughness: Gaussian heights of RMS `Rq` with the Gaussian autocorrelation
/// `Rq² exp(−(Δx/β_x)² − (Δy/β_y)²)` (`β` the lengths over which it falls to `1/e`), made as a
/// sum of [`ROUGHNESS_MODES`] cosines whose wave vectors are drawn from its spectrum and whose
/// phases are uniform (the randomisation method, Shinozuka & Deodatis, Appl. Mech. Rev. 44
/// (1991) 191–204). The surface is a function, not a grid: every grid samples the same surface,
/// and a seed gives the same surface on every machine (ChaCha8's stream is specified).
#[derive(Clone, Debug, PartialEq)]
pub struct Roughness {
    /// RMS height `Rq` [m].
    pub rq_m: f64,
    /// Correlation lengths `(β_x, β_y)` [a].
    pub correlation_a: (f64, f64),
    /// The seed it was drawn from.
    pub seed: u64,
    /// `(k_x, k_y, φ)` of each cosine [1/a, 1/a, rad].
    modes: Vec<[f64; 3]>,
    /// Where the rough surface ends downstream at the start [a] (`None`: rough everywhere): a
    /// rough patch rolling in over a smooth surface, so that a march can start from the smooth
    /// contact's steady state ([`Self::entering_at`]).
    pub edge_a: Option<f64>,
}

impl Roughness {
    /// The surface of RMS `rq_m` [m] and correlation lengths `(beta_x_a, beta_y_a)` [a] drawn
    /// from `seed`.
    pub fn new(rq_m: f64, beta_x_a: f64, beta_y_a: f64, seed: u64) -> Self {
        use rand_chacha::rand_core::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
        // Uniform in (0, 1) from the stream's top 53 bits.
        let mut uniform = || ((rng.next_u64() >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
        // The spectrum of exp(−Δx²/β²) is a normal of variance 2/β² in k.
        let (sx, sy) = (std::f64::consts::SQRT_2 / beta_x_a, std::f64::consts::SQRT_2 / beta_y_a);
        let modes = (0..ROUGHNESS_MODES)
            .map(|_| {
                // Box–Muller: two standard normals from two uniforms.
                let (r, t) = ((-2.0 * uniform().ln()).sqrt(), std::f64::consts::TAU * uniform());
                [sx * r * t.cos(), sy * r * t.sin(), std::f64::consts::TAU * uniform()]
            })
            .collect();
        Self { rq_m, correlation_a: (beta_x_a, beta_y_a), seed, modes, edge_a: None }
    }

    /// The same surface rough only upstream of `x_a` [a] at the start, the edge moving with the
    /// surfaces and blended over the correlation length (`½ (1 − tanh((x' − x_a)/β_x))` of the
    /// heights, `x'` on the moving surface): a step as sharp as a cell would be a wall the film
    /// has to climb, which no rough surface has.
    pub fn entering_at(self, x_a: f64) -> Self {
        Self { edge_a: Some(x_a), ..self }
    }

    /// The share of the heights kept at `x'` [a] on the moving surface (1 without an edge).
    #[inline]
    fn taper(&self, xs: f64) -> f64 {
        self.edge_a.map_or(1.0, |e| 0.5 * (1.0 - ((xs - e) / self.correlation_a.0).tanh()))
    }

    /// Gap added at `(x, y)` [a] after the surfaces travelled `travel_a` [a], in units of
    /// `delta` [m].
    pub fn gap(&self, x: f64, y: f64, travel_a: f64, delta: f64) -> f64 {
        let xs = x - travel_a;
        let sum: f64 = self.modes.iter().map(|[kx, ky, ph]| (kx * xs + ky * y + ph).cos()).sum();
        self.rq_m / delta * (2.0 / self.modes.len() as f64).sqrt() * sum * self.taper(xs)
    }

    /// [`Self::gap`] at every point of `grid`, added to `out`: the same sum, factored by rows
    /// and columns. Each cosine is the real part of `e^(i(k_x (x − s) + φ)) e^(i k_y y)`, so the
    /// field is one real matrix product, `[cos k_y y, −sin k_y y] · [cos(k_x x' + φ);
    /// sin(k_x x' + φ)]` (rows × 2 modes, 2 modes × columns): `M (n_x + n_y)` cosines instead
    /// of `M n_x n_y`. On 257² with 256 modes the sum point by point took half a rough march's
    /// time (the profile of a Reynolds march: 52 % in `cos`).
    pub fn add_gap_on(&self, grid: &Grid, travel_a: f64, delta: f64, out: &mut Array2<f64>) {
        let m = self.modes.len();
        let scale = self.rq_m / delta * (2.0 / m as f64).sqrt();
        let rows = Array2::from_shape_fn((grid.ny, 2 * m), |(j, q)| {
            let ky_y = self.modes[q % m][1] * grid.y(j);
            if q < m { ky_y.cos() } else { -ky_y.sin() }
        });
        // The patch's edge depends on the column alone: once a column, not once a mode.
        let weight: Vec<f64> =
            (0..grid.nx).map(|i| scale * self.taper(grid.x(i) - travel_a)).collect();
        let columns = Array2::from_shape_fn((2 * m, grid.nx), |(q, i)| {
            let [kx, _, ph] = self.modes[q % m];
            let arg = kx * (grid.x(i) - travel_a) + ph;
            weight[i] * if q < m { arg.cos() } else { arg.sin() }
        });
        ndarray::linalg::general_mat_mul(1.0, &rows, &columns, 1.0, out);
    }
}

/// A measured surface: a height map [m] on a regular grid, placed on the track and tiled along
/// and across it (the map repeats beyond its edges), carried with the surfaces; between its
/// samples, bilinear. Its mean is removed (the surface's own level is the contact's approach),
/// and a peak narrows the gap: the gap added is `−h`.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// Heights [m], rows along `y`, columns along `x`, their mean removed.
    heights_m: Array2<f64>,
    /// Spacing of the samples along `x` and `y` [a].
    pub spacing_a: (f64, f64),
    /// Where the first sample is at the start [a].
    pub origin_a: (f64, f64),
    /// RMS height `Rq` [m].
    pub rq_m: f64,
}

impl HeightMap {
    /// The map of `heights_m` [m] (rows along `y`) with samples `spacing_a` [a] apart, its first
    /// at `origin_a` [a] at the start; `None` for fewer than 2 × 2 samples.
    pub fn new(
        heights_m: Array2<f64>,
        spacing_a: (f64, f64),
        origin_a: (f64, f64),
    ) -> Option<Self> {
        let (ny, nx) = heights_m.dim();
        if nx < 2 || ny < 2 {
            return None;
        }
        let mean = heights_m.mean()?;
        let heights_m = heights_m.mapv(|h| h - mean);
        let rq_m = (heights_m.iter().map(|h| h * h).sum::<f64>() / (nx * ny) as f64).sqrt();
        Some(Self { heights_m, spacing_a, origin_a, rq_m })
    }

    /// The samples per side `(n_x, n_y)`.
    pub fn dim(&self) -> (usize, usize) {
        let (ny, nx) = self.heights_m.dim();
        (nx, ny)
    }

    /// Gap added at `(x, y)` [a] after the surfaces travelled `travel_a` [a], in units of
    /// `delta` [m].
    pub fn gap(&self, x: f64, y: f64, travel_a: f64, delta: f64) -> f64 {
        let (nx, ny) = self.dim();
        let u = (x - travel_a - self.origin_a.0) / self.spacing_a.0;
        let v = (y - self.origin_a.1) / self.spacing_a.1;
        let (u0, v0) = (u.floor(), v.floor());
        let (fu, fv) = (u - u0, v - v0);
        // Tiled: indices wrap around the map.
        let wrap = |k: f64, n: usize| (k as i64).rem_euclid(n as i64) as usize;
        let (i0, i1) = (wrap(u0, nx), wrap(u0 + 1.0, nx));
        let (j0, j1) = (wrap(v0, ny), wrap(v0 + 1.0, ny));
        let h = &self.heights_m;
        let below = h[[j0, i0]] * (1.0 - fu) + h[[j0, i1]] * fu;
        let above = h[[j1, i0]] * (1.0 - fu) + h[[j1, i1]] * fu;
        -(below * (1.0 - fv) + above * fv) / delta
    }
}

/// The surfaces' relief passing through the contact: every model adds [`Relief::gap`] to its
/// rigid gap, each at its own grid points.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Relief {
    /// Dents (or bumps) in the ball.
    pub dents: Vec<Dent>,
    /// Harmonic waviness.
    pub waves: Vec<Waviness>,
    /// Random roughness.
    pub roughness: Vec<Roughness>,
    /// Measured height maps.
    pub maps: Vec<HeightMap>,
}

impl Relief {
    /// Smooth surfaces.
    pub fn is_empty(&self) -> bool {
        self.dents.is_empty()
            && self.waves.is_empty()
            && self.roughness.is_empty()
            && self.maps.is_empty()
    }
    /// Gap added at `(x, y)` [a] after the surfaces travelled `travel_a` [a], in units of
    /// `delta` [m] (the solvers' `a²/R`).
    pub fn gap(&self, x: f64, y: f64, travel_a: f64, delta: f64) -> f64 {
        let dents: f64 =
            self.dents.iter().map(|d| d.gap(x, y, d.x_start_a + travel_a, delta)).sum();
        let waves: f64 = self.waves.iter().map(|w| w.gap(x, y, travel_a, delta)).sum();
        let rough: f64 = self.roughness.iter().map(|r| r.gap(x, y, travel_a, delta)).sum();
        let maps: f64 = self.maps.iter().map(|m| m.gap(x, y, travel_a, delta)).sum();
        dents + waves + rough + maps
    }
    /// [`Self::gap`] at every point of `grid` [units of `delta`]: what a model adds to its rigid
    /// gap, the roughness summed by rows and columns ([`Roughness::add_gap_on`]).
    pub fn gap_on(&self, grid: &Grid, travel_a: f64, delta: f64) -> Array2<f64> {
        let mut g = grid.zeros();
        if !(self.dents.is_empty() && self.waves.is_empty() && self.maps.is_empty()) {
            Zip::indexed(&mut g).par_for_each(|(j, i), v| {
                let (x, y) = (grid.x(i), grid.y(j));
                let dents: f64 =
                    self.dents.iter().map(|d| d.gap(x, y, d.x_start_a + travel_a, delta)).sum();
                let waves: f64 = self.waves.iter().map(|w| w.gap(x, y, travel_a, delta)).sum();
                let maps: f64 = self.maps.iter().map(|m| m.gap(x, y, travel_a, delta)).sum();
                *v = dents + waves + maps;
            });
        }
        for r in &self.roughness {
            r.add_gap_on(grid, travel_a, delta, &mut g);
        }
        g
    }

    /// Whether the surfaces carry a pattern (waviness, roughness, a height map) and not only
    /// dents: what covers the track and rolls through the contact without end.
    pub fn has_pattern(&self) -> bool {
        !(self.waves.is_empty() && self.roughness.is_empty() && self.maps.is_empty())
    }
    /// The relief's one wave when it is nothing else (no dent, roughness or map beside it).
    pub fn single_wave(&self) -> Option<&Waviness> {
        let alone = self.dents.is_empty() && self.roughness.is_empty() && self.maps.is_empty();
        match self.waves.as_slice() {
            [w] if alone => Some(w),
            _ => None,
        }
    }
    /// The RMS height of the relief's patterns [m]: waves' `A/√2`, roughness' and height maps'
    /// `Rq`, combined as independent (`None`: no pattern, dents alone).
    pub fn rms_m(&self) -> Option<f64> {
        if !self.has_pattern() {
            return None;
        }
        let waves = self.waves.iter().map(|w| 0.5 * w.amplitude_m * w.amplitude_m);
        let rough = self.roughness.iter().map(|r| r.rq_m * r.rq_m);
        let maps = self.maps.iter().map(|m| m.rq_m * m.rq_m);
        Some(waves.chain(rough).chain(maps).sum::<f64>().sqrt())
    }

    /// The shortest wave a grid must carry [a]: a waviness' wavelength, a roughness' `2 β`
    /// (its Gaussian spectrum's shortest waves, two standard deviations out, are about
    /// `2.2 β`), a height map's two spacings (the shortest wave its samples hold); `None`
    /// without any of them.
    pub fn shortest_wave_a(&self) -> Option<f64> {
        let waves = self.waves.iter().map(|w| w.wavelength_a);
        let rough = self.roughness.iter().map(|r| 2.0 * r.correlation_a.0.min(r.correlation_a.1));
        let maps = self.maps.iter().map(|m| 2.0 * m.spacing_a.0.min(m.spacing_a.1));
        waves.chain(rough).chain(maps).reduce(f64::min)
    }

    /// The travel after which the relief repeats [a], when it is periodic: waves alone, all
    /// with one period along the rolling direction (longitudinal waves stand and repeat at
    /// any travel). `None` with dents, roughness or a height map, or with no wave moving.
    pub fn period_a(&self) -> Option<f64> {
        if !(self.dents.is_empty() && self.roughness.is_empty() && self.maps.is_empty()) {
            return None;
        }
        let along = |w: &Waviness| {
            let c = w.angle_rad.cos().abs();
            (c > 1e-9).then(|| w.wavelength_a / c)
        };
        let mut periods = self.waves.iter().filter_map(along);
        let p = periods.next()?;
        periods.all(|q| (q / p - 1.0).abs() < 1e-9).then_some(p)
    }

    /// The travel [a] after which every wave rolling in over a smooth surface fills a domain
    /// ending at `x_max` [a] downstream: its blended edge past `x_max` by seven half
    /// wavelengths (the smooth surface's share then below `e^(−14)`, 1e-6 of the amplitude).
    /// Zero without such a wave: a periodic state cannot be judged before it.
    pub fn filled_after_a(&self, x_max: f64) -> f64 {
        let edges = self.waves.iter().filter_map(|w| w.edge_a.map(|e| (e, w.wavelength_a)));
        edges.map(|(e, l)| x_max - e + 3.5 * l).fold(0.0, f64::max)
    }
}

/// A circular hole in the supplied oil (no oil inside), carried with the surfaces.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hole {
    /// Radius [a].
    pub radius_a: f64,
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    /// Centre across the rolling direction [a].
    #[serde(default)]
    pub y_a: f64,
}

impl Hole {
    /// Whether `(x, y)` [a] is inside the hole when its centre is at `x_c` [a].
    #[inline]
    pub fn inside(&self, x: f64, y: f64, x_c: f64) -> bool {
        (x - x_c).powi(2) + (y - self.y_a).powi(2) < self.radius_a * self.radius_a
    }
}

/// The oil supplied to the contact: a layer of `thickness_m` on the track, arriving with the
/// surfaces, with holes where there is none. Every model that has a supply reads this one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Supply {
    /// Thickness of the supplied layer `l0` (the inlet layer `h_oil`) [m].
    pub thickness_m: f64,
    /// Holes in it (the seed's dry spot).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub holes: Vec<Hole>,
}

impl Supply {
    /// A uniform supply of `thickness_m` [m].
    pub fn uniform(thickness_m: f64) -> Self {
        Self { thickness_m, holes: vec![] }
    }
    /// The thickness at `(x, y)` [a] with the holes' centres moved by `travel_a` [a] [m].
    pub fn thickness_at(&self, x: f64, y: f64, travel_a: f64) -> f64 {
        if self.holes.iter().any(|h| h.inside(x, y, h.x_start_a + travel_a)) {
            0.0
        } else {
            self.thickness_m
        }
    }
}

/// Where a passing feature starts and how far beyond its centre it acts [a]: what a march
/// needs to know to end when features have passed, or when one has reached a place.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Passing {
    /// Centre at `t = 0` [a].
    pub x_start_a: f64,
    /// Half-size beyond which it has no effect [a].
    pub reach_a: f64,
}

impl From<&Dent> for Passing {
    fn from(d: &Dent) -> Self {
        Passing { x_start_a: d.x_start_a, reach_a: d.reach_a() }
    }
}

impl From<&Hole> for Passing {
    fn from(h: &Hole) -> Self {
        Passing { x_start_a: h.x_start_a, reach_a: h.radius_a }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dent_s_steepest_wall_on_a_grid_is_the_gap_s_largest_jump_between_neighbours() {
        // Cells one width apart over a film of 1 m and a dent 1000 m deep: with a point at the
        // centre its neighbours sit at 10^-10 of the depth, and the gap jumps from 1 + 1e-7 to
        // 1001 (the other placements jump less: 238 at a quarter cell, 4.2 at half). What this
        // catches: a ratio read the wrong way up, one placement only, or the depth left out.
        let d = Dent { depth_m: 1000.0, width_a: 0.1, x_start_a: 0.0, y_a: 0.0 };
        let r = d.steepest_cell_ratio(0.1, 1.0);
        let expected = 1001.0 / (1.0 + 1000.0 * 1e-10);
        assert!((r / expected - 1.0).abs() < 1e-12, "{r} against {expected}");
        // Fine cells see a gentle wall; no dent, none; a bump that closes the film, infinite.
        assert!(d.steepest_cell_ratio(1e-4, 1.0) < 1.05, "{}", d.steepest_cell_ratio(1e-4, 1.0));
        assert_eq!(Dent { depth_m: 0.0, ..d }.steepest_cell_ratio(0.01, 1.0), 1.0);
        assert_eq!(Dent { depth_m: -2.0, ..d }.steepest_cell_ratio(0.01, 1.0), f64::INFINITY);
    }

    #[test]
    fn a_dent_is_its_depth_at_the_centre_and_a_millionth_at_its_reach() {
        let d = Dent { depth_m: 2e-8, width_a: 0.1, x_start_a: -1.0, y_a: 0.2 };
        assert_eq!(d.gap(0.5, 0.2, 0.5, 1e-9), 20.0);
        let at_reach = d.gap(0.5 + d.reach_a(), 0.2, 0.5, 1e-9);
        assert!((at_reach / 20.0 - 1e-6).abs() < 1e-15, "{at_reach}");
        assert_eq!(Passing::from(&d), Passing { x_start_a: -1.0, reach_a: d.reach_a() });
    }

    #[test]
    fn transverse_waviness_travels_with_the_surfaces_and_repeats_after_a_wavelength() {
        let w = Waviness {
            amplitude_m: 1e-8,
            wavelength_a: 0.25,
            angle_rad: 0.0,
            phase_rad: 0.0,
            edge_a: None,
        };
        assert_eq!(w.gap(0.3, 0.7, 0.3, 1e-9), 10.0); // a crest carried to x = 0.3
        assert!(w.gap(0.3 + 0.125, 0.0, 0.3, 1e-9) + 10.0 < 1e-12); // a trough half a wave on
        for x in [-1.0, -0.37, 0.0, 0.81] {
            let (a, b) = (w.gap(x, 0.2, 0.1, 1e-9), w.gap(x, 0.2, 0.1 + 0.25, 1e-9));
            assert!((a - b).abs() < 1e-12, "moved by one wavelength: {a} vs {b}");
        }
        // Longitudinal: ridges along the track stand still as the surfaces roll.
        let l = Waviness { angle_rad: std::f64::consts::FRAC_PI_2, ..w };
        assert!((l.gap(0.1, 0.3, 0.0, 1e-9) - l.gap(0.1, 0.3, 0.77, 1e-9)).abs() < 1e-12);
        assert!((l.gap(0.1, 0.125, 0.0, 1e-9) + 10.0).abs() < 1e-12);
    }

    #[test]
    fn a_wavy_patch_rolls_in_over_a_smooth_surface_with_its_edge() {
        let whole = Waviness {
            amplitude_m: 1e-8,
            wavelength_a: 0.25,
            angle_rad: 0.2,
            phase_rad: 0.4,
            edge_a: None,
        };
        let patch = whole.entering_at(-1.0);
        // Upstream the patch is the whole wave (to tanh's 1e-17 at 20 half-waves); far
        // downstream smooth; at the edge half the wave, the edge carried with the surfaces.
        for &(x, y) in &[(-7.0, 0.3), (-6.1, -0.2)] {
            assert!((patch.gap(x, y, 0.0, 1e-9) - whole.gap(x, y, 0.0, 1e-9)).abs() < 1e-12);
        }
        assert!(patch.gap(5.0, 0.1, 0.0, 1e-9).abs() < 1e-12);
        for (x, travel) in [(-1.0, 0.0), (-0.4, 0.6)] {
            let (p, w) = (patch.gap(x, 0.1, travel, 1e-9), whole.gap(x, 0.1, travel, 1e-9));
            assert!((p - 0.5 * w).abs() < 1e-12, "at the edge: {p} against half of {w}");
        }
        // Half a wavelength past the edge, tanh(1): 12 % of the wave, not a cell's step.
        let (p, w) = (patch.gap(-0.875, 0.0, 0.0, 1e-9), whole.gap(-0.875, 0.0, 0.0, 1e-9));
        assert!((p / w - 0.5 * (1.0 - 1f64.tanh())).abs() < 1e-12);
        // A domain ending at 1.25 a is filled once the edge is 7 half-waves past it.
        let relief = Relief { waves: vec![patch], ..Relief::default() };
        let travel = relief.filled_after_a(1.25);
        assert!((travel - (2.25 + 3.5 * 0.25)).abs() < 1e-12, "{travel}");
        let smooth = 1.0 - patch.taper(1.25 - travel); // the share still missing at the outlet
        assert!(smooth < 1e-6 && smooth > 1e-7, "{smooth}");
        assert_eq!(Relief { waves: vec![whole], ..Relief::default() }.filled_after_a(1.25), 0.0);
    }

    /// The surface sampled on a square of `n²` points spaced `h` [a], in units of `Rq`.
    fn sampled(r: &Roughness, n: usize, h: f64) -> Vec<f64> {
        (0..n * n).map(|k| r.gap((k % n) as f64 * h, (k / n) as f64 * h, 0.0, r.rq_m)).collect()
    }

    #[test]
    fn random_roughness_has_its_rms_and_falls_to_one_over_e_at_its_correlation_length() {
        // Sampled over 60 × 30 correlation lengths (β_y = 2 β_x): the sample's
        // RMS and correlation differ from the surface's by the spectrum's own sampling with
        // 256 cosines (the correlation at lag β is a mean of 256 cosines, standard deviation
        // about 0.03): 8 % on the RMS, 0.1 on the correlation are three of those.
        let beta = 0.05;
        let r = Roughness::new(2e-8, beta, 2.0 * beta, 7);
        let (n, h) = (360, beta / 6.0);
        let z = sampled(&r, n, h);
        let mean = z.iter().sum::<f64>() / z.len() as f64;
        let rms = (z.iter().map(|v| v * v).sum::<f64>() / z.len() as f64).sqrt();
        assert!(mean.abs() < 0.05 && (rms - 1.0).abs() < 0.08, "mean {mean}, rms {rms} (Rq)");
        let lag = 6; // one correlation length
        let corr = |dx: usize, dy: usize| {
            let (mut s, mut m) = (0.0, 0);
            for j in 0..n - dy {
                for i in 0..n - dx {
                    s += z[j * n + i] * z[(j + dy) * n + i + dx];
                    m += 1;
                }
            }
            s / m as f64 / (rms * rms)
        };
        let e = (-1.0f64).exp();
        for (cx, what) in [(corr(lag, 0), "along x"), (corr(0, 2 * lag), "along y")] {
            assert!((cx - e).abs() < 0.1, "correlation at one length {what}: {cx} (1/e = {e:.3})");
        }
        let quarter = (-0.25f64).exp(); // half of β_y
        assert!((corr(0, lag) - quarter).abs() < 0.1, "{} vs {quarter}", corr(0, lag));
        assert!(corr(3 * lag, 0).abs() < 0.1, "three lengths apart: {}", corr(3 * lag, 0));
    }

    #[test]
    fn a_roughness_seed_is_one_surface_on_every_grid_and_another_seed_another() {
        let (a, b) = (Roughness::new(1e-8, 0.1, 0.3, 42), Roughness::new(1e-8, 0.1, 0.3, 42));
        assert_eq!(a, b);
        // The same point of the moving surface: at x on one grid, at x + s after travel s.
        // (to the rounding of x − s, in a sum of 256 cosines of a few units each)
        assert!((a.gap(0.1, 0.2, 0.0, 1e-9) - b.gap(0.1 + 0.5, 0.2, 0.5, 1e-9)).abs() < 1e-9);
        let c = Roughness::new(1e-8, 0.1, 0.3, 43);
        assert_ne!(a.gap(0.1, 0.2, 0.0, 1e-9), c.gap(0.1, 0.2, 0.0, 1e-9));
    }

    /// A dent and an oblique wave, the parts of the reliefs below.
    fn dent_and_wave() -> (Dent, Waviness) {
        let d = Dent { depth_m: 2e-8, width_a: 0.1, x_start_a: -1.0, y_a: 0.0 };
        let w = Waviness {
            amplitude_m: 1e-8,
            wavelength_a: 0.25,
            angle_rad: 0.3,
            phase_rad: 1.0,
            edge_a: None,
        };
        (d, w)
    }

    #[test]
    fn smooth_surfaces_add_no_gap_and_a_relief_adds_its_parts() {
        assert_eq!(Relief::default().gap(0.1, 0.2, 0.3, 1e-9), 0.0);
        let (d, w) = dent_and_wave();
        let r = Roughness::new(5e-9, 0.1, 0.1, 1);
        let all =
            Relief { dents: vec![d], waves: vec![w], roughness: vec![r.clone()], maps: vec![] };
        let (x, y, s) = (-0.6, 0.1, 0.45);
        let parts = d.gap(x, y, -1.0 + s, 1e-9) + w.gap(x, y, s, 1e-9) + r.gap(x, y, s, 1e-9);
        assert!((all.gap(x, y, s, 1e-9) - parts).abs() < 1e-12);
        assert!(!all.is_empty() && Relief::default().is_empty());
    }

    #[test]
    fn a_relief_on_a_grid_is_its_gap_at_every_point() {
        let (d, w) = dent_and_wave();
        let r = Roughness::new(5e-9, 0.1, 0.2, 7);
        let entering = Roughness::new(3e-9, 0.15, 0.15, 2).entering_at(-0.4);
        let heights = Array2::from_shape_fn((5, 7), |(j, i)| 1e-9 * ((i * i + 3 * j) % 5) as f64);
        let map = HeightMap::new(heights, (0.11, 0.07), (-0.3, 0.2)).unwrap();
        let all = Relief {
            dents: vec![d],
            waves: vec![w],
            roughness: vec![r, entering],
            maps: vec![map],
        };
        // A grid that is not square, so that rows and columns cannot be swapped unseen.
        let g = Grid::new(33, 21, (-1.3, 1.1), (-0.8, 0.9));
        let s = 0.37;
        let field = all.gap_on(&g, s, 1e-9);
        assert_eq!(field.dim(), (21, 33));
        // The factored sum against the cosines one by one: the same terms in another order
        // (256 cosines of heights of about 5 units: rounding of 1e-13, a wrong sign or a swapped
        // axis of order one).
        for ((j, i), v) in field.indexed_iter() {
            assert!((v - all.gap(g.x(i), g.y(j), s, 1e-9)).abs() < 1e-11, "at {i}, {j}");
        }
    }

    #[test]
    fn a_rough_patch_rolls_in_over_a_smooth_surface_with_its_edge() {
        let whole = Roughness::new(4e-9, 0.1, 0.1, 5);
        let patch = whole.clone().entering_at(-1.0);
        // Upstream of the edge the patch is the whole surface (to tanh's 1e-17 at 40 β); far
        // downstream it is smooth; at the edge half of it. Travel carries the edge: after 0.6 a
        // it is at -0.4 a.
        for &(x, y) in &[(-5.0, 0.3), (-3.0, -0.2)] {
            assert!((patch.gap(x, y, 0.0, 1e-9) - whole.gap(x, y, 0.0, 1e-9)).abs() < 1e-12);
        }
        assert!(patch.gap(0.5, 0.1, 0.0, 1e-9).abs() < 1e-12);
        assert!(
            (patch.gap(-1.0, 0.1, 0.0, 1e-9) - 0.5 * whole.gap(-1.0, 0.1, 0.0, 1e-9)).abs() < 1e-12
        );
        assert!(
            (patch.gap(-0.4, 0.1, 0.6, 1e-9) - 0.5 * whole.gap(-0.4, 0.1, 0.6, 1e-9)).abs() < 1e-12
        );
    }

    #[test]
    fn a_height_map_is_its_samples_at_its_nodes_bilinear_between_and_tiled_beyond() {
        // Heights 1, 2, 3 / 4, 5, 6 nm (mean 3.5) 0.1 a apart from (-0.2, 0.5): at a node the gap
        // added is minus its height over the mean; halfway between the four of one cell their
        // mean; a map's length on (3 × 0.1 a along, 2 × 0.1 a across) the same again.
        let h = Array2::from_shape_vec((2, 3), vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]).unwrap() * 1e-9;
        let m = HeightMap::new(h, (0.1, 0.1), (-0.2, 0.5)).unwrap();
        let at = |x: f64, y: f64, s: f64| m.gap(x, y, s, 1e-9);
        assert!((at(-0.2, 0.5, 0.0) - 2.5).abs() < 1e-12);
        assert!((at(0.0, 0.6, 0.0) + 2.5).abs() < 1e-12);
        assert!((at(-0.15, 0.55, 0.0) - 0.5).abs() < 1e-12, "{}", at(-0.15, 0.55, 0.0));
        for (x, y) in [(-0.13, 0.52), (0.37, -1.11)] {
            assert!((at(x + 0.3, y - 0.2, 0.0) - at(x, y, 0.0)).abs() < 1e-12);
            // Carried with the surfaces: after 0.25 a the map is 0.25 a downstream.
            assert!((at(x + 0.25, y, 0.25) - at(x, y, 0.0)).abs() < 1e-12);
        }
        // Its RMS about the mean: √(35/12) nm.
        assert!((m.rq_m - (35.0f64 / 12.0).sqrt() * 1e-9).abs() < 1e-20);
        assert!(HeightMap::new(Array2::zeros((1, 4)), (0.1, 0.1), (0.0, 0.0)).is_none());
    }

    #[test]
    fn the_supply_has_no_oil_in_its_holes_wherever_they_have_travelled() {
        let s = Supply {
            thickness_m: 2.5e-8,
            holes: vec![Hole { radius_a: 0.2, x_start_a: -1.0, y_a: 0.0 }],
        };
        assert_eq!(s.thickness_at(-1.0, 0.0, 0.0), 0.0);
        assert_eq!(s.thickness_at(-1.0, 0.0, 0.5), 2.5e-8);
        assert_eq!(s.thickness_at(-0.45, 0.1, 0.5), 0.0);
        assert_eq!(s.thickness_at(-0.45, 0.21, 0.5), 2.5e-8);
        assert_eq!(Supply::uniform(1e-8).thickness_at(0.0, 0.0, 0.0), 1e-8);
    }
}
