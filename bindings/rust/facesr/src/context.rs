//! One face's mutable state, stepped every frame.
use crate::error::{check, count, index_i32, with_c_str, Error, Result, Status};
use crate::rig::{Model, Rig};
use facesr_sys as sys;
use std::ffi::CString;
use std::ptr::{self, NonNull};
use std::sync::{Arc, Mutex};

/// How the LR simulation is solved each frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Solver {
    /// At most 3 Newton steps of 60 CG iterations per frame (for games).
    #[default]
    Realtime,
    /// Newton to a 1e-3 relative residual (offline quality).
    Accurate,
}

/// The LR simulation's arithmetic (the inference is always float).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Precision {
    /// Float with the real-time solver, double with the accurate one.
    #[default]
    Auto,
    Double,
    Float,
}

/// Which implementation runs the super-resolution network.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Inference {
    /// The OpenCL kernels.
    #[default]
    OpenCl,
    /// The plain C++ reference (slow; for checks).
    Cpu,
}

/// What `facesr_context_def` holds. `Default` is the library's defaults.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ContextOptions {
    /// OpenCL device as listed by `facesr devices`; `None`: by name or default.
    pub device_index: Option<u32>,
    /// Case-insensitive substring of the device or platform name; `None`: the
    /// default (the first CPU device).
    pub device_name: Option<String>,
    pub solver: Solver,
    pub inference: Inference,
    /// Half the device's compute units each for the simulation and the
    /// inference (faster with `step_async` on a CPU, slower without).
    pub split_device: bool,
    pub lr_precision: Precision,
}

impl Default for ContextOptions {
    fn default() -> Self {
        ContextOptions {
            device_index: None,
            device_name: None,
            solver: Solver::Realtime,
            inference: Inference::OpenCl,
            split_device: false,
            lr_precision: Precision::Auto,
        }
    }
}

/// A spring pulling one surface vertex toward a target point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringDef {
    pub vertex: usize,
    /// cm, rest frame.
    pub target: [f32; 3],
    /// kPa·cm, > 0 (library default 100).
    pub stiffness: f32,
}

impl SpringDef {
    /// A spring on `vertex` toward `target` with the library's default stiffness.
    pub fn new(vertex: usize, target: [f32; 3]) -> SpringDef {
        let d = unsafe { sys::facesr_default_spring_def() };
        SpringDef { vertex, target, stiffness: d.stiffness }
    }
}

/// A kinematic sphere pushing the face away (penalty).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereDef {
    /// cm, rest frame.
    pub centre: [f32; 3],
    /// cm, > 0.
    pub radius: f32,
    /// kPa·cm, > 0 (library default 200).
    pub stiffness: f32,
}

impl SphereDef {
    /// A sphere at `centre` with the library's default stiffness.
    pub fn new(centre: [f32; 3], radius: f32) -> SphereDef {
        let d = unsafe { sys::facesr_default_sphere_def() };
        SphereDef { centre, radius, stiffness: d.stiffness }
    }
}

/// A spring's id within its context (positive, never reused).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SpringId(pub i32);

/// A sphere's id within its context (positive, never reused).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SphereId(pub i32);

/// Serializes `facesr_context_create` within the process. OpenCL drivers'
/// first queries are not always thread-safe (PoCL's device enumeration was
/// not: concurrent first calls crashed; the library now enumerates once under
/// its own lock). Safe Rust must not crash, so the bindings keep creating one
/// context at a time as a guard; everything else stays concurrent.
static CREATE_LOCK: Mutex<()> = Mutex::new(());

/// Timings and solver effort of the latest readable frame.
pub type FrameStats = sys::facesr_frame_stats;

/// What became of a frame's LR solve (`FACESR_FRAME_*`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FrameStatus {
    /// Reached the solver's tolerance.
    Converged,
    /// Stopped at the iteration cap above tolerance (normal for the real-time preset).
    Unconverged,
    /// Diverged at first, solved by the recovery.
    Recovered,
    /// Recovery failed: the last good surface was returned.
    Diverged,
}

impl FrameStatus {
    /// The status of `stats.simulation_status`; `None` for a value this crate does not know.
    pub fn from_stats(stats: &FrameStats) -> Option<FrameStatus> {
        match stats.simulation_status {
            sys::FACESR_FRAME_CONVERGED => Some(FrameStatus::Converged),
            sys::FACESR_FRAME_UNCONVERGED => Some(FrameStatus::Unconverged),
            sys::FACESR_FRAME_RECOVERED => Some(FrameStatus::Recovered),
            sys::FACESR_FRAME_DIVERGED => Some(FrameStatus::Diverged),
            _ => None,
        }
    }
}

/// One face's mutable state (`facesr_context`).
///
/// Ownership: a context holds `Arc` clones of its rig and model, so it is
/// `'static` (it can live in a game engine's component or move to a worker
/// thread) and the rig and model are freed only after the last context made
/// from them, as facesr.h requires. (The alternative, borrowing them with a
/// lifetime, would tie every context to a stack frame.)
///
/// Threading: facesr.h allows one thread at a time per context, so it is
/// `Send` (move it to another thread) but not `Sync` (no `&Context` on two
/// threads at once: even the read-only calls must not overlap a step). The
/// controls and stepping take `&mut self`; the read-backs take `&self`.
/// `step_async` runs the frame on the context's own worker threads; `wait`
/// is called from the owning thread as usual.
///
/// The per-frame calls allocate nothing: buffers are the caller's slices,
/// names up to 127 bytes are copied to the stack.
///
/// ```compile_fail
/// fn shared<T: Sync>() {}
/// shared::<facesr::Context>(); // a context is not Sync
/// ```
pub struct Context {
    raw: NonNull<sys::facesr_context>,
    rig: Arc<Rig>,
    model: Arc<Model>,
}

// SAFETY: facesr.h: "use each context from one thread at a time". Moving the
// context to another thread is that; the library's worker threads are its
// own business (it joins them in facesr_context_destroy). Not Sync: see above.
unsafe impl Send for Context {}

impl Context {
    /// Creates a context for one face. The model must have been trained on
    /// this rig (`Status::Mismatch` otherwise).
    pub fn new(rig: Arc<Rig>, model: Arc<Model>, options: &ContextOptions) -> Result<Context> {
        let mut def = unsafe { sys::facesr_default_context_def() };
        if let Some(i) = options.device_index {
            def.device_index = index_i32(i as usize, "device_index")?;
        }
        def.solver = match options.solver {
            Solver::Realtime => sys::FACESR_SOLVER_REALTIME,
            Solver::Accurate => sys::FACESR_SOLVER_ACCURATE,
        };
        def.inference = match options.inference {
            Inference::OpenCl => sys::FACESR_INFERENCE_OPENCL,
            Inference::Cpu => sys::FACESR_INFERENCE_CPU,
        };
        def.split_device = i32::from(options.split_device);
        def.lr_precision = match options.lr_precision {
            Precision::Auto => sys::FACESR_PRECISION_AUTO,
            Precision::Double => sys::FACESR_PRECISION_DOUBLE,
            Precision::Float => sys::FACESR_PRECISION_FLOAT,
        };
        // Lives until facesr_context_create returns (the library copies it).
        let name = match &options.device_name {
            Some(n) => Some(
                CString::new(n.as_str())
                    .map_err(|_| Error::local(Status::InvalidArgument, "device_name contains a NUL byte".into()))?,
            ),
            None => None,
        };
        if let Some(n) = &name {
            def.device_name = n.as_ptr();
        }
        let mut raw = ptr::null_mut();
        let status = {
            // Tolerates a poisoned lock: it guards no data, only the call.
            let _one_at_a_time = CREATE_LOCK.lock().unwrap_or_else(|p| p.into_inner());
            unsafe { sys::facesr_context_create(rig.as_ptr(), model.as_ptr(), &def, &mut raw) }
        };
        check(status)?;
        let raw = NonNull::new(raw).ok_or_else(|| {
            Error::local(Status::Internal, "facesr_context_create returned OK and no context".to_string())
        })?;
        Ok(Context { raw, rig, model })
    }

    /// The raw handle, for `facesr_sys` calls (which must respect `&mut` for
    /// anything that changes the context). Valid while `self` lives.
    pub fn as_ptr(&self) -> *const sys::facesr_context {
        self.raw.as_ptr()
    }

    pub fn as_mut_ptr(&mut self) -> *mut sys::facesr_context {
        self.raw.as_ptr()
    }

    pub fn rig(&self) -> &Arc<Rig> {
        &self.rig
    }

    pub fn model(&self) -> &Arc<Model> {
        &self.model
    }

    /// 3 × vertices: the length of a positions or normals buffer.
    pub fn position_len(&self) -> usize {
        self.rig.position_len()
    }

    /// Back to the rest pose: controls cleared, springs and spheres removed,
    /// pending frames dropped.
    pub fn reset(&mut self) -> Result<()> {
        check(unsafe { sys::facesr_context_reset(self.as_mut_ptr()) })
    }

    // Controls take effect at the next step / step_async.

    /// Weight in [0, 1] of the blendshape at `index` (rig order).
    pub fn set_weight(&mut self, index: usize, value: f32) -> Result<()> {
        let i = index_i32(index, "blendshape index")?;
        check(unsafe { sys::facesr_set_weight(self.as_mut_ptr(), i, value) })
    }

    /// By exact (case-sensitive ARKit) name, e.g. `"jawOpen"`.
    pub fn set_weight_by_name(&mut self, name: &str, value: f32) -> Result<()> {
        let raw = self.as_mut_ptr();
        check(with_c_str(name, "name", |n| unsafe { sys::facesr_set_weight_by_name(raw, n, value) })?)
    }

    /// All weights at once: `weights.len()` must be the rig's blendshape count.
    /// Nothing changes if any value is bad.
    pub fn set_weights(&mut self, weights: &[f32]) -> Result<()> {
        check(unsafe { sys::facesr_set_weights(self.as_mut_ptr(), weights.as_ptr(), count(weights.len())) })
    }

    /// Explicit rigid jaw motion x' = R x + t: `rotation` row-major (a proper
    /// rotation), `translation` in cm. Replaces the jaw blendshapes' motion.
    pub fn set_jaw_transform(&mut self, rotation: &[f32; 9], translation: &[f32; 3]) -> Result<()> {
        check(unsafe { sys::facesr_set_jaw_transform(self.as_mut_ptr(), rotation.as_ptr(), translation.as_ptr()) })
    }

    /// The jaw follows the blendshape weights again.
    pub fn clear_jaw_transform(&mut self) -> Result<()> {
        check(unsafe { sys::facesr_clear_jaw_transform(self.as_mut_ptr()) })
    }

    pub fn add_spring(&mut self, spring: &SpringDef) -> Result<SpringId> {
        let mut def = unsafe { sys::facesr_default_spring_def() };
        def.vertex = index_i32(spring.vertex, "spring vertex")?;
        def.target = spring.target;
        def.stiffness = spring.stiffness;
        let mut id = 0;
        check(unsafe { sys::facesr_add_spring(self.as_mut_ptr(), &def, &mut id) })?;
        Ok(SpringId(id))
    }

    pub fn move_spring(&mut self, id: SpringId, target: [f32; 3]) -> Result<()> {
        check(unsafe { sys::facesr_move_spring(self.as_mut_ptr(), id.0, target.as_ptr()) })
    }

    pub fn remove_spring(&mut self, id: SpringId) -> Result<()> {
        check(unsafe { sys::facesr_remove_spring(self.as_mut_ptr(), id.0) })
    }

    pub fn add_sphere(&mut self, sphere: &SphereDef) -> Result<SphereId> {
        let mut def = unsafe { sys::facesr_default_sphere_def() };
        def.centre = sphere.centre;
        def.radius = sphere.radius;
        def.stiffness = sphere.stiffness;
        let mut id = 0;
        check(unsafe { sys::facesr_add_sphere(self.as_mut_ptr(), &def, &mut id) })?;
        Ok(SphereId(id))
    }

    pub fn move_sphere(&mut self, id: SphereId, centre: [f32; 3]) -> Result<()> {
        check(unsafe { sys::facesr_move_sphere(self.as_mut_ptr(), id.0, centre.as_ptr()) })
    }

    pub fn remove_sphere(&mut self, id: SphereId) -> Result<()> {
        check(unsafe { sys::facesr_remove_sphere(self.as_mut_ptr(), id.0) })
    }

    // Stepping.

    /// Simulates one frame and super-resolves it; the results are readable
    /// on return. `Status::State` while asynchronous frames are pending.
    pub fn step(&mut self) -> Result<()> {
        check(unsafe { sys::facesr_step(self.as_mut_ptr()) })
    }

    /// Queues a frame with the current controls (copied) and returns at once;
    /// at most 2 pending (`Status::State` beyond). `wait` returns them in
    /// order; their surfaces equal `step`'s for the same controls.
    pub fn step_async(&mut self) -> Result<()> {
        check(unsafe { sys::facesr_step_async(self.as_mut_ptr()) })
    }

    /// Blocks for the oldest pending frame, makes it the readable one and
    /// returns its frame number. `Status::State` when nothing is pending.
    pub fn wait(&mut self) -> Result<i64> {
        let mut frame = -1i64;
        check(unsafe { sys::facesr_wait(self.as_mut_ptr(), &mut frame) })?;
        Ok(frame)
    }

    /// Frames queued by `step_async` and not yet returned by `wait`.
    pub fn pending_frames(&self) -> Result<usize> {
        let mut n = 0i32;
        check(unsafe { sys::facesr_pending_frames(self.as_ptr(), &mut n) })?;
        Ok(n.max(0) as usize)
    }

    // Read-back of the latest readable frame (before the first step: the rest
    // pose). Each slice must hold exactly `position_len()` floats, else
    // `Status::BufferSize` (the message gives the required count).

    /// Super-resolved surface positions (cm).
    pub fn get_positions(&self, xyz: &mut [f32]) -> Result<()> {
        check(unsafe { sys::facesr_get_positions(self.as_ptr(), xyz.as_mut_ptr(), count(xyz.len())) })
    }

    /// Unit area-weighted vertex normals of that surface.
    pub fn get_normals(&self, xyz: &mut [f32]) -> Result<()> {
        check(unsafe { sys::facesr_get_normals(self.as_ptr(), xyz.as_mut_ptr(), count(xyz.len())) })
    }

    /// The surface carried by the LR lattice alone (no super-resolution).
    pub fn get_embedded_positions(&self, xyz: &mut [f32]) -> Result<()> {
        check(unsafe { sys::facesr_get_embedded_positions(self.as_ptr(), xyz.as_mut_ptr(), count(xyz.len())) })
    }

    pub fn frame_stats(&self) -> Result<FrameStats> {
        let mut stats = FrameStats { struct_size: std::mem::size_of::<FrameStats>() as u32, ..Default::default() };
        check(unsafe { sys::facesr_get_frame_stats(self.as_ptr(), &mut stats) })?;
        Ok(stats)
    }
}

impl Drop for Context {
    /// Waits for pending frames, then frees the context; the rig and model go
    /// when their last `Arc` does.
    fn drop(&mut self) {
        unsafe { sys::facesr_context_destroy(self.raw.as_ptr()) }
    }
}

impl std::fmt::Debug for Context {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Context").field("rig", &self.rig).field("model", &self.model).finish()
    }
}
