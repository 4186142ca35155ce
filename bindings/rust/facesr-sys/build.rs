// Links libfacesr from FACESR_LIB_DIR (default: the CMake build's lib folder,
// ../../../build/lib from this crate, i.e. <repo>/build/lib).
//
// The folder is also published to dependents as DEP_FACESR_LIB_DIR (this
// crate sets `links = "facesr"`), so the facesr crate can give its tests an
// rpath and `cargo test` runs without LD_LIBRARY_PATH.
use std::env;
use std::path::PathBuf;

fn main() {
    println!("cargo:rerun-if-env-changed=FACESR_LIB_DIR");
    println!("cargo:rerun-if-changed=build.rs");
    let dir = match env::var_os("FACESR_LIB_DIR") {
        Some(d) if !d.is_empty() => PathBuf::from(d),
        _ => {
            let crate_dir = PathBuf::from(env::var_os("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
            crate_dir.join("../../../build/lib")
        }
    };
    // An absolute path, so that rpaths made from it work from any folder.
    let dir = dir.canonicalize().unwrap_or(dir);
    let found =
        ["libfacesr.so", "libfacesr.dylib", "facesr.lib", "facesr.dll.lib"].iter().any(|f| dir.join(f).exists());
    if !found {
        println!(
            "cargo:warning=no libfacesr in {} (build it with CMake, or set FACESR_LIB_DIR); linking will fail",
            dir.display()
        );
    }
    println!("cargo:rustc-link-search=native={}", dir.display());
    println!("cargo:rustc-link-lib=dylib=facesr");
    println!("cargo:lib_dir={}", dir.display());
    // This crate's own tests and examples find the library at run time too.
    if env::var_os("CARGO_CFG_UNIX").is_some() {
        println!("cargo:rustc-link-arg-tests=-Wl,-rpath,{}", dir.display());
        println!("cargo:rustc-link-arg-examples=-Wl,-rpath,{}", dir.display());
    }
}
