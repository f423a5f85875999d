//! The plane's exact replay (docs/semantics.md §13; `core::planar::run`) against answers
//! computed independently: the line's worked example in closed form, the closest approach
//! of linear relative motion, the line's own step function on embedded problems, and a
//! dense exact evaluation around a vertex crossed while braking (a quadratic-surd instant).

use proptest::prelude::*;
use safereach::core::model::Problem;
use safereach::core::num::Exact;
use safereach::core::planar::{
    ObstacleBehaviour, PlanarBehaviour, PlanarGuard, PlanarParams, PlanarRun, run,
};
use safereach::core::plane::direction::RationalDirection;
use safereach::core::plane::path::Path;
use safereach::core::plane::point::Point;
use safereach::core::plane::rational_path::RationalPath;
use safereach::core::semantics::{Mode, RobotState, World, robot_motion, state_within};

use crate::common::line_in_plane::{decimal, embed};
use crate::common::spec::{any_spec, config};

fn point(x: f64, y: f64) -> Point {
    Point::decimal(x, y)
}

fn problem(text: &str) -> Problem {
    Problem::from_toml_str(text, "test").expect("a valid problem")
}

/// A line problem's robot and controller, any obstacle numbers (the plane's replace them).
fn line_problem(robot: &str, controller: &str) -> Problem {
    problem(&format!(
        "name = \"t\"\n[robot]\n{robot}\n[controller]\n{controller}\n\
         [environment]\nobstacle_speed = 0.0\ninitial_gap = 10.0\n"
    ))
}

/// The robot of problems/static-obstacle.toml (semantics.md §11.8), V_a = 0.
fn worked_example() -> Problem {
    line_problem(
        "max_speed = 0.2\nacceleration = 0.1\nbraking = 0.05\ncontrol_period = 0.1\nlatency = 1\nclearance = 0.0",
        "assumed_obstacle_speed = 0.0\nreaction_radius = 1.4\ndanger_rule = \"paper\"\nbuffer = 0.1\nwrong_assumption_brake = false",
    )
}

fn one_obstacle(params: &PlanarParams, start: Point, velocities: Vec<Point>) -> PlanarBehaviour {
    assert_eq!(params.obstacles.len(), 1);
    PlanarBehaviour {
        obstacles: vec![ObstacleBehaviour::moving(start, velocities)],
    }
}

/// §11.8's static obstacle, now two discs on the x axis (r_R = 0.1, r_i = 0.2, centre at
/// 10.31 so the rims are 10.01 apart): brake step 467, rest at 467·dt + v_max/b, and the
/// rims 10.01 − 9.14 − 0.4 = 0.47 m apart at rest, from the 1-D kinematics by hand. The
/// rims reach 0.47 only at the rest instant, which is no collision (§13.5).
#[test]
fn a_static_obstacle_ahead_rests_at_the_closed_form() {
    let mut params = embed(&worked_example());
    params.robot_radius = decimal(0.1);
    params.obstacles[0].radius = decimal(0.2);
    params.obstacles[0].max_speed = Exact::ZERO;
    let start = point(10.31, 0.0);
    params.obstacles[0].start = safereach::core::planar::Start::At(start.clone());
    let out = run(&params, &one_obstacle(&params, start, Vec::new()), 1000).expect("replays");
    let brake = out.brake.expect("brakes");
    assert_eq!(brake.step, 467);
    assert_eq!(brake.guard, PlanarGuard::Danger { obstacle: 0 });
    assert_eq!(out.rest, Some(decimal(46.7) + decimal(4.0)));
    let s = out.separation(0).expect("the robot moved");
    assert_eq!(
        (s.lower.clone(), s.upper.clone()),
        (decimal(0.47), decimal(0.47))
    );
    assert_eq!(s.at, decimal(50.7));
    assert_eq!(out.collides(&decimal(0.47)), Some(false));
    assert_eq!(out.collides(&decimal(0.4700001)), Some(true));
    assert_eq!(out.collides(&decimal(0.46)), Some(false));
}

/// A robot cruising along x at v from t = 0 and an obstacle crossing at constant velocity
/// (0, W), never seen (range below the closest approach): their relative motion is linear,
/// with closest distance |X·W − Y·v| / √(v² + W²) at t* = (X·v + Y·W)/(v² + W²), inside a
/// step. v = 0.3, W = 0.4, (X, Y) = (2, 1): 1 m exactly at t* = 4 s; and (2, 0.5) with
/// v = W = 0.3: 0.45/√0.18 = 1.0606… m at t* = 4.1666… s, irrational.
#[test]
fn a_perpendicular_crossing_has_the_linear_closest_approach() {
    for (v, w, x, y) in [(0.3, 0.4, 2.0, 1.0), (0.3, 0.3, 2.0, 0.5)] {
        let line = line_problem(
            &format!(
                "max_speed = {v}\nacceleration = 1.0\nbraking = 1.0\ncontrol_period = 0.3\nlatency = 0\nclearance = 0.0\ninitial_speed = {v}"
            ),
            "assumed_obstacle_speed = 0.0\nreaction_radius = 1.0\ndanger_rule = \"area\"\nbuffer = 0.0\nwrong_assumption_brake = true",
        );
        let mut params = embed(&line);
        params.obstacles[0].direction = None;
        params.obstacles[0].max_speed = decimal(w);
        params.obstacles[0].start = safereach::core::planar::Start::At(point(x, -y));
        params.sensing.range = Some(decimal(0.5));
        let steps = 40;
        let behaviour = one_obstacle(&params, point(x, -y), vec![point(0.0, w); steps]);
        let out = run(&params, &behaviour, steps).expect("replays");
        assert_eq!(out.brake, None, "never seen, never braked");
        let s = out.separation(0).expect("moved");
        let closest = (x * w - y * v).abs() / (v * v + w * w).sqrt();
        let t_star = (x * v + y * w) / (v * v + w * w);
        let (lo, hi) = (s.lower.to_f64().value(), s.upper.to_f64().value());
        assert!(
            lo <= closest + 1e-12 && closest <= hi + 1e-12,
            "{lo} {closest} {hi}"
        );
        assert!(&s.upper - &s.lower < decimal(1e-15));
        assert!((s.at.to_f64().value() - t_star).abs() < 1e-9);
        // Exactly: lower² ≤ (X·W − Y·v)²/(v² + W²) ≤ upper².
        let (ev, ew, ex, ey) = (decimal(v), decimal(w), decimal(x), decimal(y));
        let cross = &ex * &ew - &ey * &ev;
        let d2 = &cross * &cross / (&ev * &ev + &ew * &ew);
        assert!(&s.lower * &s.lower <= d2 && d2 <= &s.upper * &s.upper);
    }
}

/// The 1-D step function's run with the obstacle rushing at W: its brake step and the least
/// gap over moving instants (the gap never grows, so each moving step's lowest is its end
/// or its rest gap).
fn line_run(problem: &Problem, steps: usize) -> (Option<usize>, Option<Exact>) {
    let p = problem.params::<Exact>();
    let mut world = World::new(p.clone());
    let (mut brake, mut least): (Option<usize>, Option<Exact>) = (None, None);
    while world.k() < steps && !world.stopped() {
        let rec = world.step(p.W.clone());
        if rec.brake.is_some() && brake.is_none() {
            brake = Some(rec.k);
        }
        if rec.motion.moving_for > Exact::ZERO {
            let g = rec.rest_gap.clone().unwrap_or(rec.end_gap.clone());
            if least.as_ref().is_none_or(|l| g < *l) {
                least = Some(g);
            }
        }
    }
    (brake, least)
}

const EMBED_STEPS: usize = 1500;

fn plane_run(problem: &Problem) -> PlanarRun {
    let params = embed(problem);
    let p = &params.obstacles[0];
    let towards = p.direction.as_ref().expect("fixed").unit() * &p.max_speed;
    let start = point(0.0, 0.0);
    let start = match &p.start {
        safereach::core::planar::Start::At(q) => q.clone(),
        _ => start,
    };
    let behaviour = one_obstacle(&params, start, vec![towards; EMBED_STEPS]);
    run(&params, &behaviour, EMBED_STEPS).expect("replays")
}

proptest! {
    #![proptest_config(config(16))]

    /// §13.7: the embedded line brakes at the line's step and its least separation is
    /// max(the line's least gap, 0), exactly. (After contact the plane's disc zone also sees
    /// an obstacle behind the robot, the line's does not: brake steps then may differ, and
    /// only there.)
    #[test]
    fn the_embedded_line_replays_as_the_line(spec in any_spec()) {
        let line = spec.problem();
        let (brake, least) = line_run(&line, EMBED_STEPS);
        let plane = plane_run(&line);
        let contact = least.as_ref().is_some_and(|g| *g <= Exact::ZERO);
        if brake.is_some() || !contact {
            prop_assert_eq!(plane.brake.map(|b| b.step), brake);
        }
        match least {
            None => prop_assert!(plane.separation(0).is_none()),
            Some(g) => {
                let s = plane.separation(0).expect("moved");
                let expected = if g > Exact::ZERO { g } else { Exact::ZERO };
                prop_assert_eq!(&s.lower, &expected);
                prop_assert_eq!(&s.upper, &expected);
            }
        }
    }
}

/// A path turning by atan(4/3) at arc length 0.3 and a robot braking through the turn from
/// v0 = 1 at b = 1: s(t) = t − t²/2 meets 0.3 at t = 1 − √0.4, a quadratic surd. The static
/// obstacle at (0.4, −0.1) is nearest to the vertex itself (outside both segments' normal
/// strips), √0.02 m away. The bracket must hold √0.02 exactly, be narrower than 10⁻¹², and
/// hold every dense exact evaluation's values above its lower end.
#[test]
fn a_turn_crossed_while_braking_is_bracketed_tightly() {
    let line = line_problem(
        "max_speed = 1.0\nacceleration = 1.0\nbraking = 1.0\ncontrol_period = 0.25\nlatency = 0\nclearance = 0.0\ninitial_speed = 1.0",
        "assumed_obstacle_speed = 0.0\nreaction_radius = 1.0\ndanger_rule = \"area\"\nbuffer = 0.0\nwrong_assumption_brake = false",
    );
    let mut params = embed(&line);
    let delta = decimal(1e-9);
    let turn = Path::new(vec![point(0.0, 0.0), point(0.3, 0.0), point(0.9, 0.8)]).expect("a path");
    params.path = RationalPath::new(&turn, &delta).expect("analysable");
    assert_eq!(
        params.path.drift(),
        &Exact::ZERO,
        "3-4-5 directions are exact"
    );
    let start = point(0.4, -0.1);
    params.obstacles[0].start = safereach::core::planar::Start::At(start.clone());
    params.obstacles[0].max_speed = Exact::ZERO;
    params.obstacles[0].direction =
        Some(RationalDirection::near(&point(-1.0, 0.0), &delta).expect("a direction"));
    let out = run(
        &params,
        &one_obstacle(&params, start.clone(), Vec::new()),
        20,
    )
    .expect("replays");
    assert_eq!(out.brake.map(|b| b.step), Some(0));
    assert_eq!(out.rest, Some(Exact::ONE));
    let s = out.separation(0).expect("moved");
    assert!(
        &s.upper - &s.lower < decimal(1e-12),
        "width {}",
        (&s.upper - &s.lower).to_f64().value()
    );
    let d2 = decimal(0.02);
    assert!(&s.lower * &s.lower <= d2 && d2 <= &s.upper * &s.upper);
    // Dense exact evaluation: the robot's centre at 4000 rational instants of [0, 1].
    let p = &params.motion;
    let state = RobotState {
        position: Exact::ZERO,
        speed: Exact::ONE,
        mode: Mode::Brake,
    };
    let mut dense = None::<Exact>;
    for i in 0..=4000 {
        let t = Exact::from(i) / Exact::from(4000);
        let arc = state_within(p, &state, &t).position;
        let d = params.path.point_at(&arc).distance_squared(&start);
        assert!(&s.lower * &s.lower <= d, "a dense value below the bracket");
        if dense.as_ref().is_none_or(|m| d < *m) {
            dense = Some(d);
        }
    }
    let dense = dense.expect("evaluated");
    assert!(dense.to_f64().value().sqrt() - s.upper.to_f64().value() < 1e-3);
    assert_eq!(out.collides(&decimal(0.1414)), Some(false));
    assert_eq!(out.collides(&decimal(0.1415)), Some(true));
}

/// Occlusion (§13.3): an obstacle that hides is first seen at the first observation whose
/// instant is at or after the one its separation fell to d_det. A static obstacle on the x
/// axis with d_det below the danger distance is then braked for at once: at step L + j, j
/// the first step start with x0 − P_j ≤ d_det (rims), P_j from the line's step function.
#[test]
fn a_hiding_obstacle_is_braked_for_once_within_d_det() {
    let mut params = embed(&worked_example());
    params.obstacles[0].max_speed = Exact::ZERO;
    let x0 = decimal(10.01);
    let start = Point::new(x0.clone(), Exact::ZERO);
    params.obstacles[0].start = safereach::core::planar::Start::At(start.clone());
    let d_det = decimal(0.55);
    params.sensing.first_detection = Some(d_det.clone());
    let mut behaviour = one_obstacle(&params, start, Vec::new());
    let seen = run(&params, &behaviour, 1000).expect("replays");
    assert_eq!(
        seen.brake.map(|b| b.step),
        Some(467),
        "not hiding: as §11.8"
    );
    behaviour.obstacles[0].hide = true;
    let hidden = run(&params, &behaviour, 1000).expect("replays");
    // The drive profile: the line's motion rule, no obstacle.
    let p = worked_example().params::<Exact>();
    let mut robot = RobotState::initial(&p);
    let mut j = 0;
    while &x0 - &robot.position > d_det {
        robot = robot_motion(&p, &robot).end;
        j += 1;
    }
    assert_eq!(hidden.brake.map(|b| b.step), Some(j + params.motion.L));
    assert!(hidden.separation(0).expect("moved").upper < seen.separation(0).expect("moved").lower);
}

/// Behaviours outside the problem's bounds are refused, naming obstacle and step.
#[test]
fn behaviours_outside_the_bounds_are_refused() {
    use safereach::core::planar::BehaviourError;
    use safereach::core::plane::polygon::ConvexPolygon;
    let mut params = embed(&worked_example());
    params.obstacles[0].max_speed = decimal(0.5);
    let start = point(10.0, 0.0);
    let fast = one_obstacle(
        &params,
        start.clone(),
        vec![point(-0.5, 0.0), point(-0.6, 0.0)],
    );
    assert_eq!(
        run(&params, &fast, 10).err(),
        Some(BehaviourError::TooFast {
            obstacle: 0,
            step: 1
        })
    );
    let sideways = one_obstacle(&params, start.clone(), vec![point(0.0, 0.3)]);
    assert_eq!(
        run(&params, &sideways, 10).err(),
        Some(BehaviourError::OffDirection {
            obstacle: 0,
            step: 0
        })
    );
    let elsewhere = one_obstacle(&params, point(9.0, 0.0), Vec::new());
    assert_eq!(
        run(&params, &elsewhere, 10).err(),
        Some(BehaviourError::Start(0))
    );
    params.obstacles[0].region = Some(
        ConvexPolygon::new(vec![
            point(9.5, -1.0),
            point(10.5, -1.0),
            point(10.5, 1.0),
            point(9.5, 1.0),
        ])
        .expect("a square"),
    );
    let leaving = one_obstacle(&params, start, vec![point(-0.5, 0.0); 20]);
    assert_eq!(
        run(&params, &leaving, 20).err(),
        Some(BehaviourError::LeavesRegion {
            obstacle: 0,
            step: 11
        })
    );
}

/// Whether the guard fires at step 0 for a static obstacle at `at` (robot at rest at the
/// origin heading +x, latency 0, the `area` rule with ρ = 5: any seen obstacle within 5 m).
fn fires_at_once(params: &PlanarParams, at: Point) -> bool {
    let mut params = params.clone();
    params.obstacles[0].start = safereach::core::planar::Start::At(at.clone());
    let out = run(&params, &one_obstacle(&params, at, Vec::new()), 1).expect("replays");
    out.brake.is_some_and(|b| b.step == 0)
}

fn at_rest_area_robot() -> PlanarParams {
    let line = line_problem(
        "max_speed = 1.0\nacceleration = 1.0\nbraking = 1.0\ncontrol_period = 0.25\nlatency = 0\nclearance = 0.0",
        "assumed_obstacle_speed = 0.0\nreaction_radius = 5.0\ndanger_rule = \"area\"\nbuffer = 0.0\nwrong_assumption_brake = false",
    );
    let mut params = embed(&line);
    params.obstacles[0].max_speed = Exact::ZERO;
    params
}

/// The field of view, exactly at its sign cases: cos(θ/2) = 4/5 (a narrow view) sees
/// (1, 0.5) (26.6°) and not (1, 1) (45°); cos = −3/5 (a view of 253.7°) sees (−1, 2)
/// (116.6°) and not (−1, 1) (135°); (4, 3) lies on the 4/5 cone's edge and is seen.
#[test]
fn the_field_of_view_is_decided_exactly() {
    let mut params = at_rest_area_robot();
    params.sensing.view_cos_half = Some(decimal(0.8));
    assert!(fires_at_once(&params, point(1.0, 0.5)));
    assert!(!fires_at_once(&params, point(1.0, 1.0)));
    assert!(fires_at_once(&params, point(4.0, 3.0)));
    assert!(!fires_at_once(&params, point(-1.0, 0.1)));
    params.sensing.view_cos_half = Some(decimal(-0.6));
    assert!(fires_at_once(&params, point(-1.0, 2.0)));
    assert!(!fires_at_once(&params, point(-1.0, 1.0)));
    assert!(fires_at_once(&params, point(1.0, -1.0)));
}

/// The polygon zone in the robot's frame (x ahead, y to the left): the asymmetric stop
/// rectangle [0, 1] × [−0.1, 0.5] meets an obstacle disc of radius 0.1 at (0.5, 0.55) and
/// not its mirror image (0.5, −0.55), 0.45 m off.
#[test]
fn the_polygon_zone_reads_the_robots_frame() {
    use safereach::core::planar::DangerZone;
    use safereach::core::plane::polygon::ConvexPolygon;
    let mut params = at_rest_area_robot();
    params.obstacles[0].radius = decimal(0.1);
    let corners = [(0.0, -0.1), (1.0, -0.1), (1.0, 0.5), (0.0, 0.5)];
    let zone = ConvexPolygon::new(corners.iter().map(|&(x, y)| point(x, y)).collect());
    params.zone = DangerZone::Polygon(zone.expect("a rectangle"));
    assert!(fires_at_once(&params, point(0.5, 0.55)));
    assert!(fires_at_once(&params, point(1.1, 0.0)));
    assert!(!fires_at_once(&params, point(0.5, -0.55)));
    assert!(!fires_at_once(&params, point(1.2, 0.0)));
}
