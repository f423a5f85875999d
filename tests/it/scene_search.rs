//! The exact run search (`proof::scene_search`) against independent answers.

use safereach::analysis::analyse;
use safereach::analysis::scene::analyse_scene;
use safereach::core::model::Problem;
use safereach::core::num::Scalar;
use safereach::core::scene::Scene;
use safereach::proof::scene_search::{Separation, search_scene};

use crate::common::paths::load_problem;

fn load_scene(name: &str) -> Scene {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("problems")
        .join(name);
    Scene::load_with_overrides(&path, &[]).expect("scene loads")
}

#[test]
fn print_shipped() {
    for name in [
        "scene-oncoming.toml",
        "scene-destination.toml",
        "scene-short-sensing.toml",
    ] {
        let scene = load_scene(name);
        let t = std::time::Instant::now();
        let s = search_scene(&scene).expect("searched");
        let el = t.elapsed();
        let a = analyse_scene(&scene).expect("analysed");
        eprintln!(
            "{name}: search {:?} (unb {}) stats {:?} in {:?}; analyser {:?} never {}",
            s.min_separation().map(|v| v.as_f64()),
            s.unbounded(),
            s.stats,
            el,
            a.min_separation,
            a.never_stops
        );
        for (i, o) in s.obstacles.iter().enumerate() {
            eprintln!(
                "  {i}: {:?}",
                match o {
                    Separation::Finite(v) => Some(v.as_f64()),
                    _ => None,
                }
            );
        }
    }
    for name in [
        "seed.toml",
        "fast-obstacle.toml",
        "static-obstacle.toml",
        "area-rule.toml",
        "kinematic-rule.toml",
        "zero-latency.toml",
    ] {
        let problem: Problem = load_problem(name, &[]);
        let scene = Scene::from_problem(&problem);
        let t = std::time::Instant::now();
        let s = search_scene(&scene).expect("searched");
        let el = t.elapsed();
        let a = analyse(&problem).expect("analysed");
        eprintln!(
            "{name}: search {:?} (unb {}) {:?} in {:?}; analyser {:?}",
            s.min_separation().map(|v| v.as_f64()),
            s.unbounded(),
            s.stats,
            el,
            a.min_separation
        );
    }
}

#[test]
fn print_lanes() {
    for name in ["seed-lanes.toml"] {
        let scene = load_scene(name);
        let t = std::time::Instant::now();
        let s = search_scene(&scene).expect("searched");
        let el = t.elapsed();
        eprintln!(
            "{name}: search {:?} (unb {}) stats {:?} in {:?}",
            s.min_separation().map(|v| v.as_f64()),
            s.unbounded(),
            s.stats,
            el,
        );
        for (i, o) in s.obstacles.iter().enumerate() {
            eprintln!("  {i}: {:?}", o);
        }
        if let Some(w) = &s.worst {
            eprintln!(
                "worst {} {:?} {:?} {:?}",
                w.obstacle, w.worst.objective, w.leaf.ending, w.leaf.changes
            );
        }
    }
}

#[test]
fn print_certs() {
    use safereach::proof::search_certificate::certify_by_search;
    use safereach::proof::search_check::check_search;
    for name in [
        "seed-lanes.toml",
        "scene-short-sensing.toml",
        "scene-oncoming.toml",
        "scene-destination.toml",
    ] {
        let scene = load_scene(name);
        let c = certify_by_search(&scene).expect("cert");
        let w = c.witness.as_ref().unwrap();
        eprintln!(
            "{name}: {:?} s* {:?} lb {:?} witness sep {:?} collides {} changes {:?} brake {:?}",
            c.verdict,
            c.min_separation_exact,
            c.lower_bound,
            w.separation,
            w.collides,
            w.lane_changes,
            w.brake
        );
        eprintln!("  check {:?}", check_search(&c).map(|r| r.verdict));
    }
}
