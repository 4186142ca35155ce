//! The declarations link and run: the smallest end-to-end check (the facesr
//! crate's tests cover the behaviour). An integration test rather than a unit
//! test so that build.rs can give it an rpath to libfacesr.
use facesr_sys::*;

use std::ffi::CStr;

#[test]
fn abi_version_and_status_names() {
    unsafe {
        assert_eq!(facesr_abi_version(), FACESR_ABI_VERSION);
        let name = CStr::from_ptr(facesr_status_name(FACESR_ERROR_BUFFER_SIZE));
        assert_eq!(name.to_str().unwrap(), "FACESR_ERROR_BUFFER_SIZE");
        let version = CStr::from_ptr(facesr_version_string());
        assert!(version.to_str().unwrap().starts_with("facesr "));
    }
}

#[test]
fn defaults_come_back_by_value() {
    unsafe {
        let d = facesr_default_context_def();
        assert_eq!(d.struct_size as usize, std::mem::size_of::<facesr_context_def>());
        assert_eq!(d.device_index, -1);
        assert!(d.device_name.is_null());
        let s = facesr_default_spring_def();
        assert_eq!(s.struct_size as usize, std::mem::size_of::<facesr_spring_def>());
        assert_eq!(s.vertex, -1);
        assert_eq!(s.stiffness, 100.0);
        let p = facesr_default_sphere_def();
        assert_eq!(p.radius, 1.0);
        assert_eq!(p.stiffness, 200.0);
    }
}
