//! Safe Rust API of the facesr runtime: a cheap muscle simulation on a
//! coarse lattice, and the learned super-resolution network that infers the
//! high-resolution face surface from it (libfacesr, `capi/facesr.h`).
//!
//! ```no_run
//! use std::sync::Arc;
//! use facesr::{Context, ContextOptions, Model, Rig};
//!
//! # fn main() -> Result<(), facesr::Error> {
//! let rig = Arc::new(Rig::load("face.rig")?);
//! let model = Arc::new(Model::load("face.fsm")?);
//! let mut face = Context::new(rig.clone(), model, &ContextOptions::default())?;
//! let mut xyz = vec![0.0f32; rig.position_len()];
//! for frame in 0..30 {
//!     face.set_weight_by_name("jawOpen", frame as f32 / 30.0)?;
//!     face.step()?;
//!     face.get_positions(&mut xyz)?; // cm, rig rest frame
//! }
//! # Ok(())
//! # }
//! ```
//!
//! - [`Rig`] and [`Model`] are immutable: `Send + Sync`, shared through `Arc`.
//! - [`Context`] is one face: `Send`, not `Sync`; it holds `Arc`s of its rig
//!   and model, so they outlive it.
//! - Every fallible call returns [`Result`]; [`Error`] carries the
//!   [`Status`] and the engine's message. A failed call changes nothing.
//! - Units: cm, kPa·cm, ms. Positions are in the rig's rest frame (+y up,
//!   +z out of the face; right-handed).
//!
//! Linking: facesr-sys links `libfacesr` from `FACESR_LIB_DIR` (default:
//! the repository's `build/lib`); at run time the library must be on the
//! loader path (`LD_LIBRARY_PATH`, or beside the executable with an rpath of
//! `$ORIGIN`).

mod context;
mod error;
mod rig;

pub use context::{Context, ContextOptions, FrameStats, FrameStatus, Inference, Precision, Solver, SphereDef, SphereId, SpringDef, SpringId};
pub use error::{Error, Result, Status};
pub use facesr_sys as sys;
pub use rig::{Model, ModelInfo, Rig, RigInfo};

/// `FACESR_ABI_VERSION` of the loaded library.
pub fn abi_version() -> u32 {
    unsafe { sys::facesr_abi_version() }
}

/// `"facesr 0.1.0"`.
pub fn version_string() -> &'static str {
    unsafe { error::static_str(sys::facesr_version_string()) }
}

/// Fails if the loaded library was built for another ABI than these bindings.
pub fn ensure_compatible() -> Result<()> {
    let abi = abi_version();
    if abi != sys::FACESR_ABI_VERSION {
        return Err(Error::local(
            Status::Internal,
            format!("libfacesr has ABI {abi}; these bindings are for ABI {}", sys::FACESR_ABI_VERSION),
        ));
    }
    Ok(())
}
