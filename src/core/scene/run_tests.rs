//! The scene step function and simulator held against independent answers: the
//! single-obstacle `World`, closed forms of the robot's motion (a static obstacle, the
//! destination, lane-change instants), and the scene's own invariances.

use proptest::collection::vec;
use proptest::prelude::*;

use super::simulate::{RunEnd, SceneRun, replay, replay_exact, trace};
use super::*;
use crate::core::model::{Controller, DangerRule, Environment, Params, Problem, Robot};
use crate::core::num::{Exact, exact_decimal, exact_float};
use crate::core::semantics::{BrakeReason, Mode};
use crate::core::simulate;

fn problem(latency: u32, rule: DangerRule, wrong: bool, w: f64, g0: f64) -> Problem {
    Problem {
        name: "t".into(),
        robot: Robot {
            max_speed: 0.8,
            acceleration: 0.3,
            braking: 0.5,
            control_period: 0.1,
            latency,
            clearance: 0.05,
            braking_min: None,
            initial_speed: None,
        },
        controller: Controller {
            assumed_obstacle_speed: 0.2,
            reaction_radius: 2.0,
            danger_rule: rule,
            buffer: 0.1,
            wrong_assumption_brake: wrong,
        },
        environment: Environment {
            obstacle_speed: w,
            initial_gap: crate::core::model::Position::At(g0),
        },
        sensing: None,
    }
}

fn any_rule() -> impl Strategy<Value = DangerRule> {
    prop_oneof![
        Just(DangerRule::Paper),
        Just(DangerRule::Kinematic),
        Just(DangerRule::Area)
    ]
}

fn obstacle(name: &str, lane: i32, x: f64, w: f64, is_static: bool) -> Obstacle {
    Obstacle {
        name: name.into(),
        lane,
        position: Position::At(x),
        max_speed: w,
        is_static,
    }
}

/// A scene of `obstacles` with the robot and controller of [`problem`].
fn scene(latency: u32, rule: DangerRule, obstacles: Vec<Obstacle>, lanes: Vec<i32>) -> Scene {
    let mut s = Scene::from_problem(&problem(latency, rule, false, 0.0, 1.0));
    s.obstacles = obstacles;
    s.lanes = lanes;
    s
}

fn exact_run(s: &Scene, speeds: &[Vec<f64>], stop: bool) -> SceneRun<Exact> {
    let p: SceneParams<Exact> = s.params();
    let starts = p.nearest_starts();
    replay_exact(&p, speeds, &starts, 2000, stop)
}

/// The robot's position and speed at time t if it never brakes: accelerate at a to v_max,
/// then cruise (closed form, independent of `robot_motion`).
fn free_motion(p: &Params<Exact>, t: &Exact) -> (Exact, Exact) {
    let t_acc = p.v_max.clone() / p.a.clone();
    let two = Exact::from(2);
    if *t <= t_acc {
        (
            p.a.clone() * t.clone() * t.clone() / two,
            p.a.clone() * t.clone(),
        )
    } else {
        (
            p.v_max.clone() * p.v_max.clone() / (two * p.a.clone())
                + p.v_max.clone() * (t.clone() - t_acc),
            p.v_max.clone(),
        )
    }
}

fn at_step(p: &Params<Exact>, k: usize) -> (Exact, Exact) {
    free_motion(p, &(Exact::from(k) * p.dt.clone()))
}

fn stopping(p: &Params<Exact>, v: &Exact) -> Exact {
    v.clone() * v.clone() / (Exact::from(2) * p.b.clone())
}

/// The first step at which a robot driving freely sees a static obstacle at `x0` in its
/// lane as dangerous (V_a = 0), by the rule's formula written out.
fn static_danger_step(p: &Params<Exact>, x0: &Exact) -> Option<usize> {
    (p.L..5000).find(|&k| {
        let (x_seen, _) = at_step(p, k - p.L);
        let (_, v) = at_step(p, k);
        let g = x0.clone() - x_seen;
        let d = match p.rule {
            DangerRule::Paper => Some(v.clone() * v.clone() / p.b.clone() + p.buffer.clone()),
            DangerRule::Kinematic => Some(stopping(p, &v) + p.buffer.clone()),
            DangerRule::Area => None,
        };
        g > Exact::ZERO && g <= p.rho && d.is_none_or(|d| g <= d)
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// A scene of one moving obstacle in lane 0 is today's single-obstacle world: the same
    /// records, period by period, the same outcome and the same trace.
    #[test]
    fn one_moving_obstacle_in_lane_0_is_the_single_obstacle_world(
        latency in 0u32..3,
        rule in any_rule(),
        wrong: bool,
        w in prop_oneof![Just(0.1), Just(0.35)],
        g0 in prop_oneof![Just(2.5), Just(4.0), Just(6.3)],
        fractions in vec(0.0..=1.0f64, 0..90),
        stop: bool,
    ) {
        let single = problem(latency, rule, wrong, w, g0);
        let speeds: Vec<f64> = fractions.iter().map(|f| f * w).collect();
        let old = simulate::replay_exact(&single.params(), &speeds, 2000, stop);
        let new = exact_run(&Scene::from_problem(&single), std::slice::from_ref(&speeds), stop);
        prop_assert_eq!(old.records.len(), new.records.len());
        for (a, b) in old.records.iter().zip(&new.records) {
            let o = &b.obstacles[0];
            prop_assert_eq!(a.k, b.k);
            prop_assert_eq!(&a.robot, &b.robot);
            prop_assert_eq!(a.brake, b.brake);
            prop_assert_eq!(&a.motion, &b.motion);
            prop_assert_eq!(&a.gap, &o.gap);
            prop_assert_eq!(&a.obstacle_speed, &o.speed);
            prop_assert_eq!(&a.observation, &o.seen);
            prop_assert_eq!(&a.end_gap, &o.end_gap);
            prop_assert_eq!(&a.rest_gap, &o.rest_gap);
            prop_assert_eq!(a.collision, b.collision());
        }
        let (x, y) = (&old.outcome, &new.outcome);
        prop_assert_eq!(x.collided, y.collided);
        prop_assert_eq!(x.brake, y.brake);
        prop_assert_eq!(&x.min_moving_gap, &y.obstacles[0].sep);
        prop_assert_eq!(x.collided, y.obstacles[0].collided);
        prop_assert_eq!(x.rest_gap.clone(), y.rest_gaps.as_ref().map(|g| g[0].clone()));
        let old_rows = simulate::trace(&single.params(), &old);
        let p: SceneParams<Exact> = Scene::from_problem(&single).params();
        let new_rows: Vec<_> = trace(&p, &new).into_iter().map(|r| r.row).collect();
        prop_assert_eq!(old_rows, new_rows);
    }

    /// A static obstacle alone in lane 0: the robot brakes at the first step its danger rule
    /// with V_a = 0 fires and rests its stopping distance later (closed form).
    #[test]
    fn a_static_obstacle_alone_gives_the_stopping_distance(
        latency in 0u32..3,
        rule in prop_oneof![Just(DangerRule::Paper), Just(DangerRule::Kinematic)],
        x0 in 1.0..12.0f64,
    ) {
        let s = scene(latency, rule, vec![obstacle("wall", 0, x0, 0.0, true)], vec![0]);
        let p: SceneParams<Exact> = s.params();
        let k = static_danger_step(&p.robot, &exact_decimal(x0)).expect("the rule fires");
        let (x, v) = at_step(&p.robot, k);
        let rest_gap = exact_decimal(x0) - x - stopping(&p.robot, &v);
        let r = exact_run(&s, &[vec![]], false);
        prop_assert_eq!(r.outcome.brake, Some((k, BrakeReason::CollisionDanger)));
        prop_assert_eq!(r.outcome.rest_gaps.clone(), Some(vec![rest_gap.clone()]));
        prop_assert_eq!(r.outcome.obstacles[0].sep.clone(), Some(rest_gap.clone()));
        prop_assert_eq!(r.outcome.collided, rest_gap < p.robot.clearance);
    }

    /// Obstacles in lanes the robot never enters (no lane changes) never matter: the robot
    /// and the lane-0 obstacle go exactly as without them, and they have no separation.
    #[test]
    fn obstacles_in_lanes_never_entered_never_matter(
        latency in 0u32..3,
        rule in any_rule(),
        fractions in vec(0.0..=1.0f64, 0..60),
        others in vec((prop_oneof![Just(-1), Just(1)], 0.5..8.0f64, 0.0..0.5f64, any::<bool>()), 1..4),
    ) {
        let w = 0.3;
        let main = obstacle("main", 0, 4.0, w, false);
        let alone = scene(latency, rule, vec![main.clone()], vec![-1, 0, 1]);
        let mut obstacles = vec![main];
        let mut speeds = vec![fractions.iter().map(|f| f * w).collect::<Vec<_>>()];
        for (j, &(lane, x, w, is_static)) in others.iter().enumerate() {
            let w = if is_static { 0.0 } else { w };
            obstacles.push(obstacle(&format!("o{j}"), lane, x, w, is_static));
            speeds.push(fractions.iter().rev().map(|f| f * w).collect());
        }
        let crowded = scene(latency, rule, obstacles, vec![-1, 0, 1]);
        let a = exact_run(&alone, &speeds[..1], false);
        let b = exact_run(&crowded, &speeds, false);
        prop_assert_eq!(a.records.len(), b.records.len());
        for (x, y) in a.records.iter().zip(&b.records) {
            prop_assert_eq!(&x.robot, &y.robot);
            prop_assert_eq!(&x.motion, &y.motion);
            prop_assert_eq!(x.brake, y.brake);
            prop_assert_eq!(&x.obstacles[0], &y.obstacles[0]);
        }
        prop_assert_eq!(&a.outcome.obstacles[0], &b.outcome.obstacles[0]);
        for o in &b.outcome.obstacles[1..] {
            prop_assert!(o.sep.is_none() && !o.collided);
        }
    }

    /// The destination: the robot brakes at the first step its stopping point reaches the
    /// goal and rests there (closed form).
    #[test]
    fn the_destination_stops_the_robot_at_its_stopping_point(
        goal in 0.5..25.0f64,
        latency in 0u32..3,
    ) {
        let mut s = scene(latency, DangerRule::Kinematic, vec![], vec![0]);
        s.goal = Some(goal);
        let p: SceneParams<Exact> = s.params();
        let goal = exact_decimal(goal);
        let k = (0..5000)
            .find(|&k| {
                let (x, v) = at_step(&p.robot, k);
                x + stopping(&p.robot, &v) >= goal
            })
            .expect("reached");
        let (x, v) = at_step(&p.robot, k);
        let r = exact_run(&s, &[], false);
        prop_assert_eq!(r.outcome.brake, Some((k, BrakeReason::Destination)));
        prop_assert_eq!(r.outcome.end, RunEnd::Rest);
        let rest = r.records.last().expect("ran").motion.end.position.clone();
        prop_assert_eq!(rest.clone(), x + stopping(&p.robot, &v));
        prop_assert!(rest >= goal);
    }

    /// A sensing range R ≥ ρ changes nothing: every guard looks at gaps ≤ ρ only.
    #[test]
    fn a_sensing_range_at_the_radius_changes_nothing(
        scene_spec in any_scene(),
    ) {
        let (s, speeds) = scene_spec;
        let mut ranged = s.clone();
        ranged.sensing_range = Some(s.controller.reaction_radius);
        let a = exact_run(&s, &speeds, false);
        let b = exact_run(&ranged, &speeds, false);
        prop_assert_eq!(a.outcome, b.outcome);
    }

    /// Exact replay in `Exact` and in `Rational` agree: outcome, separations and trace.
    #[test]
    fn exact_and_rational_replays_agree(scene_spec in any_scene(), stop: bool) {
        let (s, speeds) = scene_spec;
        let p: SceneParams<Exact> = s.params();
        let starts = p.nearest_starts();
        let a = replay_exact(&p, &speeds, &starts, 2000, stop);
        let b = replay(&p, &speeds, &starts, 2000, stop);
        let seps: Vec<_> = a.outcome.obstacles.iter().map(|o| o.sep.clone()).collect();
        prop_assert_eq!(seps, b.separations());
        prop_assert_eq!(a.outcome.collided, b.collided());
        prop_assert_eq!(a.outcome.brake, b.run.outcome.brake);
        prop_assert_eq!(&a.outcome.lane_changes, &b.run.outcome.lane_changes);
        prop_assert_eq!(a.outcome.rest_gaps.clone(), b.rest_gaps());
        prop_assert_eq!(a.outcome.end, b.run.outcome.end);
        prop_assert_eq!(a.outcome.worst(), b.worst().map(|(i, _)| i));
        prop_assert_eq!(a.records.len(), b.run.records.len());
        for (x, y) in a.records.iter().zip(&b.run.records) {
            prop_assert_eq!(&x.robot.position, &y.robot.position.to_exact());
            prop_assert_eq!(&x.robot.speed, &y.robot.speed.to_exact());
            prop_assert_eq!(x.robot.mode, y.robot.mode);
            prop_assert_eq!(x.lateral, y.lateral);
            for (o, q) in x.obstacles.iter().zip(&y.obstacles) {
                prop_assert_eq!(&o.gap, &q.gap.to_exact());
                prop_assert_eq!(&o.end_gap, &q.end_gap.to_exact());
                prop_assert_eq!(o.collision(), q.collision());
            }
        }
        // The traces are the same rows; their floats are roundings of the same rationals.
        let (rows_a, rows_b) = (trace(&p, &a), b.trace());
        prop_assert_eq!(rows_a.len(), rows_b.len());
        for (x, y) in rows_a.iter().zip(&rows_b) {
            prop_assert_eq!((&x.obstacle, x.robot_lane, x.leaving_lane), (&y.obstacle, y.robot_lane, y.leaving_lane));
            prop_assert!((x.row.gap - y.row.gap).abs() <= 1e-12 * (1.0 + x.row.gap.abs()));
            prop_assert!((x.row.t - y.row.t).abs() <= 1e-12 * (1.0 + x.row.t.abs()));
        }
    }

    /// When a run ends because nothing can happen any more, nothing does: stepping on, no
    /// guard fires, no lane change starts and no separation falls.
    #[test]
    fn a_settled_run_stays_settled(scene_spec in any_scene()) {
        let (mut s, speeds) = scene_spec;
        s.goal = None;
        let p: SceneParams<Exact> = s.params();
        let r = exact_run(&s, &speeds, false);
        prop_assume!(r.outcome.end == RunEnd::Settled);
        let mut world = SceneWorld::new(p.clone(), p.nearest_starts());
        for rec in &r.records {
            let w: Vec<Exact> = rec.obstacles.iter().map(|o| o.speed.clone()).collect();
            world.step(&w);
        }
        prop_assert!(world.settled());
        for _ in 0..150 {
            let w: Vec<Exact> = p.obstacles.iter().map(|o| o.max_speed.clone()).collect();
            let rec = world.step(&w);
            prop_assert!(rec.brake.is_none() && rec.lane_change.is_none());
            for (o, total) in rec.obstacles.iter().zip(&r.outcome.obstacles) {
                if let Some(step) = &o.safety {
                    prop_assert!(!step.collision);
                    prop_assert!(total.sep.as_ref().is_some_and(|s| step.sep >= *s));
                }
            }
        }
    }
}

/// Random small scenes: up to four obstacles in lanes −1..1, moving or static, with lane
/// changes and the wrong-assumption guard on or off and perhaps a goal, and their speed
/// sequences.
fn any_scene() -> impl Strategy<Value = (Scene, Vec<Vec<f64>>)> {
    (
        0u32..3,
        any_rule(),
        (any::<bool>(), any::<bool>()),
        prop_oneof![Just(None), (3.0..20.0f64).prop_map(Some)],
        vec(
            (
                -1i32..=1,
                0.5..9.0f64,
                0.0..0.4f64,
                any::<bool>(),
                vec(0.0..=1.0f64, 0..80),
            ),
            1..5,
        ),
    )
        .prop_map(|(latency, rule, (changes, wrong), goal, spec)| {
            let mut obstacles = Vec::new();
            let mut speeds = Vec::new();
            for (j, (lane, x, w, is_static, fractions)) in spec.into_iter().enumerate() {
                let w = if is_static { 0.0 } else { w };
                obstacles.push(obstacle(&format!("o{j}"), lane, x, w, is_static));
                speeds.push(fractions.iter().map(|f| f * w).collect());
            }
            let mut s = scene(latency, rule, obstacles, vec![-1, 0, 1]);
            s.goal = goal;
            s.controller.wrong_assumption_brake = wrong;
            if changes {
                s.lane_change = Some(LaneChange {
                    periods: 4,
                    rear_gap: 0.5,
                });
            }
            (s, speeds)
        })
}

/// The lane-change scenes: a static wall in lane 0 at 6 m; lanes 0 and 1 (and −1); P = 5,
/// rear gap 0.5 m; kinematic rule, no latency.
fn wall_scene(lanes: Vec<i32>, extra: Vec<Obstacle>) -> Scene {
    let mut obstacles = vec![obstacle("wall", 0, 6.0, 0.0, true)];
    obstacles.extend(extra);
    let mut s = scene(0, DangerRule::Kinematic, obstacles, lanes);
    s.lane_change = Some(LaneChange {
        periods: 5,
        rear_gap: 0.5,
    });
    s
}

/// The step the wall becomes dangerous, and the robot's position then.
fn wall_danger() -> (usize, Exact) {
    let p: SceneParams<Exact> = wall_scene(vec![0, 1], vec![]).params();
    let k = static_danger_step(&p.robot, &Exact::from(6)).expect("fires");
    (k, at_step(&p.robot, k).0)
}

/// With lane 1 free, the robot changes lanes at the danger step instead of braking; the
/// wall, left in lane 0, is last measured when the change ends, at its gap then.
#[test]
fn a_free_lane_is_taken_at_the_danger_step() {
    let s = wall_scene(vec![0, 1], vec![]);
    let p: SceneParams<Exact> = s.params();
    let (k, _) = wall_danger();
    let r = exact_run(&s, &[vec![]], false);
    assert_eq!(
        r.outcome.lane_changes,
        vec![LaneChangeEvent {
            step: k,
            from: 0,
            to: 1
        }]
    );
    assert_eq!(r.outcome.brake, None);
    assert_eq!(r.outcome.end, RunEnd::Settled);
    let (x_left, _) = at_step(&p.robot, k + 5);
    assert_eq!(r.outcome.obstacles[0].sep, Some(Exact::from(6) - x_left));
    assert!(!r.outcome.collided);
}

/// With a static obstacle beside the robot in lane 1 the lane is not free: the robot brakes
/// at the danger step and rests at its stopping distance; with lane −1 free it goes there.
#[test]
fn an_occupied_lane_is_refused() {
    let (k, x) = wall_danger();
    // Beside the robot (to a float's precision) when the danger fires.
    let beside = obstacle("beside", 1, x.to_f64().value(), 0.0, true);
    let s = wall_scene(vec![0, 1], vec![beside.clone()]);
    let p: SceneParams<Exact> = s.params();
    let r = exact_run(&s, &[vec![], vec![]], false);
    assert!(r.outcome.lane_changes.is_empty());
    assert_eq!(r.outcome.brake, Some((k, BrakeReason::CollisionDanger)));
    let (_, v) = at_step(&p.robot, k);
    let rest = x.clone() + stopping(&p.robot, &v);
    assert_eq!(
        r.outcome.rest_gaps.as_ref().unwrap()[0],
        Exact::from(6) - rest
    );
    assert_eq!(r.outcome.obstacles[1].sep, None, "lane 1 never occupied");

    let s = wall_scene(vec![-1, 0, 1], vec![beside]);
    let r = exact_run(&s, &[vec![], vec![]], false);
    assert_eq!(r.outcome.lane_changes.len(), 1);
    assert_eq!(
        (r.outcome.lane_changes[0].step, r.outcome.lane_changes[0].to),
        (k, -1)
    );
}

/// An obstacle already passed in the lane the robot moves into is measured by −gap, from
/// the instant the robot enters the lane: its separation is how far behind it is then.
#[test]
fn an_obstacle_behind_in_the_new_lane_is_measured_by_minus_gap() {
    let (k, x) = wall_danger();
    let behind_by = exact_decimal(0.6);
    let at = (x - behind_by.clone()).to_f64().value();
    let behind = obstacle("passed", 1, at, 0.0, true);
    let s = wall_scene(vec![0, 1], vec![behind.clone()]);
    let r = exact_run(&s, &[vec![], vec![]], false);
    assert_eq!(
        r.outcome.lane_changes.len(),
        1,
        "0.6 m behind: lane 1 is free"
    );
    assert_eq!(r.outcome.lane_changes[0].step, k);
    let (x_enter, _) = at_step(&s.params::<Exact>().robot, k);
    let expected = x_enter - exact_decimal(behind.position.min());
    assert_eq!(r.outcome.obstacles[1].sep, Some(expected));
    assert!(!r.outcome.obstacles[1].collided);
}

/// Speeds replay as the exact rationals the floats are; W_i after the last given speed.
#[test]
fn replay_reads_floats_exactly_and_pads_with_the_bound() {
    let s = scene(
        0,
        DangerRule::Kinematic,
        vec![
            obstacle("a", 0, 5.0, 0.3, false),
            obstacle("b", 1, 5.0, 0.2, false),
        ],
        vec![0, 1],
    );
    let r = exact_run(&s, &[vec![0.1], vec![]], false);
    assert_eq!(r.records[0].obstacles[0].speed, exact_float(0.1));
    assert_eq!(r.records[1].obstacles[0].speed, exact_decimal(0.3));
    assert_eq!(r.records[0].obstacles[1].speed, exact_decimal(0.2));
    assert_eq!(r.records[0].robot.mode, Mode::Accelerate);
}

/// A free lane is not taken when the change cannot finish in time (the wall is observed
/// within d_lc(v) = v·P·dt + buffer): the robot brakes at the danger step.
#[test]
fn a_change_that_cannot_finish_in_time_is_not_started() {
    let mut s = wall_scene(vec![0, 1], vec![]);
    s.lane_change = Some(LaneChange {
        periods: 20,
        rear_gap: 0.5,
    });
    let (k, _) = wall_danger();
    let r = exact_run(&s, &[vec![]], false);
    assert!(r.outcome.lane_changes.is_empty());
    assert_eq!(r.outcome.brake, Some((k, BrakeReason::CollisionDanger)));
}
