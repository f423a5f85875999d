//! `check` for search certificates: the answer recomputed from the scene alone, exactly,
//! and the witness replayed.
//!
//! 1. the format tag and digest; the scene must be valid;
//! 2. the exact search is run again on the scene: every obstacle's separation, s*, the
//!    lower bound and the run counts must be what the certificate states;
//! 3. the witness's starts and speeds must be allowed (starts in their ranges, speeds in
//!    [0, W_i]); replayed exactly through the scene's step function they must reproduce its
//!    trace, lane changes, brake, collision and separation, within 1e-6 m of s*;
//! 4. the verdict must follow: `certified` iff s* > clearance, `refuted` iff the witness
//!    collides.

use crate::core::num::{Exact, Scalar, f64_at_most};
use crate::core::rational::Rational;
use crate::core::scene::simulate;
use crate::core::scene::{Position, SceneParams};
use crate::proof::check::{CheckReport, Invalid};
use crate::proof::exact_speed_runs::exact_speeds_from_segments;
use crate::proof::scene_certificate::scene_premises;
use crate::proof::scene_check::same_scene_trace;
use crate::proof::scene_search::search_scene;
use crate::proof::search_certificate::{
    RunWitness, SEARCH_FORMAT, SearchCertificate, exact_from_text, exact_text,
    obstacle_separations, witness_starts,
};
use crate::proof::search_observations::{plan_of, premises_hold};
use crate::proof::separation::{Stated, settle};

fn invalid<T>(msg: impl Into<String>) -> Result<T, Invalid> {
    Err(Invalid(msg.into()))
}

/// Re-verifies a search certificate without the solver.
pub fn check_search(cert: &SearchCertificate) -> Result<CheckReport, Invalid> {
    if cert.format != SEARCH_FORMAT {
        return invalid(format!(
            "format is {:?}, expected {SEARCH_FORMAT:?}",
            cert.format
        ));
    }
    if cert.compute_digest() != cert.digest {
        return invalid("digest mismatch: the certificate was edited after it was written");
    }
    let scene = &cert.scene;
    scene
        .validate("certificate scene")
        .map_err(|e| Invalid(format!("the certificate's scene is invalid: {e}")))?;
    if cert.clearance != scene.robot.clearance {
        return invalid("clearance differs from the scene's");
    }
    if cert.premises != scene_premises(scene) {
        return invalid("premises differ from the scene's");
    }
    let search = search_scene(scene)
        .map_err(|e| Invalid(format!("the search of the certificate's scene failed: {e}")))?;
    let obstacles = obstacle_separations(scene, &search);
    if obstacles != cert.obstacles {
        let list = |os: &[crate::proof::search_certificate::ObstacleSeparation]| {
            os.iter()
                .map(|o| {
                    let sep = match (&o.exact, o.unbounded) {
                        (_, true) => "-inf".to_string(),
                        (Some(x), _) => x.clone(),
                        (None, _) => "none".to_string(),
                    };
                    format!("{:?} {sep}", o.name)
                })
                .collect::<Vec<_>>()
                .join(", ")
        };
        return invalid(format!(
            "per-obstacle separations differ from the search: stated {}, found {}",
            list(&cert.obstacles),
            list(&obstacles)
        ));
    }
    let star = search.min_separation().cloned();
    if cert.min_separation_exact != star.as_ref().map(exact_text)
        || cert.never_stops != search.unbounded()
        || cert.lower_bound != star.as_ref().map(|s| f64_at_most(&s.to_exact()))
        || cert.min_separation != star.as_ref().map(|s| s.to_exact().to_f64().value())
    {
        let show = |exact: Option<String>, never_stops: bool| match (exact, never_stops) {
            (_, true) => "-inf (never_stops)".to_string(),
            (Some(x), _) => x,
            (None, _) => "none".to_string(),
        };
        return invalid(format!(
            "s* differs from the search: stated {}, found {}",
            show(cert.min_separation_exact.clone(), cert.never_stops),
            show(star.as_ref().map(exact_text), search.unbounded())
        ));
    }
    if cert.nodes != search.stats.nodes || cert.runs != search.stats.leaves {
        return invalid("the run counts differ from the search");
    }
    let collides = match &cert.witness {
        Some(w) => check_witness(cert, w, star.as_ref())?,
        None if search.worst.is_some() => return invalid("the certificate has no witness"),
        None => false,
    };
    let clearance = Rational::from_exact(&<Exact as Scalar>::decimal(scene.robot.clearance));
    let certified = !search.unbounded() && star.as_ref().is_none_or(|s| *s > clearance);
    let verdict = settle(
        certified,
        collides,
        Stated {
            verdict: cert.verdict,
            min_separation: cert.min_separation,
            tolerance: cert.separation_tolerance,
            lower_bound: cert.lower_bound,
            witness_separation: cert.witness.as_ref().and_then(|w| w.separation),
        },
    )
    .map_err(Invalid)?;
    Ok(CheckReport {
        verdict,
        pieces: search.stats.leaves,
        lower_bound: star.map(|s| s.to_exact()),
    })
}

/// Replays a witness exactly; returns whether it collides.
fn check_witness(
    cert: &SearchCertificate,
    w: &RunWitness,
    star: Option<&Rational>,
) -> Result<bool, Invalid> {
    let scene = &cert.scene;
    let params: SceneParams<Exact> = scene.params();
    if w.obstacle_speeds.len() != scene.obstacles.len() || w.starts.len() != scene.obstacles.len() {
        return invalid("witness lists starts or speeds for another number of obstacles");
    }
    if w.obstacle >= scene.obstacles.len() || w.lane != scene.obstacles[w.obstacle].lane {
        return invalid("witness names an obstacle or lane the scene does not have");
    }
    let mut starts: Vec<Option<Exact>> = Vec::new();
    for (o, s) in scene.obstacles.iter().zip(&w.starts) {
        let start = match (o.position, s) {
            (Position::At(_), None) => Some(None),
            (Position::Range(lo, hi), Some(text)) => exact_from_text(text)
                .filter(|x| {
                    *x >= <Exact as Scalar>::decimal(lo) && *x <= <Exact as Scalar>::decimal(hi)
                })
                .map(Some),
            _ => None,
        };
        let Some(start) = start else {
            return invalid(format!(
                "witness start of obstacle {:?} is not in its position",
                o.name
            ));
        };
        starts.push(start);
    }
    let mut speeds: Vec<Vec<Exact>> = Vec::new();
    for (i, segments) in w.obstacle_speeds.iter().enumerate() {
        let bound = &params.obstacles[i].max_speed;
        let read = exact_speeds_from_segments(segments, |t| {
            exact_from_text(t).filter(|x| *x >= Exact::ZERO && x <= bound)
        });
        match read {
            Ok(read) => speeds.push(read),
            Err(e) => {
                return invalid(format!(
                    "witness speeds of obstacle {:?}: {e}",
                    scene.obstacles[i].name
                ));
            }
        }
    }
    let periods = speeds.iter().map(Vec::len).max().unwrap_or(0);
    let exact_starts = witness_starts(scene, &starts);
    let plan = plan_of(
        &w.shown_from,
        &w.observation_errors,
        scene.obstacles.len(),
        exact_from_text,
    )
    .map_err(Invalid)?;
    // A run that ended by itself (at rest, settled, or at a collision it stops at) ends
    // there again given one period more; one cut off at its step cap runs on, and is
    // replayed to exactly its length.
    let stop = star.is_none();
    let replay_for = |periods: usize| {
        simulate::replay_observing(&params, &speeds, &plan, &exact_starts, periods, stop)
    };
    let mut replay = replay_for(periods + 1);
    if replay.periods() > periods {
        replay = replay_for(periods);
    }
    if replay.periods() != periods {
        return invalid("witness lists speeds past the end of its run");
    }
    premises_hold(&params, &plan, &replay.run).map_err(Invalid)?;
    if !w.steps.is_empty() && !same_scene_trace(&replay.trace(), &w.steps) {
        return invalid("witness trace differs from its exact replay");
    }
    if replay.run.outcome.lane_changes != w.lane_changes || replay.run.outcome.brake != w.brake {
        return invalid("witness lane changes or brake differ from its exact replay");
    }
    if replay.collided() != w.collides {
        return invalid("witness collision flag differs from its exact replay");
    }
    let sep = replay.separations()[w.obstacle].as_ref().map(f64_at_most);
    if sep != w.separation {
        return invalid("witness separation differs from its exact replay");
    }
    if star.is_some() && w.separation.is_none() {
        return invalid("s* is finite, but the witness's obstacle never stopped");
    }
    if star.is_none() && cert.never_stops && !w.collides {
        return invalid("never_stops requires a witness that collides");
    }
    Ok(replay.collided())
}
