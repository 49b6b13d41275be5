//! Hash every top-level module of `src/` with the files it depends on (see
//! `src/sources/scan.rs`), so that the build's cache keys follow the code.

#[path = "src/sources/scan.rs"]
#[allow(dead_code)]
mod scan;

fn main() {
    let dir = std::path::PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    for p in ["src", "templates", "Cargo.lock"] {
        println!("cargo:rerun-if-changed={p}");
    }
    let table = scan::table(&dir).expect("reading src/ for the module hashes");
    let out = std::path::PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it"));
    std::fs::write(out.join("sources.rs"), table).expect("writing the module hashes");
}
