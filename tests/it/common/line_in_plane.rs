//! A single-obstacle line problem embedded in the plane as docs/semantics.md §13.7 states:
//! the x axis as the path (without end), the obstacle at (g0, 0) moving along (−1, 0),
//! radii 0, the disc zone, no range or field of view; σ_p = σ_g, σ_w as on the line.

use safereach::core::model::{Position, Problem};
use safereach::core::num::{Exact, exact_decimal};
use safereach::core::planar::{DangerZone, PlanarObstacle, PlanarParams, PlanarSensing, Start};
use safereach::core::plane::direction::RationalDirection;
use safereach::core::plane::path::Path;
use safereach::core::plane::point::Point;
use safereach::core::plane::rational_path::RationalPath;

/// The plane's form of `problem` (a range of gaps is a start box of height 0 on the axis).
pub fn embed(problem: &Problem) -> PlanarParams {
    let motion = problem.params::<Exact>();
    let delta = Exact::from(1) / Exact::from(1_000_000_000);
    // An axis-parallel segment is exact (no drift); its end is not a destination.
    let axis = Path::new(vec![
        Point::origin(),
        Point::new(Exact::from(1_000_000), Exact::ZERO),
    ])
    .expect("the x axis is a path");
    let path = RationalPath::new(&axis, &delta).expect("the x axis is analysable");
    let towards = RationalDirection::near(&Point::new(Exact::from(-1), Exact::ZERO), &delta)
        .expect("(-1, 0) has a direction");
    let obstacle = PlanarObstacle {
        name: "oncoming".into(),
        radius: Exact::ZERO,
        start: match problem.environment.initial_gap {
            Position::At(_) => Start::At(Point::new(motion.g0.clone(), Exact::ZERO)),
            Position::Range(lo, hi) => Start::Box {
                min: Point::new(decimal(lo), Exact::ZERO),
                max: Point::new(decimal(hi), Exact::ZERO),
            },
        },
        max_speed: motion.W.clone(),
        direction: Some(towards),
        region: None,
    };
    let sensing = PlanarSensing {
        position_noise: motion.sigma_g.clone(),
        velocity_noise: motion.sigma_w.clone(),
        first_detection: motion.d_det.clone(),
        range: None,
        view_cos_half: None,
    };
    PlanarParams {
        robot_radius: Exact::ZERO,
        path,
        path_ends: false,
        zone: DangerZone::Disc,
        sensing,
        obstacles: vec![obstacle],
        motion,
    }
}

/// `x` as an exact decimal.
pub fn decimal(x: f64) -> Exact {
    exact_decimal(x)
}
