//! Range checks of settings, by the code that relies on them: each solver's settings type checks
//! its own fields ([`crate::DrySettings::check`] and the model crates' `check`), and a caller
//! (the scene) puts its own path in front of the field's name.

/// A setting out of its range: which field (its path inside the settings checked), what it holds,
/// and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("`{field}` = {value}: {allowed}")]
pub struct FieldError {
    /// The field's path inside the settings (`relax.omega_gs`).
    pub field: String,
    /// What it holds, as text.
    pub value: String,
    /// What is allowed.
    pub allowed: String,
}

impl FieldError {
    /// The same error with `prefix` put in front of the field's path (`reynolds.solver`).
    pub fn under(self, prefix: &str) -> FieldError {
        if prefix.is_empty() {
            return self;
        }
        FieldError { field: format!("{prefix}.{}", self.field), ..self }
    }
}

/// A number as a message shows it: plain where that is short, else in `e` notation (1e308 as
/// `1e308`, not 309 digits).
pub fn num(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (1e-4..1e6).contains(&a) || !a.is_finite() {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `v` in `[lo, hi]` (finite), else an error naming `field` and the range with its `unit`.
pub fn within(field: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), FieldError> {
    if v.is_finite() && (lo..=hi).contains(&v) {
        return Ok(());
    }
    Err(FieldError {
        field: field.into(),
        value: num(v),
        allowed: format!("must be in [{}, {}]{}", num(lo), num(hi), unit_words(unit)),
    })
}

/// `v` in `(lo, hi]` (finite: above `lo`, not at it), else an error naming `field`.
pub fn above(field: &str, v: f64, lo: f64, hi: f64, unit: &str) -> Result<(), FieldError> {
    if v.is_finite() && v > lo && v <= hi {
        return Ok(());
    }
    Err(FieldError {
        field: field.into(),
        value: num(v),
        allowed: format!("must be in ({}, {}]{}", num(lo), num(hi), unit_words(unit)),
    })
}

/// A count in `lo ..= hi`, else an error naming `field` and what the count is of.
pub fn count(field: &str, n: usize, lo: usize, hi: usize, what: &str) -> Result<(), FieldError> {
    if (lo..=hi).contains(&n) {
        return Ok(());
    }
    Err(FieldError {
        field: field.into(),
        value: n.to_string(),
        allowed: format!("must be {lo} ..= {hi}{}", unit_words(what)),
    })
}

fn unit_words(unit: &str) -> String {
    if unit.is_empty() { String::new() } else { format!(" ({unit})") }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_read_short_and_ranges_name_their_field() {
        assert_eq!(num(1e308), "1e308");
        assert_eq!(num(0.25), "0.25");
        assert_eq!(num(-3e-9), "-3e-9");
        let e = within("tolerance", -1.0, 1e-12, 0.5, "relative").unwrap_err();
        assert_eq!(e.to_string(), "`tolerance` = -1: must be in [1e-12, 0.5] (relative)");
        assert_eq!(e.under("reynolds.solver").field, "reynolds.solver.tolerance");
        assert!(above("x", 0.0, 0.0, 1.0, "").is_err() && above("x", 1.0, 0.0, 1.0, "").is_ok());
        assert!(within("x", f64::NAN, 0.0, 1.0, "").is_err());
        assert_eq!(count("n", 0, 1, 9, "cycles").unwrap_err().allowed, "must be 1 ..= 9 (cycles)");
    }
}
