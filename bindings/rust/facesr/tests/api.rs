//! The safe API against libfacesr on the tiny procedural rig: loading, names,
//! stepping and reading back, async + wait, springs and spheres, and every
//! error path the types leave open (the rest, NULL and freed handles, cannot
//! be written in safe Rust; `raw_null_handles` checks them through facesr-sys).
mod common;

use common::*;
use facesr::{sys, Context, FrameStatus, Model, Rig, SphereDef, SpringDef, SpringId, Status};
use std::sync::Arc;

fn assert_status<T: std::fmt::Debug>(r: facesr::Result<T>, want: Status, needle: &str) {
    match r {
        Ok(v) => panic!("expected {want:?}, got Ok({v:?})"),
        Err(e) => {
            assert_eq!(e.status(), want, "{e}");
            assert!(e.message().contains(needle), "message {:?} lacks {:?}", e.message(), needle);
        }
    }
}

#[test]
fn version_and_status_names() {
    facesr::ensure_compatible().unwrap();
    assert_eq!(facesr::abi_version(), sys::FACESR_ABI_VERSION);
    assert!(facesr::version_string().starts_with("facesr "));
    assert_eq!(Status::BufferSize.name(), "FACESR_ERROR_BUFFER_SIZE");
    assert_eq!(Status::from_code(sys::FACESR_OK), None);
    for code in 1..=sys::FACESR_ERROR_INTERNAL {
        let s = Status::from_code(code).unwrap();
        assert_eq!(s.code(), code);
        assert!(s.name().starts_with("FACESR_ERROR_"), "{}", s.name());
        assert!(!matches!(s, Status::Unknown(_)));
    }
    assert_eq!(Status::from_code(99), Some(Status::Unknown(99)));
    assert_eq!(Status::Unknown(99).name(), "unknown");
}

#[test]
fn load_errors_are_file_errors() {
    let missing = data_dir().join("missing.rig");
    assert_status(Rig::load(&missing), Status::File, missing.to_str().unwrap());
    assert_status(Rig::load(model_path()), Status::File, "facesr_rig_load");
    assert_status(Model::load(rig_path()), Status::File, "facesr_model_load");
    assert_status(Rig::load(data_dir()), Status::File, "directory");
    assert_status(Rig::load("a\0b.rig"), Status::InvalidArgument, "NUL");
}

#[test]
fn rig_and_model_describe_each_other() {
    let rig = rig();
    let model = model();
    let info = rig.info();
    assert!(info.num_blendshapes > 0 && info.num_surface_vertices > 0 && info.num_surface_triangles > 0);
    assert!(info.num_lr_nodes > 0 && info.num_muscles > 0);
    let axis_len = info.jaw_axis.iter().map(|a| a * a).sum::<f32>().sqrt();
    assert!((axis_len - 1.0).abs() < 1e-4, "jaw axis {:?}", info.jaw_axis);
    assert_eq!(model.info().rig_checksum, rig.checksum());
    assert_eq!(model.info().num_lr_nodes, info.num_lr_nodes);
    assert_eq!(model.info().num_surface_vertices, info.num_surface_vertices);
    assert!(model.info().num_parameters > 0);

    let names = rig.blendshape_names();
    assert_eq!(names.len(), info.num_blendshapes);
    for (i, n) in names.iter().enumerate() {
        assert_eq!(rig.blendshape_index(n).unwrap(), i);
    }
    assert!(names.iter().any(|n| n == "jawOpen"));
    assert_status(rig.blendshape_index("jawopen"), Status::NotFound, "jawopen");
    assert_status(rig.blendshape_index("jaw\0Open"), Status::InvalidArgument, "NUL");
}

#[test]
fn geometry_and_buffer_sizes() {
    let rig = rig();
    let tris = rig.triangles().unwrap();
    assert_eq!(tris.len(), 3 * rig.num_triangles());
    assert!(tris.iter().all(|&t| t >= 0 && (t as usize) < rig.num_vertices()));
    let rest = rig.rest_positions().unwrap();
    assert!(rest.iter().all(|v| v.is_finite()));
    let mut short = vec![0; tris.len() - 1];
    assert_status(rig.get_triangles(&mut short), Status::BufferSize, &tris.len().to_string());
    let mut long = vec![0.0; rest.len() + 3];
    assert_status(rig.get_rest_positions(&mut long), Status::BufferSize, &rest.len().to_string());
    assert_status(rig.get_rest_positions(&mut []), Status::BufferSize, "xyz");
}

#[test]
fn context_creation_errors() {
    let other = Arc::new(Rig::load(other_rig_path()).expect("other.rig (fixture bindings_test_data)"));
    assert_ne!(other.checksum(), rig().checksum());
    let mismatch = Context::new(other, model(), &cpu());
    assert_status(mismatch, Status::Mismatch, "facesr_context_create");

    let mut opts = cpu();
    opts.device_name = Some("no-such-opencl-device".into());
    assert_status(Context::new(rig(), model(), &opts), Status::Device, "facesr_context_create");
    opts.device_name = Some("bad\0name".into());
    assert_status(Context::new(rig(), model(), &opts), Status::InvalidArgument, "NUL");
}

#[test]
fn weights_step_and_read_back() {
    let mut c = context();
    let n = c.position_len();
    let mut rest = vec![0.0; n];
    let mut pos = vec![0.0; n];
    c.get_positions(&mut rest).unwrap();
    assert_eq!(rest, c.rig().rest_positions().unwrap());
    assert_eq!(c.frame_stats().unwrap().frame, -1);

    // Bad controls fail and change nothing.
    assert_status(c.set_weight(0, f32::NAN), Status::InvalidArgument, "facesr_set_weight");
    assert_status(c.set_weight(0, 1.5), Status::InvalidArgument, "facesr_set_weight");
    assert_status(c.set_weight(c.rig().num_blendshapes(), 0.5), Status::InvalidArgument, "facesr_set_weight");
    assert_status(c.set_weight_by_name("jawOpen", f32::NAN), Status::InvalidArgument, "facesr_set_weight_by_name");
    assert_status(c.set_weight_by_name("jawopen_typo", 0.5), Status::NotFound, "jawopen_typo");
    let nb = c.rig().num_blendshapes();
    let mut w = vec![0.0; nb];
    assert_status(c.set_weights(&w[..nb - 1]), Status::BufferSize, &nb.to_string());
    w[1] = f32::NAN;
    assert_status(c.set_weights(&w), Status::InvalidArgument, "facesr_set_weights");
    assert_status(c.get_positions(&mut pos[..n - 3]), Status::BufferSize, &n.to_string());
    assert_status(c.get_normals(&mut []), Status::BufferSize, &n.to_string());
    assert_status(c.wait(), Status::State, "facesr_wait");
    c.get_positions(&mut pos).unwrap();
    assert_eq!(max_abs_diff(&pos, &rest), 0.0);

    c.set_weight_by_name("jawOpen", 0.8).unwrap();
    c.step().unwrap();
    c.get_positions(&mut pos).unwrap();
    assert!(pos.iter().all(|v| v.is_finite()));
    assert!(max_abs_diff(&pos, &rest) > 0.01, "the mouth opened (cm)");
    let stats = c.frame_stats().unwrap();
    assert_eq!(stats.frame, 0);
    assert!(stats.newton_iterations > 0 && stats.total_ms > 0.0);
    let mut normals = vec![0.0; n];
    c.get_normals(&mut normals).unwrap();
    for v in normals.chunks(3) {
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        assert!((len - 1.0).abs() < 1e-3, "normal length {len}");
    }
    let mut embedded = vec![0.0; n];
    c.get_embedded_positions(&mut embedded).unwrap();
    assert!(max_abs_diff(&embedded, &rest) > 0.01);

    c.reset().unwrap();
    c.get_positions(&mut pos).unwrap();
    assert_eq!(max_abs_diff(&pos, &rest), 0.0);
}

#[test]
fn async_frames_equal_sync_frames() {
    let (rig, model) = (rig(), model());
    let mut sync = Context::new(rig.clone(), model.clone(), &cpu()).unwrap();
    let mut pipelined = Context::new(rig.clone(), model, &cpu()).unwrap();
    let n = rig.position_len();
    let weights = [0.3f32, 0.7, 0.1];
    let mut want = Vec::new();
    for w in weights {
        sync.set_weight_by_name("jawOpen", w).unwrap();
        sync.step().unwrap();
        let mut p = vec![0.0; n];
        sync.get_positions(&mut p).unwrap();
        want.push(p);
    }
    let mut got = vec![vec![0.0; n]; weights.len()];
    let mut p = vec![0.0; n];
    for (i, &w) in weights.iter().enumerate() {
        pipelined.set_weight_by_name("jawOpen", w).unwrap();
        pipelined.step_async().unwrap();
        // Two frames in flight, one shown; the last tick leaves two.
        if pipelined.pending_frames().unwrap() == 2 && i + 1 < weights.len() {
            let f = pipelined.wait().unwrap() as usize;
            pipelined.get_positions(&mut p).unwrap();
            got[f].copy_from_slice(&p);
        }
    }
    // Two in flight: a third submission and a sync step are refused.
    assert_eq!(pipelined.pending_frames().unwrap(), 2);
    assert_status(pipelined.step_async(), Status::State, "facesr_step_async");
    assert_status(pipelined.step(), Status::State, "facesr_step");
    while pipelined.pending_frames().unwrap() > 0 {
        let f = pipelined.wait().unwrap() as usize;
        pipelined.get_positions(&mut p).unwrap();
        got[f].copy_from_slice(&p);
    }
    assert_status(pipelined.wait(), Status::State, "facesr_wait");
    assert_eq!(pipelined.frame_stats().unwrap().frame, 2);
    for f in 0..weights.len() {
        assert_eq!(max_abs_diff(&got[f], &want[f]), 0.0, "frame {f}");
    }
    // Dropping with frames in flight waits for them.
    pipelined.step_async().unwrap();
}

/// The soft-tissue vertex that jawOpen moves most (on the LR embedding).
fn jaw_vertex(c: &mut Context, rest: &[f32]) -> usize {
    c.set_weight_by_name("jawOpen", 1.0).unwrap();
    c.step().unwrap();
    let mut open = vec![0.0; rest.len()];
    c.get_embedded_positions(&mut open).unwrap();
    c.reset().unwrap();
    let d2 = |i: usize| (0..3).map(|k| (open[3 * i + k] - rest[3 * i + k]).powi(2)).sum::<f32>();
    (0..rest.len() / 3).fold(0, |best, i| if d2(i) > d2(best) { i } else { best })
}

#[test]
fn springs_and_spheres() {
    let mut c = context();
    let n = c.position_len();
    let mut rest = vec![0.0; n];
    c.get_positions(&mut rest).unwrap();
    let v = jaw_vertex(&mut c, &rest);
    let at = [rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]];
    let forward = [at[0], at[1], at[2] + 1.0]; // 1 cm out of the face

    assert_status(c.add_spring(&SpringDef::new(c.rig().num_vertices(), forward)), Status::InvalidArgument, "");
    let mut bad = SpringDef::new(v, forward);
    assert_eq!(bad.stiffness, 100.0, "the library's default");
    bad.stiffness = 0.0;
    assert_status(c.add_spring(&bad), Status::InvalidArgument, "");
    bad.stiffness = 100.0;
    bad.target[1] = f32::NAN;
    assert_status(c.add_spring(&bad), Status::InvalidArgument, "");
    assert_status(c.move_spring(SpringId(12345), forward), Status::InvalidArgument, "12345");

    let id = c.add_spring(&SpringDef::new(v, forward)).unwrap();
    assert!(id.0 > 0);
    c.step().unwrap();
    let mut pulled = vec![0.0; n];
    c.get_embedded_positions(&mut pulled).unwrap();
    assert!(pulled[3 * v + 2] - at[2] > 0.05, "vertex {v} pulled forward: {} -> {}", at[2], pulled[3 * v + 2]);
    c.move_spring(id, at).unwrap();
    assert_status(c.move_spring(id, [0.0, f32::NAN, 0.0]), Status::InvalidArgument, "");
    c.remove_spring(id).unwrap();
    assert_status(c.remove_spring(id), Status::InvalidArgument, &id.0.to_string());

    let sphere = SphereDef::new(at, 1.0);
    assert_eq!(sphere.stiffness, 200.0, "the library's default");
    let mut bad = sphere;
    bad.radius = 0.0;
    assert_status(c.add_sphere(&bad), Status::InvalidArgument, "");
    let s = c.add_sphere(&sphere).unwrap();
    assert!(s.0 > id.0, "ids are never reused");
    c.step().unwrap();
    c.get_positions(&mut pulled).unwrap();
    assert!(pulled.iter().all(|x| x.is_finite()));
    c.move_sphere(s, [1e3, 1e3, 1e3]).unwrap();
    assert_status(c.move_spring(SpringId(s.0), at), Status::InvalidArgument, "");
    c.remove_sphere(s).unwrap();
    assert_status(c.remove_sphere(s), Status::InvalidArgument, "");
}

#[test]
fn jaw_transform() {
    let mut c = context();
    let n = c.position_len();
    let mut rest = vec![0.0; n];
    c.get_positions(&mut rest).unwrap();
    let not_a_rotation = [2.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    assert_status(c.set_jaw_transform(&not_a_rotation, &[0.0; 3]), Status::InvalidArgument, "");
    let identity = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    c.set_jaw_transform(&identity, &[0.0, -0.3, 0.0]).unwrap();
    c.step().unwrap();
    let mut pos = vec![0.0; n];
    c.get_positions(&mut pos).unwrap();
    assert!(max_abs_diff(&pos, &rest) > 0.01, "the jaw moved down");
    c.clear_jaw_transform().unwrap();
}

/// A frame the simulation cannot solve (the jaw thrown 3 m away) says so and
/// returns the last good surface; the next sane frame plays again.
#[test]
fn diverged_frame_keeps_the_last_good_surface() {
    let mut c = context();
    let n = c.position_len();
    c.set_weight_by_name("jawOpen", 0.3).unwrap();
    c.step().unwrap();
    let st = c.frame_stats().unwrap();
    let status = FrameStatus::from_stats(&st);
    assert!(matches!(status, Some(FrameStatus::Converged) | Some(FrameStatus::Unconverged)), "{:?}", status);
    assert_eq!(st.recoveries, 0);
    let mut good = vec![0.0; n];
    c.get_positions(&mut good).unwrap();
    let identity = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    c.set_jaw_transform(&identity, &[0.0, -300.0, 0.0]).unwrap();
    c.step().unwrap();
    let st = c.frame_stats().unwrap();
    assert_eq!(FrameStatus::from_stats(&st), Some(FrameStatus::Diverged));
    assert!(st.recoveries > 0);
    let mut pos = vec![0.0; n];
    c.get_positions(&mut pos).unwrap();
    assert!(pos.iter().all(|v| v.is_finite()));
    assert_eq!(max_abs_diff(&pos, &good), 0.0, "the last good surface is returned");
    c.clear_jaw_transform().unwrap();
    c.step().unwrap();
    assert_ne!(FrameStatus::from_stats(&c.frame_stats().unwrap()), Some(FrameStatus::Diverged));
    c.set_weight_by_name("jawOpen", 1.05).unwrap(); // a capture overshoot: clamped
    assert_status(c.set_weight_by_name("jawOpen", 1.2), Status::InvalidArgument, "1.1");
}

#[test]
fn shared_rig_and_model_across_threads() {
    fn send_sync<T: Send + Sync>() {}
    fn send<T: Send>() {}
    send_sync::<Rig>();
    send_sync::<Model>();
    send::<Context>();

    let (rig, model) = (rig(), model());
    let handles: Vec<_> = [0.2f32, 0.6]
        .iter()
        .map(|&w| {
            let (rig, model) = (rig.clone(), model.clone());
            std::thread::spawn(move || {
                let mut c = Context::new(rig, model, &cpu()).unwrap();
                c.set_weight_by_name("jawOpen", w).unwrap();
                c.step().unwrap();
                let mut p = vec![0.0; c.position_len()];
                c.get_positions(&mut p).unwrap();
                (c, p)
            })
        })
        .collect();
    let results: Vec<_> = handles.into_iter().map(|h| h.join().unwrap()).collect();
    assert!(max_abs_diff(&results[0].1, &results[1].1) > 0.0);
    // A context moved back from its thread still works, and keeps its rig and
    // model alive after every other Arc is gone.
    drop(rig);
    drop(model);
    let (mut c, _) = results.into_iter().next().unwrap();
    c.step().unwrap();
    assert_eq!(c.frame_stats().unwrap().frame, 1);
}

#[test]
fn raw_null_handles() {
    // What safe Rust cannot express: NULL handles, checked by the library.
    unsafe {
        assert_eq!(sys::facesr_step(std::ptr::null_mut()), sys::FACESR_ERROR_NULL_ARGUMENT);
        let mut xyz = [0.0f32; 3];
        assert_eq!(sys::facesr_get_positions(std::ptr::null(), xyz.as_mut_ptr(), 3), sys::FACESR_ERROR_NULL_ARGUMENT);
        let mut out = std::ptr::null_mut();
        assert_eq!(sys::facesr_rig_load(std::ptr::null(), &mut out), sys::FACESR_ERROR_NULL_ARGUMENT);
        assert!(out.is_null());
        sys::facesr_rig_free(std::ptr::null_mut());
        sys::facesr_model_free(std::ptr::null_mut());
        sys::facesr_context_destroy(std::ptr::null_mut());
    }
}
