//! The runtime monitor on scene certificates: runs of certified scenes, replayed exactly and
//! written by the scene trace writers, hold; a run that breaks one obstacle's own premise
//! (its W_i, its lane, standing still) is flagged at the first sample that shows it, naming
//! the obstacle; tracked objects the scene does not name are held to its largest moving
//! bound; `collision` counts exactly the samples the simulator's rows say are collisions, in
//! the lanes the robot occupies. Old single-obstacle certificates and traces give what they
//! always gave. Lane columns are read from both formats, and the command line works on scene
//! certificates with today's exit codes.
//!
//! Every expected answer comes from the simulator's rows or from the scene file, never from
//! the monitor itself.

use std::collections::BTreeSet;
use std::path::Path;

use safereach::analysis::Verdict as Proved;
use safereach::analysis::scene::analyse_scene;
use safereach::analysis::{RandomBehaviour, SpeedPattern};
use safereach::core::num::Exact;
use safereach::core::output::{
    scene_trace_csv, scene_trace_jsonl, trace_csv, trace_jsonl, write_atomic,
};
use safereach::core::scene::simulate::{SceneTraceRow, horizon, replay};
use safereach::core::scene::{LaneChange, Obstacle, Position, Scene, SceneParams};
use safereach::core::semantics::Mode;
use safereach::core::simulate::TraceRow;
use safereach::monitor::trace::{Decoded, Decoder, Format};
use safereach::monitor::{
    Check, Detail, Event, Field, Lanes, Monitor, MonitorError, Sample, Status,
};
use safereach::proof::certificate::Certificate;
use safereach::proof::certificate_file::CertificateFile;
use safereach::proof::scene_certificate::SceneCertificate;

use crate::common::cli::safereach;
use crate::common::monitoring::text_events;
use crate::common::paths::{fixture, load_problem, problem_file};
use crate::common::tmp;

// ------------------------------------------------------------------------------------------
// Scenes, certificates, runs
// ------------------------------------------------------------------------------------------

/// `problems/<name>.toml` as a scene.
fn shipped(name: &str) -> Scene {
    Scene::load(&problem_file(&format!("{name}.toml"))).expect("scene loads")
}

/// The shipped scene of several oncoming obstacles (W_i = 0.15, 0.2, 0.1) and a static box
/// in the next lane: its largest moving bound is 0.2 m/s.
fn oncoming() -> Scene {
    shipped("scene-oncoming")
}

/// The shipped destination scene with its goal 2 m ahead: the robot rests at its goal before
/// an obstacle faster than the controller assumes can reach it.
fn destination() -> Scene {
    let path = problem_file("scene-destination.toml");
    Scene::load_with_overrides(&path, &["robot.goal=2.0".to_string()]).expect("scene loads")
}

/// A static obstacle alone in the robot's lane (docs/semantics.md §11.8, at x0 = 10.01 so
/// that no observed gap lands on a threshold), with a clearance of 0.1 m.
fn static_in_lane() -> Scene {
    let problem = load_problem("static-obstacle.toml", &["robot.clearance=0.1"]);
    let mut scene = Scene::from_problem(&problem);
    scene.obstacles[0] = Obstacle {
        name: "wall".into(),
        lane: 0,
        position: Position::At(10.01),
        max_speed: 0.0,
        is_static: true,
    };
    scene
}

/// The scene's certificate, which must be `certified`.
fn certified(scene: &Scene) -> SceneCertificate {
    let analysis = analyse_scene(scene).expect("the scene is analysed");
    let cert = SceneCertificate::from_analysis(&analysis);
    assert_eq!(cert.verdict, Proved::Certified, "{}", scene.name);
    cert
}

fn monitor(cert: &SceneCertificate) -> Monitor {
    Monitor::for_scene(cert).expect("a certified scene certificate is monitored")
}

/// An exact replay of the scene with `speeds[i][k]` for obstacle i in period k (W_i after
/// the last), from each obstacle's nearest start, until the robot rests or nothing can
/// happen any more: its trace rows.
fn run(scene: &Scene, speeds: &[Vec<f64>]) -> Vec<SceneTraceRow> {
    let params: SceneParams<Exact> = scene.params();
    let starts: Vec<Exact> = params
        .obstacles
        .iter()
        .map(|o| o.start_min.clone())
        .collect();
    let periods = horizon(&scene.params::<f64>());
    replay(&params, speeds, &starts, periods, false).trace()
}

/// Every obstacle at its own W_i throughout.
fn at_full_speed(scene: &Scene) -> Vec<SceneTraceRow> {
    run(scene, &vec![Vec::new(); scene.obstacles.len()])
}

/// Monte Carlo run `i`: each obstacle's speeds drawn by the scene Monte Carlo's behaviours
/// (every speed pattern), replayed exactly.
fn random_run(scene: &Scene, i: usize) -> Vec<SceneTraceRow> {
    let params = scene.params::<f64>();
    let mut behaviour = RandomBehaviour::new(&params, 7, i, &SpeedPattern::ALL);
    let periods = horizon(&params);
    let speeds: Vec<Vec<f64>> = (0..scene.obstacles.len())
        .map(|j| (0..periods).map(|_| behaviour.next_speed(j)).collect())
        .collect();
    run(scene, &speeds)
}

/// A scene with one obstacle changed by `edit`.
fn with(scene: &Scene, name: &str, edit: impl FnOnce(&mut Obstacle)) -> Scene {
    let mut s = scene.clone();
    edit(
        s.obstacles
            .iter_mut()
            .find(|o| o.name == name)
            .expect("the obstacle exists"),
    );
    s
}

/// The events of a trace's text, fed as `safereach monitor` feeds it.
fn events_of(cert: &SceneCertificate, text: &str, format: Format) -> Vec<Event> {
    text_events(&mut monitor(cert), text, Some(format))
}

/// Events with their obstacle named as the trace names it: `(check, t, obstacle)`.
fn named(text: &str, format: Format, events: &[Event]) -> Vec<(Check, Option<f64>, String)> {
    let mut decoder = Decoder::new(Some(format), None, 1 << 16);
    for line in text.lines() {
        decoder.decode(line.as_bytes());
    }
    events
        .iter()
        .map(|e| {
            let name = e.obstacle_id.map_or("", |id| decoder.ids().name(id));
            (e.check, e.t, name.to_string())
        })
        .collect()
}

// ------------------------------------------------------------------------------------------
// Editing CSV traces (the scenes' names hold no commas)
// ------------------------------------------------------------------------------------------

/// One data row of a CSV trace, its cells by column name.
struct Row<'h> {
    header: &'h [String],
    cells: Vec<String>,
}

impl Row<'_> {
    fn column(&self, name: &str) -> usize {
        self.header.iter().position(|h| h == name).expect("column")
    }

    fn get(&self, name: &str) -> &str {
        &self.cells[self.column(name)]
    }

    fn t(&self) -> f64 {
        self.get("t").parse().unwrap()
    }

    fn set(&mut self, name: &str, value: &str) {
        let k = self.column(name);
        self.cells[k] = value.to_string();
    }
}

/// The CSV with `edit` applied to every data row.
fn edit_csv(text: &str, mut edit: impl FnMut(&mut Row)) -> String {
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut out = header.join(",") + "\n";
    for line in lines {
        let mut row = Row {
            header: &header,
            cells: line.split(',').map(String::from).collect(),
        };
        edit(&mut row);
        out += &(row.cells.join(",") + "\n");
    }
    out
}

/// The CSV without `columns`.
fn drop_columns(text: &str, columns: &[&str]) -> String {
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let keep: Vec<usize> = (0..header.len())
        .filter(|&k| !columns.contains(&header[k]))
        .collect();
    let pick = |line: &str| {
        let cells: Vec<&str> = line.split(',').collect();
        keep.iter().map(|&k| cells[k]).collect::<Vec<_>>().join(",") + "\n"
    };
    std::iter::once(header.join(","))
        .chain(lines.map(String::from))
        .map(|l| pick(&l))
        .collect()
}

const LANE_COLUMNS: [&str; 3] = ["robot_lane", "obstacle_lane", "leaving_lane"];

// ------------------------------------------------------------------------------------------
// Runs within the premises hold
// ------------------------------------------------------------------------------------------

/// Certified scenes: the witness and Monte Carlo runs of every speed pattern, replayed
/// exactly and written in both formats, raise no event; every scene obstacle is matched,
/// none is left unmatched, and `collision`, `obstacle_lane` and (where there is a static
/// obstacle) `static_obstacle` were checked and held.
#[test]
fn runs_of_certified_scenes_hold() {
    for scene in [oncoming(), destination(), static_in_lane()] {
        let cert = certified(&scene);
        let mut runs: Vec<Vec<SceneTraceRow>> = (0..12).map(|i| random_run(&scene, i)).collect();
        runs.push(at_full_speed(&scene));
        if let Some(w) = &cert.witness {
            let speeds: Vec<Vec<f64>> = w.obstacle_speeds.iter().map(|s| s.to_vec()).collect();
            runs.push(run(&scene, &speeds));
        }
        for (i, rows) in runs.iter().enumerate() {
            for (text, format) in [
                (scene_trace_csv(rows), Format::Csv),
                (scene_trace_jsonl(rows), Format::Jsonl),
            ] {
                let mut m = monitor(&cert);
                let events = text_events(&mut m, &text, Some(format));
                assert!(
                    events.is_empty(),
                    "{} run {i} {format:?}: {:?}",
                    scene.name,
                    named(&text, format, &events)
                );
                let summary = m.summary();
                let s = summary.scene.expect("a scene summary");
                assert_eq!(s.unmatched, 0);
                assert!(s.obstacles.iter().all(|o| o.seen && o.violations == 0));
                let status = |c: Check| s.checks.iter().find(|x| x.check == c).unwrap().status;
                let collision = summary
                    .behaviour
                    .iter()
                    .find(|x| x.check == Check::Collision);
                assert_eq!(collision.unwrap().status, Status::Held, "{}", scene.name);
                assert_eq!(status(Check::ObstacleLane), Status::Held);
                let has_static = scene.obstacles.iter().any(|o| o.is_static);
                let expected = if has_static {
                    Status::Held
                } else {
                    Status::NotChecked
                };
                assert_eq!(status(Check::StaticObstacle), expected, "{}", scene.name);
            }
        }
    }
}

// ------------------------------------------------------------------------------------------
// Per-obstacle bounds
// ------------------------------------------------------------------------------------------

/// "third" (W_i = 0.1) at 0.15 m/s — within the scene's largest bound 0.2, so a
/// single-bound monitor would pass it — is flagged at its first sample that shows the speed
/// (t = dt), against its own bound, naming it; with its speed estimated from positions too.
/// Renamed to an id the scene does not know, the same object passes (0.15 ≤ 0.2).
#[test]
fn a_named_obstacle_faster_than_its_own_bound_is_flagged() {
    let scene = oncoming();
    let cert = certified(&scene);
    let rows = at_full_speed(&with(&scene, "third", |o| o.max_speed = 0.15));
    let csv = scene_trace_csv(&rows);
    for (text, stated) in [
        (csv.clone(), true),
        (drop_columns(&csv, &["obstacle_v"]), false),
    ] {
        let events = events_of(&cert, &text, Format::Csv);
        let first = &events[0];
        assert_eq!(
            named(&text, Format::Csv, &events[..1]),
            [(Check::ObstacleSpeed, Some(0.1), "third".to_string())]
        );
        assert_eq!(first.bound, Some(0.1));
        let observed = first.observed.unwrap();
        if stated {
            assert_eq!(observed, 0.15);
        } else {
            assert!((observed - 0.15).abs() < 1e-9, "{observed}");
        }
        let names: BTreeSet<String> = named(&text, Format::Csv, &events)
            .into_iter()
            .map(|(check, _, name)| {
                assert_eq!(check, Check::ObstacleSpeed);
                name
            })
            .collect();
        assert_eq!(names, BTreeSet::from(["third".to_string()]));
    }
    let renamed = csv.replace(",third,", ",tracked-7,");
    assert!(events_of(&cert, &renamed, Format::Csv).is_empty());
    let mut m = monitor(&cert);
    text_events(&mut m, &renamed, Some(Format::Csv));
    let s = m.summary().scene.unwrap();
    assert_eq!(s.unmatched, 1);
    assert!(!s.obstacles.iter().find(|o| o.name == "third").unwrap().seen);
}

/// Tracked objects the scene does not name are held to its largest moving bound, 0.2 m/s:
/// one at 0.25 is flagged at each of its samples from t = dt on; one at 0.18 (above the
/// nearest obstacle's own 0.15) is not.
#[test]
fn an_unmatched_object_faster_than_the_largest_bound_is_flagged() {
    let scene = oncoming();
    let cert = certified(&scene);
    let mut wider = scene.clone();
    for (name, x, w) in [("stranger", 8.0, 0.25), ("visitor", 9.0, 0.18)] {
        wider.obstacles.push(Obstacle {
            name: name.into(),
            lane: 1,
            position: Position::At(x),
            max_speed: w,
            is_static: false,
        });
    }
    let rows = at_full_speed(&wider);
    let text = scene_trace_jsonl(&rows);
    let events = events_of(&cert, &text, Format::Jsonl);
    let expected: Vec<(Check, Option<f64>, String)> = rows
        .iter()
        .filter(|r| r.obstacle == "stranger" && r.row.t > 0.0)
        .map(|r| (Check::ObstacleSpeed, Some(r.row.t), "stranger".to_string()))
        .collect();
    assert!(!expected.is_empty());
    assert_eq!(named(&text, Format::Jsonl, &events), expected);
    assert!(events.iter().all(|e| e.bound == Some(0.2)));
    let mut m = monitor(&cert);
    text_events(&mut m, &text, Some(Format::Jsonl));
    assert_eq!(m.summary().scene.unwrap().unmatched, 2);
}

/// The static box moving at 0.05 m/s is flagged under `static_obstacle` from its first
/// sample that shows it (t = dt), from the stated speed and from positions alone. Moving
/// *away* by a millimetre, which `obstacle_speed` lets any moving obstacle do, is flagged
/// too — from its positions, although its stated speed is 0.
#[test]
fn a_static_obstacle_that_moves_is_flagged() {
    let scene = oncoming();
    let cert = certified(&scene);
    let rows = at_full_speed(&with(&scene, "box", |o| {
        o.is_static = false;
        o.max_speed = 0.05;
    }));
    let csv = scene_trace_csv(&rows);
    for text in [csv.clone(), drop_columns(&csv, &["obstacle_v"])] {
        let events = events_of(&cert, &text, Format::Csv);
        assert_eq!(
            named(&text, Format::Csv, &events[..1]),
            [(Check::StaticObstacle, Some(0.1), "box".to_string())]
        );
        assert!((events[0].observed.unwrap() - 0.05).abs() < 1e-9);
        assert_eq!(events[0].bound, Some(0.0));
        assert!(
            events
                .iter()
                .all(|e| e.check == Check::StaticObstacle && e.obstacle_id == events[0].obstacle_id)
        );
    }

    // Away by 1 mm from t = 1 s on; the stated speed stays 0.
    let held = scene_trace_csv(&at_full_speed(&scene));
    let mut first_moved = None;
    let away = edit_csv(&held, |row| {
        if row.get("obstacle_id") == "box" && row.t() >= 1.0 {
            first_moved.get_or_insert(row.t());
            row.set("obstacle_x", "5.001");
        }
    });
    let events = events_of(&cert, &away, Format::Csv);
    assert_eq!(
        named(&away, Format::Csv, &events),
        [(Check::StaticObstacle, first_moved, "box".to_string())]
    );
    assert!((events[0].observed.unwrap() - 0.001 / 0.1).abs() < 1e-9);
}

/// "first" reported in lane 1 from t = 2 s on: `obstacle_lane` at each of those samples,
/// observed 1, bound its certified lane 0. An unnamed object may be in any lane.
#[test]
fn a_named_obstacle_outside_its_lane_is_flagged() {
    let scene = oncoming();
    let cert = certified(&scene);
    let rows = at_full_speed(&scene);
    let held = scene_trace_csv(&rows);
    let moved = |row: &SceneTraceRow| row.obstacle == "first" && row.row.t >= 2.0;
    let text = edit_csv(&held, |row| {
        if row.get("obstacle_id") == "first" && row.t() >= 2.0 {
            row.set("obstacle_lane", "1");
        }
    });
    let events = events_of(&cert, &text, Format::Csv);
    let expected: Vec<_> = rows
        .iter()
        .filter(|r| moved(r))
        .map(|r| (Check::ObstacleLane, Some(r.row.t), "first".to_string()))
        .collect();
    assert_eq!(named(&text, Format::Csv, &events), expected);
    assert!(
        events
            .iter()
            .all(|e| e.observed == Some(1.0) && e.bound == Some(0.0))
    );
    let unnamed = text.replace(",first,", ",tracked-1,");
    assert!(events_of(&cert, &unnamed, Format::Csv).is_empty());
}

// ------------------------------------------------------------------------------------------
// Collisions, in the lanes the robot occupies
// ------------------------------------------------------------------------------------------

/// The samples the rows say are collisions: the robot moving with an obstacle ahead at a
/// gap ≤ clearance, or coming to rest within the step before the sample at a gap below it
/// (docs/semantics.md §6: braking at b_min from v, it rests v/b_min after the step's start,
/// the obstacle at its constant speed of the step), in its lane (`lanes`) or in any lane
/// (`!lanes`). (Every obstacle of these runs starts ahead, and the robot keeps lane 0.)
fn collisions(
    rows: &[SceneTraceRow],
    clearance: f64,
    b_min: f64,
    lanes: bool,
) -> Vec<(f64, String)> {
    // No gap on the clearance itself, where rounding would decide.
    assert!(
        rows.iter()
            .all(|r| r.row.robot_speed == 0.0 || (r.row.gap - clearance).abs() > 1e-9)
    );
    let previous = |k: usize| {
        rows[..k]
            .iter()
            .rev()
            .find(|p| p.obstacle == rows[k].obstacle)
    };
    rows.iter()
        .enumerate()
        .filter(|&(k, r)| {
            let r = &r.row;
            if r.robot_speed > 0.0 {
                return r.gap <= clearance;
            }
            previous(k).is_some_and(|p| {
                let p = &p.row;
                let rest = p.gap
                    - p.obstacle_speed * p.robot_speed / b_min
                    - (r.robot_position - p.robot_position);
                p.robot_speed > 0.0 && rest < clearance
            })
        })
        .map(|(_, r)| r)
        .filter(|r| !lanes || r.obstacle_lane == r.robot_lane)
        .map(|r| (r.row.t, r.obstacle.clone()))
        .collect()
}

/// The monitor's `collision` events as (t, obstacle).
fn collision_events(text: &str, format: Format, events: &[Event]) -> Vec<(f64, String)> {
    named(text, format, events)
        .into_iter()
        .filter(|(c, _, _)| *c == Check::Collision)
        .map(|(_, t, name)| (t.unwrap(), name))
        .collect()
}

/// "first" at 0.6 m/s runs into the robot: `collision` is raised at exactly the samples the
/// rows show as collisions in the robot's lane, with the lane columns; without them, at the
/// rows' collisions with any obstacle (`lane_columns_present_and_absent` has a run where
/// the two differ).
#[test]
fn collisions_are_the_rows_collisions_in_the_robots_lanes() {
    let scene = oncoming();
    let cert = certified(&scene);
    let fast = with(&scene, "first", |o| o.max_speed = 0.6);
    let rows = at_full_speed(&fast);
    let b_min = fast.robot.plant_braking();
    let in_lane = collisions(&rows, cert.clearance, b_min, true);
    let anywhere = collisions(&rows, cert.clearance, b_min, false);
    assert!(!in_lane.is_empty(), "the fast obstacle hits the robot");
    let csv = scene_trace_csv(&rows);
    let events = events_of(&cert, &csv, Format::Csv);
    assert_eq!(collision_events(&csv, Format::Csv, &events), in_lane);
    assert!(
        events
            .iter()
            .all(|e| e.check != Check::Collision || e.bound == Some(cert.clearance))
    );
    let lane_less = drop_columns(&csv, &LANE_COLUMNS);
    let events = events_of(&cert, &lane_less, Format::Csv);
    assert_eq!(collision_events(&lane_less, Format::Csv, &events), anywhere);
}

/// In the held runs the robot drives past the box in the next lane: with lanes nothing is
/// raised; without them the box counts as in the robot's lane, and exactly the rows where
/// the robot moves past it are raised as `collision` — and, the box looking like an obstacle
/// in the robot's lane that it drives at without braking, as `controller_reaction`, nothing
/// else.
#[test]
fn lane_columns_present_and_absent() {
    let scene = oncoming();
    let cert = certified(&scene);
    let rows = at_full_speed(&scene);
    let beside = collisions(&rows, cert.clearance, scene.robot.plant_braking(), false);
    assert!(beside.iter().all(|(_, o)| o == "box"));
    assert!(!beside.is_empty(), "the robot drives past the box");
    let csv = scene_trace_csv(&rows);
    assert!(events_of(&cert, &csv, Format::Csv).is_empty());
    let lane_less = drop_columns(&csv, &LANE_COLUMNS);
    let events = events_of(&cert, &lane_less, Format::Csv);
    assert_eq!(collision_events(&lane_less, Format::Csv, &events), beside);
    let others: Vec<Check> = events
        .iter()
        .map(|e| e.check)
        .filter(|&c| c != Check::Collision)
        .collect();
    assert!(!others.is_empty());
    assert!(
        others.iter().all(|&c| c == Check::ControllerReaction),
        "{others:?}"
    );
    let mut m = monitor(&cert);
    text_events(&mut m, &lane_less, Some(Format::Csv));
    let s = m.summary().scene.unwrap();
    let lane = s
        .checks
        .iter()
        .find(|c| c.check == Check::ObstacleLane)
        .unwrap();
    assert_eq!(lane.status, Status::NotMonitored);

    // The static-in-lane scene has no other lane: without lane columns it holds as well.
    let scene = static_in_lane();
    let cert = certified(&scene);
    let text = drop_columns(&scene_trace_csv(&at_full_speed(&scene)), &LANE_COLUMNS);
    assert!(events_of(&cert, &text, Format::Csv).is_empty());
}

/// A lane change into a lane whose obstacle is already behind the robot is no collision;
/// one that is ahead at a gap ≤ clearance is (semantics §11.6: the side is the one at the
/// robot's entry into the lane). Hand-written samples: the robot at 0.2 m/s moves into
/// lane 1 past the box (x = 5) while a cone stands ahead of it there.
#[test]
fn collision_is_measured_from_the_side_at_entry() {
    let scene = oncoming();
    let cert = certified(&scene);
    let mut m = monitor(&cert);
    assert_eq!(m.identify(0, "box"), Some(3));
    assert_eq!(m.identify(1, "cone"), None);
    let sample = |t: f64, robot_x: f64, id: u32, obstacle_x: f64| Sample {
        t,
        robot_x,
        robot_v: 0.2,
        robot_mode: Some(Mode::Drive),
        obstacle_id: id,
        obstacle_x,
        obstacle_v: None,
        obstacle_t: None,
    };
    let lanes = |robot: i32, leaving: Option<i32>| Lanes {
        robot: Some(robot),
        leaving,
        obstacle: Some(1),
    };
    let mut collisions = Vec::new();
    for (t, x, robot, leaving, cone_x) in [
        (0.0, 4.9, 0, None, 7.0),    // box ahead in the next lane
        (0.1, 5.5, 1, Some(0), 7.0), // entering lane 1: box behind, cone ahead
        (0.2, 6.0, 1, None, 7.0),    // in lane 1
        (0.3, 7.01, 1, None, 7.0),   // into the cone
        (0.4, 7.5, 1, None, 7.0),    // through it
    ] {
        for (id, ox) in [(0, 5.0), (1, cone_x)] {
            let out = m.observe_in_lanes(&sample(t, x, id, ox), lanes(robot, leaving));
            collisions.extend(
                out.events
                    .iter()
                    .filter(|e| e.check == Check::Collision)
                    .map(|e| (e.t.unwrap(), e.obstacle_id.unwrap(), e.observed.unwrap())),
            );
        }
    }
    let at: Vec<(f64, u32)> = collisions.iter().map(|&(t, id, _)| (t, id)).collect();
    assert_eq!(at, [(0.3, 1), (0.4, 1)]);
    for ((_, _, observed), gap) in collisions.iter().zip([-0.01, -0.5]) {
        assert!((observed - gap).abs() < 1e-12, "{observed}");
    }
}

// ------------------------------------------------------------------------------------------
// Reading lanes
// ------------------------------------------------------------------------------------------

/// Lanes of a run with a lane change, read back from both formats: each sample's lanes are
/// its row's (leaving_lane only during the change).
#[test]
fn lane_columns_are_read_from_both_formats() {
    let mut scene = oncoming();
    scene.lane_change = Some(LaneChange {
        periods: 10,
        rear_gap: 0.5,
    });
    let scene = with(&scene, "box", |o| o.position = Position::At(30.0));
    let rows = at_full_speed(&scene);
    assert!(
        rows.iter().any(|r| r.leaving_lane.is_some()),
        "the robot changes lanes"
    );
    for (text, format) in [
        (scene_trace_csv(&rows), Format::Csv),
        (scene_trace_jsonl(&rows), Format::Jsonl),
    ] {
        let mut decoder = Decoder::new(Some(format), None, 1 << 16);
        let mut read = Vec::new();
        for line in text.lines() {
            if let Decoded::Sample { .. } = decoder.decode(line.as_bytes()) {
                read.push(decoder.lanes());
            }
        }
        let expected: Vec<Lanes> = rows
            .iter()
            .map(|r| Lanes {
                robot: Some(r.robot_lane),
                leaving: r.leaving_lane,
                obstacle: Some(r.obstacle_lane),
            })
            .collect();
        assert_eq!(read, expected, "{format:?}");
    }
}

/// A lane that is not an integer is a malformed sample naming its column; an empty cell or
/// `null` is "not stated"; a robot lane that differs within an instant is the robot state
/// differing.
#[test]
fn bad_and_missing_lanes() {
    let header = "t,robot_x,robot_v,obstacle_id,obstacle_x,robot_lane,obstacle_lane,leaving_lane";
    let mut decoder = Decoder::new(None, None, 16);
    assert_eq!(decoder.decode(header.as_bytes()), Decoded::Header);
    for (line, field) in [
        ("0,0,0,a,5,1.5,0,", Field::RobotLane),
        ("0,0,0,a,5,0,x,", Field::ObstacleLane),
        ("0,0,0,a,5,0,0,1e0", Field::LeavingLane),
    ] {
        match decoder.decode(line.as_bytes()) {
            Decoded::Malformed { detail, .. } => assert_eq!(detail, Detail::BadLane(field)),
            other => panic!("{line}: {other:?}"),
        }
    }
    assert!(matches!(
        decoder.decode(b"0,0,0,a,5,,-1,"),
        Decoded::Sample { .. }
    ));
    assert_eq!(
        decoder.lanes(),
        Lanes {
            robot: None,
            leaving: None,
            obstacle: Some(-1)
        }
    );
    let mut json = Decoder::new(Some(Format::Jsonl), None, 16);
    let line = r#"{"t":0,"robot_x":0,"robot_v":0,"obstacle_id":"a","obstacle_x":5,"robot_lane":1,"leaving_lane":null,"obstacle_lane":2}"#;
    assert!(matches!(
        json.decode(line.as_bytes()),
        Decoded::Sample { .. }
    ));
    assert_eq!(
        json.lanes(),
        Lanes {
            robot: Some(1),
            leaving: None,
            obstacle: Some(2)
        }
    );
    let quoted = line.replace(r#""obstacle_lane":2"#, r#""obstacle_lane":"2""#);
    assert!(matches!(
        json.decode(quoted.as_bytes()),
        Decoded::Malformed {
            detail: Detail::BadLane(Field::ObstacleLane),
            ..
        }
    ));

    let cert = certified(&oncoming());
    let trace = format!("{header}\n0,0,0,first,10,0,0,\n0,0,0,second,12.5,1,0,\n");
    let events = events_of(&cert, &trace, Format::Csv);
    assert_eq!(events.len(), 1);
    assert_eq!(events[0].check, Check::MalformedSample);
    assert_eq!(events[0].detail, Some(Detail::RobotStateDiffers));
}

// ------------------------------------------------------------------------------------------
// Old certificates and traces
// ------------------------------------------------------------------------------------------

/// The seed certificate on the committed traces gives the same events and summary through
/// `Monitor::new` + `observe` as through a certificate file + `observe_decoded`, with no
/// scene part; and a one-obstacle scene trace (lane columns present) gives a single-obstacle
/// certificate the events of the same run's single-obstacle trace.
#[test]
fn old_certificates_and_traces_are_unchanged() {
    let text = std::fs::read_to_string(fixture("seed.cert.json")).unwrap();
    let cert: Certificate = serde_json::from_str(&text).unwrap();
    let file = CertificateFile::from_json(&text).unwrap();
    for (trace, format) in [
        ("seed.run.jsonl", Format::Jsonl),
        ("seed-w0.25.run.csv", Format::Csv),
    ] {
        let trace = std::fs::read_to_string(fixture(trace)).unwrap();
        let mut plain = Monitor::new(&cert).unwrap();
        let mut decoder = Decoder::new(Some(format), None, 1 << 16);
        let mut old = Vec::new();
        for line in trace.lines() {
            match decoder.decode(line.as_bytes()) {
                Decoded::Sample { sample, .. } => old.extend(plain.observe(&sample).events),
                Decoded::Malformed { t, detail, .. } => {
                    old.extend(plain.malformed(t, detail).events)
                }
                _ => {}
            }
        }
        let mut via_file = Monitor::for_certificate_file(&file).unwrap();
        assert!(!via_file.is_scene());
        assert_eq!(text_events(&mut via_file, &trace, Some(format)), old);
        assert_eq!(via_file.summary(), plain.summary());
        assert!(plain.summary().scene.is_none());
        let json = serde_json::to_value(plain.summary()).unwrap();
        assert!(json.get("scene").is_none());
    }

    let problem = load_problem("seed.toml", &["environment.obstacle_speed=0.25"]);
    let scene = Scene::from_problem(&problem);
    let rows = at_full_speed(&scene);
    let single: Vec<TraceRow> = rows.iter().map(|r| r.row.clone()).collect();
    for (scene_text, single_text, format) in [
        (
            scene_trace_csv(&rows),
            trace_csv(&single, "obstacle-0"),
            Format::Csv,
        ),
        (
            scene_trace_jsonl(&rows),
            trace_jsonl(&single, "obstacle-0"),
            Format::Jsonl,
        ),
    ] {
        let a = text_events(&mut Monitor::new(&cert).unwrap(), &scene_text, Some(format));
        let b = text_events(
            &mut Monitor::new(&cert).unwrap(),
            &single_text,
            Some(format),
        );
        assert!(!a.is_empty());
        assert_eq!(a, b);
    }
}

/// A scene certificate is checked first: an edited one, and one that is not certified, are
/// refused with the single-obstacle certificate's errors.
#[test]
fn unusable_scene_certificates_are_refused() {
    let mut cert = certified(&oncoming());
    cert.scene.obstacles[2].max_speed = 0.3;
    assert!(matches!(
        Monitor::for_scene(&cert),
        Err(MonitorError::Invalid(_))
    ));
    let refuted = SceneCertificate::from_analysis(
        &analyse_scene(&shipped("scene-short-sensing")).expect("analysed"),
    );
    assert_ne!(refuted.verdict, Proved::Certified);
    assert!(matches!(
        Monitor::for_certificate_file(&CertificateFile::Scene(Box::new(refuted))),
        Err(MonitorError::NotCertified(_))
    ));
}

// ------------------------------------------------------------------------------------------
// The command line
// ------------------------------------------------------------------------------------------

struct Run {
    code: i32,
    stdout: String,
    stderr: String,
}

fn monitor_cli(dir: &Path, args: &[&str]) -> Run {
    let out = safereach(dir)
        .arg("monitor")
        .args(["--certificate", "scene.cert.json"])
        .args(args)
        .output()
        .expect("runs");
    Run {
        code: out.status.code().expect("exited"),
        stdout: String::from_utf8(out.stdout).unwrap(),
        stderr: String::from_utf8(out.stderr).unwrap(),
    }
}

fn write(dir: &Path, name: &str, text: &str) {
    write_atomic(&dir.join(name), text.as_bytes()).expect("written");
}

/// `safereach monitor` on a scene certificate: exit 0 on a held run (the summary lists the
/// scene checks and obstacles), 1 naming the obstacle that broke its own bound, 2 for an
/// edited certificate, as for a single obstacle's.
#[test]
fn the_command_line_monitors_scene_certificates() {
    let dir = tmp();
    let scene = oncoming();
    let cert = certified(&scene);
    write(
        dir.path(),
        "scene.cert.json",
        &serde_json::to_string_pretty(&cert).unwrap(),
    );
    write(
        dir.path(),
        "held.csv",
        &scene_trace_csv(&at_full_speed(&scene)),
    );
    let r = monitor_cli(dir.path(), &["held.csv", "--events-only"]);
    assert_eq!(r.code, 0, "{}{}", r.stdout, r.stderr);
    assert!(r.stdout.contains("scene checks:"), "{}", r.stdout);
    assert!(r.stdout.contains("collision"), "{}", r.stdout);
    for o in &scene.obstacles {
        assert!(r.stdout.contains(&o.name), "{}", r.stdout);
    }
    assert!(r.stdout.contains("unmatched objects: 0"), "{}", r.stdout);

    let fast = at_full_speed(&with(&scene, "third", |o| o.max_speed = 0.15));
    write(dir.path(), "fast.jsonl", &scene_trace_jsonl(&fast));
    let r = monitor_cli(dir.path(), &["fast.jsonl", "--events-only"]);
    assert_eq!(r.code, 1, "{}{}", r.stdout, r.stderr);
    assert!(
        r.stdout.contains(
            "t=0.1 VIOLATION obstacle_speed obstacle=third observed 0.15 m/s > bound 0.1 m/s -> brake"
        ),
        "{}",
        r.stdout
    );
    let r = monitor_cli(dir.path(), &["fast.jsonl", "--json"]);
    assert_eq!(r.code, 1);
    let summary: serde_json::Value =
        serde_json::from_str(r.stdout.lines().last().unwrap()).unwrap();
    let third = &summary["summary"]["scene"]["obstacles"][2];
    assert_eq!(third["name"], "third");
    assert!(third["violations"].as_u64().unwrap() > 0);

    let mut edited: serde_json::Value = serde_json::to_value(&cert).unwrap();
    edited["scene"]["obstacles"][2]["max_speed"] = 0.3.into();
    write(dir.path(), "scene.cert.json", &edited.to_string());
    let r = monitor_cli(dir.path(), &["held.csv"]);
    assert_eq!(r.code, 2, "{}{}", r.stdout, r.stderr);
    assert!(
        r.stderr
            .contains("scene.cert.json: certificate unusable: the certificate does not verify"),
        "{}",
        r.stderr
    );
    assert_eq!(r.stdout, "");
}

// ------------------------------------------------------------------------------------------
// Scene region maps
// ------------------------------------------------------------------------------------------

/// A certified scene map is monitored as the scene at its least demanding corner (each
/// obstacle's W_i and the clearance at their upper ends, ρ and the buffer and each start at
/// their lower), held against that corner's own certificate, which the scene analyser proves
/// independently: the same events on runs inside and beyond the box; the runs of the box's
/// points hold; and the box covers more than a point inside it.
#[test]
fn a_certified_scene_map_is_monitored_as_its_least_demanding_corner() {
    use safereach::analysis::region_search::{RegionOptions, map_scene_region};
    use safereach::core::param_box::{Axis, ParamBox};
    use safereach::core::parameter::Parameter;
    use safereach::monitor::RegionPoint;

    let scene = oncoming();
    let second = Axis {
        obstacle: Some(1),
        ..Axis::new(Parameter::ObstacleSpeed, 0.1, 0.2)
    };
    let rho = Axis::new(Parameter::ReactionRadius, 1.4, 1.6);
    let whole = ParamBox::new(vec![second, rho]).unwrap();
    let options = RegionOptions {
        depth: 4,
        ..RegionOptions::default()
    };
    let m = map_scene_region(&scene, &whole, &options, &|_| {}).expect("mappable");
    assert!(m.all_certified(), "the box certifies whole");
    let by_map = Monitor::for_region(&m, &RegionPoint::default()).expect("monitorable");
    let at = |w: f64, r: f64| {
        let mut s = with(&scene, "second", |o| o.max_speed = w);
        s.controller.reaction_radius = r;
        s
    };
    let corner = monitor(&certified(&at(0.2, 1.4)));
    let mut raised = 0;
    for (w, r) in [(0.12, 1.4), (0.2, 1.4), (0.2, 1.6), (0.25, 1.4), (0.3, 1.5)] {
        let point = at(w, r);
        for i in 0..6 {
            let text = scene_trace_csv(&random_run(&point, i));
            let a = text_events(&mut by_map.clone(), &text, Some(Format::Csv));
            let b = text_events(&mut corner.clone(), &text, Some(Format::Csv));
            assert_eq!(a, b, "W_1 = {w}, ρ = {r}, run {i}");
            if w <= 0.2 {
                assert!(
                    a.is_empty(),
                    "a certified point's run holds: W_1 = {w}, run {i}"
                );
            }
            raised += usize::from(!a.is_empty());
        }
    }
    assert!(raised > 0, "runs beyond the box are flagged");
    // "second" at W_1 = 0.2 throughout passes the map's monitor, not the certificate of a
    // point of the box with W_1 = 0.15.
    let slower = monitor(&certified(&at(0.15, 1.4)));
    let fast = scene_trace_csv(&at_full_speed(&at(0.2, 1.4)));
    assert!(!text_events(&mut slower.clone(), &fast, Some(Format::Csv)).is_empty());
    assert!(text_events(&mut by_map.clone(), &fast, Some(Format::Csv)).is_empty());
}
