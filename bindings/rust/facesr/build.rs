// Gives this crate's test binaries an rpath to the folder facesr-sys linked
// libfacesr from (DEP_FACESR_LIB_DIR, published by facesr-sys's build script),
// so `cargo test` runs without LD_LIBRARY_PATH. Binaries of other crates
// still need the library on their loader path (or beside them).
use std::env;

fn main() {
    println!("cargo:rerun-if-env-changed=DEP_FACESR_LIB_DIR");
    if let Some(dir) = env::var_os("DEP_FACESR_LIB_DIR") {
        if env::var_os("CARGO_CFG_UNIX").is_some() {
            println!("cargo:rustc-link-arg-tests=-Wl,-rpath,{}", dir.to_string_lossy());
        }
    }
}
