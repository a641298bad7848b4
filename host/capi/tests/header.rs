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
