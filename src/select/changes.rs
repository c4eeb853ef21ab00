//! What changed this frame: the objects whose selection differs from the
//! previous call's, and the cross-fades those switches start, advance or
//! end. Each `select*` call swaps the selections with last frame's (free)
//! and writes them anew; with change tracking on, the two are then
//! compared 64 selections at once, object by object only in groups that
//! changed, and the ids of the changed ones are read in a pass of their
//! own, whose cache misses overlap.
//!
//! Switches to coarser LODs may then wait for a saccade
//! ([`SelectorSettings::defer_coarsening_s`](super::SelectorSettings)):
//! a waiting object's selection is set back to last frame's and it leaves
//! the change list. Wait times live in the objects' handles; the list of
//! waiting handles is rebuilt each frame from the changes alone, so
//! objects that do not switch cost nothing.

use super::objects::NONE;
use super::{Fade, FrameInput, ObjectId, Selector, positive_or_zero};

/// Selections compared at once.
const GROUP: usize = 64;

impl Selector {
    /// The objects whose selection (LOD or culled) changed in the last
    /// `select*` call, in no particular order, with
    /// [`SelectorSettings::track_changes`](super::SelectorSettings) on (or
    /// cross-fades, or switches waiting for saccades); empty otherwise.
    /// Objects added, or given another profile, since the call before
    /// count as culled before: they are listed unless culled now. An
    /// object whose selection did not change is not in it; one removed
    /// since the call still is (check with [`contains`](Self::contains)).
    /// Its storage is reused from frame to frame.
    pub fn changed(&self) -> &[ObjectId] {
        &self.changed
    }

    /// The running cross-fades, in no particular order (empty unless
    /// [`SelectorSettings::fade_time_s`](super::SelectorSettings) is set).
    pub fn fades(&self) -> &[Fade] {
        &self.fades
    }

    /// An object's running cross-fade, if any. Panics if `id` was removed
    /// or is from another selector.
    pub fn fade(&self, id: ObjectId) -> Option<Fade> {
        if let Err(e) = self.slot(id) {
            panic!("Selector::fade: {e}");
        }
        match self.handles[id.index as usize].fade {
            NONE => None,
            i => Some(self.fades[i as usize]),
        }
    }

    /// Lists the objects whose selection differs from last frame's.
    fn list_changes(&mut self) {
        self.changed.clear();
        self.switched_from.clear();
        self.changed_slots.clear();
        for (g, (now, before)) in self
            .selections
            .chunks(GROUP)
            .zip(self.previous.chunks(GROUP))
            .enumerate()
        {
            let differ = now
                .iter()
                .zip(before)
                .fold(0u8, |acc, (a, b)| acc | (a.0 ^ b.0));
            if differ == 0 {
                continue;
            }
            for (i, (a, b)) in now.iter().zip(before).enumerate() {
                if a != b {
                    self.changed_slots.push((g * GROUP + i) as u32);
                    self.switched_from.push(*b);
                }
            }
        }
        let ids = &self.slot_ids;
        self.changed
            .extend(self.changed_slots.iter().map(|&s| ids[s as usize]));
    }

    /// After a frame's selections are final: lists the changes and moves
    /// the fades on by the frame's `dt_s`, as the settings ask. Switches
    /// that wait for a saccade may add at most `room` triangles (`None`:
    /// no limit); returns the triangles they add.
    pub(super) fn finish_frame(&mut self, frame: &FrameInput, room: Option<u64>) -> u64 {
        let fade_s = self.settings.fade_time_s;
        let fading = positive_or_zero(fade_s) > 0.0;
        let deferring = self.defers_coarsening();
        if self.settings.track_changes || fading || deferring {
            self.list_changes();
        }
        let held = if deferring {
            self.defer_coarsening(frame.dt_s, room)
        } else {
            0
        };
        if fading {
            self.advance_fades(frame.dt_s, fade_s);
        }
        held
    }

    /// Holds back this frame's switches to coarser LODs unless the gaze
    /// is in a saccade, the switch has waited long enough (see
    /// [`SelectorSettings::defer_coarsening_s`](super::SelectorSettings)),
    /// or holding it would add more than the `room` left (in the order of
    /// the change list). Returns the triangles the held LODs add.
    fn defer_coarsening(&mut self, dt_s: f32, room: Option<u64>) -> u64 {
        let max_wait_s = self.settings.defer_coarsening_s;
        let mut room = room.unwrap_or(u64::MAX);
        let mut held = 0u64;
        let step_s = positive_or_zero(dt_s);
        std::mem::swap(&mut self.deferred, &mut self.deferred_before);
        self.deferred.clear();
        if self.in_saccade == Some(false) {
            let mut k = 0;
            while k < self.changed.len() {
                let (id, before) = (self.changed[k], self.switched_from[k]);
                let slot = self.changed_slots[k] as usize;
                let handle = self.handles[id.index as usize];
                let waited_s = handle.deferred_s + step_s;
                // The triangles holding the finer LOD adds; `None` unless
                // the switch is to a coarser LOD.
                let extra = match (before.lod(), self.selections[slot].lod()) {
                    (Some(from), Some(to)) if to > from => {
                        let t = &self.profiles[self.object_profiles[slot] as usize].triangles;
                        Some(u64::from(t[from].saturating_sub(t[to])))
                    }
                    _ => None,
                };
                let allowed = handle.adjust == NONE
                    || before.lod().is_some_and(|l| {
                        self.adjusted[handle.adjust as usize].range().contains(&l)
                    });
                if let Some(extra) = extra
                    && allowed
                    && waited_s < max_wait_s
                    && extra <= room
                {
                    room -= extra;
                    held += extra;
                    self.selections[slot] = before;
                    self.deferred.push((id.index, waited_s));
                    self.changed.swap_remove(k);
                    self.changed_slots.swap_remove(k);
                    self.switched_from.swap_remove(k);
                } else {
                    k += 1;
                }
            }
        }
        for &(h, _) in &self.deferred_before {
            self.handles[h as usize].deferred_s = 0.0;
        }
        for &(h, waited_s) in &self.deferred {
            self.handles[h as usize].deferred_s = waited_s;
        }
        held
    }

    fn advance_fades(&mut self, dt_s: f32, fade_s: f32) {
        let step = positive_or_zero(dt_s) / fade_s;
        let mut i = 0;
        while i < self.fades.len() {
            self.fades[i].fraction += step;
            if self.fades[i].fraction >= 1.0 {
                self.remove_fade(i);
            } else {
                i += 1;
            }
        }
        for k in 0..self.changed.len() {
            let (id, before) = (self.changed[k], self.switched_from[k]);
            let now = self.selections[self.handles[id.index as usize].slot as usize];
            let running = self.handles[id.index as usize].fade;
            let (Some(from), Some(to)) = (before.lod(), now.lod()) else {
                // Into or out of view: no fade.
                if running != NONE {
                    self.remove_fade(running as usize);
                }
                continue;
            };
            let fade = match running {
                NONE => Fade {
                    object: id,
                    from_lod: from,
                    to_lod: to,
                    fraction: 0.0,
                },
                at => {
                    let f = self.fades[at as usize];
                    if to == f.from_lod {
                        // Back to the LOD fading out: the fade reverses.
                        Fade {
                            from_lod: f.to_lod,
                            to_lod: to,
                            fraction: 1.0 - f.fraction,
                            ..f
                        }
                    } else {
                        let stronger = if f.fraction >= 0.5 {
                            f.to_lod
                        } else {
                            f.from_lod
                        };
                        Fade {
                            from_lod: stronger,
                            to_lod: to,
                            fraction: 0.0,
                            ..f
                        }
                    }
                }
            };
            if fade.fraction >= 1.0 {
                // Reversed at its very start: back where it began.
                if running != NONE {
                    self.remove_fade(running as usize);
                }
            } else if running == NONE {
                self.fades.push(fade);
                self.handles[id.index as usize].fade = self.fades.len() as u32 - 1;
            } else {
                self.fades[running as usize] = fade;
            }
        }
    }

    /// Ends fade `at`.
    pub(super) fn remove_fade(&mut self, at: usize) {
        let gone = self.fades.swap_remove(at);
        self.handles[gone.object.index as usize].fade = NONE;
        if let Some(moved) = self.fades.get(at) {
            self.handles[moved.object.index as usize].fade = at as u32;
        }
    }
}
