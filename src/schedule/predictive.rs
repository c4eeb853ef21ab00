//! The predictive scheduler (Funkhouser & Séquin 1993): a triangle budget
//! for the next frame from a [`CostModel`] and the frame-time aim, with the
//! reactive scheduler's headroom, dead band, ceiling and load memory (the
//! parent module's docs).

use super::load_step::{LoadMemory, LoadSteps};
use super::{CostModel, FrameStats, MISS_LEARNING_RATE, RETURN_FIRST_STEP, ReactiveSettings};

/// The predictive fixed-frame-rate controller: the triangle budget for the
/// next frame, from a [`CostModel`] and the frame-time aim (the module
/// docs), held while the frames stay in the dead band below the aim.
///
/// The budget falls after a frame over the period by more than the dead
/// band, or [`ReactiveSettings::settle_frames`] frames in a row over the
/// aim, to
/// what the cost model says fits the middle of the dead band; it rises
/// after as many frames in a row below the band, by half the band at
/// least. As for the reactive controller, a budget whose raise overloaded
/// the frame becomes a ceiling until the load drops, while the cost
/// floor lies above the period the budget does not fall, and after a load
/// that lasts, or a told one ([`Self::announce_load`]) that bound it, the
/// budget returns to the one before it when the frame time steps down
/// again (by more than its jitter): half of it for one frame, then all of
/// it where that frame's cost per triangle says it fits.
#[derive(Clone, Debug)]
pub struct PredictiveScheduler {
    settings: ReactiveSettings,
    cost: CostModel,
    held: Option<u64>,
    /// A budget whose raise overloaded the frame, until the load drops.
    ceiling: Option<u64>,
    /// Whether the last move of the budget was a raise.
    last_raised: bool,
    stats: FrameStats,
    /// The last frame's cost floor, s (its announced load included), where
    /// known.
    floor_s: Option<f32>,
    /// Load announced for the next frame, s ([`Self::announce_load`]).
    announced_s: f32,
    /// The last announced load and the budget it left, held while the
    /// announcements stay within 10% of it and the frames on time.
    announced_budget: Option<(f32, u64)>,
    /// The budget and the cost model before the last load that lasts
    /// lowered it, until a frame shows the load gone
    /// ([`load_step::LOAD_STEP`](super::load_step::LOAD_STEP)) or the memory is too old
    /// ([`load_step::LOAD_MEMORY_S`](super::load_step::LOAD_MEMORY_S)).
    before_load: Option<LoadMemory<(u64, CostModel)>>,
    /// The budget a return after a load goes back to once the frame drawn
    /// half-way shows that it fits ([`RETURN_FIRST_STEP`]).
    return_to: Option<u64>,
    /// The last two frames' triangles and times (their announced load
    /// taken out), to tell a step of load by.
    load_steps: LoadSteps,
}

impl PredictiveScheduler {
    /// A controller with the settings (clamped as for
    /// [`ReactiveScheduler::new`](super::ReactiveScheduler::new)) and a starting cost model.
    pub fn new(settings: ReactiveSettings, cost: CostModel) -> Self {
        Self {
            settings: settings.clamped(),
            cost,
            held: None,
            ceiling: None,
            last_raised: false,
            stats: FrameStats::new(),
            floor_s: None,
            announced_s: 0.0,
            announced_budget: None,
            before_load: None,
            return_to: None,
            load_steps: LoadSteps::new(),
        }
    }

    /// Announces work the next frame will do beyond what the frames so far
    /// contained, s (a shader to compile, a chunk to stream in, a physics
    /// burst): work an engine knows of before it starts the frame. The
    /// next [`triangle_budget`](Self::triangle_budget) leaves room for it
    /// at once, instead of after the first late frame, and the next
    /// [`observe`](Self::observe) takes it out of the frame time, so the
    /// controller does not learn it as a lasting load. The budget it leaves
    /// is held, as the budget itself is, while the announcements stay
    /// within 10% of the load it was made for and the frames on time; once
    /// the announcements stop, the budget comes back as after a load seen
    /// in the frame times, in two steps. Announcements within a frame add
    /// up; [`observe`](Self::observe) clears them. Not finite or not
    /// `> 0`: nothing.
    pub fn announce_load(&mut self, extra_s: f32) {
        if extra_s.is_finite() && extra_s > 0.0 {
            self.announced_s += extra_s;
        }
    }

    /// The settings in use (after clamping).
    pub fn settings(&self) -> &ReactiveSettings {
        &self.settings
    }

    /// The cost model as learned so far.
    pub fn cost_model(&self) -> &CostModel {
        &self.cost
    }

    /// The frame time aimed at now, s.
    pub fn aim_s(&self) -> f32 {
        self.settings.aim_s(self.stats.sigma())
    }

    /// Whether the last frame's cost floor lay above the period.
    pub fn target_unreachable(&self) -> bool {
        self.settings.beyond_reach(self.floor_s)
    }

    /// The last frame's cost floor, s, as for
    /// [`ReactiveScheduler::cost_floor_s`](super::ReactiveScheduler::cost_floor_s), with the load announced for
    /// that frame ([`Self::announce_load`]) included.
    pub fn cost_floor_s(&self) -> Option<f32> {
        self.floor_s
    }

    /// The triangle budget for the next frame (less what an announced load
    /// takes, [`Self::announce_load`]).
    pub fn triangle_budget(&mut self) -> u64 {
        let steer_s = self.settings.steer_s(self.aim_s(), self.stats.sigma());
        let held = *self
            .held
            .get_or_insert_with(|| self.cost.triangle_budget(steer_s));
        let announced_s = self.announced_s;
        if announced_s <= 0.0 {
            // A told load that bound the budget has ended: back in two
            // steps, as after a load seen in the frame times.
            if let Some((_, told)) = self.announced_budget.take()
                && told < held
            {
                return self.return_from(told, held);
            }
            return held;
        }
        // Held like the budget itself: a budget that moves with every
        // frame's reading reorders objects whose costs are close.
        let budget = match self.announced_budget {
            Some((a, b)) if (announced_s - a).abs() <= 0.1 * a => b,
            _ => {
                let b = self.cost.triangle_budget(steer_s - announced_s);
                self.announced_budget = Some((announced_s, b));
                b
            }
        };
        held.min(budget)
    }

    /// The first step back from a load's budget (`load_budget`) to the
    /// one before it (`before`): [`RETURN_FIRST_STEP`] of it (or the
    /// load's, if more), the rest once that frame shows it fits.
    fn return_from(&mut self, load_budget: u64, before: u64) -> u64 {
        let first = ((RETURN_FIRST_STEP * before as f64) as u64).max(load_budget);
        self.raise_to(first);
        self.return_to = Some(before);
        first
    }

    /// Holds `budget`, raised from the one held: the level starts again,
    /// and a frame it overloads makes it a ceiling.
    fn raise_to(&mut self, budget: u64) {
        self.last_raised = true;
        self.held = Some(budget);
        self.stats.moved();
    }

    /// Feeds back the frame just drawn: its time (s), the triangles it
    /// drew and those it would have drawn with every visible object at its
    /// coarsest LOD (for the cost floor). Invalid times change nothing.
    pub fn observe(&mut self, frame_time_s: f32, triangles: u64, coarsest_triangles: u64) {
        let announced_s = std::mem::take(&mut self.announced_s);
        if !(frame_time_s.is_finite() && frame_time_s > 0.0) {
            return;
        }
        // The announced load was budgeted for; what is left is the scene's.
        let (full_frame_s, frame_time_s) = (frame_time_s, (frame_time_s - announced_s).max(1e-6));
        let st = self.settings;
        let band = st.band(self.stats.sigma());
        // A step of the frame time that its change of triangles does not
        // explain (a cost at most proportional to them) is a change of load.
        let step = self.load_steps.see((triangles as f32).ln(), frame_time_s);
        let over = frame_time_s > st.target_frame_s;
        let rose = over && step.rose_from_both;
        // The frame after a load's first is drawn with the budget that
        // frame cut: the cost model from before the load says what it
        // should take. A load is remembered with the cost model from
        // before it learned the load.
        let (held, cost) = (self.held, self.cost);
        let load_gone = LoadMemory::follow(
            &mut self.before_load,
            frame_time_s,
            over,
            &step,
            |m| m.before.1.frame_s(triangles).min(m.level_s()),
            || held.map(|h| (h, cost)),
        );
        // The load has gone: what the cost model learned of it goes too,
        // or its reading of the load would cut the budget it returns to.
        if load_gone && let Some(m) = &self.before_load {
            self.cost = m.before.1;
        }
        // A frame clearly over the period (by more than the dead band,
        // beyond the jitter), or over it by a step of load, is news of more
        // load: learn it at once (a budget shrunk in proportion never
        // overshoots).
        let rate = self.cost.learning_rate;
        if rose || frame_time_s > (1.0 + band) * st.target_frame_s {
            self.cost.learning_rate = rate.max(MISS_LEARNING_RATE);
        }
        // A frame drawn under a told load's smaller budget says little of
        // what the held budget's triangles cost: at a few triangles its
        // proportional reading is the fixed time's error (a fixed time
        // calibrated too high reads them as nearly free), so it moves
        // neither the per-triangle cost nor, below, the held budget.
        let told_binds = announced_s > 0.0
            && self
                .announced_budget
                .zip(self.held)
                .is_some_and(|((_, told), held)| told < held);
        self.cost
            .observe_frame(frame_time_s, triangles, !told_binds);
        self.cost.learning_rate = rate;
        self.floor_s = self
            .cost
            .floor_s(coarsest_triangles)
            .map(|f| f + announced_s)
            .filter(|f| f.is_finite());
        let unreachable = self.target_unreachable();
        let aim = self.stats.see(&st, frame_time_s);
        let steer_s = st.steer_s(aim, self.stats.sigma());
        let fresh = self.cost.triangle_budget(steer_s);
        let missed = self.stats.missed(frame_time_s, st.target_frame_s, band);
        if full_frame_s > (1.0 + band) * st.target_frame_s {
            self.announced_budget = None;
        }

        let Some(held) = self.held else {
            self.held = Some(fresh);
            return;
        };
        if frame_time_s < st.clear_ratio * st.target_frame_s {
            self.ceiling = None;
        }
        // The second step of a return: to the budget from before the load,
        // or to what this frame's cost per triangle says fits if less.
        let returned = self
            .return_to
            .take()
            .filter(|_| frame_time_s <= aim)
            .map(|before| before.min(self.cost.budget_by_frame(steer_s, frame_time_s, triangles)))
            .filter(|&b| b > held);
        let lower = (missed || self.stats.busy >= st.settle_frames) && fresh < held;
        // A raise must pay: by half the dead band at least, and below a
        // budget whose raise overloaded the frame.
        let cap = self.ceiling.map_or(u64::MAX, |c| (0.97 * c as f64) as u64);
        let raised = fresh.min(cap);
        let raise = !told_binds
            && self.stats.frames >= st.settle_frames
            && self.stats.calm >= st.settle_frames
            && raised as f64 > held as f64 * (1.0 + 0.5 * f64::from(band));
        if let Some(b) = returned {
            self.raise_to(b);
        } else if lower && !unreachable {
            let spike = frame_time_s > st.spike_ratio * st.target_frame_s;
            if self.last_raised && !spike {
                self.ceiling = Some(held);
            }
            self.last_raised = false;
            self.held = Some(fresh);
            self.stats.moved();
        } else if raise {
            self.raise_to(raised);
            // Climbed back by the raise rule: nothing left to return to.
            if self
                .before_load
                .as_ref()
                .is_some_and(|m| raised >= m.before.0)
            {
                self.before_load = None;
            }
        } else if unreachable {
            self.stats.moved();
        }
        // The load has gone: back to the budget from before it, or to what
        // the cost model from before it says fits now if less, in two steps
        // (the view may have grown dearer while the load lasted, which the
        // load's frames, of few triangles, do not show).
        if load_gone && let Some(m) = self.before_load.take() {
            self.ceiling = None;
            let b0 = m.before.0.min(fresh);
            if let Some(h) = self.held.filter(|&h| h < b0) {
                self.return_from(h, b0);
            }
        }
    }
}
