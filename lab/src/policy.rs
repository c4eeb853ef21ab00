//! The LOD policies `acuity run` compares, each
//! over the same camera path: full detail, screen-size thresholds, acuity
//! with a set of model components, and acuity under the reactive or the
//! predictive fixed-frame-rate scheduler (and screen size under the
//! reactive one, the controller a user would write without acuity).
//!
//! With the scene's `cross_fade_s` set, each switch between two LODs fades
//! over that time ([`PolicyRunner::fades`]): the acuity policies take the
//! runtime selector's fades, the screen-size policy its own by the same
//! rules ([`crate::crossfade`]).
//!
//! Every policy culls the same objects: those the runtime's frustum test
//! (a [`Selector`] with culling on) puts outside the view. So triangle and
//! frame-time differences come from LOD choices alone.

use crate::crossfade::{CrossFades, FadeOut};
use crate::frames::{FrameView, Instance, World};
use crate::limits::MIN_SCALE;
use crate::scene::Policy;
use crate::screen_size::{
    BelowLast, ScreenSizeChoice, ScreenSizeLod, relative_height, thresholds_from,
};
use acuity::{
    BudgetRule, Components, CostModel, FrameInput, ObjectDesc, ObjectId, PredictiveScheduler,
    ReactiveScheduler, ReactiveSettings, ScaleRule, Selector, SelectorSettings,
};

/// The model components a policy selects with; `None` for policies that do
/// not use the acuity model.
pub fn components(policy: Policy) -> Option<Components> {
    let c = |size, eccentricity, velocity| {
        Some(Components {
            size,
            velocity,
            eccentricity,
        })
    };
    match policy {
        Policy::Full
        | Policy::ScreenSize
        | Policy::ScreenSizeReactive
        | Policy::ScreenSizeReactivePeriod => None,
        Policy::AcuitySize => c(true, false, false),
        Policy::AcuitySizeEcc => c(true, true, false),
        Policy::AcuitySizeVel => c(true, false, true),
        Policy::AcuityEccVel => c(false, true, true),
        Policy::AcuityAll
        | Policy::AcuityReactive
        | Policy::AcuityPredictive
        | Policy::AcuityPredictiveUniform
        | Policy::AcuityPredictiveUnweighted
        | Policy::AcuityReactiveNoHeadroom
        | Policy::AcuityReactiveBudgeted
        | Policy::AcuityReactivePooled
        | Policy::AcuityAllBudgeted
        | Policy::AcuityAllPooled
        | Policy::AcuityPredictiveAnnounced
        | Policy::AcuityPredictiveNoHeadroom
        | Policy::AcuityBestEffort
        | Policy::AcuityBestEffortPooled
        | Policy::AcuityBestEffortUnweighted
        | Policy::AcuityBestEffortMatched
        | Policy::AcuityBestEffortMatchedPooled
        | Policy::AcuityBudgetUniform => c(true, true, true),
    }
}

/// What a policy chose for one frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Choice {
    /// The global scale factor `s` used (1 for policies without one).
    pub scale: f32,
    /// Triangle budget of the predictive scheduler, if it set one.
    pub triangle_budget: Option<u64>,
    /// The selection's visibility in best effort's measure, deg
    /// (`Selector::selection_visibility_deg`), where the selector recorded
    /// thresholds; `None` for screen size and full detail.
    pub visibility_deg: Option<f64>,
    /// Whether the knob was at its end: the scheduler's `s` at its lowest,
    /// or the triangle budget not met with every step down the selection
    /// may take (to the lowest `s` it may use,
    /// [`SelectorSettings::min_scale`]). A late frame there ran over on
    /// the floor of what the policy may draw; `false` without a scheduler.
    pub at_limit: bool,
}

/// The scheduled reactive policies' controller: with a cost model for the
/// cost floor, and started at its lowest `s` to climb (a headset would
/// rather show its first frames coarse than late;
/// [`ReactiveScheduler::starting_at`]).
fn climbing_reactive(settings: ReactiveSettings, cost: CostModel) -> ReactiveScheduler {
    ReactiveScheduler::new(settings)
        .with_cost_model(cost)
        .starting_at(settings.min_scale)
}

/// A selector with `settings` holding every instance of `world`, and the
/// instances' ids in instance order.
fn selector_over(
    world: &World,
    settings: SelectorSettings,
) -> anyhow::Result<(Selector, Vec<ObjectId>)> {
    let mut selector = Selector::new(world.display, settings);
    let profiles = world
        .objects
        .iter()
        .map(|o| {
            selector
                .add_profile(&o.profile)
                .map_err(|e| anyhow::Error::new(e).context(format!("object `{}`: profile", o.name)))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let ids = world
        .instances
        .iter()
        .map(|i| {
            selector
                .add_object(ObjectDesc {
                    center: i.center_m,
                    radius: i.radius_m as f32,
                    rotation: i.placement.rotation.as_quat(),
                    profile: profiles[i.object],
                })
                .map_err(|e| {
                    anyhow::Error::new(e).context(format!(
                        "object `{}` copy {}",
                        world.objects[i.object].name, i.copy
                    ))
                })
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    Ok((selector, ids))
}

/// The screen-size table's LOD for one instance in a view (`None`: below
/// the table's last threshold, culled), its relative height times
/// `height_scale` (and, with the scene's `screen_size_foveated`, the
/// observer's eccentricity factor at its angle from the gaze).
fn screen_size_lod(
    world: &World,
    view: &FrameView,
    tables: &[ScreenSizeLod],
    inst: &Instance,
    height_scale: f64,
) -> Option<usize> {
    let fov_v = world.scene.display.screen_height_fov_deg();
    let to_object_m = inst.center_m - view.eye_m;
    let mut h = relative_height(inst.radius_m, to_object_m.length(), fov_v) * height_scale;
    if world.scene.run.screen_size_foveated {
        let in_camera = view.orientation.inverse() * to_object_m;
        let eccentricity_deg = in_camera.angle_between(view.gaze_camera);
        let m = world
            .scene
            .eccentricity_model
            .factor(eccentricity_deg.to_degrees() as f32);
        h *= f64::from(m);
    }
    match tables[inst.object].select_relative_height(h) {
        ScreenSizeChoice::Lod(l) => Some(l),
        ScreenSizeChoice::Culled => None,
    }
}

/// A policy's fixed-frame-rate controller.
enum Scheduler {
    /// Reactive: `s` from measured frame times, with a cost model for the
    /// cost floor or blind to it.
    Reactive(ReactiveScheduler),
    /// Predictive: a triangle budget from a cost model.
    Predictive(PredictiveScheduler),
    /// The predictive scheduler before headroom: the budget of the whole
    /// period from a cost model, every frame.
    PredictiveNoHeadroom(CostModel),
}

/// A policy's state over a run: a selector (with velocity history) and,
/// for the schedulers, their controller.
pub struct PolicyRunner {
    policy: Policy,
    selector: Selector,
    ids: Vec<ObjectId>,
    pursued: Option<ObjectId>,
    screen: Vec<ScreenSizeLod>,
    scale: f32,
    scheduler: Option<Scheduler>,
    /// The budgeted policies' share of full detail's triangles.
    budget_share: Option<f64>,
    /// Full detail's triangles over the objects in view last frame (all
    /// objects before the first): what the share applies to.
    full_detail_triangles: u64,
    /// A fixed count the budget share is of, in place of
    /// `full_detail_triangles` ([`PolicyRunner::fix_budget_base`]).
    fixed_budget_base: Option<f64>,
    /// The matched policies' ([`Policy::is_matched`]) culling selector: the
    /// objects in view this frame, whose screen-size triangles make the
    /// budget.
    culling: Option<(Selector, Vec<ObjectId>)>,
    /// The screen-size policy's fades (its LODs are not the selector's).
    screen_fades: Option<CrossFades>,
    fades: Vec<Option<FadeOut>>,
}

impl PolicyRunner {
    /// A fresh runner for `policy` over `world`'s instances. `cost` is the
    /// predictive scheduler's starting cost model (ignored by the other
    /// policies). Uses the scene's `scale_factor`, `screen_size_bias`,
    /// `target_hz` and `cross_fade_s`.
    pub fn new(
        world: &World,
        policy: Policy,
        screen_size_bias: f64,
        cost: CostModel,
    ) -> anyhow::Result<PolicyRunner> {
        let cross_fade_s = world.scene.run.cross_fade_s as f32;
        let selector_fades = !(policy == Policy::Full || policy.is_screen_size());
        let scheduled = policy.is_scheduled() && !policy.is_untuned();
        // `acuity_all_pooled` is the runtime's `s = 1` just imperceptible
        // as shipped (`acuity_reactive_pooled` under the reactive
        // scheduler, the `_pooled` budget policies under a triangle
        // budget); the other tuned schedulers add its steady switch rules
        // to their own settings.
        let base = if matches!(
            policy,
            Policy::AcuityAllPooled
                | Policy::AcuityReactivePooled
                | Policy::AcuityBestEffortPooled
                | Policy::AcuityBestEffortMatchedPooled
        ) {
            SelectorSettings::just_imperceptible()
        } else {
            SelectorSettings::default()
        };
        let when_scheduled =
            |steady: f32, otherwise: f32| if scheduled { steady } else { otherwise };
        let settings = SelectorSettings {
            fade_time_s: if selector_fades { cross_fade_s } else { 0.0 },
            components: components(policy).unwrap_or(Components::ALL),
            observer: world.scene.observer,
            eccentricity_model: world.scene.eccentricity_model,
            velocity_model: world.scene.velocity_model,
            eyes_counter_rotate: world.scene.gaze.eyes_counter_rotate,
            saccade_threshold_deg_per_s: world
                .scene
                .gaze
                .saccade_threshold_deg_per_s
                .map_or(f32::INFINITY, |v| v as f32),
            defer_coarsening_s: world.scene.gaze.defer_coarsening_s as f32,
            radius_margin: world.radius_margin,
            budget_rule: if matches!(
                policy,
                Policy::AcuityBudgetUniform | Policy::AcuityPredictiveUniform
            ) {
                BudgetRule::UniformScale
            } else if matches!(
                policy,
                Policy::AcuityBestEffortUnweighted | Policy::AcuityPredictiveUnweighted
            ) {
                BudgetRule::BestEffortUnweighted
            } else {
                BudgetRule::BestEffort
            },
            scale_rule: if matches!(
                policy,
                Policy::AcuityAllBudgeted | Policy::AcuityReactiveBudgeted
            ) {
                ScaleRule::Budgeted
            } else {
                base.scale_rule
            },
            budget_hysteresis: if policy == Policy::AcuityPredictiveNoHeadroom {
                0.0
            } else {
                base.budget_hysteresis
            },
            switch_hysteresis: when_scheduled(
                acuity::STEADY_SWITCH_HYSTERESIS,
                base.switch_hysteresis,
            ),
            switch_min_dwell_s: when_scheduled(
                acuity::STEADY_SWITCH_MIN_DWELL_S,
                base.switch_min_dwell_s,
            ),
            switch_coarsen_delay_s: when_scheduled(
                acuity::STEADY_SWITCH_COARSEN_DELAY_S,
                base.switch_coarsen_delay_s,
            ),
            min_scale: world.scene.run.min_scale,
            ..base
        };
        let (selector, ids) = selector_over(world, settings)?;
        // The matched budget counts the objects in view this frame: a
        // second selector, with the same frustum test, culls before the
        // budgeted selection runs.
        let culling = if policy.is_matched() {
            Some(selector_over(world, settings)?)
        } else {
            None
        };
        let screen = world
            .objects
            .iter()
            .zip(&world.scene.objects)
            .map(|(o, spec)| {
                ScreenSizeLod::new(
                    thresholds_from(&world.scene.run.screen_size_thresholds, o.meshes.len()),
                    screen_size_bias * spec.screen_size_bias,
                    BelowLast::KeepCoarsest,
                )
                .map_err(|e| anyhow::Error::new(e).context("screen-size policy"))
            })
            .collect::<anyhow::Result<Vec<_>>>()?;
        let run = &world.scene.run;
        if policy.is_scheduled() {
            acuity::schedule::check_target_hz("run.target_hz", run.target_hz)?;
        }
        let scale = (run.scale_factor as f32).clamp(MIN_SCALE, 1.0);
        // Every controller, screen size's too, stops at the scene's floor.
        let tuned = || {
            ReactiveSettings::for_rate_hz(run.target_hz as f32).map(|t| ReactiveSettings {
                min_scale: run.min_scale,
                ..t
            })
        };
        let scheduler = match policy {
            Policy::AcuityReactive
            | Policy::AcuityReactiveBudgeted
            | Policy::AcuityReactivePooled
            | Policy::ScreenSizeReactive
            | Policy::ScreenSizeReactivePeriod => {
                Some(Scheduler::Reactive(climbing_reactive(tuned()?, cost)))
            }
            Policy::AcuityReactiveNoHeadroom => Some(Scheduler::Reactive(ReactiveScheduler::new(
                tuned()?.without_headroom(),
            ))),
            Policy::AcuityPredictive
            | Policy::AcuityPredictiveAnnounced
            | Policy::AcuityPredictiveUniform
            | Policy::AcuityPredictiveUnweighted => Some(Scheduler::Predictive(
                PredictiveScheduler::new(tuned()?, cost),
            )),
            Policy::AcuityPredictiveNoHeadroom => Some(Scheduler::PredictiveNoHeadroom(cost)),
            _ => None,
        };
        Ok(PolicyRunner {
            policy,
            pursued: world.tracked_instance().map(|i| ids[i]),
            selector,
            ids,
            screen,
            scale,
            scheduler,
            budget_share: policy.is_budgeted().then_some(1.0),
            culling,
            full_detail_triangles: world
                .instances
                .iter()
                .map(|i| u64::from(world.objects[i.object].profile.lod_triangles[0]))
                .sum(),
            fixed_budget_base: None,
            screen_fades: (policy.is_screen_size() && cross_fade_s > 0.0)
                .then(|| CrossFades::new(cross_fade_s)),
            fades: Vec::new(),
        })
    }

    /// Sets the policy's knob: the budgeted policies' share of full
    /// detail's triangles (clamped into (0, 1]),
    /// [`Policy::ScreenSizeReactivePeriod`]'s period factor (its controller
    /// told a period of `knob` times the real one; not finite or <= 0: 1),
    /// else the global scale factor ([`PolicyRunner::set_scale`]).
    pub fn set_knob(&mut self, knob: f64) {
        if self.policy == Policy::ScreenSizeReactivePeriod {
            if let Some(Scheduler::Reactive(r)) = &self.scheduler {
                let factor = if knob.is_finite() && knob > 0.0 {
                    knob
                } else {
                    1.0
                };
                let mut settings = *r.settings();
                settings.target_frame_s *= factor as f32;
                if let Some(cost) = r.cost_model() {
                    self.scheduler = Some(Scheduler::Reactive(climbing_reactive(settings, *cost)));
                }
            }
        } else if self.budget_share.is_some() {
            self.budget_share = Some(if knob > 0.0 { knob.min(1.0) } else { 1.0 });
        } else {
            self.set_scale(knob);
        }
    }

    /// Makes a budgeted policy's share one of `triangles` (finite, > 0;
    /// otherwise ignored) in every frame, in place of full detail's
    /// triangles in view in the frame before.
    pub fn fix_budget_base(&mut self, triangles: f64) {
        if triangles.is_finite() && triangles > 0.0 {
            self.fixed_budget_base = Some(triangles);
        }
    }

    /// Sets the global scale factor `s` (clamped into (0, 1]); for the
    /// reactive scheduler it is a cap.
    pub fn set_scale(&mut self, scale: f64) {
        // A positive `s` too small for `f32` is the smallest positive one,
        // not 0 (which would read as "unset").
        self.scale = if scale > 0.0 {
            (scale as f32).clamp(MIN_SCALE, 1.0)
        } else {
            1.0
        };
    }

    /// The policy.
    pub fn policy(&self) -> Policy {
        self.policy
    }

    /// Chooses every instance's LOD for a view into `lods` (`None`: culled).
    pub fn choose(
        &mut self,
        world: &World,
        view: &FrameView,
        dt_s: f32,
        lods: &mut Vec<Option<usize>>,
    ) -> anyhow::Result<Choice> {
        // The scene's s caps what the reactive scheduler may use.
        let scale = match &self.scheduler {
            Some(Scheduler::Reactive(r)) => r.scale().min(self.scale),
            _ => self.scale,
        };
        let frame = FrameInput {
            camera: World::camera(view),
            gaze: world.gaze(view, self.pursued),
            dt_s,
            scale,
        };
        let at_lowest_scale = match &self.scheduler {
            Some(Scheduler::Reactive(r)) => r.scale() <= r.settings().min_scale,
            _ => false,
        };
        let mut choice = Choice {
            scale,
            triangle_budget: None,
            visibility_deg: None,
            at_limit: at_lowest_scale,
        };
        let matched_budget = match &mut self.culling {
            Some((culling, culling_ids)) => {
                culling.select(&frame)?;
                let in_view = world
                    .instances
                    .iter()
                    .zip(culling_ids.iter())
                    .filter(|(_, id)| !culling.selection(**id).is_culled());
                Some(
                    in_view
                        .filter_map(|(inst, _)| {
                            let lod = screen_size_lod(world, view, &self.screen, inst, 1.0)?;
                            Some(u64::from(
                                world.objects[inst.object].profile.lod_triangles[lod],
                            ))
                        })
                        .sum(),
                )
            }
            None => None,
        };
        let budget = match (&mut self.scheduler, self.budget_share) {
            (Some(Scheduler::Predictive(p)), _) => Some(p.triangle_budget()),
            (Some(Scheduler::PredictiveNoHeadroom(cost)), _) => {
                Some(cost.triangle_budget(1.0 / world.scene.run.target_hz as f32))
            }
            (_, Some(share)) => Some(
                (share
                    * self
                        .fixed_budget_base
                        .unwrap_or(self.full_detail_triangles as f64)) as u64,
            ),
            _ => matched_budget,
        };
        match budget {
            Some(budget) => {
                let out = self.selector.select_within_budget(&frame, budget)?;
                choice = Choice {
                    scale: out.scale,
                    triangle_budget: Some(budget),
                    visibility_deg: None,
                    at_limit: self.scheduler.is_some() && !out.within_budget,
                };
            }
            None => self.selector.select(&frame)?,
        }
        if !(self.policy == Policy::Full || self.policy.is_screen_size()) {
            choice.visibility_deg = self.selector.selection_visibility_deg();
        }
        // A fixed base leaves the triangles in view unused.
        if self.budget_share.is_some() && self.fixed_budget_base.is_none() {
            self.full_detail_triangles = world
                .instances
                .iter()
                .zip(&self.ids)
                .filter(|(_, id)| !self.selector.selection(**id).is_culled())
                .map(|(i, _)| u64::from(world.objects[i.object].profile.lod_triangles[0]))
                .sum();
        }
        lods.clear();
        // Under the reactive scheduler, screen size's bias times its `s`.
        let screen_scale = if self.policy.is_screen_size() && self.policy.is_scheduled() {
            f64::from(choice.scale)
        } else {
            1.0
        };
        for (inst, id) in world.instances.iter().zip(&self.ids) {
            let sel = self.selector.selection(*id);
            let lod = match self.policy {
                _ if sel.is_culled() => None,
                Policy::Full => Some(0),
                _ if self.policy.is_screen_size() => {
                    screen_size_lod(world, view, &self.screen, inst, screen_scale)
                }
                _ => sel.lod(),
            };
            lods.push(lod);
        }
        self.fades.clear();
        if let Some(c) = &mut self.screen_fades {
            c.update(lods, dt_s);
            self.fades.extend_from_slice(c.fades());
        } else if !self.selector.fades().is_empty() {
            let selector = &self.selector;
            self.fades
                .extend(self.ids.iter().zip(lods.iter()).map(|(id, lod)| {
                    lod.and(selector.fade(*id)).map(|f| FadeOut {
                        from_lod: f.from_lod,
                        fraction: f.fraction,
                    })
                }));
        }
        Ok(choice)
    }

    /// Each instance's running cross-fade after the last
    /// [`choose`](Self::choose), in instance order; empty when none runs.
    pub fn fades(&self) -> &[Option<FadeOut>] {
        &self.fades
    }

    /// Tells the predictive scheduler of work the next frame will do
    /// beyond the scene's, s
    /// ([`acuity::PredictiveScheduler::announce_load`]); for
    /// [`Policy::AcuityPredictiveAnnounced`] only (the other policies are
    /// not told), before [`choose`](Self::choose).
    pub fn announce_load(&mut self, extra_s: f64) {
        if let (Policy::AcuityPredictiveAnnounced, Some(Scheduler::Predictive(p))) =
            (self.policy, &mut self.scheduler)
        {
            p.announce_load(extra_s as f32);
        }
    }

    /// Feeds back the measured frame (seconds, triangles drawn) to the
    /// scheduler, if the policy has one.
    pub fn observe(&mut self, frame_time_s: f64, triangles: u64) {
        let t = frame_time_s as f32;
        match &mut self.scheduler {
            Some(Scheduler::Reactive(r)) => {
                r.observe(t, triangles, self.selector.coarsest_triangles());
            }
            Some(Scheduler::Predictive(p)) => {
                p.observe(t, triangles, self.selector.coarsest_triangles());
            }
            Some(Scheduler::PredictiveNoHeadroom(c)) => c.observe(t, triangles),
            None => {}
        }
    }

    /// Whether the scheduler found the last frame's cost floor above the
    /// frame period (no LOD choice reaches the target); `None` for
    /// policies without a scheduler, or blind to the floor.
    pub fn target_unreachable(&self) -> Option<bool> {
        match &self.scheduler {
            Some(Scheduler::Reactive(r)) if r.cost_model().is_some() => {
                Some(r.target_unreachable())
            }
            Some(Scheduler::Predictive(p)) => Some(p.target_unreachable()),
            _ => None,
        }
    }

    /// The scheduler's cost floor after the last frame, s; `None` where
    /// [`target_unreachable`](Self::target_unreachable) is, or while the
    /// floor is unknown.
    pub fn cost_floor_s(&self) -> Option<f64> {
        match &self.scheduler {
            Some(Scheduler::Reactive(r)) => r.cost_floor_s(),
            Some(Scheduler::Predictive(p)) => p.cost_floor_s(),
            _ => None,
        }
        .map(f64::from)
    }

    /// The frame time the scheduler aims at, s; `None` for policies
    /// without a scheduler with headroom.
    pub fn aim_s(&self) -> Option<f64> {
        match &self.scheduler {
            Some(Scheduler::Reactive(r)) => Some(r.aim_s()),
            Some(Scheduler::Predictive(p)) => Some(p.aim_s()),
            _ => None,
        }
        .map(f64::from)
    }
}

/// A cost model fitted by least squares to measured `(frame s, triangles)`
/// pairs: `frame = fixed + per_triangle * triangles`, with both terms kept
/// non-negative. With fewer than two distinct triangle counts, a guess of
/// no fixed cost and the mean time per triangle (or 10 ns per triangle
/// with no data).
pub fn fit_cost_model(samples: &[(f64, u64)]) -> CostModel {
    let n = samples.len() as f64;
    if samples.is_empty() {
        return CostModel::new(0.0, 1e-8);
    }
    let mx = samples.iter().map(|s| s.1 as f64).sum::<f64>() / n;
    let my = samples.iter().map(|s| s.0).sum::<f64>() / n;
    let sxx: f64 = samples.iter().map(|s| (s.1 as f64 - mx).powi(2)).sum();
    let sxy: f64 = samples.iter().map(|s| (s.1 as f64 - mx) * (s.0 - my)).sum();
    if sxx > 0.0 {
        let slope = (sxy / sxx).max(1e-12);
        let fixed = (my - slope * mx).max(0.0);
        CostModel::new(fixed as f32, slope as f32)
    } else if mx > 0.0 {
        CostModel::new(0.0, (my / mx) as f32)
    } else {
        CostModel::new(my as f32, 1e-8)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn components_match_policy_names() {
        assert_eq!(components(Policy::Full), None);
        assert_eq!(components(Policy::AcuityAll), Some(Components::ALL));
        let ev = components(Policy::AcuityEccVel).unwrap();
        assert!(!ev.size && ev.eccentricity && ev.velocity);
        let s = components(Policy::AcuitySize).unwrap();
        assert!(s.size && !s.eccentricity && !s.velocity);
    }

    #[test]
    fn cost_fit_recovers_a_line() {
        let samples: Vec<(f64, u64)> = (1..10u64)
            .map(|k| (0.002 + 1e-7 * (k * 10_000) as f64, k * 10_000))
            .collect();
        let m = fit_cost_model(&samples);
        assert!((m.fixed_s - 0.002).abs() < 1e-5, "{m:?}");
        assert!((m.per_triangle_s - 1e-7).abs() < 1e-9, "{m:?}");
        // Degenerate input gives a usable model, not NaN.
        let m = fit_cost_model(&[(0.01, 0), (0.01, 0)]);
        assert!(m.per_triangle_s.is_finite() && m.fixed_s.is_finite());
        assert!(fit_cost_model(&[]).per_triangle_s > 0.0);
    }
}
