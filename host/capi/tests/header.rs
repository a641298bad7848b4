//! The committed header is what cbindgen generates from the sources today.

use std::path::Path;

#[test]
fn committed_header_is_current() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("read cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen generates the header");
    let mut fresh = Vec::new();
    bindings.write(&mut fresh);
    let fresh = String::from_utf8(fresh).expect("UTF-8 header");
    let path = dir.join("include/dashpot.h");
    if std::env::var_os("DASHPOT_BLESS_HEADER").is_some() {
        std::fs::write(&path, &fresh).expect("write include/dashpot.h");
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == fresh,
        "include/dashpot.h is stale: regenerate it with `DASHPOT_BLESS_HEADER=1 cargo test -p dashpot-capi --test header` \
         and commit it"
    );
    // The header carries what a C caller needs to check the ABI and read errors.
    for needle in [
        "#define DASHPOT_ABI_VERSION 1",
        "uint32_t dashpot_abi_version(void);",
        "const char *dashpot_last_error(void);",
        "DASHPOT_ERR_NULL_POINTER = 1",
        "typedef struct DashpotRegistry DashpotRegistry;",
    ] {
        assert!(fresh.contains(needle), "header lacks `{needle}`");
    }
}

/// A `#define`'s text from `first` (after `#define `) with its continuation lines joined.
fn continued(first: &str, lines: &mut std::str::Lines<'_>) -> String {
    let mut body = first.to_string();
    let mut last = first.to_string();
    while last.trim_end().ends_with('\\') {
        last = lines.next().unwrap_or_default().to_string();
        body.push_str(&last);
    }
    body
}

/// Every `dashpot_*` function the header declares, in order: the declarations cbindgen writes,
/// then those of the `DASHPOT_*(KIND or NAME, ...)` macro lines: each macro's names with
/// `##KIND##` replaced, or the name itself when the macro declares `NAME`.
fn header_functions() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    // the generated header, then the kinds' functions it includes at its end
    let header = ["include/dashpot.h", "include/dashpot_kinds.h"]
        .map(|f| std::fs::read_to_string(dir.join(f)).unwrap_or_else(|e| panic!("read {f}: {e}")))
        .concat();
    let mut names: Vec<String> = Vec::new();
    let mut add = |name: String| {
        if !names.contains(&name) {
            names.push(name);
        }
    };
    // a name followed by `(`, ending an identifier that starts with `dashpot_`
    let declared = |text: &str| -> Vec<String> {
        let mut found = Vec::new();
        for (open, _) in text.match_indices('(') {
            let head = &text[..open];
            let start = head
                .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '#'))
                .map_or(0, |k| k + 1);
            if head[start..].starts_with("dashpot_") {
                found.push(head[start..].to_string());
            }
        }
        found
    };
    let mut macros: Vec<(String, Vec<String>)> = Vec::new();
    let mut lines = header.lines();
    while let Some(line) = lines.next() {
        let line = line.trim_start();
        if let Some(def) = line.strip_prefix("#define DASHPOT_") {
            let body = continued(def, &mut lines);
            let name = format!("DASHPOT_{}", &def[..def.find('(').unwrap_or(0)]);
            macros.push((name, declared(&body[body.find(')').unwrap_or(0)..])));
            continue;
        }
        if let Some((name, templates)) = macros.iter().find(|(m, _)| line.starts_with(&format!("{m}("))) {
            let first = line[name.len() + 1..]
                .split([',', ')'])
                .next()
                .unwrap_or_default()
                .trim();
            if templates.is_empty() && first.starts_with("dashpot_") {
                add(first.to_string());
            }
            for t in templates {
                add(t.replace("##KIND##", first));
            }
            continue;
        }
        if line.starts_with("//") || line.starts_with('*') || line.starts_with("/*") || line.starts_with('#')
        {
            continue;
        }
        for name in declared(line) {
            add(name);
        }
    }
    names
}

/// Every `dashpot_*` symbol the shared library exports (`nm -D`), or `None` when `nm` is
/// missing (skipped with a printed reason; an error under `CI=true`).
fn exported_functions() -> Option<Vec<String>> {
    let deps = std::env::current_exe()
        .expect("current_exe")
        .parent()
        .expect("deps")
        .to_path_buf();
    let lib = deps.join("libdashpot_capi.so");
    match std::process::Command::new("nm")
        .args(["-D", "--defined-only"])
        .arg(&lib)
        .output()
    {
        Ok(out) if out.status.success() => Some(
            String::from_utf8_lossy(&out.stdout)
                .lines()
                .filter_map(|l| l.split_whitespace().last())
                .filter(|s| s.starts_with("dashpot_"))
                .map(str::to_string)
                .collect(),
        ),
        other => {
            let reason = format!("`nm -D {}` did not run: {other:?}", lib.display());
            assert!(!std::env::var("CI").is_ok_and(|v| v == "true"), "{reason}");
            eprintln!("SKIPPED: {reason}");
            None
        }
    }
}

/// The header declares exactly the functions the library exports: none is missing from the
/// header (a macro line forgotten) and none is declared that the library lacks.
#[test]
fn header_declares_exactly_the_exported_functions() {
    let Some(mut exported) = exported_functions() else {
        return;
    };
    let mut declared = header_functions();
    exported.sort();
    declared.sort();
    assert_eq!(declared, exported, "header declarations vs library exports");
    assert!(declared.len() >= 50, "{declared:?}");
}

/// `word` occurs in `text` as a whole identifier, followed (after blanks) by `(`: a call.
fn called(text: &str, word: &str) -> bool {
    let lower = text.to_ascii_lowercase();
    let word = word.to_ascii_lowercase();
    let bytes = lower.as_bytes();
    let mut from = 0;
    while let Some(k) = lower[from..].find(&word) {
        let at = from + k;
        let end = at + word.len();
        let before_ok = at == 0 || !(bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_');
        let after = lower[end..].trim_start();
        if before_ok && after.starts_with('(') {
            return true;
        }
        from = end;
    }
    false
}

/// `text` followed by the calls its `#define NAME(KIND, ...)` macros make for each `NAME(kind, ...)`
/// statement: the macro's body with `##KIND##` replaced by `kind`, those of the macros it invokes
/// likewise (the C test's macros for the error paths every kind shares).
fn with_kind_macros_expanded(text: &str) -> String {
    let mut out = text.to_string();
    let mut lines = text.lines();
    let mut macros: Vec<(String, String)> = Vec::new();
    while let Some(line) = lines.next() {
        if let Some(def) = line.strip_prefix("#define ").filter(|d| d.contains("(KIND")) {
            let body = continued(def, &mut lines);
            let params_end = body.find(')').unwrap_or(0);
            macros.push((
                def[..def.find('(').unwrap_or(0)].to_string(),
                body[params_end..].to_string(),
            ));
        }
    }
    // a macro's body may invoke another of them: expand what each round adds, a few rounds deep
    let mut added = text.to_string();
    for _ in 0..4 {
        let mut next = String::new();
        for call in added.split(['\n', ';', '\\']).map(str::trim_start) {
            for (name, body) in &macros {
                if let Some(args) = call.strip_prefix(&format!("{name}(")) {
                    let kind = args.split(',').next().unwrap_or_default().trim();
                    let body = body
                        .replace("##KIND##", kind)
                        .replace("(KIND,", &format!("({kind},"));
                    next.push_str(&body.replace('\\', ";"));
                }
            }
        }
        out.push_str(&next);
        added = next;
    }
    out
}

#[test]
fn every_header_function_is_exercised_from_c_and_bound_in_fortran() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let functions = header_functions();
    // The parser sees the functions (a sanity check that it is not silently finding none).
    for f in [
        "dashpot_abi_version",
        "dashpot_contact_force_batch",
        "dashpot_contact_model_force_batch",
        "dashpot_tangential_model_force_batch",
        "dashpot_rolling_new",
        "dashpot_twisting_model_history_slots",
        "dashpot_bound_restitution_free",
    ] {
        assert!(
            functions.iter().any(|n| n == f),
            "the header parser missed {f}: {functions:?}"
        );
    }
    let c = with_kind_macros_expanded(
        &std::fs::read_to_string(dir.join("tests/c/error_paths.c")).expect("read error_paths.c"),
    );
    let fortran =
        std::fs::read_to_string(dir.join("../../examples/fortran/dashpot.f90")).expect("read dashpot.f90");
    let missing_c: Vec<&String> = functions.iter().filter(|f| !called(&c, f)).collect();
    assert!(
        missing_c.is_empty(),
        "host/capi/tests/c/error_paths.c never calls {missing_c:?}: every header function needs its error paths tested from C"
    );
    // Fortran: each function has an interface `bind(c, name="dashpot_...")`.
    let missing_f: Vec<&String> = functions
        .iter()
        .filter(|f| !fortran.contains(&format!("name=\"{f}\"")) && !fortran.contains(&format!("name='{f}'")))
        .collect();
    assert!(
        missing_f.is_empty(),
        "examples/fortran/dashpot.f90 has no bind(c, name=\"...\") interface for {missing_f:?}"
    );
}
