//! Parameter schemas: every law publishes the name, unit, default, valid range and a one-line
//! doc of each of its parameters, and the sdk validates user input against it before the law
//! ever sees a value.

use crate::error::{ErrorKind, LawError};
use abi_stable::{
    std_types::{ROption, RString},
    StableAbi,
};

/// A closed or open interval of valid values. Bounds may be infinite.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Range {
    /// Lower bound (in the parameter's unit); `-inf` for none.
    pub min: f64,
    /// Upper bound (in the parameter's unit); `+inf` for none.
    pub max: f64,
    /// Whether `min` itself is valid.
    pub min_inclusive: bool,
    /// Whether `max` itself is valid.
    pub max_inclusive: bool,
}

impl Range {
    /// (min, max]
    pub const fn open_closed(min: f64, max: f64) -> Range {
        Range {
            min,
            max,
            min_inclusive: false,
            max_inclusive: true,
        }
    }
    /// [min, max]
    pub const fn closed(min: f64, max: f64) -> Range {
        Range {
            min,
            max,
            min_inclusive: true,
            max_inclusive: true,
        }
    }
    /// (0, +inf): strictly positive and finite.
    pub const fn positive() -> Range {
        Range {
            min: 0.0,
            max: f64::INFINITY,
            min_inclusive: false,
            max_inclusive: false,
        }
    }
    /// [0, +inf): non-negative and finite.
    pub const fn non_negative() -> Range {
        Range {
            min: 0.0,
            max: f64::INFINITY,
            min_inclusive: true,
            max_inclusive: false,
        }
    }

    /// Whether `v` lies in the range (NaN never does; infinities only as inclusive bounds).
    pub fn contains(&self, v: f64) -> bool {
        if v.is_nan() {
            return false;
        }
        let lo = if self.min_inclusive {
            v >= self.min
        } else {
            v > self.min
        };
        let hi = if self.max_inclusive {
            v <= self.max
        } else {
            v < self.max
        };
        lo && hi && (v.is_finite() || (v == self.min || v == self.max))
    }
}

impl std::fmt::Display for Range {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let l = if self.min_inclusive { '[' } else { '(' };
        let r = if self.max_inclusive { ']' } else { ')' };
        let b = |x: f64| {
            if x == f64::INFINITY {
                "inf".to_string()
            } else if x == f64::NEG_INFINITY {
                "-inf".to_string()
            } else {
                format!("{x}")
            }
        };
        write!(f, "{l}{}, {}{r}", b(self.min), b(self.max))
    }
}

/// The description of one parameter of a law.
#[repr(C)]
#[derive(StableAbi, Debug, Clone, PartialEq, serde::Serialize)]
pub struct ParamSpec {
    /// The name used in `--set name=value`, TOML files and the C ABI.
    pub name: RString,
    /// SI unit of the value ("1" for dimensionless).
    pub unit: RString,
    /// Value used when the user gives none. `RNone`: the law derives it from the pair (see `doc`).
    pub default: ROption<f64>,
    /// Valid values.
    pub range: Range,
    /// One line of documentation.
    pub doc: RString,
}

impl ParamSpec {
    /// A parameter with a default value.
    pub fn new(name: &str, unit: &str, default: f64, range: Range, doc: &str) -> ParamSpec {
        ParamSpec {
            name: name.into(),
            unit: unit.into(),
            default: ROption::RSome(default),
            range,
            doc: doc.into(),
        }
    }

    /// An optional parameter without default: when absent, the law derives it (say how in `doc`).
    pub fn derived(name: &str, unit: &str, range: Range, doc: &str) -> ParamSpec {
        ParamSpec {
            name: name.into(),
            unit: unit.into(),
            default: ROption::RNone,
            range,
            doc: doc.into(),
        }
    }
}

/// A named value, as given by a user or reported by a law (in the unit of its schema).
#[repr(C)]
#[derive(StableAbi, Debug, Clone, PartialEq, serde::Serialize)]
pub struct ParamValue {
    /// Parameter name.
    pub name: RString,
    /// Value in the unit of the parameter's schema.
    pub value: f64,
}

impl ParamValue {
    /// `name = value`.
    pub fn new(name: &str, value: f64) -> ParamValue {
        ParamValue {
            name: name.into(),
            value,
        }
    }
}

/// A law's parameters after validation: every schema entry with its value (given or default),
/// or `None` for a derived parameter the user did not set.
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    law: String,
    values: Vec<(String, Option<f64>)>,
}

impl Params {
    /// Validates `given` against `schema` for the law `law`: unknown names, duplicates, NaN and
    /// out-of-range values are errors that name the parameter and its range.
    pub fn resolve(law: &str, schema: &[ParamSpec], given: &[ParamValue]) -> Result<Params, LawError> {
        let mut values: Vec<(String, Option<f64>)> = schema
            .iter()
            .map(|s| (s.name.to_string(), s.default.into_option()))
            .collect();
        let mut seen = vec![false; schema.len()];
        for g in given {
            let Some(i) = schema.iter().position(|s| s.name == g.name) else {
                let names: Vec<&str> = schema.iter().map(|s| s.name.as_str()).collect();
                return Err(LawError::new(
                    ErrorKind::UnknownParameter,
                    format!(
                        "law '{law}' has no parameter '{}'; its parameters are: {}",
                        g.name,
                        if names.is_empty() {
                            "(none)".to_string()
                        } else {
                            names.join(", ")
                        }
                    ),
                ));
            };
            if seen[i] {
                return Err(LawError::invalid_parameter(format!(
                    "parameter '{}' of law '{law}' is given twice",
                    g.name
                )));
            }
            seen[i] = true;
            let s = &schema[i];
            if !s.range.contains(g.value) {
                return Err(LawError::invalid_parameter(format!(
                    "parameter '{}' of law '{law}' = {} is out of range: valid values are {} {}",
                    g.name,
                    g.value,
                    s.range,
                    if s.unit == "1" {
                        "(dimensionless)".to_string()
                    } else {
                        s.unit.to_string()
                    }
                )));
            }
            values[i].1 = Some(g.value);
        }
        Ok(Params {
            law: law.to_string(),
            values,
        })
    }

    /// The value of `name` (given or default); an error if it is a derived parameter not given.
    pub fn get(&self, name: &str) -> Result<f64, LawError> {
        match self.get_opt(name)? {
            Some(v) => Ok(v),
            None => Err(LawError::invalid_parameter(format!(
                "law '{}' needs a value for parameter '{name}'",
                self.law
            ))),
        }
    }

    /// The value of `name`, or `None` for a derived parameter the user did not set.
    pub fn get_opt(&self, name: &str) -> Result<Option<f64>, LawError> {
        self.values
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| *v)
            .ok_or_else(|| {
                LawError::new(
                    ErrorKind::UnknownParameter,
                    format!(
                        "law '{}' asked for '{name}', which is not in its schema",
                        self.law
                    ),
                )
            })
    }

    /// All parameters in schema order.
    pub fn iter(&self) -> impl Iterator<Item = (&str, Option<f64>)> {
        self.values.iter().map(|(n, v)| (n.as_str(), *v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn schema() -> Vec<ParamSpec> {
        vec![
            ParamSpec::new("eps", "1", 0.5, Range::open_closed(0.0, 1.0), "restitution"),
            ParamSpec::derived("k", "N/m", Range::positive(), "stiffness"),
        ]
    }

    #[test]
    fn ranges_reject_nan_and_respect_inclusivity() {
        let r = Range::open_closed(0.0, 1.0);
        assert!(!r.contains(0.0) && r.contains(1.0) && r.contains(1e-300));
        assert!(!r.contains(f64::NAN) && !r.contains(1.0 + 1e-16 * 4.0));
        assert!(!Range::positive().contains(f64::INFINITY));
        assert_eq!(r.to_string(), "(0, 1]");
        assert_eq!(Range::positive().to_string(), "(0, inf)");
    }

    #[test]
    fn resolve_fills_defaults_and_reports_bad_values() {
        let p = Params::resolve("lsd", &schema(), &[]).unwrap();
        assert_eq!(p.get("eps").unwrap(), 0.5);
        assert_eq!(p.get_opt("k").unwrap(), None);
        assert!(p.get("k").is_err());
        let p = Params::resolve("lsd", &schema(), &[ParamValue::new("k", 3.0)]).unwrap();
        assert_eq!(p.get("k").unwrap(), 3.0);

        let e = Params::resolve("lsd", &schema(), &[ParamValue::new("eps", 1.5)]).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidParameter);
        assert!(e.message.contains("'eps'") && e.message.contains("1.5") && e.message.contains("(0, 1]"));
        let e = Params::resolve("lsd", &schema(), &[ParamValue::new("eps", f64::NAN)]).unwrap_err();
        assert!(e.message.contains("NaN"));
        let e = Params::resolve("lsd", &schema(), &[ParamValue::new("epz", 0.3)]).unwrap_err();
        assert_eq!(e.kind, ErrorKind::UnknownParameter);
        assert!(e.message.contains("epz") && e.message.contains("eps, k"));
    }
}
