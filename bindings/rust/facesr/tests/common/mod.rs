//! The test rig, model and performance: the CMake fixtures capi_test_data
//! (p.rig, p.fsm, talk.json, made by tests/c/make_test_data.cmake) and
//! bindings_test_data (other.rig, a rig the model was not trained on).
//! ctest sets FACESR_TEST_DATA and FACESR_TEST_OTHER_RIG; run by hand, the
//! defaults are the CMake build's folders.
#![allow(dead_code)]

use facesr::{Context, ContextOptions, Inference, Model, Rig};
use std::path::PathBuf;
use std::sync::Arc;

fn build_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../build")
}

pub fn data_dir() -> PathBuf {
    match std::env::var_os("FACESR_TEST_DATA") {
        Some(d) => PathBuf::from(d),
        None => build_dir().join("capi_test_data"),
    }
}

pub fn rig_path() -> PathBuf {
    data_dir().join("p.rig")
}

pub fn model_path() -> PathBuf {
    data_dir().join("p.fsm")
}

pub fn other_rig_path() -> PathBuf {
    match std::env::var_os("FACESR_TEST_OTHER_RIG") {
        Some(p) => PathBuf::from(p),
        None => build_dir().join("bindings_test_data/other.rig"),
    }
}

pub fn rig() -> Arc<Rig> {
    let p = rig_path();
    Arc::new(Rig::load(&p).unwrap_or_else(|e| {
        panic!(
            "cannot load the test rig {} ({e}); run ctest's capi_test_data fixture or set FACESR_TEST_DATA",
            p.display()
        )
    }))
}

pub fn model() -> Arc<Model> {
    Arc::new(Model::load(model_path()).expect("the test model"))
}

/// The CPU reference inference: deterministic, and needs no OpenCL device.
pub fn cpu() -> ContextOptions {
    ContextOptions { inference: Inference::Cpu, ..ContextOptions::default() }
}

pub fn context() -> Context {
    Context::new(rig(), model(), &cpu()).expect("a context")
}

pub fn max_abs_diff(a: &[f32], b: &[f32]) -> f32 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f32::max)
}
