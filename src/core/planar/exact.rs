//! A planar problem file's numbers made exact ([`PlanarProblem::params`]), with the
//! geometry checked exactly on the way: a path that is one (from (0, 0), no
//! zero-length segment, not crossing itself), convex polygons, nonzero directions, starts
//! inside their regions, no obstacle starting in collision or unseeable, and horizons of at
//! most a million control periods.

use crate::core::model::error::show_number;
use crate::core::model::validate::distance_horizon_violation;
use crate::core::model::{Environment, Position, Problem, Sensing};
use crate::core::num::{Exact, exact_decimal, exact_float};
use crate::core::planar::file::{PlanarProblem, StartFile, Zone};
use crate::core::planar::keys::{
    DIRECTION, DIRECTION_TOLERANCE, PATH, REGION, START, START_MIN, STOP_POLYGON,
};
use crate::core::planar::validate::{show_point, show_points};
use crate::core::planar::{DangerZone, PlanarObstacle, PlanarParams, PlanarSensing, Start};
use crate::core::plane::direction::{DirectionError, RationalDirection};
use crate::core::plane::path::Path;
use crate::core::plane::point::Point;
use crate::core::plane::polygon::ConvexPolygon;
use crate::core::plane::rational_path::RationalPath;
use crate::core::scene::keys::SceneKey;
use crate::core::scene::validate::SceneViolation;

/// The chord tolerance of directions when the file gives none.
pub const DEFAULT_DIRECTION_TOLERANCE: f64 = 1e-9;

/// How far the default path (the x axis without end) is written out (m): a segment whose
/// end is not a destination; no robot covers it within a million control periods unless
/// it drives at least 1 m per period.
pub const AXIS_LENGTH: i64 = 1_000_000;

/// A bound on the error of the float cos(θ/2), far above what f64 makes (≈ 10⁻¹⁵), so that
/// adding it rounds up.
const COS_MARGIN: f64 = 1.0 / (1u64 << 40) as f64;

fn point(p: &[f64; 2]) -> Point {
    Point::decimal(p[0], p[1])
}

fn points(p: &[[f64; 2]]) -> Vec<Point> {
    p.iter().map(point).collect()
}

/// The violation at `key` with `value` shown and `reason`.
fn at(key: SceneKey, value: String, reason: String) -> SceneViolation {
    SceneViolation { key, value, reason }
}

/// cos(θ/2) for a field of view of `theta` degrees, rounded up to a rational: exact where it
/// is rational (Niven's theorem: at θ/2 = 60°, 90°, 120°, 180° among angles in (0°, 180°]),
/// else the float plus a margin above its error.
pub(crate) fn view_cos_half(theta: f64) -> Exact {
    let half = theta / 2.0;
    let exact = [
        (60.0, (1, 2)),
        (90.0, (0, 1)),
        (120.0, (-1, 2)),
        (180.0, (-1, 1)),
    ];
    if let Some(&(_, (n, d))) = exact.iter().find(|(h, _)| *h == half) {
        return Exact::from(n) / Exact::from(d);
    }
    let up = exact_float(half.to_radians().cos()) + exact_float(COS_MARGIN);
    up.min(Exact::ONE)
}

/// The least squared distance from the origin to the start (a point or a box).
fn nearest_squared(start: &Start) -> Exact {
    match start {
        Start::At(p) => p.norm_squared(),
        Start::Box { min, max } => {
            let clamp =
                |lo: &Exact, hi: &Exact| Exact::ZERO.clone().max(lo.clone()).min(hi.clone());
            Point::new(clamp(&min.x, &max.x), clamp(&min.y, &max.y)).norm_squared()
        }
    }
}

/// The start's corners (one for a point).
fn corners(start: &Start) -> Vec<Point> {
    match start {
        Start::At(p) => vec![p.clone()],
        Start::Box { min, max } => vec![
            min.clone(),
            Point::new(max.x.clone(), min.y.clone()),
            max.clone(),
            Point::new(min.x.clone(), max.y.clone()),
        ],
    }
}

impl PlanarProblem {
    /// The problem's exact numbers (docs/semantics.md §13.10): decimals as the file writes
    /// them, directions as rational unit vectors within the chord tolerance, the path
    /// analysed (`core::plane::rational_path`), cos(θ/2) rounded up. The line's obstacle
    /// numbers in `motion`, which planar engines do not read, are W = the largest W_i,
    /// g0 = the least start centre distance (as a float's decimal), σ_g = σ_p, σ_w and d_det.
    ///
    /// # Panics
    /// If the fields were changed after reading into a problem the reader refuses.
    pub fn params(&self) -> PlanarParams {
        match self.exact() {
            Ok(p) => p,
            Err(v) => panic!(
                "a planar problem read from a file is valid: {} = {}: {}",
                self.show_key(v.key),
                v.value,
                v.reason
            ),
        }
    }

    /// The chord tolerance δ.
    fn tolerance(&self) -> Exact {
        exact_decimal(
            self.direction_tolerance
                .unwrap_or(DEFAULT_DIRECTION_TOLERANCE),
        )
    }

    /// The violation for a direction `near` could not give within δ.
    fn tolerance_violation(&self, e: &DirectionError) -> SceneViolation {
        at(
            SceneKey::Plain(DIRECTION_TOLERANCE.key),
            show_number(
                self.direction_tolerance
                    .unwrap_or(DEFAULT_DIRECTION_TOLERANCE),
            ),
            format!("too small to prove directions within it in rationals ({e}); use >= 1e-12"),
        )
    }

    /// The exact numbers, or the first geometric rule the problem breaks (its numbers are
    /// already in range).
    pub(crate) fn exact(&self) -> Result<PlanarParams, SceneViolation> {
        let delta = self.tolerance();
        let (path, path_ends) = self.path(&delta)?;
        let zone = match &self.zone {
            Zone::Disc => DangerZone::Disc,
            Zone::Polygon(p) => {
                DangerZone::Polygon(ConvexPolygon::new(points(p)).map_err(|e| {
                    at(
                        SceneKey::Plain(STOP_POLYGON.key),
                        show_points(p),
                        format!("{e} (a convex polygon in the robot's frame, vertices in order)"),
                    )
                })?)
            }
        };
        let s = &self.sensing;
        let decimal = |x: Option<f64>| x.map(exact_decimal);
        let sensing = PlanarSensing {
            position_noise: decimal(s.position_noise).unwrap_or(Exact::ZERO),
            velocity_noise: decimal(s.velocity_noise).unwrap_or(Exact::ZERO),
            first_detection: decimal(s.first_detection),
            range: decimal(s.range),
            view_cos_half: s.field_of_view.map(view_cos_half),
        };
        let obstacles = (0..self.obstacles.len())
            .map(|i| self.obstacle(i, &delta, &sensing))
            .collect::<Result<Vec<_>, _>>()?;
        self.horizon_violation(&path, path_ends)
            .map_or(Ok(()), Err)?;
        Ok(PlanarParams {
            motion: self.motion().params::<Exact>(),
            robot_radius: exact_decimal(self.body.radius),
            path,
            path_ends,
            zone,
            sensing,
            obstacles,
        })
    }

    /// The line's problem the motion is read as: the file's robot and controller, with the
    /// obstacle numbers [`PlanarProblem::params`] documents.
    fn motion(&self) -> Problem {
        let s = &self.sensing;
        let nearest = self
            .obstacles
            .iter()
            .map(|o| match o.start {
                StartFile::At(p) => p[0].hypot(p[1]),
                StartFile::Box { min, max } => {
                    let clamp = |a: usize| 0f64.max(min[a]).min(max[a]);
                    clamp(0).hypot(clamp(1))
                }
            })
            .fold(f64::INFINITY, f64::min);
        let fastest = self
            .obstacles
            .iter()
            .map(|o| o.max_speed)
            .fold(0.0, f64::max);
        Problem {
            name: self.name.clone(),
            robot: self.robot.clone(),
            controller: self.controller.clone(),
            environment: Environment {
                obstacle_speed: fastest,
                initial_gap: Position::At(nearest),
            },
            sensing: Some(Sensing {
                gap_noise: s.position_noise,
                speed_noise: s.velocity_noise,
                first_detection_gap: s.first_detection,
            }),
        }
    }

    /// The analysed path and whether it ends (a destination).
    fn path(&self, delta: &Exact) -> Result<(RationalPath, bool), SceneViolation> {
        let key = SceneKey::Plain(PATH.key);
        let vertices = match &self.body.path {
            Some(p) => points(p),
            None => vec![
                Point::origin(),
                Point::new(Exact::from(AXIS_LENGTH), Exact::ZERO),
            ],
        };
        let shown = || {
            self.body
                .path
                .as_deref()
                .map_or("the x axis".into(), show_points)
        };
        let path = Path::new(vertices).map_err(|e| at(key, shown(), e.to_string()))?;
        let analysed = RationalPath::new(&path, delta)
            .map_err(|e| self.tolerance_violation(&e))?
            .widened(&exact_decimal(self.body.path_tolerance));
        Ok((analysed, self.body.path.is_some() && self.body.stops_at_end))
    }

    /// Obstacle `i` made exact, its direction nonzero, its start inside its region, not in
    /// collision and not closer than d_det.
    fn obstacle(
        &self,
        i: usize,
        delta: &Exact,
        sensing: &PlanarSensing,
    ) -> Result<PlanarObstacle, SceneViolation> {
        let o = &self.obstacles[i];
        let key = |field: &'static str| SceneKey::Obstacle(i, field);
        let (start, start_key, shown_start) = match &o.start {
            StartFile::At(p) => (Start::At(point(p)), START.key, show_point(p)),
            StartFile::Box { min, max } => (
                Start::Box {
                    min: point(min),
                    max: point(max),
                },
                START_MIN.key,
                format!("{} to {}", show_point(min), show_point(max)),
            ),
        };
        let direction =
            match &o.direction {
                None => None,
                Some(d) => Some(RationalDirection::near(&point(d), delta).map_err(|e| {
                    match e {
                        DirectionError::Zero => at(
                            key(DIRECTION.key),
                            show_point(d),
                            "must be nonzero: the direction the obstacle moves along (any length)"
                                .into(),
                        ),
                        DirectionError::Tolerance => self.tolerance_violation(&e),
                    }
                })?),
            };
        let region = match &o.region {
            None => None,
            Some(r) => Some(ConvexPolygon::new(points(r)).map_err(|e| {
                at(
                    key(REGION.key),
                    show_points(r),
                    format!("{e} (the convex polygon the obstacle never leaves)"),
                )
            })?),
        };
        if let Some(region) = &region
            && let Some(c) = corners(&start).iter().find(|c| !region.contains(c))
        {
            let (x, y) = c.to_f64();
            let which = match &o.start {
                StartFile::At(_) => "the start".to_string(),
                StartFile::Box { .. } => format!("the box's corner {}", show_point(&[x, y])),
            };
            return Err(at(
                key(start_key),
                shown_start,
                format!(
                    "{which} lies outside the obstacle's region: it must start where it may be"
                ),
            ));
        }
        let radius = exact_decimal(o.radius);
        let reach = exact_decimal(self.body.radius) + &radius;
        let nearest = nearest_squared(&start);
        let clearance = exact_decimal(self.robot.clearance);
        let within = |d: &Exact| {
            let r = d + &reach;
            nearest <= &r * &r
        };
        if within(&clearance) {
            return Err(at(
                key(start_key),
                shown_start,
                format!(
                    "starts in collision: its separation from the robot at t = 0 (centre \
                     distance - robot.radius - radius) must be > robot.clearance = {} (m)",
                    show_number(self.robot.clearance)
                ),
            ));
        }
        if let Some(d_det) = &sensing.first_detection
            && nearest < (d_det + &reach) * (d_det + &reach)
        {
            return Err(at(
                key(start_key),
                shown_start,
                format!(
                    "starts at a separation below sensing.first_detection = {} (m): an occluded \
                     obstacle is first seen at a separation of at least d_det, so one starting \
                     closer could never be seen and every answer would hold vacuously; start it \
                     at d_det or beyond, or lower d_det",
                    show_number(self.sensing.first_detection.unwrap_or(0.0))
                ),
            ));
        }
        Ok(PlanarObstacle {
            name: o.name.clone(),
            radius,
            start,
            max_speed: exact_decimal(o.max_speed),
            direction,
            region,
        })
    }

    /// A path that ends further than a million control periods at top speed, or (for a path
    /// without end) an obstacle starting that far.
    fn horizon_violation(&self, path: &RationalPath, ends: bool) -> Option<SceneViolation> {
        let plain = |v: crate::core::model::error::Violation, key| SceneViolation {
            key,
            value: v.value,
            reason: v.reason,
        };
        if ends {
            let length = path.length().to_f64().value();
            return distance_horizon_violation(
                &self.robot,
                PATH.key,
                length,
                "path length / (max_speed * control_period)",
                "to drive the path at top speed",
            )
            .map(|v| plain(v, SceneKey::Plain(PATH.key)));
        }
        self.obstacles.iter().enumerate().find_map(|(i, o)| {
            let far = match o.start {
                StartFile::At(p) => p[0].hypot(p[1]),
                StartFile::Box { min, max } => min[0]
                    .abs()
                    .max(max[0].abs())
                    .hypot(min[1].abs().max(max[1].abs())),
            };
            distance_horizon_violation(
                &self.robot,
                START.key,
                far,
                "start distance / (max_speed * control_period)",
                "to reach the obstacle's start at top speed",
            )
            .map(|v| plain(v, SceneKey::Obstacle(i, START.key)))
        })
    }
}
