//! Solver settings as a scene writes them: what a user sets beside `advanced`, the solver's
//! internal knobs under it.
//!
//! The names a user sets (tolerances, cycle and iteration limits, the time scheme, whether the
//! solids may touch) are the scene format's promise: they keep their names and meanings, and a
//! saved scene that uses only them keeps working. The knobs under `advanced` are the solver's
//! own (sweep counts, gains, relaxation thresholds, fallback attempts): they may be renamed or
//! removed when the solver changes, and a scene that sets one shows it by where it writes it.
//! Each solver still owns its settings type and its checks; this module only decides where a
//! field is written.

use serde::de::{DeserializeOwned, Error as _};
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::{Map, Value};
use std::ops::{Deref, DerefMut};

/// A solver's settings type and the fields of it a user sets.
pub trait Tiers: Serialize + DeserializeOwned + Default {
    /// The fields written beside `advanced` (the stable ones); every other field is advanced.
    const USER: &'static [&'static str];
}

impl Tiers for ehl_core::DrySettings {
    const USER: &'static [&'static str] = &["tolerance", "max_iterations"];
}

impl Tiers for ehl_layer::SteadySettings {
    const USER: &'static [&'static str] = &["strain_tolerance", "max_iterations"];
}

impl Tiers for ehl_reynolds::ReynoldsSettings {
    const USER: &'static [&'static str] = &[
        "max_cycles",
        "film_tolerance",
        "step_film_tolerance",
        "load_tolerance",
        "mass_tolerance",
        "time_scheme",
        "stop",
        "contact",
    ];
}

/// Settings `T` read and written in two tiers; reads as a `T`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Tiered<T>(pub T);

impl<T> Deref for Tiered<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

impl<T> DerefMut for Tiered<T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.0
    }
}

impl<T: Tiers> Tiered<T> {
    /// A check's error with its field where the scene writes it (`advanced.relax.omega_gs`).
    pub fn placed(mut e: ehl_core::FieldError) -> ehl_core::FieldError {
        let first = e.field.split(['.', '[']).next().unwrap_or_default();
        if !T::USER.contains(&first) {
            e.field = format!("advanced.{}", e.field);
        }
        e
    }
}

/// The fields of `T` with their default values.
fn defaults<T: Tiers>() -> Map<String, Value> {
    match serde_json::to_value(T::default()) {
        Ok(Value::Object(m)) => m,
        _ => Map::new(),
    }
}

impl<'de, T: Tiers> Deserialize<'de> for Tiered<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let mut top = Map::<String, Value>::deserialize(d)?;
        let advanced = match top.remove("advanced") {
            None => Map::new(),
            Some(Value::Object(m)) => m,
            Some(_) => {
                return Err(D::Error::custom(
                    "`advanced`: expected an object of the solver's internal settings",
                ));
            }
        };
        let fields = defaults::<T>();
        let user = T::USER.iter().map(|u| format!("`{u}`")).collect::<Vec<_>>().join(", ");
        for k in top.keys() {
            if T::USER.contains(&k.as_str()) {
                continue;
            }
            return Err(D::Error::custom(if fields.contains_key(k) {
                format!(
                    "`{k}` is one of the solver's internal settings: write it under `advanced` \
                     (whose names may change between versions)"
                )
            } else {
                format!("unknown field `{k}`, expected one of {user} or `advanced`")
            }));
        }
        for k in advanced.keys() {
            if T::USER.contains(&k.as_str()) {
                return Err(D::Error::custom(format!(
                    "`advanced.{k}` is a user setting: write it beside `advanced`, not under it"
                )));
            }
        }
        let in_advanced: Vec<String> = advanced.keys().cloned().collect();
        top.extend(advanced);
        serde_path_to_error::deserialize(Value::Object(top)).map(Tiered).map_err(|e| {
            let path = e.path().to_string();
            let first = path.split(['.', '[']).next().unwrap_or_default();
            let path = if in_advanced.iter().any(|k| k == first) {
                format!("advanced.{path}")
            } else {
                path
            };
            D::Error::custom(if path == "." {
                e.into_inner().to_string()
            } else {
                format!("`{path}`: {}", e.into_inner())
            })
        })
    }
}

impl<T: Tiers> Serialize for Tiered<T> {
    /// Every user field, and under `advanced` the knobs that differ from their defaults (so a
    /// written scene reads back to the same settings).
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::Error as _;
        let Value::Object(all) = serde_json::to_value(&self.0).map_err(S::Error::custom)? else {
            return Err(S::Error::custom("settings serialise to a JSON object"));
        };
        let base = defaults::<T>();
        let (mut top, mut advanced) = (Map::new(), Map::new());
        for (k, v) in all {
            if T::USER.contains(&k.as_str()) {
                top.insert(k, v);
            } else if base.get(&k) != Some(&v) {
                advanced.insert(k, v);
            }
        }
        if !advanced.is_empty() {
            top.insert("advanced".into(), Value::Object(advanced));
        }
        top.serialize(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ehl_reynolds::ReynoldsSettings;

    fn read(text: &str) -> Result<ReynoldsSettings, String> {
        serde_json::from_str::<Tiered<ReynoldsSettings>>(text)
            .map(|t| t.0)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn every_user_field_is_a_field_of_its_settings() {
        fn check<T: Tiers>() {
            let fields = defaults::<T>();
            for u in T::USER {
                assert!(fields.contains_key(*u), "{u} is not a field");
            }
        }
        check::<ReynoldsSettings>();
        check::<ehl_core::DrySettings>();
        check::<ehl_layer::SteadySettings>();
    }

    #[test]
    fn user_fields_sit_beside_advanced_and_knobs_under_it() {
        let s =
            read(r#"{"max_cycles": 7, "advanced": {"pre_sweeps": 3, "relax": {"omega_gs": 0.3}}}"#)
                .unwrap();
        assert_eq!((s.max_cycles, s.pre_sweeps, s.relax.omega_gs), (7, 3, 0.3));
        assert_eq!(s.post_sweeps, ReynoldsSettings::default().post_sweeps);
    }

    #[test]
    fn a_knob_at_the_top_is_refused_with_where_it_belongs() {
        let e = read(r#"{"pre_sweeps": 3}"#).unwrap_err();
        assert!(e.contains("`pre_sweeps`") && e.contains("under `advanced`"), "{e}");
        let e = read(r#"{"advanced": {"max_cycles": 3}}"#).unwrap_err();
        assert!(e.contains("`advanced.max_cycles` is a user setting"), "{e}");
        let e = read(r#"{"max_cycle": 3}"#).unwrap_err();
        assert!(e.contains("unknown field `max_cycle`"), "{e}");
    }

    #[test]
    fn a_bad_knob_is_named_with_its_path_under_advanced() {
        let e = read(r#"{"advanced": {"relax": {"omega_gss": 0.3}}}"#).unwrap_err();
        assert!(e.contains("`advanced.relax.omega_gss`") && e.contains("unknown field"), "{e}");
        let e = read(r#"{"advanced": {"pre_sweeps": "two"}}"#).unwrap_err();
        assert!(e.contains("`advanced.pre_sweeps`"), "{e}");
    }

    #[test]
    fn written_settings_read_back_the_same_with_only_changed_knobs_under_advanced() {
        let mut s = ReynoldsSettings { max_cycles: 9, fallback_lag: 0.0, ..Default::default() };
        s.relax.omega_gs = 0.35;
        let text = serde_json::to_string(&Tiered(s)).unwrap();
        let v: Value = serde_json::from_str(&text).unwrap();
        let adv = v["advanced"].as_object().unwrap();
        assert_eq!(adv.keys().collect::<Vec<_>>(), ["fallback_lag", "relax"]);
        assert_eq!(read(&text).unwrap(), s);
        let plain = serde_json::to_string(&Tiered(ReynoldsSettings::default())).unwrap();
        assert!(!plain.contains("advanced"), "{plain}");
    }
}
