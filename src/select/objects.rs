//! Objects of a [`Selector`]: stable ids over a dense store. Every object
//! has a slot; objects with more than one LOD take slots `0..multi` (the
//! blocks the loop reads), single-LOD objects the slots after them.
//! Removing an object moves the last object of its kind into its slot, so
//! the loop never sees holes; ids go through a table of handles that
//! follows the moves.

use std::ops::RangeInclusive;

use glam::{DVec3, Quat};

use crate::camera::{MAX_WORLD_COORDINATE, normalized_rotation};
use crate::error::{Error, Result};

use super::hysteresis::SwitchRecord;
use super::store::{EMPTY_BLOCK, Lane, NO_HISTORY, NO_MOTION};
use super::{
    BLOCK, Diagnostics, ObjectDesc, ObjectId, ProfileId, Selection, Selector, positive_or_zero,
};

/// No position in a list; a free handle's slot.
pub(super) const NONE: u32 = u32::MAX;

/// An entry of the handle table.
#[derive(Clone, Copy, Debug)]
pub(super) struct Handle {
    pub(super) generation: u32,
    /// The object's slot, or [`NONE`] for a free entry.
    pub(super) slot: u32,
    /// Position in [`Selector::adjusted`], or [`NONE`].
    pub(super) adjust: u32,
    /// Position in [`Selector::fades`], or [`NONE`].
    pub(super) fade: u32,
    /// How long the object's switch to a coarser LOD has waited for a
    /// saccade, s (0: none waiting).
    pub(super) deferred_s: f32,
}

/// An object with one LOD: only culled.
#[derive(Clone, Copy, Debug)]
pub(super) struct SingleRecord {
    pub(super) center: DVec3,
    pub(super) radius: f32,
    pub(super) rotation: Quat,
    pub(super) profile: u32,
}

/// Where an object is and how it is placed, to move it between stores.
#[derive(Clone, Copy)]
struct Placement {
    center: DVec3,
    radius: f32,
    rotation: Quat,
}

impl Selector {
    /// Objects with more than one LOD: they take slots `0..multi`.
    pub(super) fn multi(&self) -> usize {
        self.object_profiles.len()
    }

    /// The slot of a live object; an error for a stale or foreign id.
    pub(super) fn slot(&self, id: ObjectId) -> Result<usize> {
        match self.handles.get(id.index as usize) {
            Some(h) if h.generation == id.generation && h.slot != NONE => Ok(h.slot as usize),
            _ => Err(Error::invalid(
                "id",
                format!("{id:?} is not in this selector (was it removed?)"),
            )),
        }
    }

    /// The slot the loop knows the pursued object by (`u32::MAX`: none, or
    /// a single-LOD, removed or foreign object).
    pub(super) fn pursued_slot(&self, pursued: Option<ObjectId>) -> u32 {
        match pursued.map(|id| self.slot(id)) {
            Some(Ok(slot)) if slot < self.multi() => slot as u32,
            _ => u32::MAX,
        }
    }

    /// Adds an object and returns its id. Objects whose profile has one
    /// LOD are kept apart and never enter the selection loop. Its
    /// selection reads culled until the next `select*` call, so it is
    /// listed as changed on its first frame unless culled there (and does
    /// not fade in).
    pub fn add_object(&mut self, desc: ObjectDesc) -> Result<ObjectId> {
        let profile = self.profile_index(desc.profile)?;
        let (center, radius, rotation) = validate_pose(desc.center, desc.radius, desc.rotation)?;
        if self.selections.len() >= (u32::MAX - 1) as usize {
            return Err(Error::invalid("objects", "more than 2^32 - 2 objects"));
        }
        let index = match self.free_handles.pop() {
            Some(i) => i,
            None => {
                self.handles.push(Handle {
                    generation: 0,
                    slot: NONE,
                    adjust: NONE,
                    fade: NONE,
                    deferred_s: 0.0,
                });
                self.handles.len() as u32 - 1
            }
        };
        let id = ObjectId {
            index,
            generation: self.handles[index as usize].generation,
        };
        self.insert(
            id,
            Placement {
                center,
                radius,
                rotation,
            },
            profile,
        );
        Ok(id)
    }

    /// Removes an object. Every other id stays valid; this one is refused
    /// from now on (see [`ObjectId`]). The object's bias, LOD range and
    /// fade go with it; a gaze still pursuing it pursues nothing.
    pub fn remove_object(&mut self, id: ObjectId) -> Result<()> {
        let slot = self.slot(id)?;
        self.take_out(slot);
        let h = id.index as usize;
        if self.handles[h].adjust != NONE {
            self.remove_adjust(self.handles[h].adjust as usize);
        }
        if self.handles[h].fade != NONE {
            self.remove_fade(self.handles[h].fade as usize);
        }
        let handle = &mut self.handles[h];
        handle.slot = NONE;
        handle.deferred_s = 0.0;
        handle.generation = handle.generation.wrapping_add(1);
        self.free_handles.push(id.index);
        Ok(())
    }

    /// Gives an object another profile (for example another asset at the
    /// same place). Its id, pose, radius, bias, LOD range and motion
    /// history are kept (a bias or range beyond the new profile's LODs
    /// clamps to them); its selection reads culled until the next
    /// `select*` call, its fade ends, and it is new to the change list
    /// (listed on the next frame unless culled there, without a fade).
    pub fn set_profile(&mut self, id: ObjectId, profile: ProfileId) -> Result<()> {
        let slot = self.slot(id)?;
        let p = self.profile_index(profile)?;
        let multi_now = slot < self.multi();
        let multi_then = self.profiles[p as usize].lod_count > 1;
        if multi_now && multi_then {
            let (block, lane) = (&mut self.blocks[slot / BLOCK], slot % BLOCK);
            block.row0[lane] = self.profile_row0[p as usize];
            self.object_profiles[slot] = p;
        } else if !multi_now && !multi_then {
            let multi = self.multi();
            self.singles[slot - multi].profile = p;
        } else {
            let placement = self.take_out(slot);
            self.insert(id, placement, p);
        }
        let slot = self.slot(id)?;
        self.selections[slot] = Selection::CULLED;
        if self.handles[id.index as usize].fade != NONE {
            self.remove_fade(self.handles[id.index as usize].fade as usize);
        }
        Ok(())
    }

    /// The profile of an object.
    pub fn profile_of(&self, id: ObjectId) -> Result<ProfileId> {
        let slot = self.slot(id)?;
        Ok(ProfileId(if slot < self.multi() {
            self.object_profiles[slot]
        } else {
            self.singles[slot - self.multi()].profile
        }))
    }

    /// Whether `id` names a live object of this selector: false once it
    /// was removed. (An id from another selector is not told apart: it
    /// may name an object here.)
    pub fn contains(&self, id: ObjectId) -> bool {
        self.slot(id).is_ok()
    }

    fn profile_index(&self, profile: ProfileId) -> Result<u32> {
        if (profile.0 as usize) < self.profiles.len() {
            Ok(profile.0)
        } else {
            Err(Error::invalid(
                "profile",
                format!("{profile:?} is not in this selector"),
            ))
        }
    }

    /// Puts an object with a free or vacated handle into the store of its
    /// profile's kind, with LOD 0 and no motion history.
    fn insert(&mut self, id: ObjectId, at: Placement, profile: u32) {
        let n = self.selections.len();
        let slot = if self.profiles[profile as usize].lod_count > 1 {
            let slot = self.multi();
            self.push_slot(id);
            if slot < n {
                // A single-LOD object holds the slot: it moves to the end.
                self.move_slot(slot, n);
                let record = self.singles.pop_front().expect("a single-LOD object");
                self.singles.push_back(record);
            }
            if slot.is_multiple_of(BLOCK) {
                self.blocks.push(EMPTY_BLOCK);
                self.motion.push(NO_HISTORY);
            }
            self.blocks[slot / BLOCK].set_lane(
                slot % BLOCK,
                Lane {
                    center: at.center.to_array(),
                    radius: at.radius,
                    row0: self.profile_row0[profile as usize],
                    rotation: at.rotation.to_array(),
                },
            );
            self.motion[slot / BLOCK].set_lane(slot % BLOCK, NO_MOTION);
            self.object_profiles.push(profile);
            self.diagnostics.push(Diagnostics::default());
            slot
        } else {
            self.push_slot(id);
            self.singles.push_back(SingleRecord {
                center: at.center,
                radius: at.radius,
                rotation: at.rotation,
                profile,
            });
            n
        };
        // Not selected yet: culled, to the change list too.
        self.selections[slot] = Selection::CULLED;
        self.previous[slot] = Selection::CULLED;
        if let Some(r) = self.switch_records.get_mut(slot) {
            *r = SwitchRecord::FRESH;
        }
        self.slot_ids[slot] = id;
        self.handles[id.index as usize].slot = slot as u32;
    }

    /// A new last slot for `id`. The per-frame lists grow here, with the
    /// objects, so that frames never allocate: they can hold every object.
    fn push_slot(&mut self, id: ObjectId) {
        self.selections.push(Selection(0));
        self.previous.push(Selection(0));
        self.slot_ids.push(id);
        let n = self.selections.len();
        self.changed.reserve(n.saturating_sub(self.changed.len()));
        self.changed_slots
            .reserve(n.saturating_sub(self.changed_slots.len()));
        self.switched_from
            .reserve(n.saturating_sub(self.switched_from.len()));
        if positive_or_zero(self.settings.fade_time_s) > 0.0 {
            self.fades.reserve(n.saturating_sub(self.fades.len()));
        }
        if self.defers_coarsening() {
            self.deferred.reserve(n.saturating_sub(self.deferred.len()));
            self.deferred_before
                .reserve(n.saturating_sub(self.deferred_before.len()));
        }
    }

    /// Takes the object at `slot` out of the store, moving another into
    /// its slot; its handle still points at the vacated slot.
    fn take_out(&mut self, slot: usize) -> Placement {
        let multi = self.multi();
        let last = self.selections.len() - 1;
        if slot < multi {
            let lane = self.blocks[slot / BLOCK].lane(slot % BLOCK);
            let end = multi - 1;
            if slot != end {
                let moved = self.blocks[end / BLOCK].lane(end % BLOCK);
                let motion = self.motion[end / BLOCK].lane(end % BLOCK);
                self.blocks[slot / BLOCK].set_lane(slot % BLOCK, moved);
                self.motion[slot / BLOCK].set_lane(slot % BLOCK, motion);
                self.object_profiles[slot] = self.object_profiles[end];
                self.diagnostics[slot] = self.diagnostics[end];
                self.move_slot(end, slot);
            }
            if last != end {
                // The last single-LOD object fills the vacated boundary slot.
                self.move_slot(last, end);
                let record = self.singles.pop_back().expect("a single-LOD object");
                self.singles.push_front(record);
            }
            self.object_profiles.pop();
            self.diagnostics.pop();
            if end.is_multiple_of(BLOCK) {
                self.blocks.pop();
                self.motion.pop();
            }
            self.pop_slot();
            Placement {
                center: DVec3::from_array(lane.center),
                radius: lane.radius,
                rotation: Quat::from_array(lane.rotation),
            }
        } else {
            let record = self.singles[slot - multi];
            if slot != last {
                self.singles[slot - multi] = self.singles[last - multi];
                self.move_slot(last, slot);
            }
            self.singles.pop_back();
            self.pop_slot();
            Placement {
                center: record.center,
                radius: record.radius,
                rotation: record.rotation,
            }
        }
    }

    fn pop_slot(&mut self) {
        self.selections.pop();
        self.previous.pop();
        self.slot_ids.pop();
        self.switch_records.truncate(self.selections.len());
    }

    /// Moves the per-slot outputs and the handle of the object at `from`
    /// to `to` (the caller moves the store's own fields).
    fn move_slot(&mut self, from: usize, to: usize) {
        self.selections[to] = self.selections[from];
        self.previous[to] = self.previous[from];
        // The dwell rule's record follows the object (kept for the
        // objects with more than one LOD only, whose slots come first).
        if to < self.switch_records.len() {
            self.switch_records[to] = self
                .switch_records
                .get(from)
                .copied()
                .unwrap_or(SwitchRecord::FRESH);
        }
        let id = self.slot_ids[from];
        self.slot_ids[to] = id;
        self.handles[id.index as usize].slot = to as u32;
    }

    /// Moves an object. Its velocity history is kept: the motion shows up
    /// as retinal velocity in the next frame.
    pub fn set_pose(&mut self, id: ObjectId, center: DVec3, rotation: Quat) -> Result<()> {
        let slot = self.slot(id)?;
        let radius = self.radius(slot);
        let (center, _, rotation) = validate_pose(center, radius, rotation)?;
        if slot < self.multi() {
            let (block, lane) = (&mut self.blocks[slot / BLOCK], slot % BLOCK);
            let old = block.lane(lane);
            block.set_lane(
                lane,
                Lane {
                    center: center.to_array(),
                    rotation: rotation.to_array(),
                    ..old
                },
            );
        } else {
            let multi = self.multi();
            let single = &mut self.singles[slot - multi];
            single.center = center;
            single.rotation = rotation;
        }
        Ok(())
    }

    /// Changes an object's bounding radius (world units, finite, `>= 0`).
    pub fn set_radius(&mut self, id: ObjectId, radius: f32) -> Result<()> {
        let slot = self.slot(id)?;
        if !(radius.is_finite() && radius >= 0.0 && (radius as f64) <= MAX_WORLD_COORDINATE) {
            return Err(Error::invalid(
                "radius",
                format!("{radius} is not a finite radius >= 0"),
            ));
        }
        if slot < self.multi() {
            self.blocks[slot / BLOCK].radius[slot % BLOCK] = radius;
        } else {
            let multi = self.multi();
            self.singles[slot - multi].radius = radius;
        }
        Ok(())
    }

    fn radius(&self, slot: usize) -> f32 {
        if slot < self.multi() {
            self.blocks[slot / BLOCK].radius[slot % BLOCK]
        } else {
            self.singles[slot - self.multi()].radius
        }
    }

    /// Number of objects, single-LOD ones included.
    pub fn object_count(&self) -> usize {
        self.selections.len()
    }

    /// The selection of an object from the last `select*` call (culled
    /// before its first). Panics if `id` was removed or is from another
    /// selector ([`contains`](Self::contains) tells).
    pub fn selection(&self, id: ObjectId) -> Selection {
        match self.slot(id) {
            Ok(slot) => self.selections[slot],
            Err(e) => panic!("Selector::selection: {e}"),
        }
    }

    /// Every object's selection from the last `select*` call, in the
    /// order of [`object_ids`](Self::object_ids): storage order, which
    /// changes as objects are added, removed or change profile (objects
    /// with one LOD are kept after the others).
    pub fn selections(&self) -> &[Selection] {
        &self.selections
    }

    /// Every object's id, in the order of [`selections`](Self::selections).
    pub fn object_ids(&self) -> &[ObjectId] {
        &self.slot_ids
    }

    /// Diagnostics of an object from the last
    /// [`select_with_diagnostics`](Self::select_with_diagnostics) call;
    /// `None` for single-LOD objects, which are never analysed. Panics if
    /// `id` was removed or is from another selector.
    pub fn diagnostics(&self, id: ObjectId) -> Option<Diagnostics> {
        match self.slot(id) {
            Ok(slot) => self.diagnostics.get(slot).copied(),
            Err(e) => panic!("Selector::diagnostics: {e}"),
        }
    }

    /// The LODs an object may take ([`set_lod_range`](Self::set_lod_range));
    /// `0..=usize::MAX` unless set.
    pub fn lod_range(&self, id: ObjectId) -> Result<RangeInclusive<usize>> {
        self.slot(id)?;
        Ok(match self.handles[id.index as usize].adjust {
            NONE => 0..=usize::MAX,
            i => self.adjusted[i as usize].range(),
        })
    }

    /// An object's bias ([`set_bias`](Self::set_bias)); 1 unless set.
    pub fn bias(&self, id: ObjectId) -> Result<f32> {
        self.slot(id)?;
        Ok(match self.handles[id.index as usize].adjust {
            NONE => 1.0,
            i => self.adjusted[i as usize].bias,
        })
    }
}

pub(super) fn validate_pose(
    center: DVec3,
    radius: f32,
    rotation: Quat,
) -> Result<(DVec3, f32, Quat)> {
    if !center.is_finite() || center.abs().max_element() > MAX_WORLD_COORDINATE {
        return Err(Error::invalid(
            "center",
            format!("{center} is not finite or beyond ±{MAX_WORLD_COORDINATE:e}"),
        ));
    }
    if !(radius.is_finite() && radius >= 0.0 && (radius as f64) <= MAX_WORLD_COORDINATE) {
        return Err(Error::invalid(
            "radius",
            format!("{radius} is not a finite radius >= 0"),
        ));
    }
    Ok((center, radius, normalized_rotation(rotation, "rotation")?))
}
