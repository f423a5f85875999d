//! Benchmark: scenes in the library. How certification time and the number of pieces grow
//! with the number of moving obstacles in the robot's lane (1, 2, 4, 8, 16), as a ratio
//! against the one-obstacle scene measured in the same run; and the shipped scenes.
//! Run with `cargo bench --bench scenes`. No timing assertions anywhere: speed is measured
//! here, never in tests.

#[path = "support/median.rs"]
mod support_median;

use std::hint::black_box;
use std::path::Path;
use std::time::{Duration, Instant};

use support_median::median;

use safereach::analysis::scene::analyse_scene;
use safereach::core::scene::{Obstacle, Position, Scene};
use safereach::proof::scene_certificate::SceneCertificate;
use safereach::proof::scene_check::check_scene;
use safereach::proof::search_certificate::certify_by_search;
use safereach::proof::search_check::check_search;

/// Median time per call of `f`, over as many calls (3 to 101) as fit in about half a
/// second: a few-millisecond case needs many to see past a loaded machine's noise.
fn median_within_budget(mut f: impl FnMut()) -> Duration {
    let start = Instant::now();
    f();
    let once = start.elapsed().max(Duration::from_micros(1));
    let rounds = (Duration::from_millis(500).as_nanos() / once.as_nanos()).clamp(3, 101) as usize;
    median(rounds | 1, f)
}

/// The seed robot with `n` oncoming obstacles in its lane, 1.5 m apart from 10 m on, with
/// bounds 0.10–0.20 m/s (all below V_a = 0.2).
fn oncoming(base: &Scene, n: usize) -> Scene {
    let mut s = base.clone();
    s.obstacles = (0..n)
        .map(|i| Obstacle {
            name: format!("o{i}"),
            lane: 0,
            position: Position::At(10.0 + 1.5 * i as f64),
            max_speed: [0.15, 0.1, 0.2, 0.12][i % 4],
            is_static: false,
        })
        .collect();
    s
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let base = Scene::load(&root.join("problems/scene-oncoming.toml")).expect("scene loads");
    println!(
        "| moving obstacles | verdict | s* (m) | pieces | programs | certify (ms) | ratio to 1 | check (ms) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    let mut one = None;
    for n in [1, 2, 4, 8, 16] {
        let scene = oncoming(&base, n);
        let a = analyse_scene(&scene).expect("analyses");
        let cert = SceneCertificate::from_analysis(&a);
        check_scene(&cert).expect("checks");
        let rounds = if n <= 2 { 9 } else { 5 };
        let t = median(rounds, || {
            black_box(analyse_scene(black_box(&scene)).expect("analyses"));
        });
        let c = median(rounds, || {
            black_box(check_scene(black_box(&cert)).expect("checks"));
        });
        let base_t = *one.get_or_insert(t);
        println!(
            "| {n} | {} | {:.3} | {} | {} | {:.1} | {:.2} | {:.1} |",
            a.verdict.as_str(),
            a.min_separation.unwrap_or(f64::NAN),
            cert.pieces(),
            a.programs_solved,
            t.as_secs_f64() * 1e3,
            t.as_secs_f64() / base_t.as_secs_f64(),
            c.as_secs_f64() * 1e3,
        );
    }
    println!();
    for name in ["scene-oncoming", "scene-destination", "scene-short-sensing"] {
        let scene = Scene::load(&root.join(format!("problems/{name}.toml"))).expect("loads");
        let a = analyse_scene(&scene).expect("analyses");
        let t = median(5, || {
            black_box(analyse_scene(black_box(&scene)).expect("analyses"));
        });
        println!(
            "{name}: {} with {} pieces, {} programs, {:.1} ms",
            a.verdict.as_str(),
            SceneCertificate::from_analysis(&a).pieces(),
            a.programs_solved,
            t.as_secs_f64() * 1e3
        );
    }
    println!();
    lane_changes(root);
}

/// The exact run search on scenes with lane changes: the shipped ones, and the seed's
/// picture with 1, 2, 3, 4, 8 oncoming obstacles in the robot's lane (parked cars beside).
fn lane_changes(root: &Path) {
    println!(
        "| scene | verdict | s* (m) | runs | step starts | certify (ms) | ratio | check (ms) |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- |");
    let lanes = Scene::load(&root.join("problems/seed-lanes.toml")).expect("loads");
    let mut cases: Vec<(String, Scene)> =
        ["seed-lanes", "lane-change-saves", "lane-change-refused"]
            .iter()
            .map(|name| {
                let s = Scene::load(&root.join(format!("problems/{name}.toml"))).expect("loads");
                (name.to_string(), s)
            })
            .collect();
    for n in [1, 2, 3, 4, 8] {
        let mut s = lanes.clone();
        let parked: Vec<Obstacle> = s.obstacles[1..].to_vec();
        s.obstacles = oncoming(&lanes, n).obstacles;
        s.obstacles.extend(parked);
        cases.push((format!("seed-lanes, {n} oncoming"), s));
    }
    let mut one = None;
    for (name, scene) in cases {
        let cert = certify_by_search(&scene).expect("searched");
        let t = median_within_budget(|| {
            black_box(certify_by_search(black_box(&scene)).expect("searched"));
        });
        let c = median_within_budget(|| {
            black_box(check_search(black_box(&cert)).expect("checks"));
        });
        let base_t = *one.get_or_insert(t);
        println!(
            "| {name} | {} | {} | {} | {} | {:.1} | {:.2} | {:.1} |",
            cert.verdict.as_str(),
            cert.min_separation_exact.as_deref().unwrap_or("-"),
            cert.runs,
            cert.nodes,
            t.as_secs_f64() * 1e3,
            t.as_secs_f64() / base_t.as_secs_f64(),
            c.as_secs_f64() * 1e3,
        );
    }
}
