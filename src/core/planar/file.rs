//! A planar problem file as read (docs/semantics.md §13.10): the file's own numbers, in the
//! file's units, before they become exact ([`PlanarProblem::params`]). The robot's motion
//! and the controller are the line's [`Robot`] and [`Controller`], read and validated as a
//! problem's.

use crate::core::model::{Controller, Robot};

/// A planar problem, as its file states it (validated when read).
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarProblem {
    /// Short name shown in reports.
    pub name: String,
    /// The chord tolerance every direction is made a rational unit vector within
    /// (`plane.direction_tolerance`; None: 10⁻⁹).
    pub direction_tolerance: Option<f64>,
    /// The robot's motion along its path: every `[robot]` key of a problem.
    pub robot: Robot,
    /// The robot's disc and path (the planar `[robot]` keys).
    pub body: PlanarRobot,
    /// The controller: every `[controller]` key of a problem.
    pub controller: Controller,
    /// The collision-danger guard's zone (`controller.danger_zone`, `controller.stop_polygon`).
    pub zone: Zone,
    /// `[sensing]`.
    pub sensing: PlanarSensingFile,
    /// The `[[obstacle]]` tables, in file order.
    pub obstacles: Vec<PlanarObstacleFile>,
}

/// The planar keys of `[robot]`.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarRobot {
    /// r_R (m), ≥ 0 (`robot.radius`, default 0).
    pub radius: f64,
    /// The path's vertices from (0, 0) (`robot.path`); None: the x axis without end.
    pub path: Option<Vec<[f64; 2]>>,
    /// How far its centre may be off the path (m), ≥ 0 (`robot.path_tolerance`, default 0).
    pub path_tolerance: f64,
    /// Whether the robot must rest at or before the path's end (`robot.path_end = "stop"`,
    /// the default for a given path) or its last segment runs on (`"continue"`). False
    /// without a path.
    pub stops_at_end: bool,
}

/// The danger zone as the file gives it.
#[derive(Clone, Debug, PartialEq)]
pub enum Zone {
    /// `danger_zone = "disc"` (the default).
    Disc,
    /// `danger_zone = "polygon"` with its `stop_polygon`, in the robot's frame (m).
    Polygon(Vec<[f64; 2]>),
}

/// `[sensing]` of a planar file (every key optional).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlanarSensingFile {
    /// σ_p (m), ≥ 0; None: 0.
    pub position_noise: Option<f64>,
    /// σ_w (m/s), ≥ 0; None: 0.
    pub velocity_noise: Option<f64>,
    /// d_det (m), > 0; None: seen whenever visible.
    pub first_detection: Option<f64>,
    /// R (m), > 0; None: unlimited.
    pub range: Option<f64>,
    /// θ (degrees), in (0, 360]; None: all round.
    pub field_of_view: Option<f64>,
}

/// One `[[obstacle]]` of a planar file.
#[derive(Clone, Debug, PartialEq)]
pub struct PlanarObstacleFile {
    /// Its name, unique in the file (default `obstacle-<index>`).
    pub name: String,
    /// r_i (m), ≥ 0 (default 0).
    pub radius: f64,
    /// Where its centre starts.
    pub start: StartFile,
    /// W_i (m/s), ≥ 0.
    pub max_speed: f64,
    /// Its fixed direction (nonzero, any length); None: free.
    pub direction: Option<[f64; 2]>,
    /// The convex polygon it never leaves (m); None: the whole plane.
    pub region: Option<Vec<[f64; 2]>>,
}

/// An obstacle's start as the file gives it.
#[derive(Clone, Debug, PartialEq)]
pub enum StartFile {
    /// `start = [x, y]`.
    At([f64; 2]),
    /// `start_min = [..]` and `start_max = [..]`: any point of the box.
    Box {
        /// The least corner.
        min: [f64; 2],
        /// The greatest corner.
        max: [f64; 2],
    },
}
