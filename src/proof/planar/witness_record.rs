//! A replayed planar behaviour as a certificate states it ([`PlanarWitness`]), and back:
//! the analyser writes the record from its replay, and `check` replays the behaviour the
//! record states and requires the same record, so every stated number is the replay's.

use crate::core::num::{Exact, f64_at_most};
use crate::core::planar::{
    ObstacleBehaviour, PlanarBehaviour, PlanarGuard, PlanarParams, PlanarRun, run,
};
use crate::core::plane::point::Point;

use super::certificate::{ObstacleMotion, PlanarWitness};
use super::exact_text::{read, read_point, write, write_point};

/// The record of `behaviour`, replayed for `steps` periods as `replay` (None: no obstacle
/// came near while the robot moved).
pub fn record(
    params: &PlanarParams,
    behaviour: &PlanarBehaviour,
    replay: &PlanarRun,
) -> Option<PlanarWitness> {
    let (i, separation) = replay.closest()?;
    let name = |k: usize| params.obstacles[k].name.clone();
    Some(PlanarWitness {
        obstacle: name(i),
        closest_at: separation.at.to_f64().value(),
        separation: write(&separation.upper),
        collides: replay.collides(&params.motion.clearance) == Some(true),
        brake_step: replay.brake.as_ref().map(|b| b.step),
        guard: replay.brake.as_ref().map(|b| match b.guard {
            PlanarGuard::Danger { obstacle } => format!("danger ({})", name(obstacle)),
            PlanarGuard::WrongAssumption { obstacle } => {
                format!("wrong assumption ({})", name(obstacle))
            }
            PlanarGuard::Destination => "destination".to_string(),
        }),
        rest: replay.rest.as_ref().map(f64_at_most),
        steps: replay.steps,
        obstacles: behaviour
            .obstacles
            .iter()
            .zip(&params.obstacles)
            .map(|(b, o)| ObstacleMotion {
                name: o.name.clone(),
                start: write_point(&b.start),
                velocities: b.velocities.iter().map(write_point).collect(),
                position_errors: b.position_errors.iter().map(write_point).collect(),
                velocity_errors: b.velocity_errors.iter().map(write_point).collect(),
                hide: b.hide,
            })
            .collect(),
    })
}

/// The behaviour `witness` states, or why it states none.
pub fn behaviour(
    params: &PlanarParams,
    witness: &PlanarWitness,
) -> Result<PlanarBehaviour, String> {
    if witness.obstacles.len() != params.obstacles.len() {
        return Err(format!(
            "it moves {} obstacles; the problem has {}",
            witness.obstacles.len(),
            params.obstacles.len()
        ));
    }
    let points = |list: &[[String; 2]], what: &str, name: &str| -> Result<Vec<Point>, String> {
        list.iter()
            .enumerate()
            .map(|(k, p)| {
                read_point(p).ok_or_else(|| format!("{name}: {what} {k} is not a rational pair"))
            })
            .collect()
    };
    let mut obstacles = Vec::new();
    for (m, o) in witness.obstacles.iter().zip(&params.obstacles) {
        if m.name != o.name {
            return Err(format!(
                "it names obstacle {:?} where the problem has {:?}",
                m.name, o.name
            ));
        }
        let start = read_point(&m.start)
            .ok_or_else(|| format!("{}: its start is not a rational pair", m.name))?;
        obstacles.push(ObstacleBehaviour {
            start,
            velocities: points(&m.velocities, "velocity", &m.name)?,
            position_errors: points(&m.position_errors, "position error", &m.name)?,
            velocity_errors: points(&m.velocity_errors, "velocity error", &m.name)?,
            hide: m.hide,
        });
    }
    Ok(PlanarBehaviour { obstacles })
}

/// Replays what `witness` states and requires its record to be the stated one; returns the
/// separation it proves s* at most (exact).
pub fn replay(params: &PlanarParams, witness: &PlanarWitness) -> Result<Exact, String> {
    let b = behaviour(params, witness)?;
    let replayed = run(params, &b, witness.steps)
        .map_err(|e| format!("the problem does not allow it: {e}"))?;
    let again = record(params, &b, &replayed)
        .ok_or("its replay never brings an obstacle near a moving robot")?;
    if again != *witness {
        return Err(format!(
            "its replay differs from what it states (replayed: closest {} at {} s, \
             separation {}, collides {}, brake step {:?})",
            again.obstacle, again.closest_at, again.separation, again.collides, again.brake_step
        ));
    }
    read(&witness.separation).ok_or_else(|| "its separation is not a rational".into())
}
