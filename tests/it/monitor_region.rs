//! The monitor built from a region map (issue 11): it is the monitor of the point
//! certificate at the box's least demanding corner (W, σ and the clearance at their upper
//! ends, ρ and the buffer at their lower, V_a as named), held against that certificate,
//! which `certify` proves independently, sample by sample on simulated runs; traces of any
//! certified point of the box hold; a map or leaf that is not certified, a ranged V_a left
//! unnamed, a value outside the box and a tampered map are refused; and the command line
//! answers as documented.

use safereach::analysis::monte_carlo_run;
use safereach::analysis::region_search::{RegionOptions, map_region};
use safereach::analysis::{Verdict, analyse};
use safereach::core::model::Problem;
use safereach::core::param_box::{Axis, ParamBox};
use safereach::core::parameter::Parameter;
use safereach::core::simulate::{horizon, trace};
use safereach::monitor::{Monitor, MonitorError, RegionPoint, Sample};
use safereach::proof::certificate::Certificate;
use safereach::proof::region_map::{LeafVerdict, RegionMap};

use crate::common::cli::{safereach, seed_box_region, stdout};
use crate::common::monitoring::{sample_events, samples_of};
use crate::common::paths::seed_file;
use crate::common::tmp;

fn map(problem: &Problem, axes: &[(Parameter, f64, f64)], depth: u32) -> RegionMap {
    let axes = axes
        .iter()
        .map(|&(parameter, lo, hi)| Axis::new(parameter, lo, hi))
        .collect();
    let options = RegionOptions {
        depth,
        min_width: 0.0,
        ..RegionOptions::default()
    };
    map_region(problem, &ParamBox::new(axes).unwrap(), &options, &|_| {}).expect("mappable")
}

/// The monitor of the point certificate `certify` gives `problem` with `sets` applied.
fn point_monitor(problem: &Problem, sets: &[(Parameter, f64)]) -> Monitor {
    let mut p = problem.clone();
    for &(parameter, v) in sets {
        parameter.set_in(&mut p, v);
    }
    let analysis = analyse(&p).expect("analyses");
    assert_eq!(analysis.verdict, Verdict::Certified, "the corner {sets:?}");
    Monitor::new(&Certificate::from_analysis(&analysis)).expect("certified")
}

/// Seeded random runs of `problem`'s controller with `sets` applied, each as samples with
/// and without stated speeds.
fn runs(problem: &Problem, sets: &[(Parameter, f64)], count: usize) -> Vec<Vec<Sample>> {
    let mut p = problem.clone();
    for &(parameter, v) in sets {
        parameter.set_in(&mut p, v);
    }
    let params = p.params::<f64>();
    (0..count)
        .flat_map(|i| {
            let run = monte_carlo_run(&params, 7, i, horizon(&params), false);
            // A hidden obstacle's trace starts at the true position its first sighting shows
            // (a sensor reports nothing of it before).
            let shown = run
                .records
                .iter()
                .position(|r| r.observation.is_some())
                .map_or(0, |k| k.saturating_sub(params.L));
            let rows = &trace(&params, &run)[shown..];
            [samples_of(rows, true), samples_of(rows, false)]
        })
        .collect()
}

/// Every run gives the same events, sample by sample, to both monitors; how many runs raised
/// anything.
fn same_events(a: &Monitor, b: &Monitor, traces: &[Vec<Sample>]) -> usize {
    let mut raised = 0;
    for samples in traces {
        let (mut a, mut b) = (a.clone(), b.clone());
        for s in samples {
            assert_eq!(a.observe(s).events, b.observe(s).events, "at t = {}", s.t);
        }
        raised += usize::from(a.verdict() != safereach::monitor::Verdict::Held);
    }
    raised
}

use Parameter::{AssumedObstacleSpeed as Va, Buffer, ObstacleSpeed as W, ReactionRadius as Rho};

#[test]
fn a_certified_box_is_monitored_as_its_least_demanding_corner() {
    let seed = Problem::load(&seed_file()).unwrap();
    let m = map(&seed, &[(W, 0.10, 0.20), (Rho, 1.3, 1.6)], 4);
    assert!(m.all_certified(), "the box certifies whole");
    let by_map = Monitor::for_region(&m, &RegionPoint::default()).expect("monitorable");
    let corner = point_monitor(&seed, &[(W, 0.20), (Rho, 1.3)]);

    // Runs of controllers across the box and beyond it, obstacles within W and beyond it.
    let mut raised = 0;
    for (w, rho) in [
        (0.12, 1.3),
        (0.2, 1.3),
        (0.2, 1.6),
        (0.18, 1.45),
        (0.25, 1.4),
        (0.2, 1.1),
    ] {
        let traces = runs(&seed, &[(W, w), (Rho, rho)], 12);
        let r = same_events(&by_map, &corner, &traces);
        if w <= 0.2 && rho >= 1.3 {
            assert_eq!(r, 0, "a certified point's runs hold (W = {w}, ρ = {rho})");
        }
        raised += r;
    }
    assert!(raised > 0, "runs beyond the box are flagged");

    // The box covers more than a point inside it: W = 0.18 runs hold here, not under W = 0.15.
    let inner = point_monitor(&seed, &[(W, 0.15), (Rho, 1.3)]);
    let faster = runs(&seed, &[(W, 0.18), (Rho, 1.3)], 12);
    let flagged = faster
        .iter()
        .filter(|s| !sample_events(&mut inner.clone(), s).is_empty())
        .count();
    assert!(
        flagged > 0,
        "the point certificate at W = 0.15 flags W = 0.18 runs"
    );
    assert!(
        faster
            .iter()
            .all(|s| sample_events(&mut by_map.clone(), s).is_empty())
    );

    // A named controller value inside the box gives that point's controller.
    let at = RegionPoint {
        leaf: None,
        controller: vec![(Rho, 1.5)],
    };
    let named = Monitor::for_region(&m, &at).unwrap();
    let corner = point_monitor(&seed, &[(W, 0.20), (Rho, 1.5)]);
    let traces = runs(&seed, &[(W, 0.2), (Rho, 1.3)], 8);
    assert!(
        same_events(&named, &corner, &traces) > 0,
        "a ρ = 1.3 robot is late for ρ = 1.5"
    );
}

#[test]
fn a_leaf_of_a_partial_map_is_monitored_as_its_own_corner() {
    let seed = Problem::load(&seed_file()).unwrap();
    let m = map(&seed, &[(W, 0.10, 0.30), (Rho, 1.0, 1.6)], 6);
    assert!(!m.all_certified());
    let whole = Monitor::for_region(&m, &RegionPoint::default());
    assert!(
        matches!(&whole, Err(MonitorError::Region(why)) if why.contains("--leaf")),
        "{whole:?}"
    );
    let mut checked = 0;
    for leaf in &m.leaves {
        let at = RegionPoint {
            leaf: Some(leaf.path.clone()),
            controller: vec![],
        };
        let got = Monitor::for_region(&m, &at);
        if leaf.verdict != LeafVerdict::Certified {
            assert!(matches!(got, Err(MonitorError::Region(_))), "{}", leaf.path);
            continue;
        }
        let [w_lo, w_hi] = leaf.bounds[W.key()];
        let [rho_lo, _] = leaf.bounds[Rho.key()];
        let corner = point_monitor(&seed, &[(W, w_hi), (Rho, rho_lo)]);
        let traces = runs(&seed, &[(W, (w_lo + w_hi) / 2.0), (Rho, rho_lo)], 3);
        assert_eq!(same_events(&got.unwrap(), &corner, &traces), 0);
        checked += 1;
    }
    assert!(checked >= 3, "{checked} certified leaves");
}

#[test]
fn what_cannot_be_monitored_is_refused_with_the_reason() {
    let seed = Problem::load(&seed_file()).unwrap();
    let m = map(&seed, &[(Va, 0.15, 0.2), (Buffer, 0.05, 0.1)], 2);
    assert!(m.all_certified());
    let refused = |at: RegionPoint, needle: &str| match Monitor::for_region(&m, &at) {
        Err(MonitorError::Region(why)) => assert!(why.contains(needle), "{why}"),
        other => panic!("{at:?}: {other:?}"),
    };
    let named = |controller| RegionPoint {
        leaf: None,
        controller,
    };
    refused(named(vec![]), "controller.assumed_obstacle_speed");
    refused(named(vec![(Va, 0.25)]), "outside the box");
    refused(named(vec![(Va, 0.2), (Rho, 1.4)]), "not ranged");
    let fast = RegionPoint {
        leaf: Some("zz".into()),
        controller: vec![(Va, 0.2)],
    };
    refused(fast, "no leaf");

    // Named: the certificate at that V_a, with the buffer at its lower end.
    let by_map = Monitor::for_region(&m, &named(vec![(Va, 0.17)])).unwrap();
    let corner = point_monitor(&seed, &[(Va, 0.17), (Buffer, 0.05)]);
    let traces = runs(&seed, &[(W, 0.19), (Va, 0.15)], 8);
    assert!(same_events(&by_map, &corner, &traces) > 0);

    // An environment key cannot be named; a tampered map is not monitored.
    let speeds = map(&seed, &[(W, 0.10, 0.15)], 1);
    let at = named(vec![(W, 0.12)]);
    assert!(
        matches!(Monitor::for_region(&speeds, &at), Err(MonitorError::Region(why)) if why.contains("upper end"))
    );
    let mut edited = speeds.clone();
    edited.ranges[0].hi = 0.3;
    edited.digest = edited.compute_digest();
    assert!(matches!(
        Monitor::for_region(&edited, &RegionPoint::default()),
        Err(MonitorError::Invalid(_))
    ));
}

#[test]
fn the_command_line_monitors_a_map() {
    let dir = tmp();
    seed_box_region(dir.path(), &["--out", "map.json"]);
    let trace = |w: &str, name: &str| {
        let out = safereach(dir.path())
            .arg("simulate")
            .arg(seed_file())
            .args(["--set", &format!("environment.obstacle_speed={w}")])
            .args(["--set", "controller.reaction_radius=1.3", "--trace", name])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(0));
    };
    trace("0.18", "slow.csv");
    trace("0.3", "fast.csv");
    let monitor = |args: &[&str]| {
        safereach(dir.path())
            .args(["monitor", "--certificate", "map.json", "--events-only"])
            .args(args)
            .output()
            .unwrap()
    };
    let held = monitor(&["slow.csv"]);
    assert_eq!(held.status.code(), Some(0), "{}", stdout(&held));
    assert!(stdout(&held).contains("bound 0.2 m/s"));
    let late = monitor(&["slow.csv", "--at", "controller.reaction_radius=1.5"]);
    assert_eq!(late.status.code(), Some(1));
    assert!(stdout(&late).contains("controller_reaction"));
    let fast = monitor(&["fast.csv"]);
    assert_eq!(fast.status.code(), Some(1));
    assert!(stdout(&fast).contains("obstacle_speed"));
    for (args, needles) in [
        (
            vec!["slow.csv", "--at", "controller.reaction_radius=1.7"],
            ["map.json", "outside the box's [1.3, 1.6]"],
        ),
        (
            vec!["slow.csv", "--at", "radius"],
            ["--at \"radius\"", "KEY=VALUE"],
        ),
        (vec!["slow.csv", "--leaf", "aB"], ["map.json", "no leaf"]),
    ] {
        let out = monitor(&args);
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(needles.iter().all(|n| err.contains(n)), "{err}");
    }
    // --leaf and --at belong to maps.
    let certificate = safereach(dir.path())
        .args(["certify"])
        .arg(seed_file())
        .args(["--out", "cert.json"])
        .output()
        .unwrap();
    assert_eq!(certificate.status.code(), Some(0));
    let out = safereach(dir.path())
        .args([
            "monitor",
            "--certificate",
            "cert.json",
            "slow.csv",
            "--leaf",
            "a",
        ])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("cert.json is a certificate"));
}

#[test]
fn a_ranged_first_sighting_is_monitored_at_its_lower_end() {
    use Parameter::FirstDetectionGap as Det;
    let seed = Problem::load(&seed_file()).unwrap();
    let m = map(&seed, &[(W, 0.10, 0.15), (Det, 1.1, 1.5)], 4);
    assert!(
        m.all_certified(),
        "the box certifies whole: {:?}",
        m.coverage
    );
    let by_map = Monitor::for_region(&m, &RegionPoint::default()).expect("monitorable");
    let corner = point_monitor(&seed, &[(W, 0.15), (Det, 1.1)]);
    // Runs whose obstacles stay hidden until a gap near 1.1 m: within the box's premises.
    let late = runs(&seed, &[(W, 0.15), (Det, 1.1)], 12);
    assert_eq!(same_events(&by_map, &corner, &late), 0);
    // The upper end would flag them: a sighting below 1.5 m breaks its premise.
    let upper = point_monitor(&seed, &[(W, 0.15), (Det, 1.5)]);
    let flagged = late
        .iter()
        .filter(|s| !sample_events(&mut upper.clone(), s).is_empty())
        .count();
    assert!(flagged > 0, "d_det = 1.5 flags sightings at 1.1 m");
}
