//! A planar problem as exact numbers, after validation: what every planar engine reads
//! (docs/semantics.md §13). The file's reader builds it; tests build it directly.

use crate::core::model::Params;
use crate::core::num::Exact;
use crate::core::plane::direction::RationalDirection;
use crate::core::plane::point::Point;
use crate::core::plane::polygon::ConvexPolygon;
use crate::core::plane::rational_path::RationalPath;

/// A planar problem's numbers, exact.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarParams {
    /// The robot's motion along its path (§13.1) and the controller's numbers: v_max, a, b,
    /// b_min, v0, dt, L, clearance, V_a, ρ, the danger rule, the buffer and whether the
    /// wrong-assumption guard is on. The line's obstacle numbers in it (W, g0, σ_g, σ_w,
    /// d_det) are unused: each obstacle and [`PlanarSensing`] carry the plane's.
    pub motion: Params<Exact>,
    /// r_R: the robot disc's radius (m), ≥ 0.
    pub robot_radius: Exact,
    /// The analysed path (rational directions and lengths). Its drift D is not in the other
    /// numbers: an engine adds it to r_R and to σ_p where it needs soundness for the file's
    /// path (§13).
    pub path: RationalPath,
    /// Whether the path ends (a destination: the robot must rest at or before its end) or
    /// its last segment runs on without end (the default x axis).
    pub path_ends: bool,
    /// The danger zone of the collision-danger guard (§13.4).
    pub zone: DangerZone,
    /// Noise, occlusion, range and field of view (§13.3).
    pub sensing: PlanarSensing,
    /// The obstacles, in file order.
    pub obstacles: Vec<PlanarObstacle>,
}

/// The collision-danger guard's zone (§13.4).
#[derive(Clone, Debug, PartialEq)]
pub enum DangerZone {
    /// Seen centre distance − r_R − r_i ≤ min(ρ, d_coll(v)).
    Disc,
    /// The seen obstacle disc meets this convex polygon, fixed in the robot's frame (origin
    /// at its centre, x along its heading).
    Polygon(ConvexPolygon),
}

/// What the robot's sensors guarantee (§13.3).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct PlanarSensing {
    /// σ_p: every seen centre is within this distance of the true one (m), ≥ 0.
    pub position_noise: Exact,
    /// σ_w: every seen velocity is within this distance of the true one (m/s), ≥ 0.
    pub velocity_noise: Exact,
    /// d_det: an obstacle may stay unseen until its separation first falls to d_det (m);
    /// None: seen whenever visible.
    pub first_detection: Option<Exact>,
    /// R: an obstacle is visible only while its centre is within R of the robot's (m);
    /// None: unlimited.
    pub range: Option<Exact>,
    /// The field of view as cos(θ/2), rational, rounded *up* from the file's θ (a narrower
    /// view sees less, so the rounding only removes observations); None: all round.
    pub view_cos_half: Option<Exact>,
}

/// One obstacle (§13.2).
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarObstacle {
    /// Its name, unique in the problem.
    pub name: String,
    /// r_i: its disc's radius (m), ≥ 0.
    pub radius: Exact,
    /// Where its centre starts.
    pub start: Start,
    /// W_i: its speed bound (m/s), ≥ 0.
    pub max_speed: Exact,
    /// Some(d): it moves along the fixed unit direction d at a speed in [0, W_i];
    /// None: in any direction.
    pub direction: Option<RationalDirection>,
    /// The convex polygon it never leaves; None: the whole plane.
    pub region: Option<ConvexPolygon>,
}

/// Where an obstacle's centre starts.
#[derive(Clone, Debug, PartialEq)]
pub enum Start {
    /// This point.
    At(Point),
    /// Any point of this axis-parallel box, min ≤ max in both coordinates (the adversary's
    /// choice).
    Box {
        /// The corner with the least coordinates.
        min: Point,
        /// The corner with the greatest coordinates.
        max: Point,
    },
}
