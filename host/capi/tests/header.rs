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

/// Every `dashpot_*` function the header declares, in order.
fn header_functions() -> Vec<String> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let header = std::fs::read_to_string(dir.join("include/dashpot.h")).expect("read include/dashpot.h");
    let mut names = Vec::new();
    for line in header.lines() {
        let line = line.trim_start();
        if line.starts_with("//") || line.starts_with('*') || line.starts_with("/*") || line.starts_with('#')
        {
            continue;
        }
        // a declaration: `<type> [*]dashpot_NAME(`
        if let Some(open) = line.find('(') {
            let head = &line[..open];
            if let Some(name) = head.split(|c: char| c.is_whitespace() || c == '*').next_back() {
                if name.starts_with("dashpot_") && !names.iter().any(|n| n == name) {
                    names.push(name.to_string());
                }
            }
        }
    }
    names
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
    ] {
        assert!(
            functions.iter().any(|n| n == f),
            "the header parser missed {f}: {functions:?}"
        );
    }
    let c = std::fs::read_to_string(dir.join("tests/c/error_paths.c")).expect("read error_paths.c");
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
