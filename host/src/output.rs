//! Result files are written whole or not at all.

use crate::registry::{kind_str, Registry};
use dashpot_sdk::LawInfo;
use serde_json::json;
use std::io::Write;
use std::path::Path;

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename, so a
/// reader (or a crash) never sees a half-written result.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    std::fs::create_dir_all(dir)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    let res = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if res.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    res
}

#[cfg(test)]
mod tests {
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
        "kind": kind_str(info.kind),
        "summary": info.summary.as_str(),
        "doc": info.doc.as_str(),
        "end_criterion": info.end_criterion.into_option().map(|e| e.as_str()),
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
            "default": s.default.into_option(),
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
