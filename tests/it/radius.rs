//! The boundary searches against independent answers: the brake-on-entry closed form, a
//! plain bisection over full analyses, monotonicity in W, and radius/max-speed inversion.

use proptest::prelude::*;
use safereach::analysis::radius::{max_speed, safe_radius};
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::{DangerRule, Problem};
use safereach::proof::certificate::{Certificate, check};

use crate::common::paths::seed_file;
use crate::common::spec::{Spec, cents};

/// A problem with the seed's controller but a reaction radius of 1 m (not validated).
#[allow(clippy::too_many_arguments)]
fn problem(
    v: f64,
    a: f64,
    b: f64,
    dt: f64,
    latency: u32,
    rule: DangerRule,
    w: f64,
    g0: f64,
) -> Problem {
    Spec {
        name: "radius-test",
        v_max: v,
        a,
        b,
        dt,
        latency,
        rho: 1.0,
        rule,
        w,
        g0,
        ..Spec::seed()
    }
    .build()
}

fn certified_at(p: &Problem, rho: f64) -> bool {
    let mut q = p.clone();
    q.controller.reaction_radius = rho;
    analyse(&q).expect("analyses").verdict == Verdict::Certified
}

/// The oracle: bisection on the verdict alone, 45 halvings.
fn bisect_radius(p: &Problem, mut lo: f64, mut hi: f64) -> f64 {
    assert!(
        !certified_at(p, lo) && certified_at(p, hi),
        "bad bracket [{lo}, {hi}]"
    );
    for _ in 0..45 {
        let mid = 0.5 * (lo + hi);
        if certified_at(p, mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// Brake on entry, no latency, cruising robot: ρ* = v²/(2b) + W·v/b + (v+W)·dt.
    #[test]
    fn brake_on_entry_radius_is_the_closed_form(
        v in cents(20, 150), b in cents(20, 300), dt in cents(2, 20), w in cents(1, 100),
    ) {
        let p = problem(v, 1.0, b, dt, 0, DangerRule::Area, w, 60.0);
        let closed = v * v / (2.0 * b) + w * v / b + (v + w) * dt;
        prop_assume!(closed < 30.0);
        let found = safe_radius(&p).expect("searches").value.expect("a radius exists");
        prop_assert!((found - closed).abs() <= 1e-9, "rho* {found} vs closed form {closed}");
    }
}

#[test]
fn radius_agrees_with_bisection_over_certify() {
    let cases = [
        problem(0.2, 0.1, 0.05, 0.1, 1, DangerRule::Paper, 0.15, 10.0),
        problem(0.8, 0.4, 0.5, 0.1, 2, DangerRule::Kinematic, 0.15, 6.0),
        problem(0.8, 0.4, 0.5, 0.1, 0, DangerRule::Kinematic, 0.3, 6.0),
        problem(0.5, 0.2, 0.3, 0.2, 1, DangerRule::Area, 0.25, 4.0),
        problem(1.0, 0.5, 1.0, 0.05, 3, DangerRule::Paper, 0.1, 3.0),
        problem(0.6, 0.6, 0.4, 0.1, 1, DangerRule::Area, 0.0, 5.0),
    ];
    for p in &cases {
        let b = safe_radius(p).expect("searches");
        let Some(rho) = b.value else {
            // No radius: then the largest radius the search tried must be uncertified too.
            assert!(
                !certified_at(p, p.environment.initial_gap.min()),
                "{:?}: {:?}",
                p,
                b.reason
            );
            continue;
        };
        let oracle = bisect_radius(p, 1e-6, p.environment.initial_gap.min());
        assert!(
            (rho - oracle).abs() <= 1e-8,
            "{p:?}: search {rho} vs bisection {oracle}"
        );
        // Newton needs a slope: with W > 0 a handful of analyses suffice. A static obstacle
        // makes s*(rho) a step function (one deterministic behaviour): bisection it is.
        if p.environment.obstacle_speed > 0.0 {
            assert!(b.analyses <= 15, "{} analyses for {p:?}", b.analyses);
        }
    }
}

#[test]
fn radius_comes_with_a_certificate_above_and_a_refutation_below() {
    let p = Problem::load(&seed_file()).expect("seed loads");
    let b = safe_radius(&p).expect("searches");
    let above = b.certified.expect("certified side");
    assert_eq!(above.verdict, Verdict::Certified);
    check(&Certificate::from_analysis(&above)).expect("certificate above rho* verifies");
    let below = b.refuted.expect("refuted side");
    assert_eq!(below.verdict, Verdict::Refuted);
    assert!(below.witness.expect("witness").collides);
}

#[test]
fn safe_radius_grows_with_the_obstacle_speed() {
    let mut last = 0.0;
    for w in [0.0, 0.05, 0.1, 0.15, 0.2, 0.25] {
        let p = problem(0.2, 0.1, 0.05, 0.1, 1, DangerRule::Paper, w, 10.0);
        let rho = safe_radius(&p)
            .expect("searches")
            .value
            .expect("a radius exists");
        assert!(rho >= last - 1e-9, "rho*({w}) = {rho} < {last}");
        last = rho;
    }
}

/// The seed's robot at ρ = 1.3 m under each rule (latency 1, 0 and 2), with its rule.
fn seed_at_rho_1_3() -> impl Iterator<Item = (DangerRule, Problem)> {
    [
        (DangerRule::Paper, 1),
        (DangerRule::Area, 0),
        (DangerRule::Kinematic, 2),
    ]
    .into_iter()
    .map(|(rule, latency)| {
        let mut p = problem(0.2, 0.1, 0.05, 0.1, latency, rule, 0.15, 10.0);
        p.controller.reaction_radius = 1.3;
        (rule, p)
    })
}

#[test]
fn max_speed_and_radius_are_inverse() {
    for (rule, p) in seed_at_rho_1_3() {
        let w_star = max_speed(&p)
            .expect("searches")
            .value
            .expect("some speed certified");
        // W* is the certified end of its bracket, so the radius search at W* itself has an
        // answer (at the root s* = 0 and, with the kinematic rule, ρ = 1.3 is already the
        // largest radius that changes anything).
        let mut q = p.clone();
        q.environment.obstacle_speed = w_star;
        let rho = safe_radius(&q)
            .expect("searches")
            .value
            .expect("a radius exists");
        assert!(
            (rho - 1.3).abs() <= 1e-7,
            "{rule:?}: radius(max_speed(1.3) = {w_star}) = {rho}"
        );
    }
}

#[test]
fn no_radius_when_the_danger_distance_caps_the_reaction() {
    // The kinematic rule reacts only within d_coll(v_max); a fast obstacle beats that.
    let mut p = problem(0.8, 0.4, 0.5, 0.1, 1, DangerRule::Kinematic, 0.6, 10.0);
    p.controller.wrong_assumption_brake = false;
    let b = safe_radius(&p).expect("searches");
    assert_eq!(b.value, None);
    let why = b.reason.expect("a reason");
    assert!(why.contains("danger distance"), "{why}");
    assert!(!certified_at(&p, 9.0));
}

/// The problem with its searched parameter set to `value`, analysed: certified, and its
/// certificate passes the exact check.
fn assert_certified_at(p: &Problem, value: f64, speed: bool, what: &str) {
    let mut q = p.clone();
    if speed {
        q.environment.obstacle_speed = value;
    } else {
        q.controller.reaction_radius = value;
    }
    let a = analyse(&q).expect("analyses");
    assert_eq!(
        a.verdict,
        Verdict::Certified,
        "{what}: {value} is not certified"
    );
    check(&Certificate::from_analysis(&a)).expect("the certificate at the boundary verifies");
}

#[test]
fn reported_boundaries_are_certified_numbers() {
    // The number printed is the certified end of the bracket, not its midpoint: on the seed
    // at rho = 1.3 with the kinematic rule and latency 2 the midpoint lay 5e-11 above W*.
    for (rule, p) in seed_at_rho_1_3() {
        let b = max_speed(&p).expect("searches");
        let w = b.value.expect("some speed certified");
        assert_certified_at(&p, w, true, &format!("{rule:?} W*"));
        let at = b.certified.as_ref().expect("the analysis at W*");
        assert_eq!(at.problem.environment.obstacle_speed, w);
        // The printed decimal is the value itself.
        assert!(
            b.describe(&p).contains(&format!("{w:.10}")),
            "{}",
            b.describe(&p)
        );
        assert_eq!(format!("{w:.10}").parse::<f64>().expect("a number"), w);
        let r = safe_radius(&p).expect("searches");
        let rho = r.value.expect("a radius exists");
        assert_certified_at(&p, rho, false, &format!("{rule:?} rho*"));
        assert_eq!(format!("{rho:.10}").parse::<f64>().expect("a number"), rho);
    }
}
