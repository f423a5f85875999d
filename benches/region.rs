//! Benchmark: the certified map of the seed plane W ∈ [0.10, 0.30] m/s × ρ ∈ [1.0, 1.6] m
//! (issue target: undecided ≤ 1% of the plane, ≤ 1 s on 2 cores), against a point sweep of
//! the same resolution (one cell per smallest leaf's width and height) measured in the same
//! run; and the map of a scene's plane (the far obstacle's own W_1 against ρ in
//! problems/scene-oncoming.toml) at depths 8 and 10. Run with `cargo bench --bench region`.

use std::time::Instant;

use rayon::prelude::*;
use safereach::analysis::region_search::{RegionOptions, map_region, map_scene_region};
use safereach::analysis::{Options, Verdict, WitnessPolicy, analyse_with};
use safereach::core::model::Problem;
use safereach::core::param_box::{Axis, ParamBox};
use safereach::core::parameter::Parameter;
use safereach::core::scene::Scene;
use safereach::proof::region_check::check_map;
use safereach::proof::region_map::{LeafVerdict, box_at};

fn main() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let seed = Problem::load(&root.join("problems/seed.toml")).expect("the seed loads");
    let whole = ParamBox::new(vec![
        Axis::new(Parameter::ObstacleSpeed, 0.10, 0.30),
        Axis::new(Parameter::ReactionRadius, 1.0, 1.6),
    ])
    .expect("a valid box");
    for depth in [12, 14, 16] {
        let options = RegionOptions {
            depth,
            min_width: 0.0,
            ..RegionOptions::default()
        };
        let start = Instant::now();
        let map = map_region(&seed, &whole, &options, &|_| {}).expect("maps");
        let took = start.elapsed().as_secs_f64();
        let start = Instant::now();
        check_map(&map).expect("the map checks");
        let checked = start.elapsed().as_secs_f64();
        let count = |v| map.leaves.iter().filter(|l| l.verdict == v).count();
        println!(
            "region depth {depth}: {:.2} s on {} threads, check {:.2} s; {} leaves ({} certified, {} refuted, {} undecided), {} programs solved; area certified {:.2}%, refuted {:.2}%, undecided {:.2}%",
            took,
            rayon::current_num_threads(),
            checked,
            map.leaves.len(),
            count(LeafVerdict::Certified),
            count(LeafVerdict::Refuted),
            count(LeafVerdict::Undecided),
            map.programs_solved,
            100.0 * map.coverage.certified,
            100.0 * map.coverage.refuted,
            100.0 * map.coverage.undecided,
        );
        if depth != 16 {
            continue;
        }
        // A point sweep as fine as the map's smallest leaves.
        let (mut dw, mut dr) = (f64::INFINITY, f64::INFINITY);
        for l in &map.leaves {
            let b = box_at(&whole, &l.path).expect("a path the search made");
            dw = dw.min(b.axes[0].hi - b.axes[0].lo);
            dr = dr.min(b.axes[1].hi - b.axes[1].lo);
        }
        let nw = (0.2 / dw).ceil() as usize;
        let nr = (0.6 / dr).ceil() as usize;
        let cells: Vec<(f64, f64)> = (0..nw)
            .flat_map(|i| {
                (0..nr).map(move |j| {
                    (
                        0.10 + 0.2 * (i as f64 + 0.5) / nw as f64,
                        1.0 + 0.6 * (j as f64 + 0.5) / nr as f64,
                    )
                })
            })
            .collect();
        // Every 40th cell, timed and scaled up: the whole sweep takes minutes.
        let sample: Vec<(f64, f64)> = cells.iter().copied().step_by(40).collect();
        let start = Instant::now();
        let certified = sample
            .par_iter()
            .filter(|(w, r)| {
                let mut p = seed.clone();
                p.environment.obstacle_speed = *w;
                p.controller.reaction_radius = *r;
                let options = Options {
                    witness: WitnessPolicy::ToRefute,
                };
                analyse_with(&p, options).is_ok_and(|a| a.verdict == Verdict::Certified)
            })
            .count();
        let sweep = start.elapsed().as_secs_f64() * cells.len() as f64 / sample.len() as f64;
        println!(
            "point sweep at the finest leaves' resolution: {} x {} = {} cells, {:.1} s (scaled from {} timed cells, {} of them certified; a statement about those points only); ratio sweep/region = {:.0}x",
            nw,
            nr,
            cells.len(),
            sweep,
            sample.len(),
            certified,
            sweep / took
        );
    }
    scene_plane(root);
}

/// The scene plane's maps: time, check, leaves, programs and areas.
fn scene_plane(root: &std::path::Path) {
    let scene = Scene::load(&root.join("problems/scene-oncoming.toml")).expect("the scene loads");
    let whole = ParamBox::new(vec![
        Axis {
            obstacle: Some(1),
            ..Axis::new(Parameter::ObstacleSpeed, 0.10, 0.30)
        },
        Axis::new(Parameter::ReactionRadius, 1.0, 1.6),
    ])
    .expect("a valid box");
    for depth in [8, 10] {
        let options = RegionOptions {
            depth,
            ..RegionOptions::default()
        };
        let start = Instant::now();
        let map = map_scene_region(&scene, &whole, &options, &|_| {}).expect("maps");
        let took = start.elapsed().as_secs_f64();
        let start = Instant::now();
        check_map(&map).expect("the map checks");
        let checked = start.elapsed().as_secs_f64();
        println!(
            "scene-oncoming W_1 x rho, depth {depth}: {took:.2} s on {} threads, check {checked:.2} s; {} leaves, {} programs solved; area certified {:.2}%, refuted {:.2}%, undecided {:.2}%",
            rayon::current_num_threads(),
            map.leaves.len(),
            map.programs_solved,
            100.0 * map.coverage.certified,
            100.0 * map.coverage.refuted,
            100.0 * map.coverage.undecided,
        );
    }
}
