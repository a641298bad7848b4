//! The registry: plugin directories in, laws and their parameter schemas out.

use crate::error::{guard, out, output, slice, string, CError, DashpotStatus, DashpotStatus::*};
use dashpot_core::{Registry, SearchPath};
use dashpot_sdk::{EndCriterion, LawInfo, LawKind, ParamValue};
use std::ffi::{c_char, c_int, CString};
use std::path::PathBuf;

/// Which kind of law.
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DashpotLawKind {
    /// A normal contact force F(δ, δ̇).
    DASHPOT_CONTACT = 1,
    /// A restitution coefficient r(v).
    DASHPOT_RESTITUTION = 2,
    /// A tangential (friction) force with per-contact history (sdk 0.2).
    DASHPOT_TANGENTIAL = 3,
    /// A rolling-resistance force with per-contact history (sdk 0.3).
    DASHPOT_ROLLING = 4,
    /// A twisting torque about the contact normal with per-contact history (sdk 0.3).
    DASHPOT_TWISTING = 5,
    /// A heat flow (W) through the contact between two temperatures (sdk 0.4).
    DASHPOT_HEAT = 6,
}

/// When a two-body contact is over (realized restitution depends on it).
#[allow(non_camel_case_types)]
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DashpotEndCriterion {
    /// Not applicable (restitution laws).
    DASHPOT_END_NONE = 0,
    /// Contact ends when the overlap returns to 0 (Antypov & Elliott's convention).
    DASHPOT_END_OVERLAP = 1,
    /// Contact ends when the normal force returns to 0 on rebound.
    DASHPOT_END_FORCE = 2,
}

impl From<Option<EndCriterion>> for DashpotEndCriterion {
    fn from(e: Option<EndCriterion>) -> Self {
        match e {
            None => DashpotEndCriterion::DASHPOT_END_NONE,
            Some(EndCriterion::Overlap) => DashpotEndCriterion::DASHPOT_END_OVERLAP,
            Some(EndCriterion::Force) => DashpotEndCriterion::DASHPOT_END_FORCE,
        }
    }
}

/// A law's description. The strings belong to the registry and stay valid until
/// `dashpot_registry_free`.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DashpotLawInfo {
    /// The name to create it by (NUL-terminated UTF-8).
    pub name: *const c_char,
    /// Contact or restitution law.
    pub kind: DashpotLawKind,
    /// One line: what the law is.
    pub summary: *const c_char,
    /// The formula, conventions and references.
    pub doc: *const c_char,
    /// Number of parameters (see `dashpot_registry_param_info`).
    pub n_params: usize,
    /// The end-of-contact criterion the law's calibration refers to (`DASHPOT_END_NONE` for a
    /// restitution law).
    pub end_criterion: DashpotEndCriterion,
}

/// One parameter of a law's schema. Strings belong to the registry (valid until
/// `dashpot_registry_free`).
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct DashpotParamInfo {
    /// Name, as passed to `dashpot_contact_new`.
    pub name: *const c_char,
    /// SI unit ("1" for dimensionless).
    pub unit: *const c_char,
    /// One line of documentation.
    pub doc: *const c_char,
    /// 1 if the parameter has a default, 0 if the law derives it from the pair when absent.
    pub has_default: c_int,
    /// The default (NaN when `has_default` is 0).
    pub default_value: f64,
    /// Lower bound of the valid range (may be -inf).
    pub min: f64,
    /// Upper bound of the valid range (may be +inf).
    pub max: f64,
    /// 1 if `min` itself is valid.
    pub min_inclusive: c_int,
    /// 1 if `max` itself is valid.
    pub max_inclusive: c_int,
}

fn c(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}

struct ParamStrings {
    name: CString,
    unit: CString,
    doc: CString,
}

struct LawStrings {
    name: CString,
    summary: CString,
    doc: CString,
    params: Vec<ParamStrings>,
}

/// Loaded plugins and their laws (opaque).
pub struct DashpotRegistry {
    pub(crate) reg: Registry,
    strings: Vec<LawStrings>,
}

impl DashpotRegistry {
    /// Wraps a registry, keeping C copies of its strings.
    pub fn new(reg: Registry) -> DashpotRegistry {
        let strings = reg
            .laws
            .iter()
            .map(|l| LawStrings {
                name: c(&l.info.name),
                summary: c(&l.info.summary),
                doc: c(&l.info.doc),
                params: l
                    .info
                    .params
                    .iter()
                    .map(|p| ParamStrings {
                        name: c(&p.name),
                        unit: c(&p.unit),
                        doc: c(&p.doc),
                    })
                    .collect(),
            })
            .collect();
        DashpotRegistry { reg, strings }
    }

    /// The index of the law called `name`.
    fn index_of(&self, name: &str) -> Result<usize, CError> {
        self.reg.find(name)?;
        Ok(self
            .reg
            .laws
            .iter()
            .position(|l| l.info.name == name)
            .unwrap_or_default())
    }

    /// The C description of law number `index`.
    fn law_info(&self, index: usize) -> Result<DashpotLawInfo, CError> {
        let info = self.law(index)?;
        let s = &self.strings[index];
        Ok(DashpotLawInfo {
            name: s.name.as_ptr(),
            kind: match info.kind {
                LawKind::Contact => DashpotLawKind::DASHPOT_CONTACT,
                LawKind::Restitution => DashpotLawKind::DASHPOT_RESTITUTION,
                LawKind::Tangential => DashpotLawKind::DASHPOT_TANGENTIAL,
                LawKind::Rolling => DashpotLawKind::DASHPOT_ROLLING,
                LawKind::Twisting => DashpotLawKind::DASHPOT_TWISTING,
                LawKind::Heat => DashpotLawKind::DASHPOT_HEAT,
            },
            summary: s.summary.as_ptr(),
            doc: s.doc.as_ptr(),
            n_params: info.params.len(),
            end_criterion: info.end_criterion.into(),
        })
    }

    /// The C description of parameter number `param` of law number `law`.
    fn param_info(&self, law: usize, param: usize) -> Result<DashpotParamInfo, CError> {
        let info = self.law(law)?;
        let p = info.params.get(param).ok_or_else(|| {
            CError::new(
                DASHPOT_ERR_INVALID_ARGUMENT,
                format!(
                    "parameter index {param} is out of range: law '{}' has {} parameters",
                    info.name,
                    info.params.len()
                ),
            )
        })?;
        let s = &self.strings[law].params[param];
        let default = p.default;
        Ok(DashpotParamInfo {
            name: s.name.as_ptr(),
            unit: s.unit.as_ptr(),
            doc: s.doc.as_ptr(),
            has_default: c_int::from(default.is_some()),
            default_value: default.unwrap_or(f64::NAN),
            min: p.range.min,
            max: p.range.max,
            min_inclusive: c_int::from(p.range.min_inclusive),
            max_inclusive: c_int::from(p.range.max_inclusive),
        })
    }

    fn law(&self, index: usize) -> Result<&LawInfo, CError> {
        self.reg.laws.get(index).map(|l| &l.info).ok_or_else(|| {
            CError::new(
                DASHPOT_ERR_INVALID_ARGUMENT,
                format!(
                    "law index {index} is out of range: the registry has {} laws",
                    self.reg.laws.len()
                ),
            )
        })
    }
}

/// Named parameters from two parallel arrays.
///
/// # Safety
/// Non-null arrays must hold `n` elements; each name a NUL-terminated string.
pub(crate) unsafe fn params(
    names: *const *const c_char,
    values: *const f64,
    n: usize,
) -> Result<Vec<ParamValue>, CError> {
    let names = unsafe { slice(names, n, "param_names") }?;
    let values = unsafe { slice(values, n, "param_values") }?;
    names
        .iter()
        .zip(values)
        .enumerate()
        .map(|(i, (&p, &v))| {
            Ok(ParamValue::new(
                unsafe { string(p, &format!("param_names[{i}]")) }?,
                v,
            ))
        })
        .collect()
}

/// Opens a registry: loads every dashpot plugin library found in `dirs` (in order), then in
/// the directories of the `DASHPOT_PLUGIN_PATH` environment variable if `use_env` is non-zero.
/// Libraries without a dashpot root module are skipped; plugins found but refused
/// (incompatible sdk version) do not stop the others and are named when a law is not found.
/// A law name found twice is taken from the first directory.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER` (`out_registry`, or `dirs` with `n_dirs` > 0, or one of
/// its strings), `DASHPOT_ERR_INVALID_ARGUMENT` (a path that is not UTF-8). An empty result is
/// not an error: check `dashpot_registry_law_count`.
///
/// Ownership: the strings are copied; `*out_registry` is a new handle owned by the caller,
/// to be freed with `dashpot_registry_free`. Thread-safe.
///
/// # Safety
/// `dirs` must be null or hold `n_dirs` pointers to NUL-terminated strings.
#[no_mangle]
pub unsafe extern "C" fn dashpot_registry_open(
    dirs: *const *const c_char,
    n_dirs: usize,
    use_env: c_int,
    out_registry: *mut *mut DashpotRegistry,
) -> DashpotStatus {
    guard(|| {
        let o = unsafe { out(out_registry, "out_registry") }?;
        let dirs = unsafe { slice(dirs, n_dirs, "dirs") }?;
        let dirs = dirs
            .iter()
            .enumerate()
            .map(|(i, &d)| unsafe { string(d, &format!("dirs[{i}]")) }.map(PathBuf::from))
            .collect::<Result<Vec<_>, _>>()?;
        let sp = SearchPath {
            dirs,
            files: vec![],
            use_env: use_env != 0,
            use_default: false,
        };
        let reg = Registry::discover(&sp)?;
        *o = Box::into_raw(Box::new(DashpotRegistry::new(reg)));
        Ok(())
    })
}

/// Frees a registry (null is accepted and ignored). Laws created from it stay valid.
/// Must not race with any other use of the same handle.
///
/// # Safety
/// `registry` must be null or a handle from `dashpot_registry_open` not yet freed.
#[no_mangle]
pub unsafe extern "C" fn dashpot_registry_free(registry: *mut DashpotRegistry) {
    unsafe { crate::handle::free(registry) }
}

/// The number of laws in the registry.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`. Thread-safe (read-only).
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_registry_law_count(
    registry: *const DashpotRegistry,
    out_count: *mut usize,
) -> DashpotStatus {
    output!(arg registry => out_count = registry.reg.laws.len())
}

/// The index of the law called `name`.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_UNKNOWN_LAW` (the message lists the laws).
/// Thread-safe (read-only).
///
/// # Safety
/// Non-null pointers must be valid; `name` NUL-terminated.
#[no_mangle]
pub unsafe extern "C" fn dashpot_registry_find(
    registry: *const DashpotRegistry,
    name: *const c_char,
    out_index: *mut usize,
) -> DashpotStatus {
    output!(arg registry, string name => out_index = registry.index_of(name)?)
}

/// The description of law number `index` (0 ≤ index < count).
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_ARGUMENT` (index out of range).
/// Ownership: the strings in `*out_info` belong to the registry (valid until it is freed).
/// Thread-safe (read-only).
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_registry_law_info(
    registry: *const DashpotRegistry,
    index: usize,
    out_info: *mut DashpotLawInfo,
) -> DashpotStatus {
    output!(arg registry => out_info = registry.law_info(index)?)
}

/// Parameter number `param` (0 ≤ param < n_params) of law number `law`.
///
/// Errors: `DASHPOT_ERR_NULL_POINTER`, `DASHPOT_ERR_INVALID_ARGUMENT` (an index out of range).
/// Ownership: the strings belong to the registry. Thread-safe (read-only).
///
/// # Safety
/// Non-null pointers must be valid.
#[no_mangle]
pub unsafe extern "C" fn dashpot_registry_param_info(
    registry: *const DashpotRegistry,
    law: usize,
    param: usize,
    out_param: *mut DashpotParamInfo,
) -> DashpotStatus {
    output!(arg registry => out_param = registry.param_info(law, param)?)
}
