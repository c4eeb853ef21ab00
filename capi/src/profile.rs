//! Profiles: loaded from bytes or a file, owned by the caller.

use std::ffi::{CStr, c_char};

use acuity::Profile;

use crate::error::{AcuityStatus, Failure, Result, borrow, check_out, guard, slice, write_out};
use crate::types::AcuityProfileInfo;

/// A profile (what the offline pass measured for one mesh), opaque. From
/// `acuity_profile_from_bytes` or `acuity_profile_load`; freed with
/// `acuity_profile_free`. Read-only once loaded: several threads may use
/// one at once.
pub struct AcuityProfile {
    pub(crate) profile: Profile,
}

fn hand_out(profile: Profile, out: *mut *mut AcuityProfile) -> Result<()> {
    let raw = Box::into_raw(Box::new(AcuityProfile { profile }));
    // SAFETY: `out` was checked non-NULL and aligned by `check_out` at the
    // start of the call; writable by the caller's contract.
    if let Err(e) = unsafe { write_out(out, "out", raw) } {
        // SAFETY: `raw` came from `Box::into_raw` just above and was not
        // handed out.
        drop(unsafe { Box::from_raw(raw) });
        return Err(e);
    }
    Ok(())
}

/// Decodes a profile from `len` bytes at `bytes`: the binary form (as
/// `acuity preprocess` writes `.acp` files) or JSON, told apart by the
/// binary form's magic bytes, and validates it. On success `*out` is a new
/// profile the caller frees with `acuity_profile_free`; on failure `*out`
/// is untouched. The bytes are not kept.
///
/// # Safety
/// `bytes` must be valid for reading `len` bytes (it may be NULL only when
/// `len` is 0); `out` must be NULL (refused) or valid for writing a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_profile_from_bytes(
    bytes: *const u8,
    len: usize,
    out: *mut *mut AcuityProfile,
) -> AcuityStatus {
    guard(|| {
        check_out(out, "out")?;
        // SAFETY: forwarded from this function's contract.
        let bytes = unsafe { slice(bytes, len, "bytes") }?;
        hand_out(Profile::from_bytes(bytes)?, out)
    })
}

/// Reads a profile file (binary or JSON) at `path`, a NUL-terminated path
/// (bytes on Unix, UTF-8 elsewhere), and validates it. On success `*out`
/// is a new profile the caller frees with `acuity_profile_free`; on
/// failure `*out` is untouched and the error names the file.
///
/// # Safety
/// `path` must be NULL (refused) or a NUL-terminated string; `out` must be
/// NULL (refused) or valid for writing a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_profile_load(
    path: *const c_char,
    out: *mut *mut AcuityProfile,
) -> AcuityStatus {
    guard(|| {
        check_out(out, "out")?;
        if path.is_null() {
            return Err(Failure::new(
                AcuityStatus::ACUITY_NULL_POINTER,
                "`path` is NULL",
            ));
        }
        // SAFETY: non-NULL (checked above) and NUL-terminated by the
        // caller's contract.
        let path = unsafe { CStr::from_ptr(path) };
        hand_out(Profile::load(to_path(path)?)?, out)
    })
}

#[cfg(unix)]
fn to_path(path: &CStr) -> Result<std::path::PathBuf> {
    use std::os::unix::ffi::OsStrExt;
    Ok(std::ffi::OsStr::from_bytes(path.to_bytes()).into())
}

#[cfg(not(unix))]
fn to_path(path: &CStr) -> Result<std::path::PathBuf> {
    path.to_str()
        .map(Into::into)
        .map_err(|e| Failure::invalid(format!("`path` is not UTF-8: {e}")))
}

/// Writes a summary of `profile` into `*out`.
///
/// # Safety
/// `profile` must be NULL (refused) or a live profile; `out` must be NULL
/// (refused) or valid for writing an `AcuityProfileInfo`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_profile_info(
    profile: *const AcuityProfile,
    out: *mut AcuityProfileInfo,
) -> AcuityStatus {
    guard(|| {
        // SAFETY: forwarded from this function's contract.
        let p = &unsafe { borrow(profile, "profile") }?.profile;
        let info = AcuityProfileInfo {
            lod_count: p.lod_count() as u32,
            finest_triangles: p.lod_triangles.first().copied().unwrap_or(0),
            coarsest_triangles: p.lod_triangles.last().copied().unwrap_or(0),
            viewpoint_count: p.viewpoints.len() as u32,
            bounding_radius: p.bounding_radius,
        };
        // SAFETY: forwarded from this function's contract.
        unsafe { write_out(out, "out", info) }
    })
}

/// Frees a profile. NULL does nothing. Selectors it was added to keep
/// their own copy and are unaffected.
///
/// # Safety
/// `profile` must be NULL or a profile from this library not freed yet,
/// and no other call may be using it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_profile_free(profile: *mut AcuityProfile) -> AcuityStatus {
    guard(|| {
        if !profile.is_null() {
            // SAFETY: from `Box::into_raw` in `hand_out` and not freed yet,
            // by the caller's contract.
            drop(unsafe { Box::from_raw(profile) });
        }
        Ok(())
    })
}
