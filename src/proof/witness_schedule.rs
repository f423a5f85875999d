//! Whether a replayed witness is a run of the piece it claims.
//!
//! A witness names its piece (and, for a merged piece, the whole steps it is shifted by).
//! The replay shows the schedule the run actually had — when the robot braked and why, when
//! the obstacle was first seen, first seen within ρ, first seen passed — and
//! [`realises`] holds the claim to it, so an edited `piece` or `shift` cannot stand beside
//! a run of another schedule. Single-obstacle and scene witnesses share it.

use crate::core::model::Params;
use crate::core::num::{Exact, Scalar};
use crate::core::semantics::{BrakeReason, Observation};
use crate::core::simulate::{Replay, RunSummary};
use crate::proof::schedule::{Ending, Piece};

/// What a replayed run shows of one obstacle's schedule (steps are step indices).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunSchedule {
    /// The step at whose start the robot braked, and why (None: it never did).
    pub brake: Option<(usize, BrakeReason)>,
    /// The first step at whose start the robot saw the obstacle at all.
    pub first_seen: Option<usize>,
    /// The first step at whose start the robot saw it within ρ (passed included).
    pub within_radius: Option<usize>,
    /// The first step at whose start the robot saw it passed (observed gap ≤ 0).
    pub passed: Option<usize>,
    /// Steps run (a run that stops at a collision may end before a step named above).
    pub steps: usize,
    /// At the brake step the robot saw the obstacle faster than V_a.
    pub seen_fast_at_brake: bool,
}

impl RunSchedule {
    /// Whether a first sighting `first` happened at step `step` (`by` it, if `by`), or the
    /// run ended before it could (a replay that stops at its collision).
    fn seen_at(&self, first: Option<usize>, step: usize, by: bool) -> bool {
        match first {
            Some(k) => k == step || (by && k < step),
            None => self.steps <= step,
        }
    }

    /// The schedule of a run from its summary (what the robot saw, as it was seen).
    pub fn of_summary<N: Scalar>(run: &RunSummary<N>) -> RunSchedule {
        let s = &run.sightings;
        RunSchedule {
            brake: run.outcome.brake,
            first_seen: s.first_seen,
            within_radius: s.within_radius,
            passed: s.passed,
            steps: run.periods,
            seen_fast_at_brake: s.seen_fast_at_brake,
        }
    }

    /// The schedule of a run from what the robot saw of the obstacle at each step's start
    /// (`seen[k]`, None: nothing), the run's brake, ρ and V_a.
    pub fn of<'a, N: Scalar + 'a>(
        seen: impl IntoIterator<Item = Option<&'a Observation<N>>>,
        brake: Option<(usize, BrakeReason)>,
        rho: &N,
        v_a: &N,
    ) -> RunSchedule {
        let mut s = RunSchedule {
            brake,
            ..RunSchedule::default()
        };
        for (k, obs) in seen.into_iter().enumerate() {
            s.steps = k + 1;
            let Some(obs) = obs else { continue };
            if brake.is_some_and(|(t, _)| t == k) {
                s.seen_fast_at_brake = obs.speed > *v_a;
            }
            let gap = &obs.gap;
            s.first_seen.get_or_insert(k);
            if *gap <= *rho {
                s.within_radius.get_or_insert(k);
            }
            if *gap <= N::zero() {
                s.passed.get_or_insert(k);
            }
        }
        s
    }
}

/// Whether a run with schedule `run` realises `piece` shifted by `shift` steps; the error
/// names the first difference. With noisy sensing (`exact_observations` false) the replay
/// picks each observation's error by its aim, so the steps a run is first *seen* within ρ or
/// passed are the environment's choice, not the schedule's, and are not compared. Brake step
/// T = brake + shift:
/// - a danger piece brakes at T on danger; a wrong-assumption piece brakes at T having seen
///   the obstacle faster than V_a (on either guard: its behaviours may show danger at T
///   too, which the guard names first); a
///   pass-through never brakes and (exact observations) first sees the obstacle passed at T;
/// - with an entry E (+ shift) and exact observations, the obstacle is first seen within ρ
///   at E, or by E for an early piece;
/// - a detected piece (occlusion) is first seen at T, at its entry (a detected twin), or
///   by its entry (an early twin);
/// - only a merged piece has a shift.
///
/// Bystander pieces are compared by the scene check, which knows what made the robot brake.
pub fn realises(
    piece: &Piece,
    shift: usize,
    run: &RunSchedule,
    exact_observations: bool,
) -> Result<(), String> {
    if shift != 0 && !piece.merged {
        return Err(format!(
            "the witness is shifted by {shift} steps, but its piece is not a merged one"
        ));
    }
    let t = piece.brake + shift;
    let braked = |reasons: &[BrakeReason]| {
        run.brake
            .is_some_and(|(k, r)| k == t && reasons.contains(&r))
    };
    let ok = match piece.ending {
        Ending::Danger => braked(&[BrakeReason::CollisionDanger]),
        Ending::WrongAssumption => {
            run.seen_fast_at_brake
                && braked(&[BrakeReason::WrongAssumption, BrakeReason::CollisionDanger])
        }
        Ending::PassThrough => {
            run.brake.is_none() && (!exact_observations || run.seen_at(run.passed, t, false))
        }
        Ending::Bystander => true,
    };
    if !ok {
        return Err(format!(
            "the witness's piece says the robot {} at step {t}, but its replay {}",
            match piece.ending {
                Ending::PassThrough => "never brakes and sees the obstacle passed",
                Ending::WrongAssumption => "brakes on seeing the obstacle faster than V_a",
                _ => "brakes on collision danger",
            },
            describe(run)
        ));
    }
    if let Some(e) = piece.entry
        && exact_observations
    {
        let e = e + shift;
        // A bystander not yet in the area at T (entry T) may enter it later, or never.
        let later = piece.ending == Ending::Bystander && e == t && !piece.early;
        let entered = if later {
            run.within_radius.is_none_or(|k| k >= e)
        } else {
            run.seen_at(run.within_radius, e, piece.early)
        };
        if !entered {
            return Err(format!(
                "the witness's piece says the obstacle is first seen within the reaction \
                 radius {} step {e}, but its replay {}",
                if piece.early { "by" } else { "at" },
                match run.within_radius {
                    Some(k) => format!("first sees it there at step {k}"),
                    None => "never sees it there".into(),
                }
            ));
        }
    }
    if piece.detected {
        // Hidden until its brake step, its entry (a detected twin), or by its early entry.
        let (k, by) = match piece.entry {
            Some(e) => (e + shift, piece.early),
            None => (t, false),
        };
        if !run.first_seen.is_some_and(|f| f == k || (by && f < k)) {
            return Err(format!(
                "the witness's piece says the obstacle is first seen {} step {k}, but its \
                 replay first sees it at {}",
                if by { "by" } else { "at" },
                run.first_seen
                    .map_or("no step".to_string(), |k| format!("step {k}"))
            ));
        }
    }
    Ok(())
}

/// Whether a single-obstacle replay (run with the witness's aim) realises `piece` shifted by
/// `shift` ([`realises`]), and, for a piece first seen at its brake step, whether that first
/// sighting shows a true gap of at least d_det, as the problem requires of every behaviour.
pub fn replay_realises(
    params: &Params<Exact>,
    replay: &Replay,
    piece: &Piece,
    shift: usize,
) -> Result<(), String> {
    let schedule = RunSchedule::of_summary(&replay.run);
    if !piece.has_objective() && !params.noisy() && schedule.passed.is_none() {
        // A single-obstacle pass-through replays to the step it claims (with noise the
        // errors decide when it is seen passed; see [`realises`]).
        return Err(
            "the witness's run ends before the robot sees the obstacle passed, as its \
             pass-through piece says it does"
                .into(),
        );
    }
    realises(piece, shift, &schedule, !params.noisy())?;
    if piece.detected
        && let Some(d_det) = &params.d_det
    {
        // Hidden until first seen at K: that observation shows the true gap g_{K−L}.
        let seen = schedule
            .first_seen
            .and_then(|k| k.checked_sub(params.L))
            .and(replay.run.sightings.first_seen_gap.as_ref());
        if seen.is_none_or(|g| g.to_exact() < *d_det) {
            return Err("the witness's obstacle is first seen at a true gap below \
                        sensing.first_detection_gap, which the problem rules out"
                .into());
        }
    }
    Ok(())
}

/// The replay's schedule in words.
fn describe(run: &RunSchedule) -> String {
    match run.brake {
        Some((k, reason)) => format!(
            "brakes at step {k} on {}",
            match reason {
                BrakeReason::CollisionDanger => "collision danger",
                BrakeReason::WrongAssumption => "a wrong assumption",
                BrakeReason::Destination => "its destination",
            }
        ),
        None => match run.passed {
            Some(k) => format!("never brakes and sees the obstacle passed at step {k}"),
            None => "never brakes".into(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXACT: bool = true;

    fn piece(entry: Option<usize>, brake: usize, ending: Ending) -> Piece {
        Piece {
            entry,
            brake,
            ending,
            merged: false,
            early: false,
            detected: false,
        }
    }

    /// The leaping replay keeps what the per-period one shows: the same summary (outcome,
    /// periods, mode segments, sightings, trace end), whose schedule is the one read from
    /// the records, whose first sighting's true gap is the record's, on random speed
    /// segments, aims and parameter sets (noise, latency, occlusion, guards active).
    #[test]
    fn the_leaping_replay_summarises_the_recorded_one() {
        use crate::core::num::Exact;
        use crate::core::semantics::tests::{Lcg, random_params};
        use crate::core::simulate::{Aim, replay_reacting_at, replay_recorded};
        use crate::proof::witness_runs::mode_segments;
        let mut rng = Lcg(7);
        for _ in 0..300 {
            let params: Params<Exact> = random_params(&mut rng).map(|x| x.to_exact());
            let w = params.W.to_f64().value();
            let mut speeds = Vec::new();
            for _ in 0..rng.below(5) + 1 {
                let len = rng.pick(&[1, 3, 40, 700, 3000]);
                let s = rng.pick(&[0.0, 0.125, 0.5, 0.875, 1.0]) * w;
                speeds.extend(std::iter::repeat_n(s, len));
            }
            let aim = Aim {
                react_at: rng.pick(&[None, Some(0), Some(15), Some(200), Some(2500)]),
                hidden_until: rng.pick(&[0, 0, 5, 60, 900]),
            };
            let max_steps = speeds.len() + rng.pick(&[0, 10, 5000]) as usize;
            let stop = rng.below(2) == 1;
            let recorded = replay_recorded(&params, &speeds, aim, max_steps, stop);
            let leaping = replay_reacting_at(&params, &speeds, aim, max_steps, stop);
            assert_eq!(leaping.run, recorded.run);
            let records = recorded.records();
            assert_eq!(recorded.periods(), records.len());
            assert_eq!(
                recorded.run.modes,
                mode_segments(records.iter().map(|r| r.robot.mode))
            );
            let schedule = RunSchedule::of(
                records.iter().map(|r| r.observation.as_ref()),
                recorded.run.outcome.brake,
                &recorded.params.rho,
                &recorded.params.V_a,
            );
            assert_eq!(RunSchedule::of_summary(&leaping.run), schedule);
            let seen_gap = schedule
                .first_seen
                .map(|k| records[k - params.L].gap.clone());
            assert_eq!(leaping.run.sightings.first_seen_gap, seen_gap);
            let rows = recorded.trace();
            assert_eq!(leaping.run.trace_rows(), rows.len());
            assert_eq!(leaping.end_time(), rows.last().map(|r| r.t));
        }
    }

    #[test]
    fn the_schedule_is_read_from_what_was_seen() {
        let seen: Vec<Option<Observation<f64>>> = [
            None,
            Some(3.0),
            Some(2.0),
            Some(0.5),
            Some(-0.1),
            Some(-0.5),
        ]
        .into_iter()
        .map(|g| g.map(|gap| Observation { gap, speed: 0.1 }))
        .collect();
        let s = RunSchedule::of(seen.iter().map(Option::as_ref), None, &1.0, &0.2);
        assert_eq!(s.first_seen, Some(1));
        assert_eq!(s.within_radius, Some(3));
        assert_eq!(s.passed, Some(4));
        assert_eq!(s.steps, 6);
    }

    #[test]
    fn a_danger_piece_is_realised_by_its_brake_step_only() {
        let run = RunSchedule {
            brake: Some((12, BrakeReason::CollisionDanger)),
            ..RunSchedule::default()
        };
        let p = piece(None, 12, Ending::Danger);
        assert!(realises(&p, 0, &run, EXACT).is_ok());
        assert!(realises(&piece(None, 11, Ending::Danger), 0, &run, EXACT).is_err());
        // Shifts belong to merged pieces.
        assert!(realises(&piece(None, 10, Ending::Danger), 2, &run, EXACT).is_err());
        let merged = Piece {
            merged: true,
            ..piece(None, 10, Ending::Danger)
        };
        assert!(realises(&merged, 2, &run, EXACT).is_ok());
        assert!(realises(&merged, 3, &run, EXACT).is_err());
        // A pass-through never brakes, and sees the obstacle passed at its step unless the run
        // ended (at its collision) before.
        assert!(realises(&piece(None, 12, Ending::PassThrough), 0, &run, EXACT).is_err());
        let pass = |passed, steps| RunSchedule {
            passed,
            steps,
            ..RunSchedule::default()
        };
        let p = piece(None, 12, Ending::PassThrough);
        assert!(realises(&p, 0, &pass(Some(12), 20), EXACT).is_ok());
        assert!(realises(&p, 0, &pass(Some(13), 20), EXACT).is_err());
        assert!(realises(&p, 0, &pass(None, 11), EXACT).is_ok());
        assert!(realises(&p, 0, &pass(None, 20), EXACT).is_err());
    }

    #[test]
    fn entries_and_sightings_are_compared_where_observations_are_exact() {
        let run = RunSchedule {
            brake: Some((12, BrakeReason::WrongAssumption)),
            first_seen: Some(2),
            within_radius: Some(9),
            passed: None,
            steps: 40,
            seen_fast_at_brake: true,
        };
        let wa = |e| piece(Some(e), 12, Ending::WrongAssumption);
        assert!(realises(&wa(9), 0, &run, EXACT).is_ok());
        assert!(realises(&wa(10), 0, &run, EXACT).is_err());
        let early = Piece {
            early: true,
            ..wa(10)
        };
        assert!(realises(&early, 0, &run, EXACT).is_ok());
        let noisy = false;
        assert!(realises(&wa(10), 0, &run, noisy).is_ok());
        // A wrong-assumption piece's run may brake on danger; a danger piece's may not brake
        // on a wrong assumption.
        assert!(realises(&piece(Some(9), 12, Ending::Danger), 0, &run, EXACT).is_err());
        let slow = RunSchedule {
            seen_fast_at_brake: false,
            brake: Some((12, BrakeReason::CollisionDanger)),
            ..run
        };
        assert!(realises(&wa(9), 0, &slow, EXACT).is_err());
        assert!(realises(&piece(Some(9), 12, Ending::Danger), 0, &slow, EXACT).is_ok());
        let detected = Piece {
            detected: true,
            ..wa(9)
        };
        assert!(realises(&detected, 0, &run, EXACT).is_err());
    }
}
