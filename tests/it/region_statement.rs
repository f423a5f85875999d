//! Region statements of `radius` and `max-speed` (issue 11): "certified for every W ≤ W0 at
//! every ρ ≥ ρ0". The two facts behind them are held to the simulator and the analyser on
//! random problems: (1) a slower world is a sub-world (s* never falls as W falls); (2) radii
//! beyond ρ_sat = g0 + σ_g are decided alike (the same choices give the same run, and the
//! analyser the same verdict and s*). The statements themselves are held to `certify` at
//! random points of the quarter-plane they claim, far beyond the map's own range; the
//! command line prints and writes them as documented.

use proptest::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use safereach::analysis::radius::{max_speed, safe_radius};
use safereach::analysis::region_statement::{region_statement, saturation_radius};
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::{Params, Problem, Sensing};
use safereach::core::num::{Exact, exact_decimal};
use safereach::core::simulate::{horizon, run_choosing, trace};
use safereach::proof::region_check::check_map;

use crate::common::cli::{safereach, stdout};
use crate::common::paths::{load_problem, seed_file};
use crate::common::spec::{any_spec, cents, config};
use crate::common::tmp;

fn with_noise(mut p: Problem, sigma_g: f64, sigma_w: f64) -> Problem {
    if sigma_g > 0.0 || sigma_w > 0.0 {
        p.sensing = Some(Sensing {
            gap_noise: Some(sigma_g),
            speed_noise: Some(sigma_w),
            first_detection_gap: None,
        });
    }
    p
}

/// The verdict and s* `certify` gives `p` with W and ρ set.
fn at(p: &Problem, w: f64, rho: f64) -> (Verdict, f64) {
    let mut q = p.clone();
    q.environment.obstacle_speed = w;
    q.controller.reaction_radius = rho;
    let a = analyse(&q).expect("analyses");
    (a.verdict, a.min_separation.unwrap_or(f64::INFINITY))
}

proptest! {
    #![proptest_config(config(48))]

    /// Fact 2 in the simulator, in exact arithmetic: the same speeds and observation errors
    /// give the same run at ρ_sat and at any larger radius, row for row. (In floats an
    /// observation g + σ_g may round above ρ_sat: the fact is about the exact semantics.)
    #[test]
    fn radii_beyond_the_farthest_reading_give_the_same_runs(
        spec in any_spec(), sigma_g in cents(0, 5), sigma_w in cents(0, 3),
        extra in cents(1, 500), seed in 0u64..1000,
    ) {
        let p = with_noise(spec.problem(), sigma_g, sigma_w);
        let sat = saturation_radius(&p);
        let periods = horizon(&p.params::<f64>());
        let mut params = p.params::<Exact>();
        let runs = |params: &Params<Exact>| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let choices: Vec<(Exact, bool)> = (0..periods)
                .map(|_| {
                    let u = Exact::from(rng.random_range(0..=1000u32)) / Exact::from(1000u32);
                    (params.W.clone() * u, rng.random::<bool>())
                })
                .collect();
            let run = run_choosing(params.clone(), params.g0.clone(), |k| choices[k].clone(), 0,
                periods, false);
            trace(params, &run)
        };
        params.rho = exact_decimal(sat);
        let at_sat = runs(&params);
        params.rho = exact_decimal(sat + extra);
        prop_assert_eq!(at_sat, runs(&params));
    }

    /// Fact 2 in the analyser, and fact 1: certified at W0 stays certified below it, with an
    /// s* that does not fall.
    #[test]
    fn the_analyser_agrees_with_both_facts(
        spec in any_spec(), sigma_g in cents(0, 3), extra in cents(1, 500), fraction in 0.0..1.0f64,
    ) {
        let p = with_noise(spec.problem(), sigma_g, 0.0);
        let sat = saturation_radius(&p);
        let (w, rho) = (p.environment.obstacle_speed, p.controller.reaction_radius);
        let (v1, s1) = at(&p, w, sat);
        let (v2, s2) = at(&p, w, sat + extra);
        prop_assert_eq!(v1, v2);
        prop_assert!((s1 - s2).abs() <= 1e-6 || s1 == s2, "s* {} vs {}", s1, s2);
        let (v0, s0) = at(&p, w, rho);
        let (vs, ss) = at(&p, w * fraction, rho);
        if v0 == Verdict::Certified {
            prop_assert_eq!(vs, Verdict::Certified);
        }
        if v0 != Verdict::Inconclusive && vs != Verdict::Inconclusive {
            prop_assert!(ss >= s0 - 1e-6, "slower W: s* {} < {}", ss, s0);
        }
    }
}

/// Why ρ_sat includes σ_g: a reading g + σ_g of an obstacle just inside g0 is outside a
/// radius of g0 but inside ρ_sat, so an obstacle seen faster than V_a is a wrong assumption
/// at ρ_sat and beyond, not at g0. Exact runs, the errors keeping the guard quiet.
#[test]
fn the_farthest_reading_is_g0_plus_the_gap_noise() {
    let mut spec = crate::common::spec::Spec::seed();
    (spec.g0, spec.v_a, spec.w, spec.latency, spec.wab) = (2.0, 0.05, 0.2, 0, true);
    let p = with_noise(spec.problem(), 0.05, 0.0);
    let sat = saturation_radius(&p);
    assert_eq!(sat, 2.05);
    let rows = |rho: f64| {
        let mut params = p.params::<Exact>();
        params.rho = exact_decimal(rho);
        let w = params.W.clone();
        let run = run_choosing(
            params.clone(),
            params.g0.clone(),
            |_| (w.clone(), false),
            0,
            400,
            false,
        );
        trace(&params, &run)
    };
    let (at_g0, at_sat, beyond) = (rows(2.0), rows(sat), rows(sat + 1.0));
    assert_eq!(at_sat, beyond);
    assert_ne!(
        at_g0, at_sat,
        "at ρ = g0 the reading g + σ_g is outside the area"
    );
}

/// `radius` and `max-speed` statements, at random points of the quarter-plane they claim
/// (W down to 0, ρ up to three times the map's end): every point certifies.
#[test]
fn statements_hold_at_random_points_far_beyond_their_maps() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let seed = Problem::load(&seed_file()).unwrap();
    let noisy = load_problem(
        "seed.toml",
        &[
            "sensing.gap_noise=0.01",
            "robot.latency=2",
            "controller.danger_rule=\"kinematic\"",
        ],
    );
    let mut statements = Vec::new();
    for (p, w) in [(&seed, 0.15), (&seed, 0.25), (&noisy, 0.1)] {
        let mut q = p.clone();
        q.environment.obstacle_speed = w;
        let b = safe_radius(&q).unwrap();
        let rho0 = b
            .certified
            .as_ref()
            .unwrap()
            .problem
            .controller
            .reaction_radius;
        statements.push((p, region_statement(&q, w, rho0).unwrap()));
    }
    let b = max_speed(&seed).unwrap();
    let w0 = b
        .certified
        .as_ref()
        .unwrap()
        .problem
        .environment
        .obstacle_speed;
    statements.push((&seed, region_statement(&seed, w0, 1.4).unwrap()));
    for (p, st) in &statements {
        assert!(st.holds(), "{}", st.describe());
        check_map(&st.map).expect("the map checks");
        assert!(st.radius >= p.controller.reaction_radius.min(st.radius));
        for _ in 0..12 {
            let w = st.speed * rng.random::<f64>();
            let rho = st.radius + 3.0 * st.saturation * rng.random::<f64>();
            let (v, s) = at(p, w, rho);
            assert_eq!(v, Verdict::Certified, "W = {w}, ρ = {rho}: s* = {s}");
        }
        let (v, _) = at(p, st.speed, st.radius);
        assert_eq!(v, Verdict::Certified, "the statement's own corner");
    }
}

#[test]
fn the_command_line_states_writes_and_refuses() {
    let dir = tmp();
    let out = safereach(dir.path())
        .arg("radius")
        .arg(seed_file())
        .args(["--speeds", "0.15", "--region", "--certificates", "out"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let text = stdout(&out);
    assert!(
        text.contains("region: certified for every W <= 0.15 m/s at every rho >= 1.070000001"),
        "{text}"
    );
    let check = safereach(dir.path())
        .args(["check", "out/radius-W0.15.region.json"])
        .output()
        .unwrap();
    assert_eq!(check.status.code(), Some(0), "{}", stdout(&check));
    assert!(stdout(&check).contains("the whole box is certified"));

    let out = safereach(dir.path())
        .arg("max-speed")
        .arg(seed_file())
        .args(["--region", "--json", "--region-out", "ms.json"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    let json: serde_json::Value = serde_json::from_str(&stdout(&out)).unwrap();
    assert_eq!(json["region"]["holds"], true);
    assert_eq!(json["region"]["radius"], 1.4);
    assert!(
        json["region"]["speed"].as_f64().unwrap() <= json["max_obstacle_speed"].as_f64().unwrap()
    );
    assert!(dir.path().join("ms.json").exists());

    // Region certificates do not cover occlusion with the wrong-assumption guard active:
    // the point answer stands, the statement is not established (exit 3), with the reason.
    let out = safereach(dir.path())
        .arg("radius")
        .arg(seed_file())
        .args(["--set", "sensing.first_detection_gap=1.5"])
        .args(["--set", "controller.assumed_obstacle_speed=0.1", "--region"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(3), "{}", stdout(&out));
    let text = stdout(&out);
    assert!(text.contains("safe radius 1.0700000001 m"), "{text}");
    assert!(
        text.contains("region: not established: sensing.first_detection_gap"),
        "{text}"
    );

    // A scene: refused before any work.
    let out = safereach(dir.path())
        .arg("radius")
        .arg(crate::common::paths::problem_file("seed-lanes.toml"))
        .arg("--region")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("not scenes"));
}
