//! The DEM benchmark links two plugin crates as rlibs (HSD and Mindlin, the "compiled in"
//! baseline), and so do the tests of the tangential springs (Mindlin and linear-history, whose
//! laws they drive directly); each crate exports abi_stable's root-module loader symbol, which
//! only matters when the library is loaded as a plugin. Whether the linker pulls in both
//! definitions depends on how rustc splits the crates into codegen units (it does without
//! incremental compilation), so let those binaries link with both.
fn main() {
    println!("cargo:rustc-link-arg-benches=-Wl,--allow-multiple-definition");
    println!("cargo:rustc-link-arg-tests=-Wl,--allow-multiple-definition");
}
