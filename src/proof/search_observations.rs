//! What a search witness shows the robot: with occlusion, the step from which each obstacle
//! is shown; with noise, the error of every observation the run reads (docs/semantics.md
//! §12). The search ([`crate::proof::scene_search::sense`]) keeps, per run, the cell each
//! read observation was shown in and each obstacle's sight; a concrete behaviour of the run
//! has its truth within the noise of each cell, so an error landing in the cell exists and
//! is picked here, exactly. Observations the run does not read stay exact: they cannot
//! change the controller's command.

use serde::{Deserialize, Serialize};

use crate::core::num::{Exact, Scalar};
use crate::core::rational::Rational;
use crate::core::scene::{ObservationPlan, SceneParams};
use crate::proof::scene_search::interval::Interval;
use crate::proof::scene_search::sense::Sight;
use crate::proof::scene_search::tree::{Ending, Leaf, Profile};

/// One observation a witness shows off the truth.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ObservationError {
    /// The obstacle (scene index).
    pub obstacle: usize,
    /// The step at whose start the robot is shown it.
    pub step: usize,
    /// Shown gap − true gap (m), exactly ("p/q").
    pub gap: String,
    /// Shown speed − true speed (m/s), exactly ("p/q").
    pub speed: String,
}

/// The observations of a witness of `leaf` whose obstacles start at `starts` and move at
/// `speeds`: per obstacle the step from which it is shown (only with occlusion; None: never
/// within the run), and the errors of the observations the run reads (only with noise).
/// None when some read cell cannot be hit, which the search rules out.
pub fn observations_of(
    p: &SceneParams<Rational>,
    leaf: &Leaf,
    starts: &[Rational],
    speeds: &[Vec<Rational>],
) -> Option<(Vec<Option<usize>>, Vec<ObservationError>)> {
    let l = p.robot.L;
    let shown_from = match &p.robot.d_det {
        None => Vec::new(),
        Some(_) => {
            let step = match leaf.ending {
                Ending::Brake { step, .. } | Ending::Forever { step } => step,
            };
            let now = step.saturating_sub(l);
            leaf.sights
                .iter()
                .map(|s| match *s {
                    Sight::Shown { from, .. } => Some(from + l),
                    // Undecided at the leaf: shown at its first undecided observation,
                    // which the leaf holds to d_det; hidden through the brake otherwise.
                    Sight::Hidden { since } if since <= now => Some(since + l),
                    Sight::Hidden { .. } => None,
                })
                .collect()
        }
    };
    let mut errors = Vec::new();
    let mut profile = Profile::new(p);
    let dt = &p.robot.dt;
    for cell in leaf.shown_cells() {
        let (i, n) = (cell.obstacle, cell.step);
        let speed_at = |j: usize| {
            speeds[i]
                .get(j)
                .cloned()
                .unwrap_or_else(|| p.obstacles[i].max_speed.clone())
        };
        let travelled = (0..n).fold(Rational::zero(), |acc, j| acc + speed_at(j) * dt.clone());
        let gap = starts[i].clone() - travelled - profile.at(p, n).position.clone();
        let gap_error = pick(&cell.gap, &gap, &p.robot.sigma_g)?;
        // No speed has been measured before the first period ends: it reads 0 exactly.
        let speed_error = if n == 0 {
            Rational::zero()
        } else {
            pick(&cell.speed, &speed_at(n - 1), &p.robot.sigma_w)?
        };
        if gap_error != Rational::zero() || speed_error != Rational::zero() {
            errors.push(ObservationError {
                obstacle: i,
                step: n + l,
                gap: gap_error.to_exact().to_string(),
                speed: speed_error.to_exact().to_string(),
            });
        }
    }
    Some((shown_from, errors))
}

/// An error within ±σ that shows `truth` in `cell`: 0 when it lies in it.
fn pick(cell: &Interval, truth: &Rational, sigma: &Rational) -> Option<Rational> {
    if cell.contains(truth) {
        return Some(Rational::zero());
    }
    let reach = Interval::closed(truth.clone() - sigma.clone(), truth.clone() + sigma.clone());
    Some(cell.intersect(&reach).inner_point()? - truth.clone())
}

/// The plan a witness's fields state, for `obstacles` obstacles; a message naming the field
/// when it does not read.
pub fn plan_of(
    shown_from: &[Option<usize>],
    errors: &[ObservationError],
    obstacles: usize,
    exact: impl Fn(&str) -> Option<Exact>,
) -> Result<ObservationPlan<Exact>, String> {
    let mut plan = ObservationPlan::exact(obstacles);
    if !shown_from.is_empty() {
        if shown_from.len() != obstacles {
            return Err(format!(
                "witness.shown_from has {} entries, the scene {obstacles} obstacles",
                shown_from.len()
            ));
        }
        plan.hidden_until = shown_from.iter().map(|s| s.unwrap_or(usize::MAX)).collect();
    }
    for e in errors {
        if e.obstacle >= obstacles {
            return Err(format!(
                "witness.observation_errors names obstacle {}, the scene has {obstacles}",
                e.obstacle
            ));
        }
        let read = |t: &String| {
            exact(t)
                .ok_or_else(|| format!("witness.observation_errors: {t:?} is not an exact number"))
        };
        let pair = (read(&e.gap)?, read(&e.speed)?);
        if plan.errors.insert((e.obstacle, e.step), pair).is_some() {
            return Err(format!(
                "witness.observation_errors lists obstacle {} at step {} twice",
                e.obstacle, e.step
            ));
        }
    }
    Ok(plan)
}

/// Whether `plan`, replayed as `run`, keeps the sensing premises of `p`: every error within
/// ±σ (and none where nothing is observed, nor on the speed read before any period has
/// ended); with occlusion, every obstacle first shown at a true gap ≥ d_det and, while the
/// robot drives, still showable (a true gap ≥ d_det) at every observation it is hidden
/// from; without occlusion, nothing hidden. A message naming the observation when not.
pub fn premises_hold(
    p: &SceneParams<Exact>,
    plan: &ObservationPlan<Exact>,
    run: &crate::core::scene::simulate::SceneRun<Rational>,
) -> Result<(), String> {
    let l = p.robot.L;
    for (&(i, k), (eg, ew)) in &plan.errors {
        let name = &p.obstacles[i].name;
        if k < l {
            return Err(format!(
                "an observation error of obstacle {name:?} at step {k}, before its first observation (step {l})"
            ));
        }
        let within = |e: &Exact, sigma: &Exact| *e <= *sigma && -e.clone() <= *sigma;
        if !within(eg, &p.robot.sigma_g) || !within(ew, &p.robot.sigma_w) {
            return Err(format!(
                "the observation error of obstacle {name:?} at step {k} is beyond the noise bounds"
            ));
        }
        if k == l && *ew != Exact::ZERO {
            return Err(format!(
                "obstacle {name:?}'s speed at step {k} is read before any period has ended: it has no error"
            ));
        }
    }
    let Some(d_det) = &p.robot.d_det else {
        return match plan.hidden_until.iter().any(|&h| h > 0) {
            true => Err("the witness hides an obstacle, but the scene has no occlusion".into()),
            false => Ok(()),
        };
    };
    let d_det = Rational::from_exact(d_det);
    let gap_at = |i: usize, n: usize| run.records.get(n).map(|r| r.obstacles[i].gap.clone());
    for (i, &hidden) in plan.hidden_until.iter().enumerate() {
        let name = &p.obstacles[i].name;
        let first = hidden.max(l);
        if let Some(g) = gap_at(i, first - l)
            && first < run.records.len()
            && g < d_det
        {
            return Err(format!(
                "obstacle {name:?} is first shown at step {first} at a true gap below d_det"
            ));
        }
        for rec in run.records.iter().take_while(|r| r.k < first) {
            let driving = rec.brake.is_some()
                || matches!(
                    rec.robot.mode,
                    crate::core::semantics::Mode::Accelerate | crate::core::semantics::Mode::Drive
                );
            let n = rec.k.saturating_sub(l);
            if driving && gap_at(i, n).is_some_and(|g| g < d_det) {
                return Err(format!(
                    "obstacle {name:?} is still hidden at step {} while the robot drives, at a \
                     true gap below d_det: it would never be detected in time",
                    rec.k
                ));
            }
        }
    }
    Ok(())
}
