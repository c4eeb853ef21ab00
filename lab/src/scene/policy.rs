//! The LOD policies a run compares, by their scene-file names.

use serde::Deserialize;

/// The LOD policies a run can compare.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Policy {
    /// LOD 0 everywhere.
    Full,
    /// Screen-relative height thresholds ([`crate::screen_size`]).
    ScreenSize,
    /// Acuity, size only.
    AcuitySize,
    /// Acuity, size and eccentricity.
    AcuitySizeEcc,
    /// Acuity, size and velocity.
    AcuitySizeVel,
    /// Acuity, eccentricity and velocity, size off (the comparison of
    /// Reddy 1998 §5.2 that shows size's share of the reduction).
    AcuityEccVel,
    /// Acuity, all components.
    AcuityAll,
    /// Acuity, all components, reactive fixed-frame-rate scheduler.
    AcuityReactive,
    /// Acuity, all components, predictive fixed-frame-rate scheduler.
    AcuityPredictive,
    /// Acuity, all components, under a triangle budget (a share of full
    /// detail's triangles, the experiment's knob), spent best effort:
    /// the least visible detail per triangle first.
    AcuityBestEffort,
    /// As [`Policy::AcuityBestEffort`] with the runtime's just-imperceptible
    /// settings ([`acuity::SelectorSettings::just_imperceptible`]): the
    /// budget caps what [`Policy::AcuityAllPooled`] draws at `s = 1`.
    AcuityBestEffortPooled,
    /// As [`Policy::AcuityBestEffort`], each step's visibility not weighed
    /// by the object's size ([`acuity::BudgetRule::BestEffortUnweighted`],
    /// the rule before; kept to measure against).
    AcuityBestEffortUnweighted,
    /// As [`Policy::AcuityBestEffort`], with one `s` lowered for every
    /// object until the budget fits.
    AcuityBudgetUniform,
    /// As [`Policy::AcuityBestEffort`], its budget in each frame the
    /// triangles the screen-size table (the knob: its bias) draws in that
    /// frame: the two rankings compared at equal triangles frame by frame,
    /// not only on average.
    AcuityBestEffortMatched,
    /// As [`Policy::AcuityBestEffortMatched`] with the runtime's
    /// just-imperceptible settings
    /// ([`acuity::SelectorSettings::just_imperceptible`]): the budget caps
    /// what [`Policy::AcuityAllPooled`] draws at `s = 1`.
    AcuityBestEffortMatchedPooled,
    /// As [`Policy::AcuityPredictive`], with one `s` lowered for every
    /// object until the predicted frame fits (the rule before best effort).
    AcuityPredictiveUniform,
    /// As [`Policy::AcuityPredictive`], with its budget spent by
    /// [`acuity::BudgetRule::BestEffortUnweighted`] (the rule before the
    /// size weight; kept to measure against).
    AcuityPredictiveUnweighted,
    /// The screen-size table with its bias times the `s` of the reactive
    /// scheduler: the frame-rate controller a user would write without
    /// acuity, to compare with [`Policy::AcuityReactive`].
    ScreenSizeReactive,
    /// [`Policy::AcuityReactive`] as it was before headroom: aiming at the
    /// frame period itself, acting on every frame, blind to the cost floor.
    AcuityReactiveNoHeadroom,
    /// [`Policy::AcuityPredictive`] as it was before headroom: the budget
    /// of the whole period recomputed every frame, no hysteresis, blind to
    /// the cost floor.
    AcuityPredictiveNoHeadroom,
    /// As [`Policy::AcuityAll`], `s < 1` spent as a budget
    /// ([`acuity::ScaleRule::Budgeted`]): the triangles one `s` would draw,
    /// coarsened best effort from the LODs at `s = 1`.
    AcuityAllBudgeted,
    /// As [`Policy::AcuityAllBudgeted`], with a budget of visibility
    /// summed over the image on top
    /// ([`acuity::VisibilityBudget::Imperceptible`], the runtime's
    /// calibration of `s = 1`, scaled by the display's field of view).
    AcuityAllPooled,
    /// As [`Policy::AcuityReactive`], the scheduler's `s` spent as a budget
    /// ([`acuity::ScaleRule::Budgeted`]).
    AcuityReactiveBudgeted,
    /// As [`Policy::AcuityReactiveBudgeted`], with the visibility budget
    /// of [`Policy::AcuityAllPooled`] on top: the runtime's
    /// [`acuity::SelectorSettings::just_imperceptible`] under the reactive
    /// scheduler.
    AcuityReactivePooled,
    /// As [`Policy::AcuityPredictive`], told of each load spike before its
    /// frames ([`acuity::PredictiveScheduler::announce_load`]): what an
    /// engine that knows its extra work (a shader to compile, a chunk to
    /// stream) gets.
    AcuityPredictiveAnnounced,
    /// As [`Policy::ScreenSizeReactive`] (the bias: the run's
    /// `screen_size_bias`), its controller told a frame period of the knob
    /// times the real one, so that its frames land longer or shorter: the
    /// points `experiment framerate` interpolates screen size's JOD
    /// between at another policy's mean frame time. Not named by scenes.
    ScreenSizeReactivePeriod,
}

impl Policy {
    /// Every policy, in report order.
    pub const ALL: [Policy; 9] = [
        Policy::Full,
        Policy::ScreenSize,
        Policy::AcuitySize,
        Policy::AcuitySizeEcc,
        Policy::AcuitySizeVel,
        Policy::AcuityEccVel,
        Policy::AcuityAll,
        Policy::AcuityReactive,
        Policy::AcuityPredictive,
    ];

    /// The policies under a fixed share of full detail's triangles, not in
    /// [`Policy::ALL`] (scenes and runs name them explicitly; `experiment
    /// error --budgets` sweeps them).
    pub const BUDGETED: [Policy; 4] = [
        Policy::AcuityBestEffort,
        Policy::AcuityBestEffortPooled,
        Policy::AcuityBestEffortUnweighted,
        Policy::AcuityBudgetUniform,
    ];

    /// Policies that scenes and runs may name besides [`Policy::ALL`] and
    /// [`Policy::BUDGETED`].
    pub const EXTRA: [Policy; 12] = [
        Policy::AcuityBestEffortMatched,
        Policy::AcuityBestEffortMatchedPooled,
        Policy::AcuityPredictiveUniform,
        Policy::AcuityPredictiveUnweighted,
        Policy::ScreenSizeReactive,
        Policy::AcuityReactiveNoHeadroom,
        Policy::AcuityPredictiveNoHeadroom,
        Policy::AcuityAllBudgeted,
        Policy::AcuityAllPooled,
        Policy::AcuityReactiveBudgeted,
        Policy::AcuityReactivePooled,
        Policy::AcuityPredictiveAnnounced,
    ];

    /// Whether a fixed-frame-rate scheduler sets this policy's knob.
    pub fn is_scheduled(self) -> bool {
        matches!(
            self,
            Policy::AcuityReactive
                | Policy::AcuityPredictive
                | Policy::AcuityPredictiveUniform
                | Policy::AcuityPredictiveUnweighted
                | Policy::ScreenSizeReactive
                | Policy::AcuityReactiveNoHeadroom
                | Policy::AcuityPredictiveNoHeadroom
                | Policy::AcuityReactiveBudgeted
                | Policy::AcuityReactivePooled
                | Policy::AcuityPredictiveAnnounced
                | Policy::ScreenSizeReactivePeriod
        )
    }

    /// Whether this is one of the controllers as they were before headroom
    /// (kept to measure against).
    pub fn is_untuned(self) -> bool {
        matches!(
            self,
            Policy::AcuityReactiveNoHeadroom | Policy::AcuityPredictiveNoHeadroom
        )
    }

    /// Whether this policy draws the screen-size table's LODs.
    pub fn is_screen_size(self) -> bool {
        matches!(
            self,
            Policy::ScreenSize | Policy::ScreenSizeReactive | Policy::ScreenSizeReactivePeriod
        )
    }

    /// The policy's name in reports: [`Policy::name`], with the knob
    /// appended where one run plays the policy under several knobs that the
    /// schedulers' tables must tell apart
    /// ([`Policy::ScreenSizeReactivePeriod`]).
    pub fn label(self, knob: f64) -> String {
        if self == Policy::ScreenSizeReactivePeriod {
            format!("{}_{knob}", self.name())
        } else {
            self.name().to_owned()
        }
    }

    /// Whether this policy's knob ([`crate::player::PolicyRun::knob`]) is
    /// the screen-size table's bias.
    pub fn knob_is_bias(self) -> bool {
        matches!(self, Policy::ScreenSize | Policy::ScreenSizeReactive) || self.is_matched()
    }

    /// Whether this policy's budget in each frame is the triangles the
    /// screen-size table draws in that frame.
    pub fn is_matched(self) -> bool {
        matches!(
            self,
            Policy::AcuityBestEffortMatched | Policy::AcuityBestEffortMatchedPooled
        )
    }

    /// Whether this policy selects under a share of full detail's
    /// triangles ([`Policy::BUDGETED`]).
    pub fn is_budgeted(self) -> bool {
        Self::BUDGETED.contains(&self)
    }

    /// Whether this is an acuity policy whose scale factor `s` is fixed
    /// (not set by a scheduler), so it can be swept across `s`.
    pub fn is_fixed_scale_acuity(self) -> bool {
        matches!(
            self,
            Policy::AcuitySize
                | Policy::AcuitySizeEcc
                | Policy::AcuitySizeVel
                | Policy::AcuityEccVel
                | Policy::AcuityAll
                | Policy::AcuityAllBudgeted
                | Policy::AcuityAllPooled
        )
    }

    /// The name used in scene files and reports.
    pub fn name(self) -> &'static str {
        match self {
            Policy::Full => "full",
            Policy::ScreenSize => "screen_size",
            Policy::AcuitySize => "acuity_size",
            Policy::AcuitySizeEcc => "acuity_size_ecc",
            Policy::AcuitySizeVel => "acuity_size_vel",
            Policy::AcuityEccVel => "acuity_ecc_vel",
            Policy::AcuityAll => "acuity_all",
            Policy::AcuityReactive => "acuity_reactive",
            Policy::AcuityPredictive => "acuity_predictive",
            Policy::AcuityBestEffort => "acuity_best_effort",
            Policy::AcuityBestEffortPooled => "acuity_best_effort_pooled",
            Policy::AcuityBestEffortUnweighted => "acuity_best_effort_unweighted",
            Policy::AcuityBudgetUniform => "acuity_budget_uniform",
            Policy::AcuityBestEffortMatched => "acuity_best_effort_matched",
            Policy::AcuityBestEffortMatchedPooled => "acuity_best_effort_matched_pooled",
            Policy::AcuityPredictiveUniform => "acuity_predictive_uniform",
            Policy::AcuityPredictiveUnweighted => "acuity_predictive_unweighted",
            Policy::ScreenSizeReactive => "screen_size_reactive",
            Policy::AcuityReactiveNoHeadroom => "acuity_reactive_no_headroom",
            Policy::AcuityPredictiveNoHeadroom => "acuity_predictive_no_headroom",
            Policy::AcuityAllBudgeted => "acuity_all_budgeted",
            Policy::AcuityAllPooled => "acuity_all_pooled",
            Policy::AcuityReactiveBudgeted => "acuity_reactive_budgeted",
            Policy::AcuityReactivePooled => "acuity_reactive_pooled",
            Policy::AcuityPredictiveAnnounced => "acuity_predictive_announced",
            Policy::ScreenSizeReactivePeriod => "screen_size_reactive_period",
        }
    }
}

/// A policy by its scene-file name.
pub fn policy_by_name(name: &str) -> anyhow::Result<Policy> {
    let known = || {
        Policy::ALL
            .into_iter()
            .chain(Policy::BUDGETED)
            .chain(Policy::EXTRA)
    };
    known().find(|p| p.name() == name.trim()).ok_or_else(|| {
        let names: Vec<&str> = known().map(|p| p.name()).collect();
        crate::error::input_error(format!(
            "unknown policy `{name}` (known: {})",
            names.join(", ")
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_nameable_policy_is_listed_once_and_found_by_its_name() {
        let listed: Vec<Policy> = Policy::ALL
            .into_iter()
            .chain(Policy::BUDGETED)
            .chain(Policy::EXTRA)
            .collect();
        for (i, p) in listed.iter().enumerate() {
            assert!(!listed[..i].contains(p), "{p:?} listed twice");
            assert_eq!(policy_by_name(p.name()).unwrap(), *p);
        }
        // Set by `experiment framerate` alone, never named.
        assert!(!listed.contains(&Policy::ScreenSizeReactivePeriod));
        let err = policy_by_name("nonsense").unwrap_err().to_string();
        assert!(err.contains("acuity_best_effort_pooled"), "{err}");
    }
}
