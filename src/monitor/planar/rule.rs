//! What a planar certificate assumed, as the numbers the planar monitor compares with: read
//! once from the certificate's own problem (its text and overrides, as `check` reads them).

use super::geometry::{FloatPath, Xy};
use crate::core::model::Params;
use crate::core::num::Exact;
use crate::core::planar::{DangerZone, PlanarParams, Start};
use crate::core::plane::polygon::ConvexPolygon;

/// The danger zone (§13.4), as floats.
#[derive(Clone, Debug)]
pub(super) enum Zone {
    /// Seen separation ≤ min(ρ, d(v)).
    Disc,
    /// The seen disc meets this convex polygon in the robot's frame.
    Polygon(Vec<Xy>),
}

/// One certified obstacle.
#[derive(Clone, Debug)]
pub(super) struct ObstacleRule {
    pub(super) name: String,
    /// r_i (m).
    pub(super) radius: f64,
    /// W_i (m/s).
    pub(super) max_speed: f64,
    /// Its start box (a point is a box of one point).
    pub(super) start: (Xy, Xy),
    /// The convex region it keeps to.
    pub(super) region: Option<Vec<Xy>>,
}

/// The certified robot, controller, sensing and obstacles.
#[derive(Clone, Debug)]
pub(super) struct PlanarRule {
    /// v_max, a, b, b_min, dt, L, ρ, V_a, the danger rule and buffer, the guards.
    pub(super) motion: Params<f64>,
    /// r_R (m).
    pub(super) robot_radius: f64,
    /// The analysed path and its drift D from the file's (m).
    pub(super) path: FloatPath,
    pub(super) drift: f64,
    pub(super) zone: Zone,
    /// σ_p (m), σ_w (m/s).
    pub(super) position_noise: f64,
    pub(super) velocity_noise: f64,
    /// d_det (m), the range R (m), cos(θ/2) of the field of view.
    pub(super) first_detection: Option<f64>,
    pub(super) range: Option<f64>,
    pub(super) view_cos_half: Option<f64>,
    pub(super) obstacles: Vec<ObstacleRule>,
}

fn f(x: &Exact) -> f64 {
    x.to_f64().value()
}

fn vertices(p: &ConvexPolygon) -> Vec<Xy> {
    p.vertices().iter().map(|v| v.to_f64()).collect()
}

impl PlanarRule {
    /// The rule of `params`.
    pub(super) fn of(params: &PlanarParams) -> PlanarRule {
        let path = FloatPath::new(
            params.path.segments().iter().map(|s| {
                (
                    s.start.to_f64(),
                    s.direction.unit().to_f64(),
                    f(&s.length),
                    f(&s.arc_start),
                )
            }),
            params.path_ends,
        );
        let s = &params.sensing;
        PlanarRule {
            motion: params.motion.map(f),
            robot_radius: f(&params.robot_radius),
            path,
            drift: f(params.path.drift()),
            zone: match &params.zone {
                DangerZone::Disc => Zone::Disc,
                DangerZone::Polygon(p) => Zone::Polygon(vertices(p)),
            },
            position_noise: f(&s.position_noise),
            velocity_noise: f(&s.velocity_noise),
            first_detection: s.first_detection.as_ref().map(f),
            range: s.range.as_ref().map(f),
            view_cos_half: s.view_cos_half.as_ref().map(f),
            obstacles: params
                .obstacles
                .iter()
                .map(|o| ObstacleRule {
                    name: o.name.clone(),
                    radius: f(&o.radius),
                    max_speed: f(&o.max_speed),
                    start: match &o.start {
                        Start::At(p) => (p.to_f64(), p.to_f64()),
                        Start::Box { min, max } => (min.to_f64(), max.to_f64()),
                    },
                    region: o.region.as_ref().map(vertices),
                })
                .collect(),
        }
    }

    /// Whether the robot sees all round (no field of view, or one of 360°).
    pub(super) fn all_round(&self) -> bool {
        self.view_cos_half.is_none_or(|c| c <= -1.0)
    }

    /// The largest speed bound (m/s): what an object the certificate does not name is held
    /// to.
    pub(super) fn largest_speed(&self) -> f64 {
        self.obstacles
            .iter()
            .map(|o| o.max_speed)
            .fold(0.0, f64::max)
    }
}
