//! A planar behaviour's replay as rows (one per obstacle per step start), for traces
//! (`simulate --replay --trace`, read back by the planar monitor: the columns are its
//! names) and the top-view figure: the exact replay's positions, rounded to floats only
//! here, where they are shown.
//!
//! A row's mode is the robot's from its instant on: after the guards of that step start (a
//! guard that fires there shows `brake`, a brake at rest `stop`), as the monitor reads it;
//! its velocity is the obstacle's over the period that ended at the row (none at t = 0).

use serde::Serialize;

use crate::core::num::Exact;
use crate::core::planar::{BehaviourError, PlanarBehaviour, PlanarParams, PlanarRun, run_observed};
use crate::core::plane::point::Point;

/// One obstacle at one step start.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlanarTraceRow {
    /// The step.
    pub step: usize,
    /// Its start (s).
    pub t: f64,
    /// The robot's centre (m).
    pub robot_x: f64,
    /// The robot's centre (m).
    pub robot_y: f64,
    /// The robot's speed (m/s).
    #[serde(rename = "robot_v")]
    pub robot_speed: f64,
    /// The robot's mode from this instant on (`accelerate`, `drive`, `brake`, `stop`).
    #[serde(rename = "robot_mode")]
    pub mode: String,
    /// The obstacle.
    #[serde(rename = "obstacle_id")]
    pub obstacle: String,
    /// Its centre (m).
    #[serde(rename = "obstacle_x")]
    pub x: f64,
    /// Its centre (m).
    #[serde(rename = "obstacle_y")]
    pub y: f64,
    /// Its velocity over the period that ended at `t` (m/s; none at the first row).
    #[serde(rename = "obstacle_vx")]
    pub vx: Option<f64>,
    /// The same, y.
    #[serde(rename = "obstacle_vy")]
    pub vy: Option<f64>,
}

/// The rows of `behaviour` replayed for at most `steps` periods, and the finished run.
pub fn planar_trace(
    params: &PlanarParams,
    behaviour: &PlanarBehaviour,
    steps: usize,
) -> Result<(Vec<PlanarTraceRow>, PlanarRun), BehaviourError> {
    let mut rows = Vec::new();
    let f = |x: &Exact| x.to_f64().value();
    let mut previous: Vec<Point> = Vec::new();
    let run = run_observed(params, behaviour, steps, |r| {
        let robot = r.robot();
        let centre = r.robot_centre();
        for (i, o) in params.obstacles.iter().enumerate() {
            let at = r.centre(i);
            let velocity = previous.get(i).map(|p| {
                (
                    &(&at.x - &p.x) / &params.motion.dt,
                    &(&at.y - &p.y) / &params.motion.dt,
                )
            });
            rows.push(PlanarTraceRow {
                step: r.k(),
                t: f(&(Exact::from(r.k()) * &params.motion.dt)),
                robot_x: f(&centre.x),
                robot_y: f(&centre.y),
                robot_speed: f(&robot.speed),
                mode: format!("{:?}", robot.mode).to_lowercase(),
                obstacle: o.name.clone(),
                x: f(&at.x),
                y: f(&at.y),
                vx: velocity.as_ref().map(|v| f(&v.0)),
                vy: velocity.as_ref().map(|v| f(&v.1)),
            });
        }
        previous = (0..params.obstacles.len())
            .map(|i| r.centre(i).clone())
            .collect();
    })?;
    // The mode from each instant on: the guard that fired at a step start brakes there.
    let n = params.obstacles.len().max(1);
    if let Some(brake) = run.brake {
        for row in rows.iter_mut().skip(brake.step * n).take(n) {
            row.mode = "brake".into();
        }
    }
    for row in &mut rows {
        if row.mode == "brake" && row.robot_speed <= 0.0 {
            row.mode = "stop".into();
        }
    }
    Ok((rows, run))
}
