//! Cross-fades of LODs chosen outside the runtime (the screen-size
//! policy), by the runtime's rules ([`acuity::SelectorSettings::fade_time_s`]),
//! so every policy of a run fades alike; the acuity policies take theirs
//! from the runtime's selector. What a frame draws of a fade is a
//! [`FadeOut`]: the LOD going, drawn beside the chosen one with the
//! complementary dither mask.

/// An instance's LOD fading out while its chosen LOD fades in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FadeOut {
    /// The LOD fading out.
    pub from_lod: usize,
    /// How far the fade has gone, in `[0, 1)`: the share of the instance's
    /// pixels the chosen LOD covers.
    pub fraction: f32,
}

/// Per-instance fades over chosen LODs (`None`: culled or not drawn).
#[derive(Debug, Clone)]
pub struct CrossFades {
    fade_s: f32,
    before: Vec<Option<usize>>,
    fades: Vec<Option<FadeOut>>,
}

impl CrossFades {
    /// Fades lasting `fade_s` seconds (> 0).
    pub fn new(fade_s: f32) -> CrossFades {
        CrossFades {
            fade_s,
            before: Vec::new(),
            fades: Vec::new(),
        }
    }

    /// After a frame's choice: moves running fades on by `dt_s` seconds
    /// (ending those that reach 1), then starts one per switch between two
    /// LODs. A switch back to the LOD fading out reverses its fade; to a
    /// third LOD starts a new fade from whichever of the two had the larger
    /// share; into or out of view ends it.
    pub fn update(&mut self, lods: &[Option<usize>], dt_s: f32) {
        let step = if dt_s.is_finite() && dt_s > 0.0 {
            dt_s / self.fade_s
        } else {
            0.0
        };
        self.before.resize(lods.len(), None);
        self.fades.resize(lods.len(), None);
        for (i, &now) in lods.iter().enumerate() {
            let mut fade = self.fades[i].map(|f| FadeOut {
                fraction: f.fraction + step,
                ..f
            });
            fade = fade.filter(|f| f.fraction < 1.0);
            let before = self.before[i];
            if before != now {
                fade = match (before, now, fade) {
                    (Some(from_lod), Some(_), None) => Some(FadeOut {
                        from_lod,
                        fraction: 0.0,
                    }),
                    (Some(was), Some(to), Some(f)) if to == f.from_lod => Some(FadeOut {
                        from_lod: was,
                        fraction: 1.0 - f.fraction,
                    })
                    .filter(|f| f.fraction < 1.0),
                    (Some(was), Some(_), Some(f)) => Some(FadeOut {
                        from_lod: if f.fraction >= 0.5 { was } else { f.from_lod },
                        fraction: 0.0,
                    }),
                    _ => None,
                };
            }
            self.fades[i] = fade;
        }
        self.before.clear();
        self.before.extend_from_slice(lods);
    }

    /// Each instance's running fade, in the order of the last
    /// [`update`](Self::update)'s LODs.
    pub fn fades(&self) -> &[Option<FadeOut>] {
        &self.fades
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(from_lod: usize, fraction: f32) -> Option<FadeOut> {
        Some(FadeOut { from_lod, fraction })
    }

    #[test]
    fn a_switch_fades_over_the_fade_time_then_ends() {
        let mut c = CrossFades::new(0.5);
        c.update(&[Some(1), Some(2)], 0.125);
        assert_eq!(c.fades(), &[None, None], "the first frame switches nothing");
        c.update(&[Some(0), Some(2)], 0.125);
        assert_eq!(c.fades(), &[f(1, 0.0), None]);
        c.update(&[Some(0), Some(2)], 0.125);
        c.update(&[Some(0), Some(2)], 0.125);
        c.update(&[Some(0), Some(2)], 0.125);
        assert_eq!(c.fades()[0], f(1, 0.75));
        c.update(&[Some(0), Some(2)], 0.125);
        assert_eq!(c.fades()[0], None, "ends on the frame it reaches 1");
    }

    #[test]
    fn switches_during_a_fade_reverse_or_restart_it_and_culling_ends_it() {
        let mut c = CrossFades::new(1.0);
        c.update(&[Some(2)], 0.25);
        c.update(&[Some(1)], 0.25);
        c.update(&[Some(1)], 0.25);
        assert_eq!(c.fades()[0], f(2, 0.25));
        // Back to 2: 1 now fades out, 2 keeps the share it had.
        c.update(&[Some(2)], 0.25);
        assert_eq!(c.fades()[0], f(1, 0.5));
        // To a third LOD: from the stronger of the two (2 at 0.75).
        c.update(&[Some(0)], 0.25);
        assert_eq!(c.fades()[0], f(2, 0.0));
        c.update(&[Some(1)], 0.25);
        assert_eq!(
            c.fades()[0],
            f(2, 0.0),
            "0 had 0.25: 2 stays the one fading out"
        );
        c.update(&[None], 0.25);
        assert_eq!(c.fades()[0], None);
        c.update(&[Some(3)], 0.25);
        assert_eq!(c.fades()[0], None, "coming into view does not fade");
    }
}
