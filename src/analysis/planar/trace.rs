//! A planar behaviour's replay as rows (one per obstacle per step start), for traces
//! (`simulate --replay --trace`) and the top-view figure: the exact replay's positions,
//! rounded to floats only here, where they are shown.

use serde::Serialize;

use crate::core::num::Exact;
use crate::core::planar::{BehaviourError, PlanarBehaviour, PlanarParams, PlanarRun, run_observed};

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
    pub robot_speed: f64,
    /// The robot's mode (`accelerate`, `drive`, `brake`, `stop`).
    pub mode: String,
    /// The obstacle.
    pub obstacle: String,
    /// Its centre (m).
    pub x: f64,
    /// Its centre (m).
    pub y: f64,
}

/// The rows of `behaviour` replayed for at most `steps` periods, and the finished run.
pub fn planar_trace(
    params: &PlanarParams,
    behaviour: &PlanarBehaviour,
    steps: usize,
) -> Result<(Vec<PlanarTraceRow>, PlanarRun), BehaviourError> {
    let mut rows = Vec::new();
    let f = |x: &Exact| x.to_f64().value();
    let run = run_observed(params, behaviour, steps, |r| {
        let robot = r.robot();
        let centre = r.robot_centre();
        for (i, o) in params.obstacles.iter().enumerate() {
            let at = r.centre(i);
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
            });
        }
    })?;
    Ok((rows, run))
}
