//! The immutable rig and model.
use crate::error::{check, count, with_c_str, Error, Result, Status};
use facesr_sys as sys;
use std::ffi::CString;
use std::os::raw::c_char;
use std::path::Path;
use std::ptr::{self, NonNull};

/// What `facesr_rig_info` reports, read once at load.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigInfo {
    /// ARKit-named controls, in rig order.
    pub num_blendshapes: usize,
    /// M: vertices of the output face surface.
    pub num_surface_vertices: usize,
    pub num_surface_triangles: usize,
    /// N: nodes of the LR simulation lattice.
    pub num_lr_nodes: usize,
    pub num_muscles: usize,
    /// Identifies the rig; a model records the one it was trained on.
    pub checksum: u64,
    /// A point on the jaw hinge axis (cm).
    pub jaw_pivot: [f32; 3],
    /// Unit hinge axis; a positive angle opens the mouth.
    pub jaw_axis: [f32; 3],
}

/// A loaded rig (`facesr_rig`): the anatomy, the LR lattice and the output
/// surface's topology.
///
/// Immutable once loaded; facesr.h lets any number of contexts on any threads
/// share it, so it is `Send + Sync`. Wrap it in an `Arc` to make contexts.
pub struct Rig {
    raw: NonNull<sys::facesr_rig>,
    info: RigInfo,
    names: Vec<String>,
}

// SAFETY: facesr.h: "The rig and the model are immutable once loaded and may
// be shared by any number of contexts on any threads." Every function taking
// a rig takes it as `const facesr_rig*`, and freeing happens only in Drop,
// which has the rig to itself.
unsafe impl Send for Rig {}
unsafe impl Sync for Rig {}

/// A path as the C ABI's `const char*`. On Unix the bytes as they are; elsewhere
/// the path must be valid Unicode (it goes in as UTF-8).
pub(crate) fn path_c_string(path: &Path) -> Result<CString> {
    #[cfg(unix)]
    let bytes = {
        use std::os::unix::ffi::OsStrExt;
        path.as_os_str().as_bytes().to_vec()
    };
    #[cfg(not(unix))]
    let bytes = match path.to_str() {
        Some(s) => s.as_bytes().to_vec(),
        None => {
            return Err(Error::local(Status::InvalidArgument, format!("path {} is not valid Unicode", path.display())))
        }
    };
    CString::new(bytes).map_err(|_| Error::local(Status::InvalidArgument, "path contains a NUL byte".to_string()))
}

fn to_usize(v: i32) -> usize {
    // The library never reports negative counts.
    v.max(0) as usize
}

impl Rig {
    /// Loads and validates a rig file (from `facesr rig build`).
    pub fn load(path: impl AsRef<Path>) -> Result<Rig> {
        let c_path = path_c_string(path.as_ref())?;
        let mut raw = ptr::null_mut();
        check(unsafe { sys::facesr_rig_load(c_path.as_ptr(), &mut raw) })?;
        let raw = NonNull::new(raw)
            .ok_or_else(|| Error::local(Status::Internal, "facesr_rig_load returned OK and no rig".to_string()))?;
        // From here Drop frees the rig, whatever fails below.
        let mut rig = Rig {
            raw,
            info: RigInfo {
                num_blendshapes: 0,
                num_surface_vertices: 0,
                num_surface_triangles: 0,
                num_lr_nodes: 0,
                num_muscles: 0,
                checksum: 0,
                jaw_pivot: [0.0; 3],
                jaw_axis: [0.0; 3],
            },
            names: Vec::new(),
        };
        let mut info = sys::facesr_rig_info {
            struct_size: std::mem::size_of::<sys::facesr_rig_info>() as u32,
            ..Default::default()
        };
        check(unsafe { sys::facesr_rig_get_info(rig.as_ptr(), &mut info) })?;
        rig.info = RigInfo {
            num_blendshapes: to_usize(info.num_blendshapes),
            num_surface_vertices: to_usize(info.num_surface_vertices),
            num_surface_triangles: to_usize(info.num_surface_triangles),
            num_lr_nodes: to_usize(info.num_lr_nodes),
            num_muscles: to_usize(info.num_muscles),
            checksum: info.checksum,
            jaw_pivot: info.jaw_pivot,
            jaw_axis: info.jaw_axis,
        };
        for i in 0..info.num_blendshapes {
            rig.names.push(rig.read_name(i)?);
        }
        Ok(rig)
    }

    fn read_name(&self, index: i32) -> Result<String> {
        let mut len = 0i32;
        // The length first (buf_size 0), then the bytes and the NUL.
        check(unsafe { sys::facesr_rig_blendshape_name(self.as_ptr(), index, ptr::null_mut(), 0, &mut len) })?;
        let mut buf = vec![0u8; to_usize(len) + 1];
        check(unsafe {
            sys::facesr_rig_blendshape_name(
                self.as_ptr(),
                index,
                buf.as_mut_ptr() as *mut c_char,
                buf.len() as i32,
                &mut len,
            )
        })?;
        buf.truncate(to_usize(len));
        String::from_utf8(buf)
            .map_err(|_| Error::local(Status::Internal, format!("blendshape {index}'s name is not UTF-8")))
    }

    /// The raw handle, for `facesr_sys` calls. Valid while `self` lives.
    pub fn as_ptr(&self) -> *const sys::facesr_rig {
        self.raw.as_ptr()
    }

    pub fn info(&self) -> &RigInfo {
        &self.info
    }

    pub fn num_blendshapes(&self) -> usize {
        self.info.num_blendshapes
    }

    pub fn num_vertices(&self) -> usize {
        self.info.num_surface_vertices
    }

    pub fn num_triangles(&self) -> usize {
        self.info.num_surface_triangles
    }

    /// 3 × vertices: the length of a positions or normals buffer.
    pub fn position_len(&self) -> usize {
        3 * self.info.num_surface_vertices
    }

    pub fn checksum(&self) -> u64 {
        self.info.checksum
    }

    /// The blendshape names in rig order (case-sensitive ARKit names).
    pub fn blendshape_names(&self) -> &[String] {
        &self.names
    }

    /// Index of a blendshape by exact name (`Status::NotFound` if none).
    pub fn blendshape_index(&self, name: &str) -> Result<usize> {
        let mut index = -1i32;
        let status =
            with_c_str(name, "name", |n| unsafe { sys::facesr_rig_blendshape_index(self.as_ptr(), n, &mut index) })?;
        check(status)?;
        Ok(to_usize(index))
    }

    /// The surface's triangle indices, counter-clockwise seen from outside;
    /// `out.len()` must be 3 × triangles (else `Status::BufferSize`).
    pub fn get_triangles(&self, out: &mut [i32]) -> Result<()> {
        check(unsafe { sys::facesr_rig_get_triangles(self.as_ptr(), out.as_mut_ptr(), count(out.len())) })
    }

    pub fn triangles(&self) -> Result<Vec<i32>> {
        let mut t = vec![0; 3 * self.info.num_surface_triangles];
        self.get_triangles(&mut t)?;
        Ok(t)
    }

    /// Rest positions of the surface (cm); `out.len()` must be `position_len()`.
    pub fn get_rest_positions(&self, out: &mut [f32]) -> Result<()> {
        check(unsafe { sys::facesr_rig_get_rest_positions(self.as_ptr(), out.as_mut_ptr(), count(out.len())) })
    }

    pub fn rest_positions(&self) -> Result<Vec<f32>> {
        let mut v = vec![0.0; self.position_len()];
        self.get_rest_positions(&mut v)?;
        Ok(v)
    }
}

impl Drop for Rig {
    fn drop(&mut self) {
        unsafe { sys::facesr_rig_free(self.raw.as_ptr()) }
    }
}

impl std::fmt::Debug for Rig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Rig").field("info", &self.info).finish()
    }
}

/// What `facesr_model_info` reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModelInfo {
    /// The checksum of the rig it was trained on (`Rig::checksum`).
    pub rig_checksum: u64,
    pub num_lr_nodes: usize,
    pub num_surface_vertices: usize,
    /// Trainable scalars.
    pub num_parameters: usize,
}

/// A loaded super-resolution model (`facesr_model`). Immutable and shareable
/// like the rig: `Send + Sync`.
pub struct Model {
    raw: NonNull<sys::facesr_model>,
    info: ModelInfo,
}

// SAFETY: as for Rig: immutable once loaded, shareable across threads by
// facesr.h, freed only in Drop.
unsafe impl Send for Model {}
unsafe impl Sync for Model {}

impl Model {
    /// Loads and validates a model file (from `facesr train`).
    pub fn load(path: impl AsRef<Path>) -> Result<Model> {
        let c_path = path_c_string(path.as_ref())?;
        let mut raw = ptr::null_mut();
        check(unsafe { sys::facesr_model_load(c_path.as_ptr(), &mut raw) })?;
        let raw = NonNull::new(raw)
            .ok_or_else(|| Error::local(Status::Internal, "facesr_model_load returned OK and no model".to_string()))?;
        let mut model = Model {
            raw,
            info: ModelInfo { rig_checksum: 0, num_lr_nodes: 0, num_surface_vertices: 0, num_parameters: 0 },
        };
        let mut info = sys::facesr_model_info {
            struct_size: std::mem::size_of::<sys::facesr_model_info>() as u32,
            ..Default::default()
        };
        check(unsafe { sys::facesr_model_get_info(model.as_ptr(), &mut info) })?;
        model.info = ModelInfo {
            rig_checksum: info.rig_checksum,
            num_lr_nodes: to_usize(info.num_lr_nodes),
            num_surface_vertices: to_usize(info.num_surface_vertices),
            num_parameters: to_usize(info.num_parameters),
        };
        Ok(model)
    }

    pub fn as_ptr(&self) -> *const sys::facesr_model {
        self.raw.as_ptr()
    }

    pub fn info(&self) -> &ModelInfo {
        &self.info
    }
}

impl Drop for Model {
    fn drop(&mut self) {
        unsafe { sys::facesr_model_free(self.raw.as_ptr()) }
    }
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Model").field("info", &self.info).finish()
    }
}
