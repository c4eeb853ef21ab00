//! Selection under a triangle budget (best effort and one uniform `s`),
//! `s < 1` spent as a budget ([`ScaleRule::Budgeted`]), and the
//! visibility a budget may spend. The switch rules under a budget are in
//! `switching.rs`.

mod common;

use acuity::{
    BudgetRule, Display, FrameInput, IMPERCEPTIBLE_VISIBILITY_DEG, STEADY_SWITCH_COARSEN_DELAY_S,
    STEADY_SWITCH_HYSTERESIS, STEADY_SWITCH_MIN_DWELL_S, ScaleRule, Selector, SelectorSettings,
    VISIBILITY_POOLING_EXPONENT, VisibilityBudget,
};
use common::{
    big_and_small_saver, display, four_lod_profile, frame_at, lods, on_axis, random_scene,
    two_lod_profile, with_scale,
};
use glam::DVec3;

/// Selects within `fraction` of `full` triangles and checks that the
/// budget is met and reported as the selection's count.
fn met_budget(
    sel: &mut Selector,
    frame: &FrameInput,
    full: u64,
    fraction: f64,
) -> (acuity::BudgetOutcome, u64) {
    let budget = (full as f64 * fraction) as u64;
    let out = sel.select_within_budget(frame, budget).unwrap();
    assert!(
        out.within_budget && out.triangles <= budget,
        "{fraction}: {out:?}"
    );
    assert_eq!(
        out.triangles,
        sel.triangles(),
        "the reported count is the selection's"
    );
    (out, budget)
}

#[test]
fn the_uniform_budget_is_met_with_the_largest_scale_that_fits() {
    let settings = SelectorSettings {
        budget_rule: BudgetRule::UniformScale,
        ..SelectorSettings::default()
    };
    let (mut sel, _) = random_scene(settings, 3000, 21, DVec3::ZERO);
    let frame = frame_at(DVec3::ZERO, 0.016);
    sel.select(&frame).unwrap();
    let full_acuity = sel.triangles();
    for fraction in [1.5, 0.8, 0.5, 0.3] {
        let (out, budget) = met_budget(&mut sel, &frame, full_acuity, fraction);
        if fraction >= 1.0 {
            assert_eq!(out.scale, 1.0);
        } else {
            // 5% more scale would not fit: the choice is near the largest.
            sel.select(&FrameInput {
                scale: out.scale * 1.05,
                ..frame
            })
            .unwrap();
            assert!(
                sel.triangles() > budget,
                "{fraction}: s = {} is not near the largest",
                out.scale
            );
        }
    }
    let out = sel.select_within_budget(&frame, 10).unwrap();
    assert!(!out.within_budget);
    assert!((out.scale - sel.settings().min_scale).abs() < 1e-6);
}

#[test]
fn best_effort_meets_the_budget_and_only_ever_coarsens_what_s_max_chose() {
    let (mut sel, ids) = random_scene(SelectorSettings::default(), 3000, 21, DVec3::ZERO);
    let frame = frame_at(DVec3::ZERO, 0.016);
    sel.select(&frame).unwrap();
    let at_one = lods(&sel, &ids);
    let full_acuity = sel.triangles();
    for fraction in [1.5, 0.8, 0.5, 0.3] {
        let (out, _) = met_budget(&mut sel, &frame, full_acuity, fraction);
        if fraction >= 1.0 {
            assert_eq!(out.scale, 1.0);
            assert_eq!(lods(&sel, &ids), at_one);
        } else {
            assert!(out.scale < 1.0, "{fraction}: {out:?}");
            for (now, before) in lods(&sel, &ids).iter().zip(&at_one) {
                assert!(now.lod() >= before.lod(), "{now:?} finer than {before:?}");
            }
        }
    }
    // Nothing below min_scale: an impossible budget stops there.
    let out = sel.select_within_budget(&frame, 10).unwrap();
    assert!(!out.within_budget);
    assert!(out.scale >= sel.settings().min_scale);
    let settings = SelectorSettings {
        budget_rule: BudgetRule::UniformScale,
        ..SelectorSettings::default()
    };
    let (mut uniform, _) = random_scene(settings, 3000, 21, DVec3::ZERO);
    let floor = uniform.select_within_budget(&frame, 10).unwrap();
    assert!(out.triangles >= floor.triangles, "{out:?} {floor:?}");
}

#[test]
fn best_effort_drops_the_step_that_saves_3000_triangles_before_the_one_that_saves_40_at_the_same_visibility()
 {
    for rule in [
        BudgetRule::BestEffort,
        BudgetRule::BestEffortUnweighted,
        BudgetRule::UniformScale,
    ] {
        let settings = SelectorSettings {
            budget_rule: rule,
            ..SelectorSettings::default()
        };
        let (mut sel, a, b) = big_and_small_saver(settings, 60.0);
        let frame = frame_at(DVec3::ZERO, 0.016);
        sel.select(&frame).unwrap();
        assert_eq!(
            (sel.selection(a).lod(), sel.selection(b).lod()),
            (Some(0), Some(0))
        );
        let out = sel.select_within_budget(&frame, 1100).unwrap();
        assert!(out.within_budget, "{rule:?}: {out:?}");
        let lods = (sel.selection(a).lod(), sel.selection(b).lod());
        match rule {
            // The big saver goes; the small one keeps its detail.
            BudgetRule::BestEffort | BudgetRule::BestEffortUnweighted => {
                assert_eq!(lods, (Some(1), Some(0)), "{out:?}")
            }
            // One s for both: both go at the same breakpoint.
            BudgetRule::UniformScale => assert_eq!(lods, (Some(1), Some(1)), "{out:?}"),
        }
    }
}

#[test]
fn best_effort_coarsens_the_smaller_of_two_objects_whose_steps_are_as_visible_first() {
    // Two objects of one profile on the line of sight, one twice as far:
    // at twice the distance the far one's threshold (judged at half the
    // size, a rung lower) is half the near one's; a bias of 2 makes its
    // step as visible, a bias of 2.6 more visible. One step fits 5,500
    // triangles.
    let choose = |rule, bias: f32| {
        let settings = SelectorSettings {
            budget_rule: rule,
            ..SelectorSettings::default()
        };
        let mut sel = Selector::new(display(), settings);
        let p = sel
            .add_profile(&two_lod_profile([4000, 1000], 60.0))
            .unwrap();
        let (near, far) = (on_axis(&mut sel, p, -10.0), on_axis(&mut sel, p, -20.0));
        sel.set_bias(far, bias).unwrap();
        let frame = frame_at(DVec3::ZERO, 0.016);
        sel.select(&frame).unwrap();
        assert_eq!(sel.triangles(), 8000, "both visible at s = 1");
        let out = sel.select_within_budget(&frame, 5500).unwrap();
        assert!(out.within_budget, "{rule:?}: {out:?}");
        (sel.selection(near).lod(), sel.selection(far).lod())
    };
    let far_goes = (Some(0), Some(1));
    // Weighed by size, the step on half the angular size costs half.
    assert_eq!(choose(BudgetRule::BestEffort, 2.0), far_goes);
    assert_eq!(choose(BudgetRule::BestEffort, 2.6), far_goes);
    // Unweighted, the far step is now the more visible one.
    assert_eq!(
        choose(BudgetRule::BestEffortUnweighted, 2.6),
        (Some(1), Some(0))
    );
}

#[test]
fn coarsest_triangles_count_the_visible_objects_at_their_last_lod() {
    let (mut sel, ids) = random_scene(SelectorSettings::default(), 500, 3, DVec3::ZERO);
    let frame = frame_at(DVec3::ZERO, 0.016);
    sel.select(&frame).unwrap();
    let last = *four_lod_profile(7).lod_triangles.last().unwrap() as u64;
    let visible = ids
        .iter()
        .filter(|&&id| !sel.selection(id).is_culled())
        .count() as u64;
    assert_eq!(sel.coarsest_triangles(), visible * last);
    assert!(sel.coarsest_triangles() <= sel.triangles());
}

fn budgeted_scale() -> SelectorSettings {
    SelectorSettings {
        scale_rule: ScaleRule::Budgeted,
        ..SelectorSettings::default()
    }
}

#[test]
fn a_budgeted_scale_chooses_as_the_uniform_one_at_s_1_and_never_draws_more_below() {
    let frame = frame_at(DVec3::ZERO, 0.016);
    let (mut uniform, ids) = random_scene(SelectorSettings::default(), 3000, 5, DVec3::ZERO);
    let (mut budgeted, _) = random_scene(budgeted_scale(), 3000, 5, DVec3::ZERO);
    let mut fewer = 0;
    for scale in [1.0, 0.8, 0.5, 0.3, 0.1] {
        let frame = with_scale(frame, scale);
        uniform.select(&frame).unwrap();
        budgeted.select(&frame).unwrap();
        if scale == 1.0 {
            assert_eq!(lods(&budgeted, &ids), lods(&uniform, &ids));
            continue;
        }
        let (b, u) = (budgeted.triangles(), uniform.triangles());
        assert!(b <= u, "s = {scale}: {b} triangles against uniform {u}");
        fewer += usize::from(b < u || lods(&budgeted, &ids) != lods(&uniform, &ids));
    }
    assert!(fewer > 0, "the budgeted rule never chose other LODs");
}

#[test]
fn a_budgeted_scale_drops_the_big_saver_where_the_uniform_one_drops_the_small_one() {
    // The small saver's step is a little less visible (a higher critical
    // frequency), so one `s` drops it first; spent as a budget, the
    // triangles that `s` draws go to the step that saves 3000.
    let choose = |scale_rule| {
        let settings = SelectorSettings {
            scale_rule,
            ..SelectorSettings::default()
        };
        big_and_small_saver(settings, 66.0)
    };
    let (mut uniform, a, b) = choose(ScaleRule::Uniform);
    let frame = frame_at(DVec3::ZERO, 0.016);
    let lods_at = |sel: &mut Selector, scale| {
        sel.select(&with_scale(frame, scale)).unwrap();
        (sel.selection(a).lod(), sel.selection(b).lod())
    };
    assert_eq!(lods_at(&mut uniform, 1.0), (Some(0), Some(0)));
    let scale = (1..400)
        .map(|i| 0.99f32.powi(i))
        .find(|&s| lods_at(&mut uniform, s) == (Some(0), Some(1)))
        .expect("an s at which one s drops only the small saver");
    let (mut budgeted, ..) = choose(ScaleRule::Budgeted);
    assert_eq!(
        lods_at(&mut budgeted, scale),
        (Some(1), Some(0)),
        "s = {scale}"
    );
    assert!(budgeted.triangles() <= uniform.triangles());
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 64, failure_persistence: None, ..Default::default() })]

    #[test]
    fn a_budgeted_scale_refuses_what_the_uniform_one_refuses_and_never_draws_more(
        seed in 0u64..1000,
        scale in proptest::prop_oneof![
            4 => 1e-6f32..1.0,
            1 => proptest::num::f32::ANY,
            1 => proptest::strategy::Just(f32::MIN_POSITIVE),
        ],
    ) {
        let frame = with_scale(frame_at(DVec3::ZERO, 0.016), scale);
        let (mut uniform, _) = random_scene(SelectorSettings::default(), 300, seed, DVec3::ZERO);
        let (mut budgeted, _) = random_scene(budgeted_scale(), 300, seed, DVec3::ZERO);
        let (u, b) = (uniform.select(&frame), budgeted.select(&frame));
        proptest::prop_assert_eq!(u.is_ok(), b.is_ok(), "s = {}", scale);
        if u.is_ok() {
            proptest::prop_assert!(budgeted.triangles() <= uniform.triangles(), "s = {}", scale);
        }
    }
}

#[test]
fn the_selection_visibility_is_0_at_s_1_and_grows_as_s_falls() {
    let frame = frame_at(DVec3::ZERO, 0.016);
    let (mut plain, _) = random_scene(SelectorSettings::default(), 2000, 6, DVec3::ZERO);
    plain.select(&frame).unwrap();
    assert_eq!(
        plain.selection_visibility_deg(),
        None,
        "no thresholds recorded"
    );
    let recording = SelectorSettings {
        switch_hysteresis: 0.1,
        ..SelectorSettings::default()
    };
    let (mut at_one, _) = random_scene(recording, 2000, 6, DVec3::ZERO);
    at_one.select(&frame).unwrap();
    assert_eq!(at_one.selection_visibility_deg(), Some(0.0));
    let mut last = 0.0;
    for scale in [0.5, 0.2, 0.05] {
        let (mut sel, _) = random_scene(budgeted_scale(), 2000, 6, DVec3::ZERO);
        sel.select(&with_scale(frame, scale)).unwrap();
        let v = sel.selection_visibility_deg().unwrap();
        assert!(
            v.is_finite() && v > last,
            "s = {scale}: {v}, {last} at the s before"
        );
        last = v;
    }
}

fn visibility_budgeted(budget_deg: f32) -> SelectorSettings {
    SelectorSettings {
        visibility_budget: VisibilityBudget::Deg(budget_deg),
        ..budgeted_scale()
    }
}

/// A visibility budget too small to buy any step: the visibility the
/// triangles from `s` spend alone, in the budget's measure (counted from
/// `VISIBILITY_COUNTED_FROM`, as no budget at all does not count).
const NEAR_ZERO_DEG: f32 = 1e-9;

#[test]
fn a_visibility_budget_spends_its_degrees_at_s_1_and_no_more() {
    let frame = frame_at(DVec3::ZERO, 0.016);
    let (mut off, _) = random_scene(budgeted_scale(), 3000, 8, DVec3::ZERO);
    off.select(&frame).unwrap();
    let (mut none, _) = random_scene(visibility_budgeted(NEAR_ZERO_DEG), 3000, 8, DVec3::ZERO);
    none.select(&frame).unwrap();
    // At `s = 1` the triangles may not exceed the rule's without a budget
    // (steps just inside the edge are taken, the cheapest per triangle
    // first); what the budget buys comes on top of those steps.
    assert!(none.triangles() <= off.triangles());
    let from_triangles = none.selection_visibility_deg().unwrap();
    let mut last = none.triangles();
    let mut spent = from_triangles;
    for budget_deg in [0.5, 2.0, 8.0, 32.0] {
        let (mut sel, _) = random_scene(visibility_budgeted(budget_deg), 3000, 8, DVec3::ZERO);
        sel.select(&frame).unwrap();
        let shown = sel.selection_visibility_deg().unwrap();
        assert!(
            shown - from_triangles <= f64::from(budget_deg) * 1.0001,
            "{budget_deg} deg: {shown} deg shown, {from_triangles} from the triangles"
        );
        assert!(
            shown >= spent,
            "{budget_deg} deg: {shown} deg, {spent} for less"
        );
        assert!(sel.triangles() <= last, "{budget_deg} deg drew more");
        spent = shown;
        last = sel.triangles();
    }
    assert!(last < off.triangles(), "32 deg saved nothing");
    assert!(
        spent - from_triangles > 16.0,
        "32 deg spent only {}",
        spent - from_triangles
    );
    // Off for 0, NaN, negative and infinite budgets: as without.
    for budget_deg in [0.0, f32::NAN, -1.0, f32::INFINITY] {
        let (mut sel, _) = random_scene(visibility_budgeted(budget_deg), 3000, 8, DVec3::ZERO);
        sel.select(&frame).unwrap();
        assert_eq!(sel.triangles(), off.triangles(), "{budget_deg}");
    }
}

#[test]
fn a_visibility_budget_pools_each_objects_margin_with_the_pooling_exponent() {
    // One object that an ample budget takes to its coarse LOD: its
    // visibility is `theta m^beta`, its margin `m = ln(b v / v0)` growing by
    // `ln 2` with each doubling of its bias `b`. So `V^(1 / beta)` grows by
    // equal steps, and `V` itself by growing ones (a plain sum would grow
    // by equal steps): two objects a little beyond the edge count for less
    // than one twice as far beyond it.
    let visibility = |bias: f32| {
        let mut sel = Selector::new(display(), visibility_budgeted(1e6));
        let p = sel
            .add_profile(&two_lod_profile([4000, 1000], 60.0))
            .unwrap();
        let id = on_axis(&mut sel, p, -10.0);
        sel.set_bias(id, bias).unwrap();
        sel.select(&frame_at(DVec3::ZERO, 0.016)).unwrap();
        assert_eq!(sel.selection(id).lod(), Some(1), "bias {bias}");
        sel.selection_visibility_deg().unwrap()
    };
    let beta = f64::from(VISIBILITY_POOLING_EXPONENT);
    assert!(beta > 1.0);
    let [a, b, c] = [2.0, 4.0, 8.0].map(visibility);
    assert!(a > 0.0, "{a}");
    let root = |v: f64| v.powf(1.0 / beta);
    let (first, second) = (root(b) - root(a), root(c) - root(b));
    assert!(
        (first - second).abs() < 1e-3 * root(c),
        "{a} {b} {c}: steps {first} {second}"
    );
    assert!(c - b > 1.05 * (b - a), "{a} {b} {c}");
}

#[test]
fn below_s_1_a_visibility_budget_spends_its_degrees_beyond_the_triangles_from_s() {
    let budget_deg = 64.0;
    let frame = frame_at(DVec3::ZERO, 0.016);
    let (mut at_one, _) = random_scene(visibility_budgeted(budget_deg), 2000, 9, DVec3::ZERO);
    at_one.select(&frame).unwrap();
    let mut above = at_one.triangles();
    let spent = |sel: &Selector| sel.selection_visibility_deg().unwrap();
    for scale in [0.9, 0.7, 0.4, 0.2, 0.1] {
        let frame = with_scale(frame, scale);
        let (mut off, _) = random_scene(visibility_budgeted(NEAR_ZERO_DEG), 2000, 9, DVec3::ZERO);
        let (mut on, _) = random_scene(visibility_budgeted(budget_deg), 2000, 9, DVec3::ZERO);
        off.select(&frame).unwrap();
        on.select(&frame).unwrap();
        // Not `s = 1`'s selection again while the budget from `s` is
        // looser: a lower `s` always draws fewer triangles.
        assert!(
            on.triangles() < above,
            "s = {scale}: {} triangles, {above} at the s above",
            on.triangles()
        );
        assert!(on.triangles() < off.triangles(), "s = {scale}: none spent");
        let beyond_deg = spent(&on) - spent(&off);
        assert!(
            beyond_deg > 0.0 && beyond_deg <= f64::from(budget_deg) * 1.001,
            "s = {scale}: {beyond_deg} deg beyond the budget from s alone"
        );
        above = on.triangles();
    }
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 48, failure_persistence: None, ..Default::default() })]

    #[test]
    fn a_visibility_budget_never_draws_more_and_its_visibility_stays_finite(
        seed in 0u64..1000,
        scale in 1e-4f32..=1.0,
        budget_deg in proptest::prop_oneof![
            4 => 0.0f32..200.0,
            1 => proptest::num::f32::ANY,
        ],
    ) {
        let frame = with_scale(frame_at(DVec3::ZERO, 0.016), scale);
        // One `s` for all: what the budget from `s` allows. The budget
        // prices steps from within the invisible zone, so its order may
        // differ from the rule without it, but it never draws more.
        let (mut uniform, _) = random_scene(SelectorSettings::default(), 300, seed, DVec3::ZERO);
        let (mut on, _) = random_scene(visibility_budgeted(budget_deg), 300, seed, DVec3::ZERO);
        uniform.select(&frame).unwrap();
        on.select(&frame).unwrap();
        proptest::prop_assert!(on.triangles() <= uniform.triangles(), "{} deg at s = {}", budget_deg, scale);
        // Monotone in `s`: lower never draws more (a fresh selector, so no
        // switch rule carries the higher `s`'s LODs over).
        let (mut lower, _) = random_scene(visibility_budgeted(budget_deg), 300, seed, DVec3::ZERO);
        lower.select(&with_scale(frame_at(DVec3::ZERO, 0.016), scale * 0.8)).unwrap();
        proptest::prop_assert!(lower.triangles() <= on.triangles(), "{} deg: s = {} drew {}, {} at s = {}", budget_deg, scale * 0.8, lower.triangles(), on.triangles(), scale);
        if let Some(v) = on.selection_visibility_deg() {
            proptest::prop_assert!(v.is_finite() && v >= 0.0, "{} deg shown", v);
        }
    }
}

#[test]
fn the_imperceptible_budget_is_the_calibration_on_the_selectors_display_and_follows_it() {
    let on = |display: &Display| VisibilityBudget::Imperceptible.deg_on(display);
    let reddy = Display::new([640, 480], [43.6, 33.4]).unwrap();
    assert!((on(&reddy) - IMPERCEPTIBLE_VISIBILITY_DEG).abs() < 1e-4);
    // A sum over the image: 2.25 times the field's area, 2.25 times the budget.
    let wide = Display::new([960, 768], [65.4, 50.1]).unwrap();
    assert!((on(&wide) / on(&reddy) - 2.25).abs() < 0.01);
    assert_eq!(VisibilityBudget::Off.deg_on(&wide), 0.0);

    // Calibrated with the steady switch rules, and set with them.
    let just = SelectorSettings::just_imperceptible();
    assert_eq!(
        (
            just.switch_hysteresis,
            just.switch_min_dwell_s,
            just.switch_coarsen_delay_s
        ),
        (
            STEADY_SWITCH_HYSTERESIS,
            STEADY_SWITCH_MIN_DWELL_S,
            STEADY_SWITCH_COARSEN_DELAY_S
        )
    );

    let frame = frame_at(DVec3::ZERO, 0.016);
    let (mut plain, ids) = random_scene(SelectorSettings::default(), 3000, 8, DVec3::ZERO);
    let (mut calibrated, _) =
        random_scene(SelectorSettings::just_imperceptible(), 3000, 8, DVec3::ZERO);
    let (mut fixed, _) = random_scene(visibility_budgeted(on(&display())), 3000, 8, DVec3::ZERO);
    for sel in [&mut plain, &mut calibrated, &mut fixed] {
        sel.select(&frame).unwrap();
    }
    assert_eq!(lods(&calibrated, &ids), lods(&fixed, &ids));
    assert!(
        calibrated.triangles() < plain.triangles(),
        "the calibrated budget saved nothing at s = 1"
    );
    let spent = |sel: &Selector| sel.selection_visibility_deg().unwrap();
    let (mut none, _) = random_scene(visibility_budgeted(NEAR_ZERO_DEG), 3000, 8, DVec3::ZERO);
    none.select(&frame).unwrap();
    assert!(spent(&calibrated) - spent(&none) <= f64::from(on(&display())) * 1.0001);
    // A new display: the budget of its field, with no new settings (the
    // wider field spends more than the old budget).
    let on_wide = |settings: SelectorSettings| {
        let (mut sel, _) = random_scene(settings, 3000, 8, DVec3::ZERO);
        sel.set_display(wide);
        sel.select(&frame).unwrap();
        spent(&sel)
    };
    let near_zero = SelectorSettings {
        visibility_budget: VisibilityBudget::Deg(NEAR_ZERO_DEG),
        ..SelectorSettings::just_imperceptible()
    };
    let shown = on_wide(SelectorSettings::just_imperceptible()) - on_wide(near_zero);
    assert!(
        shown <= f64::from(on(&wide)) * 1.0001 && shown > f64::from(on(&display())),
        "{shown} deg on a field with a budget of {} deg",
        on(&wide)
    );
}

#[test]
fn a_floor_outside_its_domain_never_gives_a_scale_outside_it() {
    // NaN, infinite, zero, negative or above 1: the selection reaches no
    // scale outside `[LOWEST_MIN_SCALE, 1]`, and a floor that is not
    // finite is the default one.
    let frame = frame_at(DVec3::ZERO, 0.016);
    for rule in [BudgetRule::BestEffort, BudgetRule::UniformScale] {
        let scene = |min_scale| {
            let settings = SelectorSettings {
                min_scale,
                budget_rule: rule,
                ..SelectorSettings::default()
            };
            random_scene(settings, 500, 7, DVec3::ZERO).0
        };
        for floor in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 0.0, -1.0, 2.0] {
            let mut sel = scene(floor);
            // A floor that is not finite selects as the default floor,
            // frame by frame (as the schedulers read it).
            let mut with_default =
                (!floor.is_finite()).then(|| scene(SelectorSettings::default().min_scale));
            for budget in [10, 20_000, u64::MAX] {
                let out = sel.select_within_budget(&frame, budget).unwrap();
                assert!(
                    out.scale.is_finite() && (acuity::LOWEST_MIN_SCALE..=1.0).contains(&out.scale),
                    "{rule:?}, floor {floor}, budget {budget}: {out:?}"
                );
                assert_eq!(out.triangles, sel.triangles());
                if let Some(reference) = &mut with_default {
                    let default = reference.select_within_budget(&frame, budget).unwrap();
                    assert_eq!(out, default, "{rule:?}: {floor} is the default floor");
                }
            }
        }
    }
}

/// The settings whose `select` spends `s` as a budget, with and without
/// the visibility budget and the steady switch rules, and the default.
fn scale_rules() -> [(&'static str, SelectorSettings); 4] {
    let imperceptible = SelectorSettings::just_imperceptible();
    [
        ("default", SelectorSettings::default()),
        ("budgeted scale", budgeted_scale()),
        (
            "visibility budget",
            SelectorSettings {
                switch_hysteresis: 0.0,
                switch_min_dwell_s: 0.0,
                switch_coarsen_delay_s: 0.0,
                ..imperceptible
            },
        ),
        ("just imperceptible", imperceptible),
    ]
}

#[test]
fn a_budget_never_draws_more_than_the_selection_without_it_and_one_that_does_not_bind_draws_the_same()
 {
    for (name, settings) in scale_rules() {
        for scale in [1.0f32, 0.5, 0.1] {
            for share in [f64::INFINITY, 0.8, 0.5] {
                let (mut free, ids) = random_scene(settings, 3000, 8, DVec3::ZERO);
                let (mut capped, _) = random_scene(settings, 3000, 8, DVec3::ZERO);
                for i in 0..60 {
                    let frame = FrameInput {
                        scale,
                        ..frame_at(DVec3::new(0.0, 0.0, -0.5 * f64::from(i)), 1.0 / 60.0)
                    };
                    free.select(&frame).unwrap();
                    let budget = if share.is_finite() {
                        (free.triangles() as f64 * share) as u64
                    } else {
                        u64::MAX
                    };
                    let out = capped.select_within_budget(&frame, budget).unwrap();
                    let what = format!("{name}, s = {scale}, budget x{share}, frame {i}");
                    assert!(out.triangles <= free.triangles(), "{what}: drew more");
                    if share.is_infinite() {
                        assert_eq!(lods(&capped, &ids), lods(&free, &ids), "{what}");
                    } else {
                        assert_eq!(out.within_budget, out.triangles <= budget, "{what}");
                    }
                }
            }
        }
    }
}

#[test]
fn the_triangles_a_budget_draws_never_fall_as_it_rises() {
    let frame = FrameInput {
        scale: 0.5,
        ..frame_at(DVec3::ZERO, 1.0 / 60.0)
    };
    for (name, settings) in scale_rules() {
        let (mut free, _) = random_scene(settings, 2000, 9, DVec3::ZERO);
        free.select(&frame).unwrap();
        let mut last = 0;
        for percent in (5..=110).step_by(5) {
            let budget = free.triangles() * percent / 100;
            let (mut sel, _) = random_scene(settings, 2000, 9, DVec3::ZERO);
            let drawn = sel.select_within_budget(&frame, budget).unwrap().triangles;
            assert!(
                drawn >= last,
                "{name}: {percent}% drew {drawn}, less did {last}"
            );
            last = drawn;
        }
        assert_eq!(last, free.triangles(), "{name}");
    }
}
