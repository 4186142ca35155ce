//! Statuses as `Result`s, and strings across the boundary.
use facesr_sys as sys;
use std::ffi::CStr;
use std::fmt;
use std::os::raw::c_char;

/// A failed status of the C ABI (`facesr_status` other than `FACESR_OK`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// A required pointer or handle is NULL.
    NullArgument,
    /// NaN, out of range, unknown spring/sphere id, bad `struct_size`, bad enum.
    InvalidArgument,
    /// A buffer's element count is not the required one (the message gives it).
    BufferSize,
    /// Missing, unreadable, truncated, corrupt or malformed file.
    File,
    /// The model was trained on another rig.
    Mismatch,
    /// No such OpenCL device, or the device failed.
    Device,
    /// No blendshape of that name.
    NotFound,
    /// Not possible now (e.g. `wait` with nothing pending).
    State,
    /// The simulation failed on this frame (state kept).
    Simulation,
    /// A bug in the library: please report the message.
    Internal,
    /// A code this version of the bindings does not know (a newer library).
    Unknown(i32),
}

impl Status {
    /// The status of a raw code; `None` for `FACESR_OK`.
    pub fn from_code(code: sys::facesr_status) -> Option<Status> {
        Some(match code {
            sys::FACESR_OK => return None,
            sys::FACESR_ERROR_NULL_ARGUMENT => Status::NullArgument,
            sys::FACESR_ERROR_INVALID_ARGUMENT => Status::InvalidArgument,
            sys::FACESR_ERROR_BUFFER_SIZE => Status::BufferSize,
            sys::FACESR_ERROR_FILE => Status::File,
            sys::FACESR_ERROR_MISMATCH => Status::Mismatch,
            sys::FACESR_ERROR_DEVICE => Status::Device,
            sys::FACESR_ERROR_NOT_FOUND => Status::NotFound,
            sys::FACESR_ERROR_STATE => Status::State,
            sys::FACESR_ERROR_SIMULATION => Status::Simulation,
            sys::FACESR_ERROR_INTERNAL => Status::Internal,
            other => Status::Unknown(other),
        })
    }

    /// The raw `facesr_status` code.
    pub fn code(self) -> sys::facesr_status {
        match self {
            Status::NullArgument => sys::FACESR_ERROR_NULL_ARGUMENT,
            Status::InvalidArgument => sys::FACESR_ERROR_INVALID_ARGUMENT,
            Status::BufferSize => sys::FACESR_ERROR_BUFFER_SIZE,
            Status::File => sys::FACESR_ERROR_FILE,
            Status::Mismatch => sys::FACESR_ERROR_MISMATCH,
            Status::Device => sys::FACESR_ERROR_DEVICE,
            Status::NotFound => sys::FACESR_ERROR_NOT_FOUND,
            Status::State => sys::FACESR_ERROR_STATE,
            Status::Simulation => sys::FACESR_ERROR_SIMULATION,
            Status::Internal => sys::FACESR_ERROR_INTERNAL,
            Status::Unknown(c) => c,
        }
    }

    /// `"FACESR_ERROR_BUFFER_SIZE"`, ... (`facesr_status_name`).
    pub fn name(self) -> &'static str {
        // Static storage in the library, for any code.
        unsafe { static_str(sys::facesr_status_name(self.code())) }
    }
}

/// A failed call: its status and the engine's message, e.g.
/// `facesr_get_positions: xyz has 10 elements; 2610 (3 * num_surface_vertices) are required`.
/// The object the call was made on is unchanged and still usable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Error {
    status: Status,
    message: String,
}

impl Error {
    pub fn status(&self) -> Status {
        self.status
    }

    /// The engine's message (or the bindings', for a check made on this side,
    /// which then starts with "facesr (rust):").
    pub fn message(&self) -> &str {
        &self.message
    }

    /// An error found by the bindings before calling the library, with the
    /// status the library would give.
    pub(crate) fn local(status: Status, message: String) -> Error {
        Error { status, message: format!("facesr (rust): {message}") }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.status.name(), self.message)
    }
}

impl std::error::Error for Error {}

pub type Result<T> = std::result::Result<T, Error>;

/// `Ok` for `FACESR_OK`, else the status with this thread's last error
/// message. Must run on the thread that made the call, right after it (the
/// message is per thread): every caller here does.
pub(crate) fn check(code: sys::facesr_status) -> Result<()> {
    match Status::from_code(code) {
        None => Ok(()),
        Some(status) => {
            let message = unsafe { CStr::from_ptr(sys::facesr_last_error_message()) }.to_string_lossy().into_owned();
            Err(Error { status, message })
        }
    }
}

/// A string in static storage of the library.
pub(crate) unsafe fn static_str(p: *const c_char) -> &'static str {
    if p.is_null() {
        return "";
    }
    CStr::from_ptr(p).to_str().unwrap_or("")
}

/// Runs `f` with `s` as a NUL-terminated C string. Short strings (names) are
/// copied to the stack, so setting weights by name every frame does not
/// allocate.
pub(crate) fn with_c_str<R>(s: &str, what: &str, f: impl FnOnce(*const c_char) -> R) -> Result<R> {
    if s.as_bytes().contains(&0) {
        return Err(Error::local(Status::InvalidArgument, format!("{what} contains a NUL byte")));
    }
    let mut buf = [0u8; 128];
    if s.len() < buf.len() {
        buf[..s.len()].copy_from_slice(s.as_bytes());
        return Ok(f(buf.as_ptr() as *const c_char));
    }
    let owned = std::ffi::CString::new(s).expect("checked for NUL bytes above");
    Ok(f(owned.as_ptr()))
}

/// An element count as the C ABI's int64_t.
pub(crate) fn count(len: usize) -> i64 {
    // Slices never exceed isize::MAX elements.
    len as i64
}

/// A usize index as the C ABI's int32_t.
pub(crate) fn index_i32(i: usize, what: &str) -> Result<i32> {
    if i > i32::MAX as usize {
        return Err(Error::local(Status::InvalidArgument, format!("{what} {i} does not fit in int32_t")));
    }
    Ok(i as i32)
}
