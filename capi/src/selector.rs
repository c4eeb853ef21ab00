//! The selector: objects under stable handles, one selection a frame.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};

use acuity::glam::Quat;
use acuity::{
    Camera, Display, FrameInput, Gaze, ObjectDesc, ObjectId, ProfileId, Selection, Selector,
    Tracker,
};

use crate::error::{
    AcuityStatus, Failure, OutArray, Result, borrow, borrow_mut, check_out, finite, guard,
    non_negative, slice, write_out,
};
use crate::profile::AcuityProfile;
use crate::types::{
    ACUITY_LOD_CULLED, ACUITY_NO_BUDGET, ACUITY_NO_OBJECT, ACUITY_TRACKER_EYE, ACUITY_TRACKER_HEAD,
    ACUITY_TRACKER_NONE, AcuityChange, AcuityDisplay, AcuityFade, AcuityFrame, AcuityObject,
    AcuityObjectDesc, AcuityQuat, AcuitySettings, AcuityStats, AcuityVec3d,
};

/// A selector: a display, the profiles added to it, its objects, and each
/// object's selection from the last frame. Opaque; from
/// `acuity_selector_new`, freed with `acuity_selector_free`. Not
/// thread-safe: one thread at a time (use a lock to share one).
pub struct AcuitySelector {
    inner: Selector,
    /// The global scale `s` of the frames, in (0, 1].
    scale: f32,
    /// The frames' triangle budget, if any (`acuity_selector_set_budget`).
    budget: Option<u64>,
    /// Profile indices handed out -> the runtime's ids.
    profiles: Vec<ProfileId>,
    /// Object handles: `(generation << 32) | (entry + 1)`.
    entries: Vec<Entry>,
    free_entries: Vec<u32>,
    /// The runtime's ids -> entries, for the change list and fades.
    entry_of: HashMap<ObjectId, u32>,
    /// Set when a panic went through a call: the state may be torn.
    poisoned: bool,
}

#[derive(Clone, Copy)]
struct Entry {
    generation: u32,
    id: Option<ObjectId>,
}

fn handle(entry: u32, generation: u32) -> AcuityObject {
    (u64::from(generation) << 32) | (u64::from(entry) + 1)
}

fn lod_of(selection: Selection) -> u8 {
    selection.lod().map_or(ACUITY_LOD_CULLED, |l| l as u8)
}

impl AcuitySelector {
    fn id(&self, object: AcuityObject) -> Result<ObjectId> {
        let low = object as u32;
        let entry = low.wrapping_sub(1) as usize;
        match self.entries.get(entry) {
            Some(e) if low != 0 && e.generation == (object >> 32) as u32 => e.id,
            _ => None,
        }
        .ok_or_else(|| {
            Failure::new(
                AcuityStatus::ACUITY_UNKNOWN_OBJECT,
                format!("object {object:#x} is not in this selector (was it removed?)"),
            )
        })
    }

    fn handle_of(&self, id: ObjectId) -> AcuityObject {
        match self.entry_of.get(&id) {
            Some(&e) => handle(e, self.entries[e as usize].generation),
            None => ACUITY_NO_OBJECT,
        }
    }

    /// Sets the knobs of the next frames: `s` (in (0, 1]) and the
    /// triangle budget (`None`: none).
    pub(crate) fn set_knobs(&mut self, scale: f32, budget: Option<u64>) {
        self.scale = scale;
        self.budget = budget;
    }

    /// The triangles of the last frame's selections, and of every visible
    /// object's coarsest LOD.
    pub(crate) fn triangles(&self) -> (u64, u64) {
        (self.inner.triangles(), self.inner.coarsest_triangles())
    }

    /// Refuses a selector a panic went through.
    pub(crate) fn check_usable(&self) -> Result<()> {
        if self.poisoned {
            return Err(Failure::new(
                AcuityStatus::ACUITY_PANIC,
                "this selector is unusable after an internal panic; free it",
            ));
        }
        Ok(())
    }

    fn profile(&self, index: u32) -> Result<ProfileId> {
        self.profiles.get(index as usize).copied().ok_or_else(|| {
            Failure::new(
                AcuityStatus::ACUITY_UNKNOWN_PROFILE,
                format!(
                    "profile {index} is not in this selector ({} added)",
                    self.profiles.len()
                ),
            )
        })
    }
}

/// Runs a call on a live, unpoisoned selector; a panic poisons it.
pub(crate) fn with_selector(
    selector: *mut AcuitySelector,
    body: impl FnOnce(&mut AcuitySelector) -> Result<()>,
) -> AcuityStatus {
    guard(|| {
        // SAFETY: every entry point taking a selector requires it to be
        // NULL (refused here) or live and used by no other thread.
        let s = unsafe { borrow_mut(selector, "selector") }?;
        s.check_usable()?;
        match catch_unwind(AssertUnwindSafe(|| body(s))) {
            Ok(result) => result,
            Err(payload) => {
                s.poisoned = true;
                resume_unwind(payload)
            }
        }
    })
}

/// Creates a selector for `display` with `settings` (NULL: the defaults
/// of `acuity_settings_default`). On success `*out` is a new selector the
/// caller frees with `acuity_selector_free`; its scale `s` is 1.
///
/// # Safety
/// `display` must be NULL (refused) or point to an `AcuityDisplay`;
/// `settings` NULL or point to an `AcuitySettings`; `out` NULL (refused)
/// or be valid for writing a pointer.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_new(
    display: *const AcuityDisplay,
    settings: *const AcuitySettings,
    out: *mut *mut AcuitySelector,
) -> AcuityStatus {
    guard(|| {
        check_out(out, "out")?;
        // SAFETY: forwarded from this function's contract.
        let d = unsafe { borrow(display, "display") }?;
        let settings = if settings.is_null() {
            AcuitySettings::default()
        } else {
            // SAFETY: forwarded from this function's contract.
            *unsafe { borrow(settings, "settings") }?
        };
        let display = Display::new(
            [d.width_px, d.height_px],
            [
                finite(d.fov_x_deg, "display.fov_x_deg")?,
                finite(d.fov_y_deg, "display.fov_y_deg")?,
            ],
        )?;
        let selector = AcuitySelector {
            inner: Selector::new(display, settings.to_runtime()?),
            scale: 1.0,
            budget: None,
            profiles: Vec::new(),
            entries: Vec::new(),
            free_entries: Vec::new(),
            entry_of: HashMap::new(),
            poisoned: false,
        };
        let raw = Box::into_raw(Box::new(selector));
        // SAFETY: `out` checked non-NULL and aligned above; writable by
        // the caller's contract.
        unsafe { write_out(out, "out", raw) }
    })
}

/// Frees a selector and everything in it. NULL does nothing. Handles of
/// its objects and profile indices mean nothing afterwards.
///
/// # Safety
/// `selector` must be NULL or a selector from this library not freed yet,
/// and no other call may be using it.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_free(selector: *mut AcuitySelector) -> AcuityStatus {
    guard(|| {
        if !selector.is_null() {
            // SAFETY: from `Box::into_raw` in `acuity_selector_new` and
            // not freed yet, by the caller's contract.
            drop(unsafe { Box::from_raw(selector) });
        }
        Ok(())
    })
}

/// Adds a profile to the selector (validated, and compiled for its
/// display) and writes its index (0, 1, ... in the order added) into
/// `*out_index`, for `AcuityObjectDesc::profile`. The selector keeps its
/// own copy: the profile may be freed afterwards, or added to other
/// selectors.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses; `profile` NULL (refused) or a live profile; `out_index` NULL
/// (refused) or valid for writing a `uint32_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_add_profile(
    selector: *mut AcuitySelector,
    profile: *const AcuityProfile,
    out_index: *mut u32,
) -> AcuityStatus {
    with_selector(selector, |s| {
        check_out(out_index, "out_index")?;
        // SAFETY: forwarded from this function's contract.
        let p = unsafe { borrow(profile, "profile") }?;
        if s.profiles.len() >= u32::MAX as usize {
            return Err(Failure::invalid("more than 2^32 - 1 profiles"));
        }
        let id = s.inner.add_profile(&p.profile)?;
        s.profiles.push(id);
        // SAFETY: checked above; writable by the caller's contract.
        unsafe { write_out(out_index, "out_index", s.profiles.len() as u32 - 1) }
    })
}

/// Adds an object and writes its handle (never 0) into `*out`. Its LOD
/// reads `ACUITY_LOD_CULLED` until the next `acuity_selector_select`.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses; `desc` NULL (refused) or point to an `AcuityObjectDesc`; `out`
/// NULL (refused) or valid for writing an `AcuityObject`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_add_object(
    selector: *mut AcuitySelector,
    desc: *const AcuityObjectDesc,
    out: *mut AcuityObject,
) -> AcuityStatus {
    with_selector(selector, |s| {
        check_out(out, "out")?;
        // SAFETY: forwarded from this function's contract.
        let d = *unsafe { borrow(desc, "desc") }?;
        let profile = s.profile(d.profile)?;
        if s.free_entries.is_empty() && s.entries.len() >= (u32::MAX - 1) as usize {
            return Err(Failure::invalid("more than 2^32 - 2 objects"));
        }
        let id = s.inner.add_object(ObjectDesc {
            center: d.center.into(),
            radius: d.radius,
            rotation: d.rotation.into(),
            profile,
        })?;
        let entry = match s.free_entries.pop() {
            Some(e) => e,
            None => {
                s.entries.push(Entry {
                    generation: 0,
                    id: None,
                });
                s.entries.len() as u32 - 1
            }
        };
        s.entries[entry as usize].id = Some(id);
        s.entry_of.insert(id, entry);
        let h = handle(entry, s.entries[entry as usize].generation);
        // SAFETY: checked above; writable by the caller's contract.
        unsafe { write_out(out, "out", h) }
    })
}

/// Removes an object; its handle is refused from now on. Every other
/// handle stays valid.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_remove_object(
    selector: *mut AcuitySelector,
    object: AcuityObject,
) -> AcuityStatus {
    with_selector(selector, |s| {
        let id = s.id(object)?;
        s.inner.remove_object(id)?;
        let entry = s.entry_of.remove(&id).expect("entry of a live object");
        let e = &mut s.entries[entry as usize];
        e.id = None;
        e.generation = e.generation.wrapping_add(1);
        s.free_entries.push(entry);
        Ok(())
    })
}

/// Moves an object: its bounding sphere's centre and its rotation.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses; `center` and `rotation` NULL (refused) or point to their structs.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_set_pose(
    selector: *mut AcuitySelector,
    object: AcuityObject,
    center: *const AcuityVec3d,
    rotation: *const AcuityQuat,
) -> AcuityStatus {
    with_selector(selector, |s| {
        // SAFETY: forwarded from this function's contract.
        let (center, rotation) =
            unsafe { (*borrow(center, "center")?, *borrow(rotation, "rotation")?) };
        let id = s.id(object)?;
        Ok(s.inner.set_pose(id, center.into(), rotation.into())?)
    })
}

/// Sets an object's bounding radius, world units (finite, >= 0).
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_set_radius(
    selector: *mut AcuitySelector,
    object: AcuityObject,
    radius: f32,
) -> AcuityStatus {
    with_selector(selector, |s| {
        let id = s.id(object)?;
        Ok(s.inner.set_radius(id, finite(radius, "radius")?)?)
    })
}

/// Sets an object's bias (finite, > 0; 1 is the default): a multiplier on
/// its acuity threshold, like a scale `s` of its own. Above 1 the object
/// keeps more detail (a hero object), below 1 less.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_set_bias(
    selector: *mut AcuitySelector,
    object: AcuityObject,
    bias: f32,
) -> AcuityStatus {
    with_selector(selector, |s| {
        let id = s.id(object)?;
        Ok(s.inner.set_bias(id, finite(bias, "bias")?)?)
    })
}

/// Clamps an object's LOD into `[min_lod, max_lod]` (0 the finest; a
/// `max_lod` past the profile's coarsest LOD, such as `UINT32_MAX`, means
/// the coarsest). `0, UINT32_MAX` is the default; `min_lod > max_lod` is
/// refused. Culling is unaffected.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_set_lod_range(
    selector: *mut AcuitySelector,
    object: AcuityObject,
    min_lod: u32,
    max_lod: u32,
) -> AcuityStatus {
    with_selector(selector, |s| {
        let id = s.id(object)?;
        let max = if max_lod == u32::MAX {
            usize::MAX
        } else {
            max_lod as usize
        };
        Ok(s.inner.set_lod_range(id, min_lod as usize..=max)?)
    })
}

/// Sets the global scale factor `s` of the following frames, in (0, 1]:
/// 1 (the default) drops only detail the viewer cannot see; lower values
/// drop detail sooner. Values above 1 count as 1; NaN, zero, negative and
/// infinite values are refused.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_set_scale(
    selector: *mut AcuitySelector,
    s: f32,
) -> AcuityStatus {
    with_selector(selector, |sel| {
        let s = finite(s, "s")?;
        if s <= 0.0 {
            return Err(Failure::invalid(format!("`s` is {s}; it must be > 0")));
        }
        sel.scale = s.min(1.0);
        Ok(())
    })
}

/// Sets the triangle budget of the next frames: `acuity_selector_select`
/// then chooses the LODs at the selector's `s` and, where they draw more
/// than `triangles` (single-LOD objects included), coarsens first where
/// the predicted visibility per triangle saved is lowest (the settings'
/// `budget_rule`), down to `min_scale`. `ACUITY_NO_BUDGET` turns the
/// budget off (the default). A predictive scheduler sets it
/// (`acuity_scheduler_apply`).
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_set_budget(
    selector: *mut AcuitySelector,
    triangles: u64,
) -> AcuityStatus {
    with_selector(selector, |s| {
        s.budget = (triangles != ACUITY_NO_BUDGET).then_some(triangles);
        Ok(())
    })
}

/// Selects every object's LOD for one frame. Read the results with
/// `acuity_selector_changes`, `acuity_selector_lods`,
/// `acuity_selector_lod`, `acuity_selector_fades` and
/// `acuity_selector_stats`. Fails only on an invalid frame (non-finite or
/// out-of-range numbers, a zero gaze or rotation, an unknown tracker),
/// leaving the selector as it was.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses; `frame` NULL (refused) or point to an `AcuityFrame`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_select(
    selector: *mut AcuitySelector,
    frame: *const AcuityFrame,
) -> AcuityStatus {
    with_selector(selector, |s| {
        // SAFETY: forwarded from this function's contract.
        let f = *unsafe { borrow(frame, "frame") }?;
        let dt_s = non_negative(f.dt_s, "frame.dt_s")?;
        let tracker = match f.tracker {
            ACUITY_TRACKER_NONE => Tracker::None,
            ACUITY_TRACKER_HEAD => Tracker::Head,
            ACUITY_TRACKER_EYE => {
                let error_deg = non_negative(f.tracker_error_deg, "frame.tracker_error_deg")?;
                Tracker::Eye { error_deg }
            }
            other => {
                return Err(Failure::invalid(format!(
                    "`frame.tracker` is {other}; it must be ACUITY_TRACKER_NONE (0), \
                     _HEAD (1) or _EYE (2)"
                )));
            }
        };
        let pursued = match f.pursued {
            ACUITY_NO_OBJECT => None,
            h => s.id(h).ok(),
        };
        let orientation: Quat = f.camera_orientation.into();
        let frame = FrameInput {
            camera: Camera {
                position: f.camera_position.into(),
                orientation,
            },
            gaze: Gaze {
                direction_camera: f.gaze_direction.into(),
                tracker,
                pursued,
            },
            dt_s,
            scale: s.scale,
        };
        match s.budget {
            Some(budget) => {
                s.inner.select_within_budget(&frame, budget)?;
            }
            None => s.inner.select(&frame)?,
        }
        Ok(())
    })
}

/// Writes one object's LOD from the last frame into `*out_lod` (0 the
/// finest, `ACUITY_LOD_CULLED` when culled or not selected yet).
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses; `out_lod` NULL (refused) or valid for writing a `uint8_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_lod(
    selector: *mut AcuitySelector,
    object: AcuityObject,
    out_lod: *mut u8,
) -> AcuityStatus {
    with_selector(selector, |s| {
        check_out(out_lod, "out_lod")?;
        let lod = lod_of(s.inner.selection(s.id(object)?));
        // SAFETY: checked above; writable by the caller's contract.
        unsafe { write_out(out_lod, "out_lod", lod) }
    })
}

/// Writes the LODs of `count` objects (`objects[i]`'s into `lods_out[i]`,
/// `ACUITY_LOD_CULLED` when culled): the bulk form of
/// `acuity_selector_lod`, a table lookup an object. An unknown handle
/// gets `ACUITY_LOD_CULLED` and the call returns
/// `ACUITY_UNKNOWN_OBJECT` after writing all the others.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses; `objects` valid for reading and `lods_out` for writing `count`
/// items (either may be NULL only when `count` is 0).
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_lods(
    selector: *mut AcuitySelector,
    objects: *const AcuityObject,
    count: usize,
    lods_out: *mut u8,
) -> AcuityStatus {
    with_selector(selector, |s| {
        // SAFETY: forwarded from this function's contract.
        let objects = unsafe { slice(objects, count, "objects") }?;
        // SAFETY: forwarded from this function's contract.
        let mut out = unsafe { OutArray::new(lods_out, count, "lods_out") }?;
        let mut unknown = None;
        for (i, &object) in objects.iter().enumerate() {
            let lod = match s.id(object) {
                Ok(id) => lod_of(s.inner.selection(id)),
                Err(_) => {
                    unknown.get_or_insert((i, object));
                    ACUITY_LOD_CULLED
                }
            };
            out.set(i, lod);
        }
        match unknown {
            None => Ok(()),
            Some((i, object)) => Err(Failure::new(
                AcuityStatus::ACUITY_UNKNOWN_OBJECT,
                format!("objects[{i}] ({object:#x}) is not in this selector (was it removed?)"),
            )),
        }
    })
}

/// Lists the objects whose selection changed in the last frame (with
/// `track_changes` or cross-fades on; otherwise the list is empty), with
/// their new LODs: up to `capacity` entries into `out`, and the total
/// into `*out_count`. With `out` NULL and `capacity` 0 it only counts.
/// When `capacity` is less than the total the first `capacity` are
/// written and the call returns `ACUITY_BUFFER_TOO_SMALL`.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses; `out` valid for writing `capacity` items (NULL only when
/// `capacity` is 0); `out_count` NULL (refused) or valid for writing a
/// `size_t`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_changes(
    selector: *mut AcuitySelector,
    out: *mut AcuityChange,
    capacity: usize,
    out_count: *mut usize,
) -> AcuityStatus {
    with_selector(selector, |s| {
        check_out(out_count, "out_count")?;
        // SAFETY: forwarded from this function's contract.
        let mut array = unsafe { OutArray::new(out, capacity, "out") }?;
        let changed = s.inner.changed();
        for (i, &id) in changed.iter().enumerate().take(array.len()) {
            array.set(
                i,
                AcuityChange {
                    object: s.handle_of(id),
                    lod: u32::from(lod_of(s.inner.selection(id))),
                },
            );
        }
        // SAFETY: checked above; writable by the caller's contract.
        unsafe { write_out(out_count, "out_count", changed.len()) }?;
        too_small(capacity, changed.len(), out.is_null())
    })
}

/// Lists the cross-fades in progress after the last frame (with
/// `fade_time_s` > 0), as `acuity_selector_changes` lists changes.
///
/// # Safety
/// As `acuity_selector_changes`, for `AcuityFade` items.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_fades(
    selector: *mut AcuitySelector,
    out: *mut AcuityFade,
    capacity: usize,
    out_count: *mut usize,
) -> AcuityStatus {
    with_selector(selector, |s| {
        check_out(out_count, "out_count")?;
        // SAFETY: forwarded from this function's contract.
        let mut array = unsafe { OutArray::new(out, capacity, "out") }?;
        let fades = s.inner.fades();
        for (i, f) in fades.iter().enumerate().take(array.len()) {
            array.set(
                i,
                AcuityFade {
                    object: s.handle_of(f.object),
                    from_lod: f.from_lod as u32,
                    to_lod: f.to_lod as u32,
                    fraction: f.fraction,
                },
            );
        }
        // SAFETY: checked above; writable by the caller's contract.
        unsafe { write_out(out_count, "out_count", fades.len()) }?;
        too_small(capacity, fades.len(), out.is_null())
    })
}

/// A count-only call (NULL array, no capacity) is a success; a short
/// array is not.
fn too_small(capacity: usize, total: usize, counting: bool) -> Result<()> {
    if total > capacity && !(counting && capacity == 0) {
        return Err(Failure::new(
            AcuityStatus::ACUITY_BUFFER_TOO_SMALL,
            format!("{total} entries, room for {capacity}; the first {capacity} were written"),
        ));
    }
    Ok(())
}

/// Writes counts after the last frame into `*out`: objects, visible
/// objects, triangles, changes and fades. Visible objects and triangles
/// are counted over every object, so call it when you need the numbers,
/// not in a tight loop.
///
/// # Safety
/// `selector` must be NULL (refused) or a live selector no other thread
/// uses; `out` NULL (refused) or valid for writing an `AcuityStats`.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn acuity_selector_stats(
    selector: *mut AcuitySelector,
    out: *mut AcuityStats,
) -> AcuityStatus {
    with_selector(selector, |s| {
        check_out(out, "out")?;
        let inner = &s.inner;
        let stats = AcuityStats {
            objects: inner.object_count() as u64,
            visible: inner.selections().iter().filter(|x| !x.is_culled()).count() as u64,
            triangles: inner.triangles(),
            changed: inner.changed().len() as u64,
            fading: inner.fades().len() as u64,
        };
        // SAFETY: checked above; writable by the caller's contract.
        unsafe { write_out(out, "out", stats) }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_is_caught_and_poisons_the_selector() {
        let display = AcuityDisplay {
            width_px: 640,
            height_px: 480,
            fov_x_deg: 60.0,
            fov_y_deg: 45.0,
        };
        let mut s = std::ptr::null_mut();
        // SAFETY: live display and out-pointer.
        let status = unsafe { acuity_selector_new(&display, std::ptr::null(), &mut s) };
        assert_eq!(status, AcuityStatus::ACUITY_OK);
        let status = with_selector(s, |_| panic!("deliberate"));
        assert_eq!(status, AcuityStatus::ACUITY_PANIC);
        // SAFETY: never NULL, NUL-terminated.
        let message = unsafe { std::ffi::CStr::from_ptr(crate::acuity_last_error()) };
        assert_eq!(message.to_str().unwrap(), "internal panic: deliberate");
        // SAFETY: live selector.
        let status = unsafe { acuity_selector_set_scale(s, 0.5) };
        assert_eq!(status, AcuityStatus::ACUITY_PANIC, "poisoned");
        // SAFETY: from acuity_selector_new, freed once.
        let status = unsafe { acuity_selector_free(s) };
        assert_eq!(status, AcuityStatus::ACUITY_OK);
    }
}
