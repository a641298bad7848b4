//! Finding plugin libraries and selecting laws by name.

use crate::laws::{
    ContactLawHandle, Heat, LawHandle, LoadedPlugin, RestitutionLawHandle, Rolling, TangentialLawHandle,
    Twisting,
};
use dashpot_sdk::{CalibrationTarget, EndCriterion, ErrorKind, LawError, LawInfo, LawKind, Pair, ParamValue};
use std::collections::HashSet;
use std::path::{Path, PathBuf};

/// The environment variable listing plugin directories (separated like `PATH`).
pub const PLUGIN_PATH_ENV: &str = "DASHPOT_PLUGIN_PATH";

/// The file extension of a shared library on this platform ("so", "dylib" or "dll").
pub const DYLIB_EXT: &str = std::env::consts::DLL_EXTENSION;

/// Where plugins are looked for, in order.
#[derive(Debug, Clone, Default)]
pub struct SearchPath {
    /// Directories given on the command line (`--plugin-dir`), searched first.
    pub dirs: Vec<PathBuf>,
    /// Individual plugin files (`--plugin FILE`), loaded first of all.
    pub files: Vec<PathBuf>,
    /// Whether to add the directories of `DASHPOT_PLUGIN_PATH`.
    pub use_env: bool,
    /// Whether to add the default directories (next to the executable), after all the others.
    pub use_default: bool,
}

impl SearchPath {
    /// Command-line dirs, then `DASHPOT_PLUGIN_PATH`, then the defaults.
    pub fn standard(dirs: Vec<PathBuf>, files: Vec<PathBuf>) -> SearchPath {
        SearchPath {
            dirs,
            files,
            use_env: true,
            use_default: true,
        }
    }

    /// The default plugin directories: the executable's own directory (where `cargo build`
    /// puts the plugin libraries next to `dashpot`), then `../lib/dashpot` beside it (an
    /// installed layout).
    pub fn default_dirs() -> Vec<PathBuf> {
        let mut v = Vec::new();
        if let Some(dir) = std::env::current_exe()
            .ok()
            .and_then(|p| p.parent().map(Path::to_path_buf))
        {
            v.push(dir.join("../lib/dashpot"));
            v.insert(0, dir);
        }
        v
    }

    /// All directories to scan, in order: the command-line ones, those of
    /// `DASHPOT_PLUGIN_PATH`, then (with `use_default`) the default ones. Plugin files and
    /// directories given by the user add to the built-in laws, they do not replace them; a name
    /// they share with a built-in law shadows it (and [`Registry::shadowed`] says so).
    pub fn all_dirs(&self) -> Vec<PathBuf> {
        let mut v = self.dirs.clone();
        if self.use_env {
            if let Some(p) = std::env::var_os(PLUGIN_PATH_ENV) {
                v.extend(std::env::split_paths(&p).filter(|p| !p.as_os_str().is_empty()));
            }
        }
        if self.use_default {
            v.extend(Self::default_dirs());
        }
        v
    }
}

/// Where a law comes from.
#[derive(Debug, Clone)]
pub struct LawEntry {
    /// The law's description.
    pub info: LawInfo,
    /// Index of its plugin in [`Registry::plugins`].
    pub plugin: usize,
}

/// A law name provided by two plugins: the first found is used, the other is hidden.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Shadowed {
    /// The law's name.
    pub name: String,
    /// The plugin file whose law is used.
    pub used: PathBuf,
    /// The plugin file whose law of the same name is hidden.
    pub hidden: PathBuf,
}

/// Loaded plugins and the laws they provide, selectable by name.
#[derive(Debug, Default)]
pub struct Registry {
    /// Every plugin loaded, in search order.
    pub plugins: Vec<LoadedPlugin>,
    /// Every law, first occurrence of each name.
    pub laws: Vec<LawEntry>,
    /// Non-fatal findings while scanning (shadowed law names), as sentences.
    pub notes: Vec<String>,
    /// Law names provided by more than one plugin.
    pub shadowed: Vec<Shadowed>,
    /// Plugins found in a directory that were refused (wrong sdk version, stale layout, ...).
    /// They do not stop the other plugins from loading; their errors are repeated whenever a
    /// law cannot be found.
    pub refused: Vec<LawError>,
    /// The directories that were scanned, in order.
    pub searched: Vec<PathBuf>,
}

/// The file stem of dashpot's own C library (`libdashpot_capi.so`), which sits beside the
/// plugins in `target/<profile>/` but is never one: the scan does not even open it (loading it
/// again into a program that already links it statically would only waste memory).
pub const C_LIBRARY_STEM: &str = "libdashpot_capi";

/// A shared library that is not one of cargo's hashed dependency artifacts
/// (`libfoo-0123456789abcdef.so`, e.g. proc macros in `deps/`), nor dashpot's C library.
pub(crate) fn is_candidate(p: &Path) -> bool {
    let stem = p.file_stem().and_then(|s| s.to_str());
    let hashed = stem.is_some_and(|s| {
        s.rsplit_once('-')
            .is_some_and(|(_, h)| h.len() == 16 && h.bytes().all(|b| b.is_ascii_hexdigit()))
    });
    let c_library = stem.is_some_and(|s| s == C_LIBRARY_STEM || s == "dashpot_capi");
    p.extension().is_some_and(|e| e == DYLIB_EXT) && !hashed && !c_library
}

/// Whether the library at `path` exports a dashpot/abi_stable root module, checked with a bare
/// `dlopen` so that ordinary libraries in a plugin directory are skipped quietly.
fn exports_root_module(path: &Path) -> bool {
    // SAFETY: loading a library runs its initialisers; plugin directories are trusted input.
    let Ok(lib) = (unsafe { libloading::Library::new(path) }) else {
        return false;
    };
    let sym = dashpot_sdk::abi::__private::abi_stable::library::ROOT_MODULE_LOADER_NAME_WITH_NUL;
    let found = unsafe { lib.get::<*const u8>(sym.as_bytes()) }.is_ok();
    // Keep it loaded: abi_stable will open it again, and unloading Rust libraries is unsafe.
    std::mem::forget(lib);
    found
}

impl Registry {
    /// An empty registry.
    pub fn new() -> Registry {
        Registry::default()
    }

    /// Loads every plugin found on `search`. Files are loaded once (by canonical path, and by
    /// file name across directories so that a copy in `deps/` does not shadow its original).
    /// Fails on a plugin file that was named explicitly and cannot be loaded; a plugin found in a
    /// directory that is refused (wrong sdk version, stale layout) is recorded in
    /// [`Registry::refused`] instead.
    pub fn discover(search: &SearchPath) -> Result<Registry, LawError> {
        let mut reg = Registry::new();
        let mut seen_paths = HashSet::new();
        let mut seen_names = HashSet::new();
        for f in &search.files {
            let f = explicit_file(f)?;
            reg.load_file(&f)?;
            if let Ok(c) = f.canonicalize() {
                seen_paths.insert(c);
            }
        }
        reg.searched = search.all_dirs();
        for dir in reg.searched.clone() {
            let Ok(rd) = std::fs::read_dir(&dir) else {
                continue;
            };
            let mut files: Vec<PathBuf> = rd
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| is_candidate(p))
                .collect();
            files.sort();
            for f in files {
                let Ok(canon) = f.canonicalize() else { continue };
                let fname = f.file_name().map(|n| n.to_os_string());
                if !seen_paths.insert(canon) || fname.as_ref().is_some_and(|n| seen_names.contains(n)) {
                    continue;
                }
                if !exports_root_module(&f) {
                    continue;
                }
                if let Err(e) = reg.load_file(&f) {
                    reg.refused.push(e);
                    continue;
                }
                if let Some(n) = fname {
                    seen_names.insert(n);
                }
            }
        }
        Ok(reg)
    }

    /// Loads one plugin file and registers its laws (a name already registered is shadowed,
    /// with a note). A plugin that exports one name twice is refused: which of the two a user
    /// would get is not theirs to guess.
    pub fn load_file(&mut self, path: &Path) -> Result<(), LawError> {
        let plugin = LoadedPlugin::load(path)?;
        let mut names = HashSet::new();
        for info in &plugin.laws {
            if !names.insert(info.name.as_str()) {
                return Err(LawError::new(
                    ErrorKind::Load,
                    format!(
                        "cannot load plugin {}: it exports the law name '{}' twice (plugin {} {}); \
                         each law of a plugin needs its own NAME. Rename one of them and rebuild.",
                        plugin.path.display(),
                        info.name,
                        plugin.name,
                        plugin.version
                    ),
                ));
            }
        }
        let idx = self.plugins.len();
        for info in &plugin.laws {
            if let Some(prev) = self.laws.iter().find(|l| l.info.name == info.name) {
                let used = self.plugins[prev.plugin].path.clone();
                self.notes.push(format!(
                    "law '{}' in {} is shadowed by the one in {}",
                    info.name,
                    plugin.path.display(),
                    used.display()
                ));
                self.shadowed.push(Shadowed {
                    name: info.name.to_string(),
                    used,
                    hidden: plugin.path.clone(),
                });
                continue;
            }
            self.laws.push(LawEntry {
                info: info.clone(),
                plugin: idx,
            });
        }
        self.plugins.push(plugin);
        Ok(())
    }

    /// The law called `name`, or an error listing the laws that exist.
    pub fn find(&self, name: &str) -> Result<(&LawEntry, &LoadedPlugin), LawError> {
        match self.laws.iter().find(|l| l.info.name == name) {
            Some(e) => Ok((e, &self.plugins[e.plugin])),
            None => Err(LawError::new(
                ErrorKind::UnknownLaw,
                format!(
                    "unknown law '{name}'{}; available laws: {}{}",
                    did_you_mean(name, self.laws.iter().map(|l| l.info.name.as_str())),
                    self.names_or_hint(),
                    self.refused_note()
                ),
            )),
        }
    }

    /// The end-of-contact criterion law `name` declares (its `END_CRITERION`; overlap for a law
    /// that declares none): the default of `collide`, `sweep` and `calibrate`, so that a law
    /// calibrated for a criterion is also run by it.
    pub fn end_criterion(&self, name: &str) -> Result<EndCriterion, LawError> {
        Ok(self
            .find(name)?
            .0
            .info
            .end_criterion
            .unwrap_or(EndCriterion::Overlap))
    }

    /// The plugin files whose law `name` is hidden by the one in use.
    pub fn hidden(&self, name: &str) -> Vec<&Path> {
        self.shadowed
            .iter()
            .filter(|s| s.name == name)
            .map(|s| s.hidden.as_path())
            .collect()
    }

    /// A note listing the refused plugins, or nothing.
    pub fn refused_note(&self) -> String {
        if self.refused.is_empty() {
            return String::new();
        }
        let mut s = format!("\n{} plugin(s) found but refused:", self.refused.len());
        for e in &self.refused {
            s.push_str("\n  - ");
            s.push_str(e.message.lines().next().unwrap_or(""));
        }
        s
    }

    fn names_or_hint(&self) -> String {
        if self.laws.is_empty() {
            "none found (build the plugins with `cargo build --release`, or point --plugin-dir or \
             DASHPOT_PLUGIN_PATH at a directory of plugin libraries)"
                .to_string()
        } else {
            self.laws
                .iter()
                .map(|l| format!("{} ({})", l.info.name, l.info.kind.as_str()))
                .collect::<Vec<_>>()
                .join(", ")
        }
    }

    /// The plugin of law `name`, checking that the law is of `kind`.
    fn find_kind(&self, name: &str, kind: LawKind) -> Result<&LoadedPlugin, LawError> {
        let (e, p) = self.find(name)?;
        if e.info.kind != kind {
            let hint = if kind == LawKind::Restitution && e.info.kind == LawKind::Contact {
                format!(
                    ". A contact law serves as a restitution law as 'from:{name}' (its r(v) from \
                     the collision driver), e.g. `dashpot bed --restitution from:{name}`"
                )
            } else {
                String::new()
            };
            return Err(LawError::new(
                ErrorKind::UnknownLaw,
                format!(
                    "law '{name}' is a {} law, but a {} law is needed here{hint}; {} laws loaded: {}",
                    e.info.kind.as_str(),
                    kind.as_str(),
                    kind.as_str(),
                    self.names_of(kind)
                ),
            ));
        }
        Ok(p)
    }

    /// Creates law `name` of `kind` from `params` (checked against its schema here, with a
    /// suggestion for a misspelled name) by the plugin's constructor `new`.
    fn create<H>(
        &self,
        name: &str,
        params: &[ParamValue],
        kind: LawKind,
        new: fn(&LoadedPlugin, &str, &[ParamValue]) -> Result<H, LawError>,
    ) -> Result<H, LawError> {
        let p = self.find_kind(name, kind)?;
        self.check_names(name, params)?;
        new(p, name, params)
    }

    /// Creates contact law `name` from `params`.
    pub fn contact(&self, name: &str, params: &[ParamValue]) -> Result<ContactLawHandle, LawError> {
        self.create(name, params, LawKind::Contact, LoadedPlugin::new_contact)
    }

    /// Creates tangential law `name` from `params`.
    pub fn tangential(&self, name: &str, params: &[ParamValue]) -> Result<TangentialLawHandle, LawError> {
        self.create(name, params, LawKind::Tangential, LoadedPlugin::new_tangential)
    }

    /// Creates rolling law `name` from `params`.
    pub fn rolling(&self, name: &str, params: &[ParamValue]) -> Result<LawHandle<Rolling>, LawError> {
        self.create(name, params, LawKind::Rolling, LoadedPlugin::new_rolling)
    }

    /// Creates twisting law `name` from `params`.
    pub fn twisting(&self, name: &str, params: &[ParamValue]) -> Result<LawHandle<Twisting>, LawError> {
        self.create(name, params, LawKind::Twisting, LoadedPlugin::new_twisting)
    }

    /// Creates heat law `name` from `params` (sdk 0.4).
    pub fn heat(&self, name: &str, params: &[ParamValue]) -> Result<LawHandle<Heat>, LawError> {
        self.create(name, params, LawKind::Heat, LoadedPlugin::new_heat)
    }

    /// Creates restitution law `name` from `params`.
    pub fn restitution(&self, name: &str, params: &[ParamValue]) -> Result<RestitutionLawHandle, LawError> {
        self.create(name, params, LawKind::Restitution, LoadedPlugin::new_restitution)
    }

    /// Refuses a parameter name outside law `name`'s schema, with the closest name of the
    /// schema ("did you mean"), before the plugin sees it (the plugin refuses it too, without a
    /// suggestion: the sdk's resolver cannot know what a user meant).
    fn check_names(&self, name: &str, params: &[ParamValue]) -> Result<(), LawError> {
        let (entry, _) = self.find(name)?;
        let names: Vec<&str> = entry.info.params.iter().map(|s| s.name.as_str()).collect();
        match params.iter().find(|p| !names.contains(&p.name.as_str())) {
            None => Ok(()),
            Some(p) => Err(LawError::new(
                ErrorKind::UnknownParameter,
                format!(
                    "law '{name}' has no parameter '{}'{}; its parameters are: {}",
                    p.name,
                    did_you_mean(p.name.as_str(), names.iter().copied()),
                    if names.is_empty() {
                        "(none)".to_string()
                    } else {
                        names.join(", ")
                    }
                ),
            )),
        }
    }

    /// Closed-form calibration of contact law `name`, if it offers one.
    pub fn calibrate(
        &self,
        name: &str,
        target: &CalibrationTarget,
        pair: &Pair,
        fixed: &[ParamValue],
    ) -> Result<Option<Vec<ParamValue>>, LawError> {
        let (entry, p) = self.find(name)?;
        let values = p.calibrate(name, target, pair, fixed)?;
        if let Some(v) = &values {
            let what = match target.contact_time {
                Some(t) => format!("restitution {} and contact time {t:e} s", target.restitution),
                None => format!("restitution {}", target.restitution),
            };
            crate::checks::calibrated(name, &what, &entry.info.params, v)?;
        }
        Ok(values)
    }

    /// Names of the laws of one kind, comma-separated.
    pub fn names_of(&self, kind: LawKind) -> String {
        let v: Vec<&str> = self
            .laws
            .iter()
            .filter(|l| l.info.kind == kind)
            .map(|l| l.info.name.as_str())
            .collect();
        if v.is_empty() {
            "none".to_string()
        } else {
            v.join(", ")
        }
    }
}

/// A plugin file the user named (`--plugin FILE`), checked before the dynamic loader sees it:
/// it must exist and be a shared library. A relative path is made absolute, so that a bare file
/// name means the file in the current directory (the dynamic loader would search the system's
/// library paths for a name without a slash).
pub fn explicit_file(path: &Path) -> Result<PathBuf, LawError> {
    let refuse = |why: String| {
        LawError::new(
            ErrorKind::Load,
            format!("cannot load plugin {}: {why}", path.display()),
        )
    };
    let abs = std::path::absolute(path).map_err(|e| refuse(e.to_string()))?;
    let meta = std::fs::metadata(&abs).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            refuse(format!(
                "no such file ({} does not exist; --plugin takes the path of a plugin library, \
                 e.g. target/release/libmy_law.{DYLIB_EXT})",
                abs.display()
            ))
        } else {
            refuse(e.to_string())
        }
    })?;
    if meta.is_dir() {
        return Err(refuse(
            "it is a directory; use --plugin-dir DIR for a directory of plugins".to_string(),
        ));
    }
    let mut magic = [0u8; 4];
    let n = std::fs::File::open(&abs)
        .and_then(|mut f| std::io::Read::read(&mut f, &mut magic))
        .map_err(|e| refuse(e.to_string()))?;
    let shared_library = n == 4
        && (magic == *b"\x7fELF"
            || magic[..2] == *b"MZ"
            || matches!(
                u32::from_le_bytes(magic),
                0xfeed_face | 0xfeed_facf | 0xcefa_edfe | 0xcffa_edfe | 0xcafe_babe | 0xbeba_feca
            ));
    if !shared_library {
        return Err(refuse(format!(
            "it is not a shared library ({} bytes, not an ELF, Mach-O or PE file); a plugin is the \
             .{DYLIB_EXT} file that `cargo build` writes for a crate with crate-type = [\"cdylib\"]",
            meta.len()
        )));
    }
    Ok(abs)
}

/// The name of `candidates` closest to `name` by edit distance (Damerau–Levenshtein: a typo
/// of one or two letters, a swap), if one is close enough to be what was meant: at most one edit
/// for names of up to four letters, two for longer ones, and fewer edits than the name has
/// letters. Ties go to the first candidate.
pub fn closest<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    let len = name.chars().count();
    let limit = if len <= 4 { 1 } else { 2 };
    let folded = name.to_lowercase();
    candidates
        .into_iter()
        .filter(|c| *c != name)
        .map(|c| (strsim::damerau_levenshtein(&folded, &c.to_lowercase()), c))
        .filter(|&(d, _)| d <= limit && d < len)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

/// " (did you mean `x`?)" for the name of `candidates` closest to `name` ([`closest`]), or
/// nothing.
pub fn did_you_mean<'a>(name: &str, candidates: impl IntoIterator<Item = &'a str>) -> String {
    closest(name, candidates)
        .map(|c| format!(" (did you mean `{c}`?)"))
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn typos_find_the_name_meant_and_nothing_else() {
        let laws = ["lsd", "hsd", "kuwabara-kono", "mcnamara-falcon", "constant"];
        assert_eq!(closest("hdd", laws), Some("hsd"));
        assert_eq!(closest("HSD", laws), Some("hsd"));
        assert_eq!(closest("kuwabara-kno", laws), Some("kuwabara-kono"));
        assert_eq!(closest("konstant", laws), Some("constant"));
        // two edits in a short name, or nothing alike: no guess
        assert_eq!(closest("abc", laws), None);
        assert_eq!(closest("hertz", laws), None);
        assert_eq!(closest("epsx", ["eps", "k"]), Some("eps"));
        assert_eq!(closest("x", ["eps", "k"]), None);
        assert_eq!(
            closest(
                "velocty",
                ["position", "velocity", "angular_velocity", "diameter"]
            ),
            Some("velocity")
        );
        assert_eq!(did_you_mean("hdd", laws), " (did you mean `hsd`?)");
        assert_eq!(did_you_mean("zzz", laws), "");
    }

    #[test]
    fn the_scan_skips_cargo_artifacts_and_the_c_library() {
        let f = |stem: &str| PathBuf::from(format!("/x/{stem}.{DYLIB_EXT}"));
        assert!(is_candidate(&f("libdashpot_hsd")));
        assert!(!is_candidate(&f("libdashpot_capi")));
        assert!(!is_candidate(&f("libserde_derive-0123456789abcdef")));
        assert!(!is_candidate(Path::new("/x/libdashpot_capi.a")));
    }
}
