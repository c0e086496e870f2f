//! What a scene may ask: the plausible range of each physical input and the limits of a run,
//! which the checks (`validate.rs`) hold every scene to.

/// The fastest rolling speed a scene may ask for [m/s]. The models are isothermal, which a
/// point contact stops being long before this (shear heating); and a march steps a cell's
/// travel at a time, so a speed far above the reference speed costs as many more steps.
pub const MAX_SPEED_M_S: f64 = 100.0;

/// The plausible range of each physical input, SI: `(field, least, most, unit, why)`. Beyond
/// them no ball-on-disc contact the models describe exists (a ball of a kilometre, a modulus of
/// a gas), and the arithmetic would overflow or lose every digit before a model could say so.
pub const PLAUSIBLE: &[(&str, f64, f64, &str, &str)] = &[
    ("conditions.ball_radius_m", 1e-6, 10.0, "m", "from a micro-sphere to a large bearing ball"),
    ("conditions.load_n", 1e-6, 1e7, "N", "from a micro-newton probe to a heavy bearing"),
    ("conditions.reduced_modulus_pa", 1e5, 1e13, "Pa", "from a soft elastomer to diamond"),
    ("lubricant.eta0_pa_s", 1e-6, 1e6, "Pa s", "from a gas to a bitumen"),
    ("lubricant.alpha_per_pa", 0.0, 1e-6, "1/Pa", "oils are 1e-8 to 4e-8"),
    ("lubricant.p0_roelands_pa", 1e6, 1e10, "Pa", "Roelands' constant is 1.96e8"),
    ("supply.thickness_m", 1e-12, 1e-3, "m", "from a molecular layer to a millimetre of oil"),
];

/// The fewest grid cells a wavelength of the surfaces' relief may span: a wave on fewer
/// points is aliased (on two, a crest and a trough or nothing, as its phase falls).
pub const MIN_CELLS_PER_WAVELENGTH: f64 = 4.0;

/// The largest distance of any place in a scene from the contact's centre, in units of `a`:
/// a feature or a hole further out never reaches a domain the checks allow.
pub const MAX_PLACE_A: f64 = 1e4;

/// The most snapshots a run may take (times and positions together): each holds two whole
/// fields in memory until the run is written (1000 on 1025² is 16 GB).
pub const MAX_SNAPSHOTS: usize = 1000;

/// The farthest a domain may reach from the contact's centre, in units of `a` (an inlet 50 `a`
/// long is already far beyond any starvation study's).
pub const MAX_DOMAIN_A: f64 = 1000.0;

/// The largest `a / R` a scene may reach: Hertz's half-space and the small-slope gap hold for
/// a contact small against the ball (`a/R` ≤ 0.2 keeps the parabolic gap within 1 % of the
/// sphere's at the contact's edge).
pub const MAX_A_OVER_R: f64 = 0.2;

/// The longest time a scene may ask for [s]: a stop, a ramp, a table's knot, a snapshot, a time
/// limit. Steps are held to a budget too; this keeps the plan's arithmetic finite.
pub const MAX_TIME_S: f64 = 1e4;
