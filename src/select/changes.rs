//! What changed this frame: the objects whose selection differs from the
//! previous call's (found by comparing 64 selections at a time, so a frame
//! where little changes costs about a byte read per object), and the
//! cross-fades those switches start, advance or end.

use super::objects::NONE;
use super::{Fade, FrameInput, ObjectId, Selector};

/// Selections compared at once.
const GROUP: usize = 64;

impl Selector {
    /// The objects whose selection (LOD or culled) changed in the last
    /// `select*` call, compared with the call before, in no particular
    /// order. Objects added since, or whose profile changed since, count
    /// as culled before: they are listed unless culled now. An object whose
    /// selection did not change is not in it. The list's storage is
    /// reused from frame to frame.
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

    /// Lists the changed objects, makes this frame's selections the
    /// previous ones, and moves the fades on by the frame's `dt_s`.
    pub(super) fn finish_frame(&mut self, frame: &FrameInput) {
        self.changed.clear();
        self.switched_from.clear();
        for (g, (now, before)) in self
            .selections
            .chunks(GROUP)
            .zip(self.previous.chunks_mut(GROUP))
            .enumerate()
        {
            let differ = now
                .iter()
                .zip(before.iter())
                .fold(0u8, |acc, (a, b)| acc | (a.0 ^ b.0));
            if differ == 0 {
                continue;
            }
            for (i, (a, b)) in now.iter().zip(before.iter_mut()).enumerate() {
                if a != b {
                    self.changed.push(self.slot_ids[g * GROUP + i]);
                    self.switched_from.push(*b);
                    *b = *a;
                }
            }
        }
        let fade_s = self.settings.fade_time_s;
        if fade_s.is_finite() && fade_s > 0.0 {
            self.advance_fades(frame.dt_s, fade_s);
        }
    }

    fn advance_fades(&mut self, dt_s: f32, fade_s: f32) {
        let step = if dt_s.is_finite() && dt_s > 0.0 {
            dt_s / fade_s
        } else {
            0.0
        };
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
