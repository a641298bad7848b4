//! The DEM benchmark links two plugin crates as rlibs (HSD and Mindlin, the "compiled in"
//! baseline), and some tests several; each exports abi_stable's root-module loader symbol,
//! which only matters when the library is loaded as a plugin (which codegen unit holds it, hence
//! whether the linker sees it twice, changes from build to build). Let the benchmark and test
//! binaries link with both definitions.
fn main() {
    println!("cargo:rustc-link-arg-benches=-Wl,--allow-multiple-definition");
    println!("cargo:rustc-link-arg-tests=-Wl,--allow-multiple-definition");
}
