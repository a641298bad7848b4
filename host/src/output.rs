//! Result files are written whole or not at all; and the one progress bar of every run.

use crate::registry::Registry;
use dashpot_sdk::{LawError, LawInfo, ParamValue};
use serde_json::json;
use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` whole or not at all, every error naming the path and the reason:
/// a regular file (or a new one) through a temporary file beside it, synced and renamed over it,
/// so a reader (or a crash) never sees it half-written; a path that is not a regular file (a
/// device such as `/dev/null` or `/dev/stdout`, a pipe) is written in place and flushed, never
/// replaced. A symbolic link is followed: its target is what is written.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = AtomicFile::create(path)?;
    // (its writes name the path already)
    f.write_all(bytes)?;
    f.commit()
}

/// `e` with the path it was about: "cannot write PATH: REASON" (the kind kept).
pub fn write_error(path: &Path, e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("cannot write {}: {e}", path.display()))
}

/// Where an [`AtomicFile`] writes.
enum Sink {
    /// A temporary file beside the result, renamed over it at the end.
    Temp(std::io::BufWriter<tempfile::NamedTempFile>),
    /// The path itself: a device or a pipe, written in place.
    InPlace(std::io::BufWriter<std::fs::File>),
}

/// A result file written as it grows (a trajectory), which appears at its path only when
/// [`AtomicFile::commit`] is called: until then it is a temporary file beside it (tempfile's
/// `NamedTempFile`), removed if the writer is dropped uncommitted (a run that failed leaves no
/// half-written result). A path that is not a regular file (a device, a pipe) is written in
/// place (see [`write_atomic`]). Every error names the path.
pub struct AtomicFile {
    path: std::path::PathBuf,
    w: Sink,
}

impl AtomicFile {
    /// A new file to become `path` (its folder created if need be).
    pub fn create(path: &Path) -> std::io::Result<AtomicFile> {
        let fail = |e| write_error(path, e);
        // a link is followed (renaming over it would replace the link, not its target)
        let target = match std::fs::canonicalize(path) {
            Ok(t) => t,
            Err(_) => path.to_path_buf(),
        };
        if let Ok(meta) = std::fs::metadata(&target) {
            if meta.is_dir() {
                return Err(fail(std::io::Error::new(
                    std::io::ErrorKind::IsADirectory,
                    "it is a directory",
                )));
            }
            if !meta.is_file() {
                let f = std::fs::OpenOptions::new()
                    .write(true)
                    .open(&target)
                    .map_err(fail)?;
                return Ok(AtomicFile {
                    path: path.to_path_buf(),
                    w: Sink::InPlace(std::io::BufWriter::new(f)),
                });
            }
        }
        let dir = target
            .parent()
            .filter(|d| !d.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        std::fs::create_dir_all(dir).map_err(fail)?;
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_default();
        let prefix = format!(".{name}.");
        let mut b = tempfile::Builder::new();
        b.prefix(&prefix).suffix(".tmp");
        // a result file's usual mode (under the umask), not a temporary's owner-only 0600
        #[cfg(unix)]
        b.permissions(std::os::unix::fs::PermissionsExt::from_mode(0o666));
        let tmp = b.tempfile_in(dir).map_err(fail)?;
        Ok(AtomicFile {
            path: target,
            w: Sink::Temp(std::io::BufWriter::new(tmp)),
        })
    }

    /// `e` naming this file's path.
    fn failed(&self, e: std::io::Error) -> std::io::Error {
        write_error(&self.path, e)
    }

    /// Flushes the file, syncs it and moves it to its path (a device or a pipe: flushes it).
    pub fn commit(self) -> std::io::Result<()> {
        let path = self.path;
        let fail = |e| write_error(&path, e);
        match self.w {
            Sink::Temp(w) => {
                let tmp = w.into_inner().map_err(|e| fail(e.into_error()))?;
                tmp.as_file().sync_all().map_err(fail)?;
                tmp.persist(&path).map(|_| ()).map_err(|e| fail(e.error))
            }
            Sink::InPlace(mut w) => w.flush().map_err(fail),
        }
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let r = match &mut self.w {
            Sink::Temp(w) => w.write(buf),
            Sink::InPlace(w) => w.write(buf),
        };
        r.map_err(|e| self.failed(e))
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let r = match &mut self.w {
            Sink::Temp(w) => w.flush(),
            Sink::InPlace(w) => w.flush(),
        };
        r.map_err(|e| self.failed(e))
    }
}

/// A print to the standard output or error that failed (a full disk, a closed pipe): `println!`
/// panics with it, [`catch_print_failures`] turns that panic into this value.
#[derive(Debug, Clone, PartialEq)]
pub struct PrintFailure {
    /// The reason, e.g. "failed printing to stdout: No space left on device (os error 28)".
    pub message: String,
    /// The reader went away (a pipe closed early, as `dashpot laws | head -1` does).
    pub broken_pipe: bool,
}

/// The message of a panic payload, if it is text.
fn panic_text(p: &(dyn std::any::Any + Send)) -> Option<&str> {
    p.downcast_ref::<String>()
        .map(|s| s.as_str())
        .or_else(|| p.downcast_ref::<&str>().copied())
}

/// Whether a panic message is that of a failed `print!`/`eprint!`.
fn is_print_failure(m: &str) -> bool {
    m.starts_with("failed printing to std")
}

/// Runs `f`; a print of it to stdout or stderr that fails (which panics in `println!`) ends it
/// as a [`PrintFailure`] instead of a crash, without the panic's message and backtrace. Other
/// panics go on as they were. Stdout is flushed at the end, its failure reported the same way.
pub fn catch_print_failures<T>(f: impl FnOnce() -> T) -> Result<T, PrintFailure> {
    static HOOK: std::sync::Once = std::sync::Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if panic_text(info.payload()).is_some_and(is_print_failure) {
                return;
            }
            previous(info)
        }));
    });
    let failure = |message: String| PrintFailure {
        broken_pipe: message.contains("Broken pipe") || message.contains("os error 32"),
        message,
    };
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)) {
        Ok(v) => match std::io::stdout().flush() {
            Ok(()) => Ok(v),
            Err(e) => Err(failure(format!("failed printing to stdout: {e}"))),
        },
        Err(p) => match panic_text(&*p) {
            Some(m) if is_print_failure(m) => Err(failure(m.to_string())),
            _ => std::panic::resume_unwind(p),
        },
    }
}

#[cfg(test)]
mod tests {
    use std::io::Write;

    #[test]
    fn a_growing_file_appears_only_when_committed() {
        let dir = std::env::temp_dir().join(format!("dashpot-grow-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("t.xyz");
        // dropped uncommitted: nothing is left, neither the file nor its temporary
        {
            let mut f = super::AtomicFile::create(&p).unwrap();
            f.write_all(b"frame 1").unwrap();
        }
        assert!(!p.exists());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0);
        let mut f = super::AtomicFile::create(&p).unwrap();
        f.write_all(b"frame 1\n").unwrap();
        assert!(!p.exists());
        f.write_all(b"frame 2\n").unwrap();
        f.commit().unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"frame 1\nframe 2\n");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A committed file has the mode a plain `File::create` gives (the umask's), not the
    /// owner-only mode of a temporary file.
    #[cfg(unix)]
    #[test]
    fn a_committed_file_has_a_plain_files_mode() {
        use std::os::unix::fs::PermissionsExt;
        let dir = std::env::temp_dir().join(format!("dashpot-mode-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let plain = dir.join("plain");
        std::fs::File::create(&plain).unwrap();
        let p = dir.join("result.csv");
        super::write_atomic(&p, b"x").unwrap();
        let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode(&p), mode(&plain));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn writes_whole_file_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("dashpot-out-{}", std::process::id()));
        let p = dir.join("a.txt");
        super::write_atomic(&p, b"hello").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"hello");
        let n = std::fs::read_dir(&dir).unwrap().count();
        assert_eq!(n, 1);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// A law's description as JSON: kind, plugin file and versions, parameter schema, history.
pub fn law_json(reg: &Registry, info: &LawInfo) -> serde_json::Value {
    let plugin = reg.find(info.name.as_str()).map(|(_, p)| p).ok();
    json!({
        "name": info.name.as_str(),
        "kind": info.kind.as_str(),
        "summary": info.summary.as_str(),
        "doc": info.doc.as_str(),
        "end_criterion": info.end_criterion.map(|e| e.as_str()),
        "plugin": plugin.map(|p| json!({
            "file": p.path.display().to_string(),
            "name": p.name,
            "version": p.version,
            "sdk_version": p.sdk_version,
        })),
        "history": info.history.iter().map(|h| json!({"name": h.name.as_str(), "unit": h.unit.as_str(), "doc": h.doc.as_str()})).collect::<Vec<_>>(),
        "params": info.params.iter().map(|s| json!({
            "name": s.name.as_str(),
            "unit": s.unit.as_str(),
            "default": s.default,
            "range": s.range.to_string(),
            "min": finite_or_null(s.range.min),
            "max": finite_or_null(s.range.max),
            "min_inclusive": s.range.min_inclusive,
            "max_inclusive": s.range.max_inclusive,
            "doc": s.doc.as_str(),
        })).collect::<Vec<_>>(),
    })
}

fn finite_or_null(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// Where a result came from: the law, the plugin file that provided it, the versions, and every
/// parameter value including those left at their defaults. Every command that computes with a
/// law builds one ([`Provenance::of`]) and prints it with its result: JSON (`"provenance"`),
/// CSV (`#` comment lines before the header), text and reports ([`Provenance::lines`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Provenance {
    /// The law's name.
    pub law: String,
    /// The law's kind ([`LawKind::as_str`](dashpot_sdk::LawKind::as_str)).
    pub kind: &'static str,
    /// The plugin library the law was taken from.
    pub plugin_file: String,
    /// The plugin crate's name.
    pub plugin_name: String,
    /// The plugin crate's version.
    pub plugin_version: String,
    /// The dashpot-sdk version the plugin was built against.
    pub plugin_sdk: String,
    /// The dashpot-sdk version of this host.
    pub host_sdk: &'static str,
    /// dashpot's version.
    pub dashpot: &'static str,
    /// Every parameter of the schema, in schema order: (name, value, where it came from).
    /// The value is `None` for a parameter the law derives from the pair when unset.
    pub params: Vec<(String, Option<f64>, ParamSource)>,
    /// Plugin files that also provide a law of this name, hidden by the one used.
    pub hidden: Vec<String>,
}

/// Where a parameter value came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamSource {
    /// Given by the user (`--set`, a config file, a calibration).
    Given,
    /// The schema's default.
    Default,
    /// Left unset: the law derives it from the pair.
    Derived,
}

impl ParamSource {
    /// "given", "default" or "derived".
    pub fn as_str(self) -> &'static str {
        match self {
            ParamSource::Given => "given",
            ParamSource::Default => "default",
            ParamSource::Derived => "derived from the pair",
        }
    }
}

impl Provenance {
    /// The provenance of law `name` used with the parameters `given` (the rest at their
    /// defaults).
    pub fn of(reg: &Registry, name: &str, given: &[ParamValue]) -> Result<Provenance, LawError> {
        let (entry, plugin) = reg.find(name)?;
        let mut params: Vec<(String, Option<f64>, ParamSource)> = entry
            .info
            .params
            .iter()
            .map(|s| {
                let n = s.name.to_string();
                match given.iter().find(|p| p.name == s.name.as_str()) {
                    Some(p) => (n, Some(p.value), ParamSource::Given),
                    None => match s.default {
                        Some(d) => (n, Some(d), ParamSource::Default),
                        None => (n, None, ParamSource::Derived),
                    },
                }
            })
            .collect();
        // names outside the schema (the law refuses them; kept so nothing given is hidden)
        for p in given {
            if !params.iter().any(|(n, _, _)| n == p.name.as_str()) {
                params.push((p.name.to_string(), Some(p.value), ParamSource::Given));
            }
        }
        Ok(Provenance {
            law: name.to_string(),
            kind: entry.info.kind.as_str(),
            plugin_file: plugin.path.display().to_string(),
            plugin_name: plugin.name.clone(),
            plugin_version: plugin.version.clone(),
            plugin_sdk: plugin.sdk_version.clone(),
            host_sdk: dashpot_sdk::abi::ABI_VERSION,
            dashpot: env!("CARGO_PKG_VERSION"),
            params,
            hidden: reg.hidden(name).iter().map(|p| p.display().to_string()).collect(),
        })
    }

    /// Every parameter as a JSON object, name → value (null: derived from the pair).
    pub fn params_json(&self) -> serde_json::Value {
        let m: serde_json::Map<String, serde_json::Value> = self
            .params
            .iter()
            .map(|(n, v, _)| (n.clone(), json!(v)))
            .collect();
        serde_json::Value::Object(m)
    }

    /// The whole provenance as JSON.
    pub fn json(&self) -> serde_json::Value {
        let sources: serde_json::Map<String, serde_json::Value> = self
            .params
            .iter()
            .map(|(n, _, s)| (n.clone(), json!(s.as_str())))
            .collect();
        json!({
            "law": self.law,
            "kind": self.kind,
            "plugin": {
                "file": self.plugin_file,
                "name": self.plugin_name,
                "version": self.plugin_version,
                "sdk_version": self.plugin_sdk,
            },
            "params": self.params_json(),
            "param_sources": sources,
            "shadows": self.hidden,
            "dashpot_version": self.dashpot,
            "host_sdk_version": self.host_sdk,
        })
    }

    /// The parameters in one line: `eps = 0.5 (given), k = derived from the pair`.
    pub fn params_line(&self) -> String {
        if self.params.is_empty() {
            return "(no parameters)".to_string();
        }
        self.params
            .iter()
            .map(|(n, v, s)| match v {
                Some(v) => format!("{n} = {v} ({})", s.as_str()),
                None => format!("{n} = {}", s.as_str()),
            })
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// Human-readable lines: law and parameters, plugin file and versions, dashpot's version,
    /// and the hidden plugins if the name is shadowed.
    pub fn lines(&self) -> Vec<String> {
        let mut v = vec![
            format!("law: {} ({}): {}", self.law, self.kind, self.params_line()),
            format!(
                "plugin: {} ({} {}, built against dashpot-sdk {}); dashpot {} (sdk {})",
                self.plugin_file,
                self.plugin_name,
                self.plugin_version,
                self.plugin_sdk,
                self.dashpot,
                self.host_sdk
            ),
        ];
        for h in &self.hidden {
            v.push(format!(
                "note: this '{}' shadows the law of the same name in {h}",
                self.law
            ));
        }
        v
    }

    /// The lines as CSV comments (`# ...`), each ending in a newline, to put before the header.
    pub fn csv_comment(&self) -> String {
        self.lines().iter().map(|l| format!("# {l}\n")).collect()
    }

    /// Warns on stderr when the law's name is shadowed: the result comes from a plugin other
    /// than a user expecting the usual one would think.
    pub fn warn_if_shadowed(&self) {
        for h in &self.hidden {
            eprintln!(
                "warning: law '{}' is taken from {}; it shadows the law of the same name in {h} \
                 (the first plugin found wins: --plugin files, then --plugin-dir, \
                 DASHPOT_PLUGIN_PATH, the built-in directory; see `dashpot laws`)",
                self.law, self.plugin_file
            );
        }
    }
}

/// The progress bar of every long run (`what`: what it counts), on stderr, hidden when stderr
/// is not a terminal.
pub fn progress_bar(len: u64, what: &str) -> indicatif::ProgressBar {
    use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
    use std::io::IsTerminal;
    let target = if std::io::stderr().is_terminal() {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    };
    let pb = ProgressBar::with_draw_target(Some(len), target);
    if let Ok(style) = ProgressStyle::with_template(&format!(
        "{what} [{{elapsed_precise}}] {{wide_bar}} {{pos}}/{{len}} {{msg}} (eta {{eta}})"
    )) {
        pb.set_style(style);
    }
    pb
}
