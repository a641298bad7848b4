//! Parameter schemas: every law publishes the name, unit, default, valid range and a one-line
//! doc of each of its parameters, and the sdk validates user input against it before the law
//! ever sees a value.

use crate::error::{ErrorKind, LawError};
use abi_stable::StableAbi;

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
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ParamSpec {
    /// The name used in `--set name=value`, TOML files and the C ABI.
    pub name: String,
    /// SI unit of the value ("1" for dimensionless).
    pub unit: String,
    /// Value used when the user gives none. `None`: the law derives it from the pair (see `doc`).
    pub default: Option<f64>,
    /// Valid values.
    pub range: Range,
    /// One line of documentation.
    pub doc: String,
}

impl ParamSpec {
    /// A parameter with a default value.
    pub fn new(name: &str, unit: &str, default: f64, range: Range, doc: &str) -> ParamSpec {
        ParamSpec {
            name: name.into(),
            unit: unit.into(),
            default: Some(default),
            range,
            doc: doc.into(),
        }
    }

    /// An optional parameter without default: when absent, the law derives it (say how in `doc`).
    pub fn derived(name: &str, unit: &str, range: Range, doc: &str) -> ParamSpec {
        ParamSpec {
            name: name.into(),
            unit: unit.into(),
            default: None,
            range,
            doc: doc.into(),
        }
    }
}

/// A named value, as given by a user or reported by a law (in the unit of its schema).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ParamValue {
    /// Parameter name.
    pub name: String,
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
        let mut values: Vec<(String, Option<f64>)> =
            schema.iter().map(|s| (s.name.clone(), s.default)).collect();
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

    /// The parameters as the typed struct `P` (declared with [`law_params!`](crate::law_params)).
    pub fn parse<P: LawParams>(&self) -> Result<P, LawError> {
        P::from_params(self)
    }
}

/// Law `T` (named `name`) from named values: validated against its schema, read as its struct,
/// then checked together by `check`.
pub(crate) fn configure<T: LawParams>(
    name: &str,
    given: &[ParamValue],
    check: fn(&T) -> Result<(), LawError>,
) -> Result<T, LawError> {
    let law: T = Params::resolve(name, &T::schema(), given)?.parse()?;
    check(&law)?;
    Ok(law)
}

/// A law's parameters as a plain Rust struct: its schema, and how to read it from validated
/// [`Params`]. Declare one with [`law_params!`](crate::law_params), which writes the struct and
/// this implementation from one list (name, type, unit, default, range and doc of each field),
/// so that the schema and the struct cannot disagree. A law *is* its parameters: every law
/// trait ([`ContactLaw`](crate::ContactLaw), ...) requires `LawParams`.
pub trait LawParams: Sized {
    /// The schema: one entry per field, in order.
    fn schema() -> Vec<ParamSpec>;
    /// The struct from parameters already validated against [`LawParams::schema`] (every
    /// value in range, defaults filled in).
    fn from_params(p: &Params) -> Result<Self, LawError>;
}

/// The type of a field of a [`law_params!`](crate::law_params) struct: `f64` for a parameter
/// with a default, `Option<f64>` for one the law derives when it is not given.
pub trait ParamField: Sized {
    /// Whether the parameter has no default (the law derives it when absent).
    const DERIVED: bool;
    /// The value of parameter `name` of `p`.
    fn read(p: &Params, name: &str) -> Result<Self, LawError>;
}

impl ParamField for f64 {
    const DERIVED: bool = false;
    fn read(p: &Params, name: &str) -> Result<f64, LawError> {
        p.get(name)
    }
}

impl ParamField for Option<f64> {
    const DERIVED: bool = true;
    fn read(p: &Params, name: &str) -> Result<Option<f64>, LawError> {
        p.get_opt(name)
    }
}

/// The doc lines of a field as one line of schema documentation.
#[doc(hidden)]
pub fn join_doc(lines: &[&str]) -> String {
    lines
        .iter()
        .map(|l| l.trim())
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Declares a law's parameters once: the struct (the law itself, usually) and its
/// [`LawParams`] implementation, schema included. Each field is `name: f64 { unit, default,
/// range }` (a parameter with a default) or `name: Option<f64> { unit, range }` (one the law
/// derives when it is absent); its doc comment is the parameter's one-line documentation, its
/// name the parameter's name. A field's type and whether it has a default must agree (checked
/// at compile time). A law without parameters is a unit struct: `law_params! { pub struct L; }`.
///
/// ```
/// use dashpot_sdk::{law_params, Range};
///
/// law_params! {
///     /// A linear spring-dashpot, configured.
///     #[derive(Debug, Clone)]
///     pub struct Spring {
///         /// spring constant
///         pub k: f64 { unit: "N/m", default: 1e5, range: Range::positive() },
///         /// damping coefficient; derived from the restitution when absent
///         pub c: Option<f64> { unit: "N·s/m", range: Range::non_negative() },
///     }
/// }
///
/// use dashpot_sdk::{LawParams, ParamValue, Params};
/// let p = Params::resolve("spring", &Spring::schema(), &[ParamValue::new("k", 2e5)]).unwrap();
/// let s: Spring = p.parse().unwrap();
/// assert_eq!((s.k, s.c), (2e5, None));
/// assert_eq!(Spring::schema()[0].doc, "spring constant");
/// ```
#[macro_export]
macro_rules! law_params {
    (
        $(#[$attr:meta])*
        $vis:vis struct $name:ident {
            $(
                $(#[doc = $doc:literal])*
                $fvis:vis $field:ident : $ty:ty {
                    unit: $unit:expr
                    $(, default: $default:expr)?
                    , range: $range:expr $(,)?
                }
            ),* $(,)?
        }
    ) => {
        $(#[$attr])*
        $vis struct $name {
            $($(#[doc = $doc])* $fvis $field: $ty,)*
        }

        impl $crate::LawParams for $name {
            fn schema() -> ::std::vec::Vec<$crate::ParamSpec> {
                ::std::vec![$({
                    const _: () = ::std::assert!(
                        <$ty as $crate::ParamField>::DERIVED
                            == $crate::law_params!(@none $($default)?),
                        ::std::concat!(
                            "parameter '", ::std::stringify!($field),
                            "': an f64 field takes a default, an Option<f64> field none"
                        )
                    );
                    $crate::ParamSpec {
                        name: ::std::stringify!($field).into(),
                        unit: ::std::string::String::from($unit),
                        default: $crate::law_params!(@default $($default)?),
                        range: $range,
                        doc: $crate::__join_doc(&[$($doc),*]),
                    }
                }),*]
            }

            fn from_params(_p: &$crate::Params) -> ::std::result::Result<Self, $crate::LawError> {
                ::std::result::Result::Ok($name {
                    $($field: <$ty as $crate::ParamField>::read(_p, ::std::stringify!($field))?,)*
                })
            }
        }
    };
    ($(#[$attr:meta])* $vis:vis struct $name:ident;) => {
        $(#[$attr])*
        $vis struct $name;

        impl $crate::LawParams for $name {
            fn schema() -> ::std::vec::Vec<$crate::ParamSpec> {
                ::std::vec::Vec::new()
            }

            fn from_params(_p: &$crate::Params) -> ::std::result::Result<Self, $crate::LawError> {
                ::std::result::Result::Ok($name)
            }
        }
    };
    (@none) => { true };
    (@none $default:expr) => { false };
    (@default) => { ::std::option::Option::None };
    (@default $default:expr) => { ::std::option::Option::Some($default) };
}

#[cfg(test)]
mod tests {
    use super::*;

    crate::law_params! {
        /// Two parameters, one derived.
        #[derive(Debug, PartialEq)]
        struct Two {
            /// restitution,
            /// over two lines
            eps: f64 { unit: "1", default: 0.5, range: Range::open_closed(0.0, 1.0) },
            /// stiffness
            k: Option<f64> { unit: "N/m", range: Range::positive() },
        }
    }

    #[test]
    fn the_macro_writes_the_schema_and_reads_the_struct() {
        assert_eq!(Two::schema(), schema_of_two());
        let p = Params::resolve("two", &Two::schema(), &[ParamValue::new("k", 3.0)]).unwrap();
        assert_eq!(
            p.parse::<Two>().unwrap(),
            Two {
                eps: 0.5,
                k: Some(3.0)
            }
        );
        let p = Params::resolve("two", &Two::schema(), &[]).unwrap();
        assert_eq!(p.parse::<Two>().unwrap(), Two { eps: 0.5, k: None });
    }

    fn schema_of_two() -> Vec<ParamSpec> {
        vec![
            ParamSpec::new(
                "eps",
                "1",
                0.5,
                Range::open_closed(0.0, 1.0),
                "restitution, over two lines",
            ),
            ParamSpec::derived("k", "N/m", Range::positive(), "stiffness"),
        ]
    }

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
