//! The rule of imports, read from the sources: cli → report → experiments → engines → law
//! traits → sdk. An engine (the event-driven bed engine, the DEM engine) imports neither the CLI
//! nor the reports nor the other engine; nothing outside `cli/` imports `cli`; only
//! `host/core/src/laws.rs` names the sdk's ABI handle types.

use std::path::{Path, PathBuf};

/// Every `.rs` file under `dir`, recursively.
fn sources(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap_or_else(|e| panic!("{}: {e}", d.display())) {
            let p = e.expect("directory entry").path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The code of a file without its comments (`//` to the end of a line).
fn code(p: &Path) -> String {
    let text = std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    text.lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("\n")
}

fn host_src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// The path of `p` below `root`, with `/` separators.
fn rel(root: &Path, p: &Path) -> String {
    p.strip_prefix(root)
        .expect("below root")
        .to_string_lossy()
        .replace('\\', "/")
}

/// (file, forbidden path it names) for every file of `host/src` whose relative path satisfies
/// `which` and whose code names one of `forbidden`.
fn offences(which: impl Fn(&str) -> bool, forbidden: &[&str]) -> Vec<(String, String)> {
    let root = host_src();
    let mut found = Vec::new();
    for p in sources(&root) {
        let r = rel(&root, &p);
        if !which(&r) {
            continue;
        }
        let c = code(&p);
        for f in forbidden {
            if c.contains(f) {
                found.push((r.clone(), f.to_string()));
            }
        }
    }
    found
}

fn is_dem_engine(r: &str) -> bool {
    r.starts_with("dem/")
}

fn is_event_engine(r: &str) -> bool {
    r.starts_with("bed/engine/") || r == "bed/events.rs" || r == "bed/cells.rs"
}

#[test]
fn nothing_outside_cli_imports_cli() {
    let bad = offences(
        |r| !r.starts_with("cli/") && r != "main.rs" && r != "lib.rs",
        &["crate::cli", "super::cli"],
    );
    assert!(bad.is_empty(), "imports of cli outside cli/: {bad:?}");
}

#[test]
fn engines_import_neither_the_cli_nor_the_reports_nor_each_other() {
    let up = ["crate::cli", "crate::report", "crate::plot", "crate::reproduce"];
    let bad = offences(|r| is_dem_engine(r) || is_event_engine(r), &up);
    assert!(bad.is_empty(), "an engine imports the CLI or a report: {bad:?}");
    let bad = offences(is_dem_engine, &["crate::bed"]);
    assert!(bad.is_empty(), "the DEM engine imports the bed: {bad:?}");
    let bad = offences(is_event_engine, &["crate::dem"]);
    assert!(
        bad.is_empty(),
        "the event-driven engine imports the DEM engine: {bad:?}"
    );
}

#[test]
fn reports_do_not_import_the_cli() {
    let bad = offences(|r| r.starts_with("report/"), &["crate::cli"]);
    assert!(bad.is_empty(), "a report imports the CLI: {bad:?}");
}

#[test]
fn only_the_law_traits_name_abi_handle_types() {
    let core = Path::new(env!("CARGO_MANIFEST_DIR")).join("core/src");
    let mut bad = Vec::new();
    for root in [host_src(), core.clone()] {
        for p in sources(&root) {
            if p == core.join("laws.rs") {
                continue;
            }
            let c = code(&p);
            // Any type the sdk's ABI module exports, named through that module.
            for (i, _) in c.match_indices("abi::") {
                let after = &c[i + 5..];
                let name: String = after
                    .chars()
                    .skip_while(|c| *c == '{' || c.is_whitespace())
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                if name.ends_with("Handle") || c[i..].starts_with("abi::{") && after.contains("Handle") {
                    bad.push(rel(&root, &p));
                }
            }
        }
    }
    bad.dedup();
    assert!(
        bad.is_empty(),
        "files naming the sdk's ABI handles outside laws.rs: {bad:?}"
    );
}

/// The check itself can fail: a file that imports the CLI from an engine is caught.
#[test]
fn the_checks_catch_an_offending_line() {
    let dir =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("arch-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let f = dir.join("x.rs");
    std::fs::write(
        &f,
        "// crate::cli in a comment is fine\nuse crate::cli::UsageError;\n",
    )
    .expect("write");
    let c = code(&f);
    assert_eq!(
        c.matches("crate::cli").count(),
        1,
        "comments are skipped, code is not"
    );
    std::fs::remove_dir_all(&dir).ok();
}
