//! The guide cannot go stale: every `dashpot ...` command in a ```sh block of README.md and of
//! docs/*.md runs and exits 0, against this build's binary and plugins. Commands that are
//! templates (`[--json]`, `PATH`, `FILE`, `DIR`, `...`, alternatives with `|`, a plugin of the
//! reader's own) and the long ones (`reproduce`, `scaling`, several seeds) are skipped, by rule.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// Why a documented command is not run, if it is not.
fn skip_reason(cmd: &str) -> Option<&'static str> {
    const TEMPLATE: [&str; 8] = ["[", "...", "PATH", "FILE", "DIR", "|", "\\", "libmy_law"];
    const LONG: [&str; 3] = ["reproduce", "scaling", "--seeds"];
    if TEMPLATE.iter().any(|t| cmd.contains(t)) {
        Some("a template")
    } else if LONG.iter().any(|t| cmd.contains(t)) {
        Some("minutes long")
    } else {
        None
    }
}

/// The `dashpot` commands of the ```sh blocks of `file` (comments after `  #` dropped).
fn commands(file: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
    let mut out = Vec::new();
    let mut in_sh = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("```") {
            in_sh = !in_sh && t == "```sh";
            continue;
        }
        if in_sh {
            let cmd = t.split("  #").next().unwrap_or("").trim();
            if cmd.starts_with("dashpot ") {
                out.push(cmd.to_string());
            }
        }
    }
    out
}

#[test]
fn every_command_of_the_readme_and_the_guide_runs() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let mut files = vec![root.join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(root.join("docs"))
        .expect("docs/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    let work =
        std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("docs-{}", std::process::id()));
    std::fs::create_dir_all(&work).expect("scratch directory");
    let examples = root.join("examples").canonicalize().expect("examples/");
    let (mut ran, mut failures) = (0, Vec::new());
    for f in &files {
        for cmd in commands(f) {
            if let Some(why) = skip_reason(&cmd) {
                eprintln!("skipped ({why}): {cmd}");
                continue;
            }
            let args: Vec<String> = cmd
                .split_whitespace()
                .skip(1)
                .map(|a| a.replace("examples/", &format!("{}/", examples.display())))
                .collect();
            let out = Command::new(env!("CARGO_BIN_EXE_dashpot"))
                .arg("--plugin-dir")
                .arg(common::all_plugins_dir())
                .args(&args)
                .current_dir(&work)
                .output()
                .expect("run dashpot");
            ran += 1;
            if !out.status.success() {
                failures.push(format!(
                    "{}: `{cmd}` exited {}: {}",
                    f.display(),
                    out.status,
                    String::from_utf8_lossy(&out.stderr)
                ));
            }
        }
    }
    std::fs::remove_dir_all(&work).ok();
    assert!(ran >= 10, "only {ran} documented commands found");
    assert!(
        failures.is_empty(),
        "documented commands failed:\n{}",
        failures.join("\n")
    );
}

#[test]
fn the_skip_rules_keep_real_commands() {
    assert_eq!(skip_reason("dashpot collide --law hsd --v0 1"), None);
    assert!(skip_reason("dashpot laws [--json]").is_some());
    assert!(skip_reason("dashpot reproduce --out results").is_some());
}
