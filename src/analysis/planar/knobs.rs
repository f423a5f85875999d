//! The two planar boundary searches users ask for, as `safereach radius` / `max-speed` and
//! the Python package run them: the smallest certified reaction radius at given speed
//! bounds, and the largest certified speed bound at the file's radius — which keys each
//! moves, over which interval, to which resolution ([`planar_boundary`] does the bisection).

use crate::core::planar::PlanarProblem;

use super::boundary::{BoundaryError, PlanarBoundary, PlanarProbe, Safer, planar_boundary};

/// Radii and speeds are searched to this (m, m/s).
pub const RESOLUTION: f64 = 1e-3;

/// The `obstacle.N.max_speed` keys of the moving obstacles `name` selects (all moving
/// obstacles: None); the reason, naming `flag`, when there is none.
pub fn speed_keys(
    problem: &PlanarProblem,
    name: Option<&str>,
    flag: &str,
) -> Result<Vec<String>, String> {
    if let Some(n) = name
        && !problem.obstacles.iter().any(|o| o.name == n)
    {
        return Err(format!("--obstacle {n}: the problem has no such obstacle"));
    }
    let keys: Vec<String> = problem
        .obstacles
        .iter()
        .enumerate()
        .filter(|(_, o)| name.map_or(o.max_speed > 0.0, |n| o.name == n))
        .map(|(i, _)| format!("obstacle.{i}.max_speed"))
        .collect();
    if keys.is_empty() {
        return Err(format!("{flag}: the problem has no moving obstacle"));
    }
    Ok(keys)
}

/// The smallest certified reaction radius in [10⁻³ m, the sensing range] (4ρ without a
/// range) of the problem file `text` (read as from `origin`, with `sets`, as `base`), with
/// every selected obstacle's speed bound at `speed` when given (the file's otherwise);
/// `seen` is told after each probe. The probes' overrides are `sets` and then the speeds.
pub fn safe_radius_search(
    text: &str,
    origin: &str,
    sets: &[String],
    base: &PlanarProblem,
    speed: Option<(f64, Option<&str>)>,
    seen: impl FnMut(&PlanarProbe),
) -> Result<(Vec<String>, PlanarBoundary), KnobError> {
    let hi = base
        .sensing
        .range
        .unwrap_or(4.0 * base.controller.reaction_radius);
    let mut probe_sets = sets.to_vec();
    if let Some((w, obstacle)) = speed {
        let keys = speed_keys(base, obstacle, "--speeds").map_err(KnobError::Input)?;
        probe_sets.extend(keys.iter().map(|k| format!("{k}={w}")));
    }
    let key = vec!["controller.reaction_radius".to_string()];
    let b = planar_boundary(
        text,
        origin,
        &probe_sets,
        &key,
        (RESOLUTION, hi),
        RESOLUTION,
        Safer::Larger,
        seen,
    )?;
    Ok((probe_sets, b))
}

/// The largest certified speed bound in [0, 4W] (W the largest of the selected obstacles'
/// bounds; 10 m/s when all are 0), given to every moving obstacle together or to the one
/// `obstacle` names, at the file's reaction radius; see [`safe_radius_search`].
pub fn max_speed_search(
    text: &str,
    origin: &str,
    sets: &[String],
    base: &PlanarProblem,
    obstacle: Option<&str>,
    seen: impl FnMut(&PlanarProbe),
) -> Result<PlanarBoundary, KnobError> {
    let keys = speed_keys(base, obstacle, "max-speed").map_err(KnobError::Input)?;
    let w = base
        .obstacles
        .iter()
        .filter(|o| obstacle.is_none_or(|n| o.name == n))
        .map(|o| o.max_speed)
        .fold(0.0, f64::max);
    let hi = if w > 0.0 { 4.0 * w } else { 10.0 };
    Ok(planar_boundary(
        text,
        origin,
        sets,
        &keys,
        (0.0, hi),
        RESOLUTION,
        Safer::Smaller,
        seen,
    )?)
}

/// Why a search could not run.
#[derive(Debug, thiserror::Error)]
pub enum KnobError {
    /// The request names no obstacle the problem has (or it has no moving one).
    #[error("{0}")]
    Input(String),
    /// A probe could not be answered.
    #[error(transparent)]
    Probe(#[from] BoundaryError),
}
