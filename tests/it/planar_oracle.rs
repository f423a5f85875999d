//! The brute-force planar oracle (tests/it/common/planar_oracle.rs) against the plane's
//! lower bound (`analysis::planar::lower_bound`): on small hand-built problems — a free
//! direction, a fixed direction, a box of starts — no behaviour the oracle replays separates
//! by less than the bound (issue 36, 5b), and on a problem built to collide the oracle
//! finds the collision.

use safereach::analysis::planar::{BoundOptions, lower_bound};
use safereach::core::model::Problem;
use safereach::core::num::Exact;
use safereach::core::planar::{PlanarParams, Start};
use safereach::core::plane::direction::RationalDirection;
use safereach::core::plane::point::Point;

use crate::common::line_in_plane::{decimal, embed};
use crate::common::planar_oracle::{OracleAnswer, along, compass, explore};

/// A short-period robot (dt = 0.25 s) and controller, with one obstacle of radius 0.2 m
/// starting at `start`, moving freely at up to `w`; the robot's radius is 0.3 m.
fn small(latency: u32, rho: f64, w: f64, start: Point) -> PlanarParams {
    let text = format!(
        "name = \"t\"\n[robot]\nmax_speed = 1.0\nacceleration = 2.0\nbraking = 1.0\n\
         control_period = 0.25\nlatency = {latency}\nclearance = 0.0\n[controller]\n\
         assumed_obstacle_speed = 0.3\nreaction_radius = {rho}\ndanger_rule = \"kinematic\"\n\
         buffer = 0.1\nwrong_assumption_brake = true\n[environment]\nobstacle_speed = {w}\n\
         initial_gap = 10.0\n"
    );
    let mut params = embed(&Problem::from_toml_str(&text, "test").expect("valid"));
    params.robot_radius = decimal(0.3);
    let o = &mut params.obstacles[0];
    o.radius = decimal(0.2);
    o.direction = None;
    o.start = Start::At(start);
    params
}

/// The oracle's least separation is not below the bound asked to prove a little more.
fn holds_the_bound(params: &PlanarParams, oracle: &OracleAnswer) {
    let goal = &oracle.least_upper + decimal(1e-6);
    let bound = lower_bound(params, &goal, &BoundOptions::default()).expect("the plane bounds");
    eprintln!(
        "oracle: {} runs, least separation in [{}, {}]; bound {} ({} programs)",
        oracle.runs,
        oracle.least_lower.to_f64().value(),
        oracle.least_upper.to_f64().value(),
        bound.lower.to_f64().value(),
        bound.programs
    );
    assert!(oracle.runs > 100);
    assert!(
        oracle.least_upper >= bound.lower && oracle.least_lower >= &bound.lower - decimal(1e-12),
        "a replayed behaviour separates by less than the proved bound"
    );
}

fn at(x: f64, y: f64) -> Point {
    Point::decimal(x, y)
}

/// The oracle from the obstacle's one start, free at up to `w`, over `n` steps of choices.
fn compass_oracle(params: &PlanarParams, start: Point, w: f64, n: usize) -> OracleAnswer {
    explore(params, &[vec![start]], &[compass(&decimal(w))], n, 24)
}

#[test]
fn free_direction_never_beats_the_bound() {
    let params = small(0, 2.0, 0.2, at(3.0, 0.8));
    let oracle = compass_oracle(&params, at(3.0, 0.8), 0.2, 4);
    holds_the_bound(&params, &oracle);
}

#[test]
fn fixed_direction_never_beats_the_bound() {
    let mut params = small(0, 1.2, 0.6, at(2.0, -1.5));
    let d = RationalDirection::near(&at(0.0, 1.0), &decimal(1e-9)).expect("a direction");
    let speeds = along(d.unit(), &decimal(0.6), 2);
    params.obstacles[0].direction = Some(d);
    let oracle = explore(&params, &[vec![at(2.0, -1.5)]], &[speeds], 6, 24);
    holds_the_bound(&params, &oracle);
}

#[test]
fn a_box_of_starts_never_beats_the_bound() {
    let (min, max) = (at(3.0, -0.5), at(3.5, 0.5));
    let mut params = small(0, 2.0, 0.2, min.clone());
    params.obstacles[0].start = Start::Box {
        min: min.clone(),
        max: max.clone(),
    };
    let starts: Vec<Vec<Point>> = [min, max, at(3.0, 0.5), at(3.5, -0.5), at(3.25, 0.0)]
        .into_iter()
        .map(|p| vec![p])
        .collect();
    let oracle = explore(&params, &starts, &[compass(&decimal(0.2))], 3, 24);
    holds_the_bound(&params, &oracle);
}

/// A start box of height 0 on the robot's own line, the obstacle coming straight down it
/// (the line's range of gaps in the plane): every centre lies on the ray between two
/// quarter arcs of the anchor's cover, which a strict sector row once proved empty, and
/// the bound rose above the oracle's collision-free least separation by metres.
#[test]
fn a_box_of_height_0_on_the_robots_line_never_beats_the_bound() {
    let (min, max) = (at(3.0, 0.0), at(4.0, 0.0));
    let mut params = small(1, 1.5, 0.4, min.clone());
    let d = RationalDirection::near(&at(-1.0, 0.0), &decimal(1e-9)).expect("a direction");
    let speeds = along(d.unit(), &decimal(0.4), 2);
    params.obstacles[0].direction = Some(d);
    params.obstacles[0].start = Start::Box {
        min: min.clone(),
        max: max.clone(),
    };
    let starts: Vec<Vec<Point>> = [min, at(3.5, 0.0), max]
        .into_iter()
        .map(|p| vec![p])
        .collect();
    let oracle = explore(&params, &starts, &[speeds], 6, 24);
    holds_the_bound(&params, &oracle);
}

/// A robot that reacts late (ρ = 0.3 m, latency 2) and an obstacle as fast as it: rushing
/// at the robot's path, the obstacle meets it before it can stop.
#[test]
fn the_oracle_finds_a_built_collision() {
    let params = small(2, 0.3, 0.8, at(2.0, 1.0));
    let oracle = compass_oracle(&params, at(2.0, 1.0), 0.8, 3);
    assert!(
        oracle.collides,
        "least separation {}",
        oracle.least_upper.to_f64().value()
    );
    assert!(oracle.least_upper < Exact::ZERO);
}

/// A 120° field of view (cos 60° = 1/2): an obstacle starting beside the robot, outside
/// the view, is never seen there; the bound covers the outside of the view (Lemma P1(3)).
#[test]
fn a_field_of_view_never_beats_the_bound() {
    let mut params = small(0, 2.0, 0.2, at(1.2, 1.4));
    params.sensing.view_cos_half = Some(decimal(0.5));
    let oracle = compass_oracle(&params, at(1.2, 1.4), 0.2, 3);
    holds_the_bound(&params, &oracle);
}

/// A Nav2-style stop polygon (1.5 m ahead, 1 m wide, in the robot's frame) instead of the
/// disc zone: the bound covers the polygon's outside edge by edge (Lemma P1(5)).
#[test]
fn a_stop_polygon_never_beats_the_bound() {
    use safereach::core::planar::DangerZone;
    use safereach::core::plane::polygon::ConvexPolygon;
    let mut params = small(0, 2.0, 0.2, at(3.0, 0.8));
    let zone = ConvexPolygon::new(vec![
        at(0.0, -0.5),
        at(1.5, -0.5),
        at(1.5, 0.5),
        at(0.0, 0.5),
    ])
    .expect("a convex polygon");
    params.zone = DangerZone::Polygon(zone);
    let oracle = compass_oracle(&params, at(3.0, 0.8), 0.2, 3);
    holds_the_bound(&params, &oracle);
}

/// Random runs (random headings and speeds, `analysis::planar::planar_monte_carlo`) are
/// behaviours too: none separates by less than the bound, and on the problem built to
/// collide some of them collide.
#[test]
fn random_runs_never_beat_the_bound_and_find_the_built_collision() {
    use safereach::analysis::planar::planar_monte_carlo;
    let params = small(0, 2.0, 0.2, at(3.0, 0.8));
    let random = planar_monte_carlo(&params, 40, 7, 60);
    let closest = random.closest.expect("the robot moves");
    let bound = lower_bound(&params, &closest.separation.upper, &BoundOptions::default())
        .expect("the plane bounds");
    assert!(
        closest.separation.lower >= bound.lower,
        "a random run beats the bound"
    );
    assert_eq!(random.collisions, 0);
    let colliding = small(2, 0.3, 0.8, at(2.0, 1.0));
    let random = planar_monte_carlo(&colliding, 200, 7, 60);
    assert!(random.collisions > 0, "no collision in 200 random runs");
}
