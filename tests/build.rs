//! The DEM benchmark links two plugin crates as rlibs (HSD and Mindlin, the "compiled in"
//! baseline); each exports abi_stable's root-module loader symbol, which only matters when the
//! library is loaded as a plugin. Let the benchmark binaries link with both definitions.
fn main() {
    println!("cargo:rustc-link-arg-benches=-Wl,--allow-multiple-definition");
}
