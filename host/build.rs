//! Some host tests link plugin crates as rlibs (HSD, Mindlin, rolling SDS) to compare the engine
//! against the laws called directly; each plugin exports abi_stable's root-module loader symbol,
//! which only matters when its library is loaded as a plugin. Which codegen unit holds that
//! symbol, hence whether the linker sees it twice, changes from build to build: let the test
//! binaries link with both definitions (no test binary is ever loaded as a plugin).
fn main() {
    println!("cargo:rustc-link-arg-tests=-Wl,--allow-multiple-definition");
}
