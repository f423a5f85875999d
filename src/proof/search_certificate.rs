//! Certificates of the exact run search ([`crate::proof::scene_search`]): the answer for a
//! scene with lane changes or position ranges, in a form `check` re-verifies.
//!
//! The search needs no solver: every case split and every bound is exact. So the
//! certificate carries the answer (s* per obstacle, exactly, and the verdict) and a
//! concrete worst-case behaviour, and [`check_search`](crate::proof::search_check::check_search)
//! re-runs the search from the scene alone, compares every number, and replays the witness
//! exactly through the scene's step function. The independent checks of the search itself
//! are the brute-force oracle, the exhaustive explorer and the schedule analyser on scenes
//! both decide (docs/crosschecks.md).

use crate::proof::exact_speed_runs::{ExactSpeedSegment, exact_speed_segments};
use serde::{Deserialize, Serialize};

use crate::core::num::{Exact, Scalar, f64_at_most};
use crate::core::rational::Rational;
use crate::core::scene::simulate::{self, SceneTraceRow};
use crate::core::scene::{LaneChangeEvent, Position, Scene, SceneParams};
use crate::core::semantics::BrakeReason;
use crate::proof::premise::Premise;
use crate::proof::scene_certificate::scene_premises;
use crate::proof::scene_search::tree::{Ending, TreeError};
use crate::proof::scene_search::{SceneSearch, Separation, search_scene, worst_behaviour};
use crate::proof::search_observations::{ObservationError, observations_of, plan_of};
use crate::proof::separation::SEPARATION_TOLERANCE;
use crate::proof::verdict::Verdict;

/// The format tag written into every search certificate.
pub const SEARCH_FORMAT: &str = "safereach-scene-search-certificate/4";

/// One obstacle's worst case.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct ObstacleSeparation {
    /// Its index in the scene.
    pub obstacle: usize,
    /// Its name.
    pub name: String,
    /// Its lane.
    pub lane: i32,
    /// Its exact worst-case separation, as "p/q" (null: the robot never moves in its lane,
    /// or −∞, see `unbounded`).
    pub exact: Option<String>,
    /// The same, rounded down to a float.
    pub min_separation: Option<f64>,
    /// Its separation is −∞: the robot can drive on for ever in its lane with it ahead.
    pub unbounded: bool,
}

/// A concrete behaviour of the worst run, replayed exactly.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct RunWitness {
    /// Scene index of the obstacle whose separation is the worst case.
    pub obstacle: usize,
    /// Its lane.
    pub lane: i32,
    /// Per obstacle, its start when its position is a range, as an exact number ("p/q");
    /// null for a fixed position.
    pub starts: Vec<Option<String>>,
    /// Speeds per obstacle (scene order) as constant-speed segments from period 0, each
    /// speed an exact number ("p/q": the search's worst cases sit on guard thresholds such
    /// as V_a, which a float would cross); W_i after the last.
    pub obstacle_speeds: Vec<Vec<ExactSpeedSegment>>,
    /// Occlusion: per obstacle, the step at whose start the robot is first shown it (null:
    /// never within the replay); empty without occlusion, when every obstacle is shown
    /// from the start.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub shown_from: Vec<Option<usize>>,
    /// Noise: the observations the run reads that are shown off the truth, with their
    /// exact errors; every other observation is exact. Empty without noise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub observation_errors: Vec<ObservationError>,
    /// The lane changes of the run.
    pub lane_changes: Vec<LaneChangeEvent>,
    /// The step at whose start the robot brakes, and why (null: it never brakes).
    pub brake: Option<(usize, BrakeReason)>,
    /// The replay collides.
    pub collides: bool,
    /// The obstacle's replayed separation, rounded down (null: −∞ or not measured).
    pub separation: Option<f64>,
    /// The replayed trace, one row per obstacle per instant: only with `certify --steps`
    /// (it grows with the horizon; `check` replays the speeds either way and compares the
    /// rows when they are present).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<SceneTraceRow>,
}

/// The search certificate file (and `certify --json` output for such scenes).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SearchCertificate {
    /// Always [`SEARCH_FORMAT`].
    pub format: String,
    /// The verdict.
    pub verdict: Verdict,
    /// s* over every obstacle (m), rounded to the nearest float; null when −∞ or no
    /// obstacle's lane is ever driven in.
    pub min_separation: Option<f64>,
    /// s* exactly, as "p/q" (null as `min_separation`).
    pub min_separation_exact: Option<String>,
    /// How wide the s* bracket [`lower_bound`, `witness.separation`] may be (m): 1e-6
    /// ([`crate::proof::separation`]; s* itself is exact here, and the witness replays
    /// within a nanometre of it).
    ///
    /// [`lower_bound`]: SearchCertificate::lower_bound
    pub separation_tolerance: f64,
    /// s* = −∞.
    pub never_stops: bool,
    /// s* rounded down: a rigorous lower bound (null as `min_separation`).
    pub lower_bound: Option<f64>,
    /// The clearance (m).
    pub clearance: f64,
    /// Premises of the verdict.
    pub premises: Vec<Premise>,
    /// The worst-case behaviour.
    pub witness: Option<RunWitness>,
    /// The scene answered.
    pub scene: Scene,
    /// Per obstacle, in scene order.
    pub obstacles: Vec<ObstacleSeparation>,
    /// Step starts the search expanded.
    pub nodes: usize,
    /// Runs it finished.
    pub runs: usize,
    /// SHA-256 (hex) of this certificate serialised with an empty digest.
    pub digest: String,
}

impl SearchCertificate {
    /// SHA-256 of the certificate with an empty digest field.
    pub fn compute_digest(&self) -> String {
        let mut copy = self.clone();
        copy.digest.clear();
        crate::proof::digest::json_sha256(&copy)
    }
}

/// Why a scene got no search certificate.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SearchError {
    /// The search did not finish.
    #[error("{0}")]
    Search(#[from] TreeError),
    /// A certified s* and a colliding witness: a bug, reported rather than resolved.
    #[error("internal inconsistency: {0}")]
    Inconsistent(String),
}

/// The exact rational as "p/q" (or "p").
pub fn exact_text(r: &Rational) -> String {
    r.to_exact().to_string()
}

/// Reads "p/q" or "p" (integers) exactly; None when it is not such a number.
pub fn exact_from_text(text: &str) -> Option<Exact> {
    let (num, den) = text.split_once('/').unwrap_or((text, "1"));
    let n: dashu_int::IBig = num.trim().parse().ok()?;
    let d: dashu_int::UBig = den.trim().parse().ok()?;
    (d != dashu_int::UBig::ZERO).then(|| Exact::from_parts(n, d))
}

/// Each obstacle's answer, from a search.
pub fn obstacle_separations(scene: &Scene, search: &SceneSearch) -> Vec<ObstacleSeparation> {
    scene
        .obstacles
        .iter()
        .zip(&search.obstacles)
        .enumerate()
        .map(|(i, (o, s))| {
            let (exact, unbounded) = match s {
                Separation::Finite(v) => (Some(v), false),
                Separation::Unbounded => (None, true),
                Separation::Unmeasured => (None, false),
            };
            ObstacleSeparation {
                obstacle: i,
                name: o.name.clone(),
                lane: o.lane,
                exact: exact.map(exact_text),
                min_separation: exact.map(|v| f64_at_most(&v.to_exact())),
                unbounded,
            }
        })
        .collect()
}

/// Searches a (validated) scene and writes its certificate (the witness without rows per
/// period).
pub fn certify_by_search(scene: &Scene) -> Result<SearchCertificate, SearchError> {
    certify_search(scene, false)
}

/// [`certify_by_search`] with the witness's rows per period (`certify --steps`).
pub fn certify_by_search_with_steps(scene: &Scene) -> Result<SearchCertificate, SearchError> {
    certify_search(scene, true)
}

fn certify_search(scene: &Scene, steps: bool) -> Result<SearchCertificate, SearchError> {
    let search = search_scene(scene)?;
    let clearance = Rational::from_exact(&<Exact as Scalar>::decimal(scene.robot.clearance));
    let star = search.min_separation().cloned();
    let never_stops = search.unbounded();
    let witness = witness(scene, &search, star.as_ref(), &clearance, steps);
    let certified = !never_stops && star.as_ref().is_none_or(|s| *s > clearance);
    let collides = witness.as_ref().is_some_and(|w| w.collides);
    if certified && collides {
        return Err(SearchError::Inconsistent(
            "s* above the clearance and a colliding witness".into(),
        ));
    }
    let verdict = if certified {
        Verdict::Certified
    } else if collides {
        Verdict::Refuted
    } else {
        Verdict::Inconclusive
    };
    let mut cert = SearchCertificate {
        format: SEARCH_FORMAT.into(),
        verdict,
        min_separation: star.as_ref().map(|s| s.to_exact().to_f64().value()),
        min_separation_exact: star.as_ref().map(exact_text),
        separation_tolerance: SEPARATION_TOLERANCE,
        never_stops,
        lower_bound: star.as_ref().map(|s| f64_at_most(&s.to_exact())),
        clearance: scene.robot.clearance,
        premises: scene_premises(scene),
        witness,
        scene: scene.clone(),
        obstacles: obstacle_separations(scene, &search),
        nodes: search.stats.nodes,
        runs: search.stats.leaves,
        digest: String::new(),
    };
    cert.digest = cert.compute_digest();
    Ok(cert)
}

/// The worst run's behaviour, as floats, replayed exactly.
fn witness(
    scene: &Scene,
    search: &SceneSearch,
    star: Option<&Rational>,
    clearance: &Rational,
    steps: bool,
) -> Option<RunWitness> {
    let run = search.worst.as_ref()?;
    // Close enough to s* to fall below the clearance when s* does; otherwise a nanometre.
    let nano = Rational::int(1) / Rational::int(1_000_000_000);
    let slack = match star {
        Some(s) if s < clearance => {
            let half = (clearance.clone() - s.clone()) / Rational::int(2);
            if half < nano { half } else { nano }
        }
        _ => nano,
    };
    let (starts, speeds) = worst_behaviour(scene, run, &slack)?;
    let p: SceneParams<Rational> = scene.params::<Exact>().map(Rational::from_exact);
    let (shown_from, errors) = observations_of(&p, &run.leaf, &starts, &speeds)?;
    let starts: Vec<Option<Exact>> = scene
        .obstacles
        .iter()
        .zip(&starts)
        .map(|(o, s)| match o.position {
            Position::At(_) => None,
            Position::Range(..) => Some(s.to_exact()),
        })
        .collect();
    let speeds: Vec<Vec<Exact>> = speeds
        .iter()
        .map(|ws| ws.iter().map(Rational::to_exact).collect())
        .collect();
    let last = match &run.leaf.ending {
        Ending::Brake { step, .. } => *step,
        Ending::Forever { step } => *step,
    };
    let max_steps = last + simulate::horizon(&scene.params::<f64>());
    Some(replay_witness(
        scene,
        run.obstacle,
        &starts,
        speeds,
        (shown_from, errors),
        max_steps,
        star.is_none(),
        steps,
    ))
}

/// The exact starts of a witness: the fixed positions, or the numbers given for ranges.
pub fn witness_starts(scene: &Scene, starts: &[Option<Exact>]) -> Vec<Exact> {
    let params: SceneParams<Exact> = scene.params();
    params
        .obstacles
        .iter()
        .zip(starts)
        .map(|(o, s)| s.clone().unwrap_or_else(|| o.start_min.clone()))
        .collect()
}

/// Replays exact speeds (W_i after the last) from starts, with `observations` (the
/// witness's `shown_from` and `observation_errors`), up to `max_steps`, into a witness for
/// obstacle `obstacle`, with its rows per period when `steps`.
#[allow(clippy::too_many_arguments)] // One caller; each argument is one field of the witness.
fn replay_witness(
    scene: &Scene,
    obstacle: usize,
    starts: &[Option<Exact>],
    mut speeds: Vec<Vec<Exact>>,
    observations: (Vec<Option<usize>>, Vec<ObservationError>),
    max_steps: usize,
    stop_at_collision: bool,
    steps: bool,
) -> RunWitness {
    let params: SceneParams<Exact> = scene.params();
    for (s, o) in speeds.iter_mut().zip(&params.obstacles) {
        s.resize(max_steps.max(s.len()), o.max_speed.clone());
    }
    let exact_starts = witness_starts(scene, starts);
    let (shown_from, observation_errors) = observations;
    let plan = plan_of(
        &shown_from,
        &observation_errors,
        params.obstacles.len(),
        exact_from_text,
    )
    .expect("the search writes a plan that reads");
    let replay = simulate::replay_observing(
        &params,
        &speeds,
        &plan,
        &exact_starts,
        max_steps,
        stop_at_collision,
    );
    for s in &mut speeds {
        s.truncate(replay.periods());
    }
    RunWitness {
        obstacle,
        lane: scene.obstacles[obstacle].lane,
        starts: starts
            .iter()
            .map(|s| s.as_ref().map(Exact::to_string))
            .collect(),
        obstacle_speeds: speeds.iter().map(|ws| exact_speed_segments(ws)).collect(),
        shown_from,
        observation_errors,
        lane_changes: replay.run.outcome.lane_changes.clone(),
        brake: replay.run.outcome.brake,
        collides: replay.collided(),
        separation: replay.separations()[obstacle].as_ref().map(f64_at_most),
        steps: if steps { replay.trace() } else { Vec::new() },
    }
}
