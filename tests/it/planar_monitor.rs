//! The planar monitor (`monitor::planar`) against the planar model itself: every run of the
//! model (random headings, speeds, starts and hiding, replayed exactly) is a trace on which
//! no premise and no model check may fail, on every shipped planar problem — danger zones
//! (disc, polygon), range, field of view, hiding, regions; and each way a trace can leave the
//! model is caught by the check that names it.

use std::collections::BTreeSet;

use safereach::analysis::planar::{PlanarTraceRow, planar_trace, random_run};
use safereach::core::planar::PlanarProblem;
use safereach::core::semantics::Mode;
use safereach::monitor::planar::{PlanarMonitor, PlanarSample};
use safereach::monitor::{Check, Verdict};

const PROBLEMS: [&str; 5] = [
    "seed-in-plane",
    "crossing-car",
    "pedestrian-crossing",
    "overtaking",
    "nav2-stop-polygon",
];

fn problem(name: &str) -> PlanarProblem {
    let path = format!("{}/problems/planar/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    PlanarProblem::load(std::path::Path::new(&path)).expect("a shipped problem")
}

fn mode(name: &str) -> Mode {
    Mode::from_name(name.as_bytes()).expect("a mode")
}

/// The rows of random run `seed` of `p` (at most `steps` periods), and whether it collided.
fn random_trace(p: &PlanarProblem, seed: u64, steps: usize) -> (Vec<PlanarTraceRow>, bool) {
    let params = p.params();
    let run = random_run(&params, seed, steps, &params.motion.clearance).expect("a run");
    let (rows, _) = planar_trace(&params, &run.behaviour, steps).expect("replays");
    (rows, run.collided)
}

fn sample(r: &PlanarTraceRow, id: u32) -> PlanarSample {
    PlanarSample {
        t: r.t,
        robot_x: r.robot_x,
        robot_y: r.robot_y,
        robot_v: r.robot_speed,
        robot_mode: Some(mode(&r.mode)),
        obstacle_id: id,
        obstacle_x: r.x,
        obstacle_y: r.y,
        obstacle_velocity: r.vx.zip(r.vy),
    }
}

/// The checks `rows` violate under `p`'s premises, obstacles identified by name.
fn violated(p: &PlanarProblem, rows: &[PlanarTraceRow]) -> BTreeSet<&'static str> {
    monitored(p, rows).0
}

/// [`violated`], and the monitor after the trace.
fn monitored(
    p: &PlanarProblem,
    rows: &[PlanarTraceRow],
) -> (BTreeSet<&'static str>, PlanarMonitor) {
    let mut monitor = PlanarMonitor::for_problem(p);
    let mut names: Vec<String> = Vec::new();
    let mut found = BTreeSet::new();
    for r in rows {
        let id = match names.iter().position(|n| *n == r.obstacle) {
            Some(i) => i as u32,
            None => {
                names.push(r.obstacle.clone());
                let id = names.len() as u32 - 1;
                monitor.identify(id, &r.obstacle);
                id
            }
        };
        for e in monitor.observe(&sample(r, id)).events {
            found.insert(e.check.as_str());
        }
    }
    assert_eq!(monitor.verdict() == Verdict::Held, found.is_empty());
    (found, monitor)
}

#[test]
fn runs_of_the_model_raise_nothing_but_their_own_collisions_on_every_planar_problem() {
    for name in PROBLEMS {
        let p = problem(name);
        let mut collided = 0;
        let mut reactions = 0;
        for seed in 0..10 {
            let (rows, collides) = random_trace(&p, seed, 400);
            let (found, monitor) = monitored(&p, &rows);
            reactions += monitor.checks(Check::ControllerReaction);
            let expected: BTreeSet<&str> = if collides {
                collided += 1;
                // Judged at instants: a run may touch within a step and part again.
                found
                    .iter()
                    .copied()
                    .filter(|&c| c == "collision")
                    .collect()
            } else {
                BTreeSet::new()
            };
            assert_eq!(found, expected, "{name}, run {seed}");
        }
        eprintln!("{name}: 10 runs, {collided} colliding, {reactions} reactions judged");
        assert!(reactions > 0, "{name}: the controller was never judged");
    }
}

/// A run of the seed in the plane (run 3: the robot brakes for the oncoming obstacle).
fn seed_rows() -> (PlanarProblem, Vec<PlanarTraceRow>) {
    let p = problem("seed-in-plane");
    let (rows, collides) = random_trace(&p, 3, 700);
    assert!(!collides);
    assert!(rows.iter().any(|r| r.mode == "brake"), "the run brakes");
    assert!(violated(&p, &rows).is_empty());
    (p, rows)
}

/// `rows` after `edit`, and the checks the edited trace violates.
fn after(
    p: &PlanarProblem,
    rows: &[PlanarTraceRow],
    edit: impl FnOnce(&mut Vec<PlanarTraceRow>),
) -> BTreeSet<&'static str> {
    let mut rows = rows.to_vec();
    edit(&mut rows);
    violated(p, &rows)
}

/// An edit of a trace.
type Edit = Box<dyn FnOnce(&mut Vec<PlanarTraceRow>)>;

#[test]
fn each_way_out_of_the_model_is_caught_by_its_check() {
    let (p, rows) = seed_rows();
    let brake = rows.iter().position(|r| r.mode == "brake").expect("brakes");
    let cases: Vec<(&str, Edit)> = vec![
        (
            "obstacle_speed",
            Box::new(|r: &mut Vec<PlanarTraceRow>| {
                // From step 50 on it closes 0.05 m per period more: 0.5 m/s above its W.
                for (k, row) in r.iter_mut().enumerate().skip(50) {
                    row.x -= 0.05 * (k - 49) as f64;
                    row.vx = None;
                    row.vy = None;
                }
            }),
        ),
        (
            "observation_inconsistent",
            Box::new(|r: &mut Vec<PlanarTraceRow>| r[60].vy = Some(0.1)),
        ),
        (
            "controller_reaction",
            Box::new(move |r: &mut Vec<PlanarTraceRow>| {
                for row in r.iter_mut().skip(brake).take(2) {
                    row.mode = "drive".into();
                }
            }),
        ),
        (
            "robot_path",
            Box::new(|r: &mut Vec<PlanarTraceRow>| r[80].robot_y = 0.01),
        ),
        (
            "uncertified_obstacle",
            Box::new(|r: &mut Vec<PlanarTraceRow>| {
                for row in r.iter_mut() {
                    row.obstacle = "ghost".into();
                }
            }),
        ),
        (
            "obstacle_start",
            Box::new(|r: &mut Vec<PlanarTraceRow>| {
                for row in r.iter_mut() {
                    row.x += 1.0;
                }
            }),
        ),
        (
            "robot_envelope",
            Box::new(|r: &mut Vec<PlanarTraceRow>| r[120].robot_speed = 0.25),
        ),
        (
            "robot_motion",
            Box::new(|r: &mut Vec<PlanarTraceRow>| {
                for row in r.iter_mut().skip(150) {
                    row.robot_x += 0.05;
                }
            }),
        ),
        (
            "control_period",
            Box::new(|r: &mut Vec<PlanarTraceRow>| {
                r.remove(100);
            }),
        ),
        (
            "braking_deceleration",
            Box::new(move |r: &mut Vec<PlanarTraceRow>| {
                // Slower braking from the brake on: its speed falls by half of b_min·dt.
                let v0 = r[brake].robot_speed;
                for (k, row) in r.iter_mut().enumerate().skip(brake + 1).take(3) {
                    row.robot_speed = v0 - 0.0025 * (k - brake) as f64;
                }
            }),
        ),
    ];
    for (check, edit) in cases {
        let found = after(&p, &rows, edit);
        assert!(found.contains(check), "{check}: {found:?}");
    }
}

#[test]
fn an_obstacle_leaving_its_region_or_reaching_the_robot_is_reported() {
    let p = problem("crossing-car");
    let (rows, collides) = random_trace(&p, 1, 400);
    assert!(violated(&p, &rows).is_empty() || collides);
    // The car's lane is x in [11, 12.5]: 0.5 m beyond it.
    let found = after(&p, &rows, |r| r[30].x = 13.0);
    assert!(found.contains("obstacle_region"), "{found:?}");
    // The car's centre on the moving robot's.
    let moving = rows
        .iter()
        .position(|r| r.robot_speed > 0.0)
        .expect("moves");
    let found = after(&p, &rows, |r| {
        r[moving].x = r[moving].robot_x;
        r[moving].y = r[moving].robot_y;
    });
    assert!(found.contains("collision"), "{found:?}");
}

#[test]
fn a_robot_that_drives_past_its_destination_is_reported() {
    // The seed's robot with a path that ends 3 m on: it must brake before it.
    let text = std::fs::read_to_string(format!(
        "{}/problems/planar/seed-in-plane.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replacen(
        "radius = 0.0 ",
        "radius = 0.0\npath = [[0, 0], [3, 0]]\n#",
        1,
    );
    let p = PlanarProblem::from_toml_str(&text, "seed with a destination").expect("reads");
    let (rows, _) = random_trace(&p, 0, 400);
    assert!(violated(&p, &rows).is_empty());
    let rest = rows
        .iter()
        .position(|r| r.mode == "brake")
        .expect("brakes for the end");
    // It drives on at its speed where braking at b would end exactly at the path's end.
    let (x, v) = (rows[rest].robot_x, rows[rest].robot_speed);
    let found = after(&p, &rows, |r| {
        for (k, row) in r.iter_mut().skip(rest).take(3).enumerate() {
            row.mode = "drive".into();
            row.robot_speed = v;
            row.robot_x = x + v * 0.1 * k as f64;
        }
    });
    assert!(found.contains("controller_reaction"), "{found:?}");
}
