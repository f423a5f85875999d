//! Benchmark: the planar `certify` (issue 36, item 6) on the shipped seed in the plane and
//! the crossing car, against the line's analyser on the seed in the same run (the ratio is
//! what compares across machines), and how the cost grows with the number of obstacles
//! (copies of the seed's obstacle further out) and with the horizon (the control period
//! halved); and the solver-free `check` of each certificate. Run with
//! `cargo bench --bench planar`.

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use safereach::analysis::analyse;
use safereach::analysis::planar::{BoundOptions, ProblemText, certify_planar, planar_certificate};
use safereach::core::model::Problem;
use safereach::core::num::{Exact, exact_decimal};
use safereach::core::planar::{PlanarParams, PlanarProblem, Start};
use safereach::core::plane::point::Point;
use safereach::proof::planar::check::check_planar;

#[path = "support/median.rs"]
mod support;

fn load(name: &str) -> PlanarParams {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    PlanarProblem::load(&root.join(format!("problems/planar/{name}.toml")))
        .expect("a shipped planar problem")
        .params()
}

fn certify_time(params: &PlanarParams, rounds: usize) -> (Duration, usize) {
    let tolerance = exact_decimal(1e-6);
    let mut programs = 0;
    let t = support::median(rounds, || {
        let a = certify_planar(black_box(params), &BoundOptions::default(), &tolerance)
            .expect("bounds");
        programs = a.programs;
    });
    (t, programs)
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let seed = Problem::load(&root.join("problems/seed.toml")).expect("the seed");
    let line = support::median(21, || {
        black_box(analyse(black_box(&seed)).expect("analyses"));
    });
    println!("line seed analyse (baseline): {line:?}");
    for name in ["seed-in-plane", "crossing-car"] {
        let params = load(name);
        let (t, programs) = certify_time(&params, 5);
        println!(
            "planar certify {name}: {t:?} ({programs} programs, {:?} per program, {:.0}x the baseline)",
            t / programs.max(1) as u32,
            t.as_secs_f64() / line.as_secs_f64()
        );
        let text = std::fs::read_to_string(root.join(format!("problems/planar/{name}.toml")))
            .expect("a shipped planar problem");
        let options = BoundOptions::default();
        let answer = certify_planar(&params, &options, &exact_decimal(1e-6)).expect("bounds");
        let stored = ProblemText {
            toml: &text,
            overrides: &[],
        };
        let cert = planar_certificate(&stored, name, &params, &answer, &options, 1e-6);
        let c = support::median(5, || {
            black_box(check_planar(black_box(&cert)).expect("checks"));
        });
        println!(
            "planar check {name}: {c:?} ({} leaves, {:.0}x the baseline)",
            cert.leaves(),
            c.as_secs_f64() / line.as_secs_f64()
        );
    }
    let base = load("seed-in-plane");
    for n in [1usize, 2, 4] {
        let mut params = base.clone();
        let first = params.obstacles[0].clone();
        params.obstacles = (0..n)
            .map(|i| {
                let mut o = first.clone();
                o.name = format!("o{i}");
                if let Start::At(p) = &first.start {
                    o.start = Start::At(Point::new(&p.x + Exact::from(i as i64), p.y.clone()));
                }
                o
            })
            .collect();
        let (t, programs) = certify_time(&params, 3);
        println!("seed-in-plane with {n} obstacles: {t:?} ({programs} programs)");
    }
    let mut fine = base.clone();
    fine.motion.dt = &fine.motion.dt / Exact::from(2);
    let (t, programs) = certify_time(&fine, 3);
    println!("seed-in-plane with dt halved (twice the periods): {t:?} ({programs} programs)");
}
