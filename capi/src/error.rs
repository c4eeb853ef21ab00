//! Status codes, the per-thread last error, and the guard every entry
//! point runs its body in (panics caught, pointers checked).

use std::cell::RefCell;
use std::ffi::{CString, c_char};
use std::panic::{AssertUnwindSafe, catch_unwind};

/// What a call did: `ACUITY_OK` (0) or why it failed;
/// `acuity_last_error` has the details. New codes may be added; treat an
/// unknown non-zero code as a failure.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[allow(non_camel_case_types)]
pub enum AcuityStatus {
    /// Success.
    ACUITY_OK = 0,
    /// A required pointer was NULL (or misaligned for its type).
    ACUITY_NULL_POINTER = 1,
    /// A number outside its documented domain (NaN, infinite, negative
    /// where it must not be, an empty LOD range, an unknown tracker), or a
    /// path that is not valid text on this platform.
    ACUITY_INVALID_ARGUMENT = 2,
    /// An object handle that is not (or no longer) in this selector.
    ACUITY_UNKNOWN_OBJECT = 3,
    /// A profile index not returned by `acuity_selector_add_profile` of
    /// this selector.
    ACUITY_UNKNOWN_PROFILE = 4,
    /// Profile bytes that cannot be decoded: truncated, corrupt (the binary
    /// form's checksum), or not JSON.
    ACUITY_PROFILE_FORMAT = 5,
    /// A profile that decodes but breaks a rule of the format.
    ACUITY_PROFILE_INVALID = 6,
    /// A profile written by a format version this build cannot read
    /// (regenerate it with `acuity preprocess --force`).
    ACUITY_PROFILE_VERSION = 7,
    /// Reading a file failed (missing, unreadable, not a regular file,
    /// too large).
    ACUITY_IO = 8,
    /// An output array was too small; the count written says how many
    /// entries there are.
    ACUITY_BUFFER_TOO_SMALL = 9,
    /// The library caught an internal panic (a bug: please report the
    /// message). A selector it happened in refuses further calls.
    ACUITY_PANIC = 10,
    /// An error of the runtime with no code of its own.
    ACUITY_ERROR = 11,
}

/// A failed call: its status and message.
#[derive(Debug)]
pub(crate) struct Failure {
    pub(crate) status: AcuityStatus,
    pub(crate) message: String,
}

impl Failure {
    pub(crate) fn new(status: AcuityStatus, message: impl Into<String>) -> Self {
        Self {
            status,
            message: message.into(),
        }
    }

    pub(crate) fn invalid(message: impl Into<String>) -> Self {
        Self::new(AcuityStatus::ACUITY_INVALID_ARGUMENT, message)
    }
}

impl From<acuity::Error> for Failure {
    fn from(e: acuity::Error) -> Self {
        use AcuityStatus::*;
        let status = match &e {
            acuity::Error::InvalidParameter { .. } => ACUITY_INVALID_ARGUMENT,
            acuity::Error::ProfileFormat { .. } => ACUITY_PROFILE_FORMAT,
            acuity::Error::ProfileInvalid { .. } => ACUITY_PROFILE_INVALID,
            acuity::Error::ProfileVersion { .. } => ACUITY_PROFILE_VERSION,
            acuity::Error::Io { .. } => ACUITY_IO,
            _ => ACUITY_ERROR,
        };
        Self::new(status, e.to_string())
    }
}

pub(crate) type Result<T, E = Failure> = std::result::Result<T, E>;

thread_local! {
    /// The message of the last call on this thread ("" after a success).
    static LAST_ERROR: RefCell<CString> = RefCell::new(CString::default());
}

fn set_last_error(message: &str) {
    // Interior NULs would cut the C string short; show them instead.
    let text = CString::new(message.replace('\0', "\\0")).unwrap_or_default();
    let _ = LAST_ERROR.try_with(|e| *e.borrow_mut() = text);
}

fn clear_last_error() {
    let _ = LAST_ERROR.try_with(|e| {
        if !e.borrow().is_empty() {
            *e.borrow_mut() = CString::default();
        }
    });
}

/// The message of the last call made on the calling thread: why it failed,
/// or "" when it succeeded. Never NULL. The string belongs to the library
/// and stays valid until the next call of an `acuity_*` function on the
/// same thread (other threads' calls do not touch it); copy it to keep it.
#[unsafe(no_mangle)]
pub extern "C" fn acuity_last_error() -> *const c_char {
    LAST_ERROR
        .try_with(|e| e.borrow().as_ptr())
        .unwrap_or(c"".as_ptr())
}

/// This library's version, as "major.minor.patch". Never NULL; static.
#[unsafe(no_mangle)]
pub extern "C" fn acuity_version() -> *const c_char {
    const VERSION: &str = concat!(env!("CARGO_PKG_VERSION"), "\0");
    VERSION.as_ptr().cast()
}

/// Runs an entry point's body: clears the last error, catches any panic,
/// and turns a failure into its status and message.
pub(crate) fn guard(body: impl FnOnce() -> Result<()>) -> AcuityStatus {
    clear_last_error();
    let outcome = catch_unwind(AssertUnwindSafe(body)).unwrap_or_else(|payload| {
        Err(Failure::new(
            AcuityStatus::ACUITY_PANIC,
            format!("internal panic: {}", panic_message(&*payload)),
        ))
    });
    match outcome {
        Ok(()) => AcuityStatus::ACUITY_OK,
        Err(failure) => {
            set_last_error(&failure.message);
            failure.status
        }
    }
}

pub(crate) fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "(no message)".to_owned()
    }
}

fn null(name: &str) -> Failure {
    Failure::new(
        AcuityStatus::ACUITY_NULL_POINTER,
        format!("`{name}` is NULL or misaligned"),
    )
}

/// Borrows what a caller's pointer points to, for the call.
///
/// # Safety
/// A non-NULL, aligned `ptr` must point to a valid, initialised `T` that
/// nothing mutates for `'a` (the C API's documented contract).
pub(crate) unsafe fn borrow<'a, T>(ptr: *const T, name: &str) -> Result<&'a T> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(null(name));
    }
    // SAFETY: non-NULL and aligned, checked above; valid by the caller's
    // contract.
    Ok(unsafe { &*ptr })
}

/// Borrows mutably what a caller's pointer points to, for the call.
///
/// # Safety
/// A non-NULL, aligned `ptr` must point to a valid `T` that nothing else
/// reads or writes for `'a`.
pub(crate) unsafe fn borrow_mut<'a, T>(ptr: *mut T, name: &str) -> Result<&'a mut T> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(null(name));
    }
    // SAFETY: non-NULL and aligned, checked above; exclusive and valid by
    // the caller's contract.
    Ok(unsafe { &mut *ptr })
}

/// Writes an out-parameter.
///
/// # Safety
/// A non-NULL, aligned `ptr` must be valid for writing a `T`.
pub(crate) unsafe fn write_out<T>(ptr: *mut T, name: &str, value: T) -> Result<()> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(null(name));
    }
    // SAFETY: non-NULL and aligned, checked above; writable by the
    // caller's contract. `write` does not drop the old (maybe
    // uninitialised) value.
    unsafe { ptr.write(value) };
    Ok(())
}

/// Checks an out-parameter before any work is done, so that a NULL one
/// fails the call without side effects.
pub(crate) fn check_out<T>(ptr: *mut T, name: &str) -> Result<()> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(null(name));
    }
    Ok(())
}

/// Borrows a caller's array of `len` items; NULL is allowed when `len` is 0.
///
/// # Safety
/// A non-NULL `ptr` must point to `len` valid, initialised `T`s that
/// nothing mutates for `'a`.
pub(crate) unsafe fn slice<'a, T>(ptr: *const T, len: usize, name: &str) -> Result<&'a [T]> {
    if len == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(null(name));
    }
    if len
        .checked_mul(size_of::<T>())
        .is_none_or(|b| b > isize::MAX as usize)
    {
        return Err(Failure::invalid(format!(
            "`{name}`: {len} items is too many"
        )));
    }
    // SAFETY: non-NULL, aligned, size in range (checked above); `len`
    // valid items by the caller's contract.
    Ok(unsafe { std::slice::from_raw_parts(ptr, len) })
}

/// A caller's output array of `len` items, written item by item (never
/// read, so it may be uninitialised memory).
pub(crate) struct OutArray<T> {
    ptr: *mut T,
    len: usize,
}

impl<T> OutArray<T> {
    /// Checks a caller's output array; NULL is allowed when `len` is 0.
    ///
    /// # Safety
    /// A non-NULL `ptr` must be valid for writing `len` items, and used by
    /// nothing else while the `OutArray` lives (within one call).
    pub(crate) unsafe fn new(ptr: *mut T, len: usize, name: &str) -> Result<Self> {
        if len > 0 && (ptr.is_null() || !ptr.is_aligned()) {
            return Err(null(name));
        }
        Ok(Self { ptr, len })
    }

    /// How many items fit.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    /// Writes item `i`; `i` past the end is ignored.
    pub(crate) fn set(&mut self, i: usize, value: T) {
        if i < self.len {
            // SAFETY: `i < len`, and `ptr` is non-NULL, aligned (checked
            // in `new`) and valid for `len` writes by `new`'s contract;
            // `write` reads and drops nothing there.
            unsafe { self.ptr.add(i).write(value) };
        }
    }
}

/// Refuses NaN, infinities and values below 0, naming `name`.
pub(crate) fn non_negative(value: f32, name: &str) -> Result<f32> {
    let value = finite(value, name)?;
    if value < 0.0 {
        return Err(Failure::invalid(format!(
            "`{name}` is {value}; it must be >= 0"
        )));
    }
    Ok(value)
}

/// Refuses NaN and infinities.
pub(crate) fn finite(value: f32, name: &str) -> Result<f32> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Failure::invalid(format!(
            "`{name}` is {value}; it must be finite"
        )))
    }
}
