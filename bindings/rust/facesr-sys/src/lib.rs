//! Raw declarations of the facesr C ABI (`capi/facesr.h`), written by hand
//! (no bindgen) and kept a plain mirror of the header: the same names, the
//! same `#[repr(C)]` struct layouts, one `extern "C"` function per
//! `FACESR_API` function. The test `bindings_consistency` compares this file
//! with the header (function names and parameter kinds, constants) and the
//! struct sizes and offsets printed by `examples/print_layout.rs` with the C
//! compiler's.
//!
//! Everything here is `unsafe` to call; the `facesr` crate is the safe API.
//! Units: cm, kPa·cm, ms. Strings are NUL-terminated UTF-8.
#![allow(non_camel_case_types)]

use std::marker::{PhantomData, PhantomPinned};
use std::os::raw::c_char;

pub type facesr_status = i32;

pub const FACESR_ABI_VERSION: u32 = 1;

pub const FACESR_OK: facesr_status = 0;
pub const FACESR_ERROR_NULL_ARGUMENT: facesr_status = 1;
pub const FACESR_ERROR_INVALID_ARGUMENT: facesr_status = 2;
pub const FACESR_ERROR_BUFFER_SIZE: facesr_status = 3;
pub const FACESR_ERROR_FILE: facesr_status = 4;
pub const FACESR_ERROR_MISMATCH: facesr_status = 5;
pub const FACESR_ERROR_DEVICE: facesr_status = 6;
pub const FACESR_ERROR_NOT_FOUND: facesr_status = 7;
pub const FACESR_ERROR_STATE: facesr_status = 8;
pub const FACESR_ERROR_SIMULATION: facesr_status = 9;
pub const FACESR_ERROR_INTERNAL: facesr_status = 10;

pub const FACESR_SOLVER_REALTIME: i32 = 0;
pub const FACESR_SOLVER_ACCURATE: i32 = 1;

pub const FACESR_PRECISION_AUTO: i32 = 0;
pub const FACESR_PRECISION_DOUBLE: i32 = 1;
pub const FACESR_PRECISION_FLOAT: i32 = 2;

pub const FACESR_INFERENCE_OPENCL: i32 = 0;
pub const FACESR_INFERENCE_CPU: i32 = 1;

pub const FACESR_FRAME_CONVERGED: i32 = 0;
pub const FACESR_FRAME_UNCONVERGED: i32 = 1;
pub const FACESR_FRAME_RECOVERED: i32 = 2;
pub const FACESR_FRAME_DIVERGED: i32 = 3;

// Opaque handles: never constructed or moved in Rust, only pointed to. The
// marker keeps them !Send, !Sync and !Unpin; the safe crate decides what may
// cross threads.
#[repr(C)]
pub struct facesr_rig {
    _private: [u8; 0],
    _marker: PhantomData<(*mut u8, PhantomPinned)>,
}

#[repr(C)]
pub struct facesr_model {
    _private: [u8; 0],
    _marker: PhantomData<(*mut u8, PhantomPinned)>,
}

#[repr(C)]
pub struct facesr_context {
    _private: [u8; 0],
    _marker: PhantomData<(*mut u8, PhantomPinned)>,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct facesr_rig_info {
    pub struct_size: u32,
    pub num_blendshapes: i32,
    pub num_surface_vertices: i32,
    pub num_surface_triangles: i32,
    pub num_lr_nodes: i32,
    pub num_muscles: i32,
    pub checksum: u64,
    pub jaw_pivot: [f32; 3],
    pub jaw_axis: [f32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct facesr_model_info {
    pub struct_size: u32,
    pub rig_checksum: u64,
    pub num_lr_nodes: i32,
    pub num_surface_vertices: i32,
    pub num_parameters: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct facesr_context_def {
    pub struct_size: u32,
    pub device_index: i32,
    pub device_name: *const c_char,
    pub solver: i32,
    pub inference: i32,
    pub split_device: i32,
    pub lr_precision: i32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct facesr_spring_def {
    pub struct_size: u32,
    pub vertex: i32,
    pub target: [f32; 3],
    pub stiffness: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct facesr_sphere_def {
    pub struct_size: u32,
    pub centre: [f32; 3],
    pub radius: f32,
    pub stiffness: f32,
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct facesr_frame_stats {
    pub struct_size: u32,
    pub frame: i64,
    pub simulation_ms: f32,
    pub inference_ms: f32,
    pub total_ms: f32,
    pub newton_iterations: i32,
    pub cg_iterations: i32,
    pub relative_residual: f32,
    pub simulation_status: i32,
    pub inverted_tets: i32,
    pub recoveries: i32,
}



extern "C" {
    // status
    pub fn facesr_abi_version() -> u32;
    pub fn facesr_version_string() -> *const c_char;
    pub fn facesr_last_error_message() -> *const c_char;
    pub fn facesr_status_name(status: facesr_status) -> *const c_char;

    // rig
    pub fn facesr_rig_load(path: *const c_char, out_rig: *mut *mut facesr_rig) -> facesr_status;
    pub fn facesr_rig_free(rig: *mut facesr_rig);
    pub fn facesr_rig_get_info(rig: *const facesr_rig, info: *mut facesr_rig_info) -> facesr_status;
    pub fn facesr_rig_blendshape_name(
        rig: *const facesr_rig,
        index: i32,
        buf: *mut c_char,
        buf_size: i32,
        out_length: *mut i32,
    ) -> facesr_status;
    pub fn facesr_rig_blendshape_index(
        rig: *const facesr_rig,
        name: *const c_char,
        out_index: *mut i32,
    ) -> facesr_status;
    pub fn facesr_rig_get_triangles(rig: *const facesr_rig, indices: *mut i32, count: i64) -> facesr_status;
    pub fn facesr_rig_get_rest_positions(rig: *const facesr_rig, xyz: *mut f32, count: i64) -> facesr_status;

    // model
    pub fn facesr_model_load(path: *const c_char, out_model: *mut *mut facesr_model) -> facesr_status;
    pub fn facesr_model_free(model: *mut facesr_model);
    pub fn facesr_model_get_info(model: *const facesr_model, info: *mut facesr_model_info) -> facesr_status;

    // context
    pub fn facesr_default_context_def() -> facesr_context_def;
    pub fn facesr_context_create(
        rig: *const facesr_rig,
        model: *const facesr_model,
        def: *const facesr_context_def,
        out_context: *mut *mut facesr_context,
    ) -> facesr_status;
    pub fn facesr_context_destroy(context: *mut facesr_context);
    pub fn facesr_context_reset(context: *mut facesr_context) -> facesr_status;

    // controls
    pub fn facesr_set_weight(context: *mut facesr_context, index: i32, value: f32) -> facesr_status;
    pub fn facesr_set_weight_by_name(context: *mut facesr_context, name: *const c_char, value: f32) -> facesr_status;
    pub fn facesr_set_weights(context: *mut facesr_context, weights: *const f32, count: i64) -> facesr_status;
    pub fn facesr_set_jaw_transform(
        context: *mut facesr_context,
        rotation: *const f32,
        translation: *const f32,
    ) -> facesr_status;
    pub fn facesr_clear_jaw_transform(context: *mut facesr_context) -> facesr_status;
    pub fn facesr_default_spring_def() -> facesr_spring_def;
    pub fn facesr_default_sphere_def() -> facesr_sphere_def;
    pub fn facesr_add_spring(
        context: *mut facesr_context,
        def: *const facesr_spring_def,
        out_id: *mut i32,
    ) -> facesr_status;
    pub fn facesr_move_spring(context: *mut facesr_context, id: i32, target: *const f32) -> facesr_status;
    pub fn facesr_remove_spring(context: *mut facesr_context, id: i32) -> facesr_status;
    pub fn facesr_add_sphere(
        context: *mut facesr_context,
        def: *const facesr_sphere_def,
        out_id: *mut i32,
    ) -> facesr_status;
    pub fn facesr_move_sphere(context: *mut facesr_context, id: i32, centre: *const f32) -> facesr_status;
    pub fn facesr_remove_sphere(context: *mut facesr_context, id: i32) -> facesr_status;

    // stepping
    pub fn facesr_step(context: *mut facesr_context) -> facesr_status;
    pub fn facesr_step_async(context: *mut facesr_context) -> facesr_status;
    pub fn facesr_wait(context: *mut facesr_context, out_frame: *mut i64) -> facesr_status;
    pub fn facesr_pending_frames(context: *const facesr_context, out_count: *mut i32) -> facesr_status;

    // read-back
    pub fn facesr_get_positions(context: *const facesr_context, xyz: *mut f32, count: i64) -> facesr_status;
    pub fn facesr_get_normals(context: *const facesr_context, xyz: *mut f32, count: i64) -> facesr_status;
    pub fn facesr_get_embedded_positions(context: *const facesr_context, xyz: *mut f32, count: i64) -> facesr_status;
    pub fn facesr_get_frame_stats(context: *const facesr_context, stats: *mut facesr_frame_stats) -> facesr_status;
}
