//! Law and particle configuration from TOML files, with command-line overrides.
//!
//! ```toml
//! [law]
//! name = "hsd"
//! params = { eps = 0.54 }
//!
//! [particle]            # SI units; any field omitted keeps the MCC default
//! diameter = 0.01
//! density = 1500.0
//! young = 6.0e9
//! poisson = 0.3
//!
//! [partner]             # what the particle hits: another sphere (default: an identical one) or a wall
//! type = "wall"
//! ```

use dashpot_sdk::{LawError, MaterialPair, Pair, ParamValue, Particle};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// What a particle collides with. New kinds of partner are new `typetag` implementations.
#[typetag::serde(tag = "type")]
pub trait Partner: std::fmt::Debug + Send + Sync {
    /// The effective pair of `particle` and this partner.
    fn pair(&self, particle: &Particle) -> Result<Pair, LawError>;
    /// The effective moduli of `particle` and this partner.
    fn materials(&self, particle: &Particle) -> Result<MaterialPair, LawError>;
    /// One line for reports.
    fn describe(&self, particle: &Particle) -> String;
}

/// A second sphere: particle properties as a file gives them, those left out the first
/// particle's.
pub type Sphere = ParticleConfig;

impl Sphere {
    fn resolve(&self, p: &Particle) -> Particle {
        Particle {
            diameter: self.diameter.unwrap_or(p.diameter),
            density: self.density.unwrap_or(p.density),
            young: self.young.unwrap_or(p.young),
            poisson: self.poisson.unwrap_or(p.poisson),
        }
    }
}

#[typetag::serde(name = "sphere")]
impl Partner for Sphere {
    fn pair(&self, particle: &Particle) -> Result<Pair, LawError> {
        Pair::spheres(particle, &self.resolve(particle))
    }
    fn materials(&self, particle: &Particle) -> Result<MaterialPair, LawError> {
        MaterialPair::spheres(particle, &self.resolve(particle))
    }
    fn describe(&self, particle: &Particle) -> String {
        let q = self.resolve(particle);
        if q == *particle {
            "two identical spheres".to_string()
        } else {
            format!(
                "sphere against sphere (d = {} m, ρ = {} kg/m³, E = {} Pa, ν = {})",
                q.diameter, q.density, q.young, q.poisson
            )
        }
    }
}

/// A flat rigid wall of infinite mass.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Wall {}

#[typetag::serde(name = "wall")]
impl Partner for Wall {
    fn pair(&self, particle: &Particle) -> Result<Pair, LawError> {
        Pair::wall(particle)
    }
    fn materials(&self, particle: &Particle) -> Result<MaterialPair, LawError> {
        MaterialPair::wall(particle)
    }
    fn describe(&self, _particle: &Particle) -> String {
        "sphere against a flat rigid wall".to_string()
    }
}

/// Particle properties as they appear in a file (each optional).
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticleConfig {
    /// Diameter (m).
    pub diameter: Option<f64>,
    /// Density (kg/m³).
    pub density: Option<f64>,
    /// Young's modulus (Pa).
    pub young: Option<f64>,
    /// Poisson's ratio.
    pub poisson: Option<f64>,
}

/// A law selection as it appears in a file.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LawConfig {
    /// The law's name.
    pub name: Option<String>,
    /// Parameter values by name.
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
}

/// A whole configuration file.
#[derive(Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// The law.
    #[serde(default)]
    pub law: LawConfig,
    /// The particle.
    #[serde(default)]
    pub particle: ParticleConfig,
    /// The partner (default: an identical sphere).
    pub partner: Option<Box<dyn Partner>>,
}

/// A configuration error (file unreadable, bad TOML, bad `--set`).
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// The file is not valid for this schema.
    #[error("{path} is not a valid dashpot configuration: {message}")]
    Parse {
        /// The file.
        path: String,
        /// The TOML parser's message, with line and column.
        message: String,
    },
    /// A `--set` argument is malformed.
    #[error("--set expects NAME=VALUE with a number VALUE (e.g. eps=0.5 or k=1e6), got '{0}'")]
    BadSet(String),
    /// A `--set` value is not a number.
    #[error(
        "--set {name}={value}: '{value}' is not a number (write plain SI values without units, \
         e.g. {name}=1e6)"
    )]
    BadValue {
        /// The parameter.
        name: String,
        /// What was given.
        value: String,
    },
    /// The same parameter was set twice.
    #[error("--set {name} is given twice ({first} and {second}); give each parameter once")]
    Duplicate {
        /// The parameter.
        name: String,
        /// The first value.
        first: f64,
        /// The second value.
        second: f64,
    },
}

impl Config {
    /// Reads a TOML file.
    pub fn from_file(path: &Path) -> Result<Config, ConfigError> {
        let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
            path: path.display().to_string(),
            source,
        })?;
        from_toml(&text).map_err(|message| ConfigError::Parse {
            path: path.display().to_string(),
            message,
        })
    }
}

/// Reads a TOML document into `T` (a scene, a configuration); an error's first line names what
/// a user must change: the key path (`particle[3].velocity`), the type expected and the type
/// found, or for an unknown key the closest known one ("did you mean `velocity`?") and all the
/// keys valid there, then the line and column; the lines after it quote the document there.
pub fn from_toml<T: serde::de::DeserializeOwned>(text: &str) -> Result<T, String> {
    let de = toml::Deserializer::parse(text).map_err(|e| syntax_error(text, &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let what = explain(&path, inner.message());
        let at = place(text, inner.span())
            .map(|p| format!(" ({p})"))
            .unwrap_or_default();
        format!("{what}{at}{}", quote(&inner))
    })
}

/// "line L, column C" of the start of `span` in `text`, if the parser gave one.
fn place(text: &str, span: Option<std::ops::Range<usize>>) -> Option<String> {
    span.map(|s| {
        let (line, col) = line_col(text, s.start);
        format!("line {line}, column {col}")
    })
}

/// A document that is not TOML at all: where, and the parser's words.
fn syntax_error(text: &str, e: &toml::de::Error) -> String {
    let at = place(text, e.span())
        .map(|p| format!(" at {p}"))
        .unwrap_or_default();
    format!("not valid TOML{at}: {}{}", e.message().trim(), quote(e))
}

/// The parser's quotation of the document at the error (its lines after the first, without
/// the message repeated), as lines to append.
fn quote(e: &toml::de::Error) -> String {
    let full = e.to_string();
    let lines: Vec<&str> = full.lines().collect();
    if lines.len() < 3 || !lines[0].starts_with("TOML parse error") {
        return String::new();
    }
    lines[1..]
        .iter()
        .take_while(|l| l.trim_start().starts_with('|') || l.contains(" | "))
        .map(|l| format!("\n{l}"))
        .collect()
}

/// 1-based line and column of byte `at` of `text`.
fn line_col(text: &str, at: usize) -> (usize, usize) {
    let before = &text[..at.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// Serde's message about the value at `path`, said for a user: the key first, types in words.
fn explain(path: &str, msg: &str) -> String {
    let key = |p: &str| {
        if p.is_empty() || p == "." {
            "the top level".to_string()
        } else {
            format!("`{p}`")
        }
    };
    // "unknown field `x`, expected one of `a`, `b`" (the path ends in the unknown key)
    for (what, pre) in [("key", "unknown field `"), ("value", "unknown variant `")] {
        if let Some(rest) = msg.strip_prefix(pre) {
            let (name, tail) = rest.split_once('`').unwrap_or((rest, ""));
            let known: Vec<&str> = tail.split('`').skip(1).step_by(2).collect();
            // the path ends in the unknown key, except inside a tagged enum (buffered)
            let parent = match path.rsplit_once('.') {
                Some((p, last)) if last == name => p,
                None if path == name => "",
                _ => path,
            };
            let full = if parent.is_empty() || parent == "." {
                name.to_string()
            } else {
                format!("{parent}.{name}")
            };
            let hint = crate::registry::did_you_mean(name, known.iter().copied());
            let valid = if known.is_empty() {
                "none".to_string()
            } else {
                known
                    .iter()
                    .map(|k| format!("`{k}`"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return if what == "key" {
                format!(
                    "unknown key `{full}`{hint}: the keys valid in {} are {valid}",
                    key(parent)
                )
            } else {
                format!(
                    "{} = \"{name}\" is not a valid choice{hint}: the choices are {valid}",
                    key(path)
                )
            };
        }
    }
    if let Some(rest) = msg.strip_prefix("missing field `") {
        let name = rest.split('`').next().unwrap_or(rest);
        let full = if path.is_empty() || path == "." {
            name.to_string()
        } else {
            format!("{path}.{name}")
        };
        return format!("`{full}` is missing: it is required in {}", key(path));
    }
    for pre in ["invalid type: ", "invalid value: ", "invalid length "] {
        if let Some(rest) = msg.strip_prefix(pre) {
            if let Some((found, expected)) = rest.rsplit_once(", expected ") {
                return format!(
                    "{}: expected {}, found {}",
                    key(path),
                    type_words(expected),
                    type_words(found)
                );
            }
        }
    }
    // an untagged enum's `expecting` ("a number or an array ...")
    format!("{}: expected {}", key(path), msg.trim())
}

/// serde's names of types in words a user of a TOML file knows.
fn type_words(t: &str) -> String {
    let t = t.trim();
    let words = match t {
        "f64" | "f32" => "a number",
        "usize" | "u64" | "u32" | "u8" => "a whole number >= 0",
        "i64" | "i32" => "a whole number",
        "a sequence" => "an array",
        "a boolean" | "bool" => "true or false",
        "a map" => "a table",
        _ if t.starts_with("struct ") || t.starts_with("internally tagged enum") => "a table",
        _ => return t.replace("sequence", "array").replace("map", "table"),
    };
    words.to_string()
}

/// Parses `NAME=VALUE` (VALUE a number; NaN is accepted here and rejected by the law's range).
pub fn parse_set(s: &str) -> Result<(String, f64), ConfigError> {
    let (k, v) = s
        .split_once('=')
        .ok_or_else(|| ConfigError::BadSet(s.to_string()))?;
    let k = k.trim();
    if k.is_empty() {
        return Err(ConfigError::BadSet(s.to_string()));
    }
    let v: f64 = v.trim().parse().map_err(|_| ConfigError::BadValue {
        name: k.to_string(),
        value: v.trim().to_string(),
    })?;
    Ok((k.to_string(), v))
}

/// The command-line parser of one `--set` (clap's `value_parser`): a malformed `NAME=VALUE`
/// is a malformed command line (exit status 2, with the usage line).
pub fn set_arg(s: &str) -> Result<String, String> {
    parse_set(s).map(|_| s.to_string()).map_err(|e| {
        // clap prefixes "invalid value '...' for '--set <NAME=VALUE>': "
        match e {
            ConfigError::BadValue { name, value } => {
                format!("'{value}' is not a number (write plain SI values without units, e.g. {name}=1e6)")
            }
            _ => "expected NAME=VALUE with a number VALUE (e.g. eps=0.5 or k=1e6)".to_string(),
        }
    })
}

/// Parses every `--set`, refusing a parameter given twice (as the sdk's own resolver refuses a
/// duplicate: the last one silently winning would hide a typo).
pub fn parse_sets(sets: &[String]) -> Result<Vec<(String, f64)>, ConfigError> {
    let mut out: Vec<(String, f64)> = Vec::with_capacity(sets.len());
    for s in sets {
        let (k, v) = parse_set(s)?;
        if let Some((_, first)) = out.iter().find(|(n, _)| *n == k) {
            return Err(ConfigError::Duplicate {
                name: k,
                first: *first,
                second: v,
            });
        }
        out.push((k, v));
    }
    Ok(out)
}

/// File parameters overridden by `--set` values, in a stable order.
pub fn merge_params(file: &BTreeMap<String, f64>, sets: &[(String, f64)]) -> Vec<ParamValue> {
    let mut m = file.clone();
    for (k, v) in sets {
        m.insert(k.clone(), *v);
    }
    m.iter().map(|(k, v)| ParamValue::new(k, *v)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_with_a_wall_partner_parses() {
        let c: Config = toml::from_str(
            "[law]\nname = \"hsd\"\nparams = { eps = 0.3 }\n[particle]\ndiameter = 0.002\n[partner]\ntype = \"wall\"\n",
        )
        .unwrap();
        assert_eq!(c.law.name.as_deref(), Some("hsd"));
        let p = Particle {
            diameter: 0.002,
            ..Particle::MCC
        };
        let pair = c.partner.unwrap().pair(&p).unwrap();
        assert_eq!(pair.radius, 0.001);
    }

    #[test]
    fn unequal_spheres_use_the_effective_definitions() {
        let c: Config = toml::from_str("[partner]\ntype = \"sphere\"\ndiameter = 0.03\n").unwrap();
        let p = Particle::MCC;
        let pair = c.partner.unwrap().pair(&p).unwrap();
        assert!((pair.radius - 0.005 * 0.015 / 0.02).abs() < 1e-15);
    }

    #[test]
    fn sets_override_file_values() {
        let mut f = BTreeMap::new();
        f.insert("eps".to_string(), 0.3);
        let m = merge_params(&f, &[parse_set("eps=0.9").unwrap(), parse_set("k = 5").unwrap()]);
        assert_eq!(m, vec![ParamValue::new("eps", 0.9), ParamValue::new("k", 5.0)]);
        assert!(parse_set("eps").is_err());
        assert!(parse_set("eps=abc").is_err());
        assert!(parse_set("eps=nan").unwrap().1.is_nan());
        let e = parse_set("k=1e6N").unwrap_err().to_string();
        assert!(e.contains("'1e6N' is not a number"), "{e}");
    }

    #[test]
    fn a_parameter_set_twice_is_refused() {
        let e = parse_sets(&["eps=0.3".into(), "k=1".into(), "eps=0.5".into()])
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "--set eps is given twice (0.3 and 0.5); give each parameter once"
        );
        assert_eq!(
            parse_sets(&["eps=0.3".into()]).unwrap(),
            [("eps".to_string(), 0.3)]
        );
    }

    #[test]
    fn unknown_keys_are_rejected() {
        assert!(toml::from_str::<Config>("[particle]\ndiamter = 1.0\n").is_err());
    }

    #[test]
    fn toml_errors_put_the_key_and_the_place_on_the_first_line() {
        let e = from_toml::<Config>("[law]\nname = \"hsd\"\n[particle\n").unwrap_err();
        let first = e.lines().next().unwrap();
        assert!(first.starts_with("not valid TOML at line 3, column 10: "), "{e}");
        // the quotation of the line follows
        assert!(e.contains("3 | [particle"), "{e}");
        let e = from_toml::<Config>("[law]\nname = 3\n").unwrap_err();
        assert!(
            e.starts_with("`law.name`: expected a string, found integer `3` (line 2, column 8)"),
            "{e}"
        );
        let e = from_toml::<Config>("[law]\nnmae = \"hsd\"\n").unwrap_err();
        assert!(
            e.starts_with(
                "unknown key `law.nmae` (did you mean `name`?): the keys valid in `law` are `name`, `params`"
            ),
            "{e}"
        );
        // nothing close: the valid keys, no guess
        let e = from_toml::<Config>("[law]\nzzzz = 1\n").unwrap_err();
        assert!(
            !e.contains("did you mean") && e.contains("`name`, `params`"),
            "{e}"
        );
    }
}
