//! The analyser: pieces → linear programs → Clarabel → bounds, witnesses and a verdict.
//!
//! For every piece of the [`Decomposition`] the analyser looks for a proof — an exact
//! lower bound on its worst-case separation, or an exact proof that it is infeasible —
//! first without the solver (a single row no point of the box satisfies, or the sum of all
//! rows), then with Clarabel, whose multipliers are re-checked exactly. The worst case s*
//! is the least piece optimum; its *witness* is re-solved with every strict row a small
//! margin inside (the closed optimum may sit on a guard's boundary, where a replay would
//! fire one step early) and replayed exactly through the semantics.
//!
//! Verdicts: `certified` iff every piece is proved and the least bound exceeds the
//! clearance; `refuted` iff a witness, replayed exactly, collides; else `inconclusive`.

use crate::analysis::lp::{self, LpOutcome, PointSource};
use crate::core::model::{Params, Problem};
use crate::core::num::{Exact, exact_float, f64_at_most};
use crate::core::simulate;
use crate::proof::program::{Program, ProofKind};
use crate::proof::schedule::{Decomposition, Piece};
pub use crate::proof::verdict::{REPLAY_TOLERANCE, TRACE_TOLERANCE, Verdict, Witness};
use crate::proof::witness_runs::Speeds;
use crate::proof::witness_schedule::replay_realises;

/// Strict rows are moved this far inside when extracting a witness (m, or m/s for speeds).
pub const WITNESS_MARGIN: f64 = 1e-7;

/// What was established about one piece.
#[derive(Clone, Debug, PartialEq)]
pub enum PieceResult {
    /// A proof: multipliers and the exact bound they give (for `Infeasible`, > 0).
    Proved {
        /// Bound or infeasibility.
        kind: ProofKind,
        /// One multiplier per program row.
        z: Vec<f64>,
        /// The exact value proved.
        bound: Exact,
        /// The solver's optimum and point, when it solved the piece.
        optimum: Option<(f64, Vec<f64>)>,
    },
    /// No proof: the piece is feasible with no objective (a pass-through: the robot never
    /// brakes), or the solver failed.
    Unproved {
        /// Why.
        reason: String,
        /// A feasible point, when the solver found one.
        point: Option<Vec<f64>>,
    },
}

/// A piece and its result.
#[derive(Clone, Debug)]
pub struct PieceOutcome {
    /// The piece.
    pub piece: Piece,
    /// Its result.
    pub result: PieceResult,
}

/// The analyser's full answer.
#[derive(Clone, Debug)]
pub struct Analysis {
    /// The problem analysed.
    pub problem: Problem,
    /// Its pieces.
    pub decomposition: Decomposition,
    /// One outcome per piece, in the decomposition's order.
    pub outcomes: Vec<PieceOutcome>,
    /// Exact least bound over all pieces (None: some piece is unproved, so no finite bound).
    pub lower_bound: Option<Exact>,
    /// The worst-case minimum separation s*: the optimum of the piece whose witness was
    /// realised (None with `never_stops`: −∞).
    pub min_separation: Option<f64>,
    /// The worst case is a robot that never brakes (s* = −∞).
    pub never_stops: bool,
    /// The worst-case behaviour, if one was realised.
    pub witness: Option<Witness>,
    /// The verdict.
    pub verdict: Verdict,
    /// Linear programs handed to Clarabel.
    pub programs_solved: usize,
}

/// Analysis failures that are not verdicts.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AnalysisError {
    /// The engines disagree: a certified bound and a colliding witness. A bug, reported
    /// rather than resolved either way.
    #[error("internal inconsistency: {0}")]
    Inconsistent(String),
    /// The initial gap is a range: this analyser takes one start. The scene engines answer
    /// it exactly (`SceneAnswer::of(&Scene::from_problem(problem))`; the CLI does so).
    #[error(
        "environment.initial_gap is a range: analyse it as a scene \
         (SceneAnswer::of(&Scene::from_problem(&problem)))"
    )]
    GapRange,
    /// A search would pass its budget of analysed control periods.
    #[error(transparent)]
    OverBudget(#[from] crate::core::budget::OverBudget),
}

/// When the analyser extracts and replays a worst-case witness.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WitnessPolicy {
    /// Always: the colliding behaviour when refuted, the closest approach when certified.
    #[default]
    Always,
    /// Only when the problem is not certified (a refutation always needs its witness). A
    /// certified answer then reports s* as the least piece optimum, unreplayed — what sweeps
    /// and boundary searches want, at a fraction of the cost.
    ToRefute,
    /// Never: the verdict is `certified` or `inconclusive` (nothing replayed can refute),
    /// for callers that ask only whether a point certifies.
    Never,
}

/// Analysis options.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Options {
    /// When to extract a witness.
    pub witness: WitnessPolicy,
}

/// Analyses a (validated) problem with the default options.
pub fn analyse(problem: &Problem) -> Result<Analysis, AnalysisError> {
    analyse_with(problem, Options::default())
}

/// Analyses a (validated) problem.
pub fn analyse_with(problem: &Problem, options: Options) -> Result<Analysis, AnalysisError> {
    if problem.environment.initial_gap.is_range() {
        return Err(AnalysisError::GapRange);
    }
    let dec = Decomposition::new(problem);
    let mut solved = 0;
    let programs: Vec<Program> = dec.pieces.iter().map(|piece| dec.program(piece)).collect();
    let mut outcomes: Vec<PieceOutcome> = dec
        .pieces
        .iter()
        .zip(&programs)
        .map(|(piece, program)| PieceOutcome {
            piece: *piece,
            result: prove(program, piece, &mut solved),
        })
        .collect();
    let params: Params<Exact> = dec.params.clone();
    let (mut lower_bound, mut certified) = least_bound(&outcomes, &params);
    let candidates = worst_case_candidates(&outcomes);
    let unreplayed = match options.witness {
        WitnessPolicy::Always => false,
        WitnessPolicy::ToRefute => certified,
        WitnessPolicy::Never => true,
    };
    let realised = if unreplayed {
        Realised {
            min_separation: candidates.first().map(|c| c.0),
            ..Realised::default()
        }
    } else {
        let r = realise_worst_case(&dec, &programs, &mut outcomes, &candidates, &mut solved);
        if r.emptied {
            (lower_bound, certified) = least_bound(&outcomes, &params);
        }
        r
    };
    let collides = realised.witness.as_ref().is_some_and(|w| w.collides);
    if certified && collides {
        return Err(AnalysisError::Inconsistent(
            "a certified bound above the clearance and a colliding witness".into(),
        ));
    }
    let verdict = if certified {
        Verdict::Certified
    } else if collides {
        Verdict::Refuted
    } else {
        Verdict::Inconclusive
    };
    Ok(Analysis {
        problem: problem.clone(),
        decomposition: dec,
        outcomes,
        lower_bound,
        min_separation: realised.min_separation,
        never_stops: realised.never_stops,
        witness: realised.witness,
        verdict,
        programs_solved: solved,
    })
}

/// Candidates for the worst case, most dangerous first: (optimum, outcome index), with a
/// feasible pass-through (the robot never brakes) at −∞.
fn worst_case_candidates(outcomes: &[PieceOutcome]) -> Vec<(f64, usize)> {
    let mut candidates: Vec<(f64, usize)> = outcomes
        .iter()
        .enumerate()
        .filter_map(|(i, o)| match &o.result {
            PieceResult::Proved {
                optimum: Some((v, _)),
                kind: ProofKind::Bound,
                ..
            } => Some((*v, i)),
            PieceResult::Unproved { point: Some(_), .. } if !o.piece.has_objective() => {
                Some((f64::NEG_INFINITY, i))
            }
            _ => None,
        })
        .collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    candidates
}

/// The worst case as far as a replayed behaviour realises it.
#[derive(Default)]
struct Realised {
    witness: Option<Witness>,
    min_separation: Option<f64>,
    never_stops: bool,
    /// Some piece was proved empty on the way (the least bound must be recomputed).
    emptied: bool,
}

/// Tries the candidates in order until one yields a witness that replays to its optimum;
/// a piece whose optimum no behaviour realises is proved empty (it may hold only on a
/// guard's boundary, which the semantics' strict inequality excludes).
fn realise_worst_case(
    dec: &Decomposition,
    programs: &[Program],
    outcomes: &mut [PieceOutcome],
    candidates: &[(f64, usize)],
    solved: &mut usize,
) -> Realised {
    let mut out = Realised::default();
    for &(value, i) in candidates {
        let piece = &outcomes[i].piece;
        if let Some(w) = extract_witness(dec, piece, &programs[i], value, solved) {
            out.never_stops = !piece.has_objective();
            out.min_separation = if out.never_stops { None } else { Some(value) };
            out.witness = Some(w);
            break;
        }
        if let Some((z, bound)) = prove_strictly_empty(&programs[i], solved) {
            outcomes[i].result = PieceResult::Proved {
                kind: ProofKind::Infeasible,
                z,
                bound,
                optimum: None,
            };
            out.emptied = true;
        }
    }
    out
}

/// The least proved bound over all pieces (None: some piece is unproved) and whether it
/// certifies.
fn least_bound(outcomes: &[PieceOutcome], params: &Params<Exact>) -> (Option<Exact>, bool) {
    let mut lower_bound: Option<Exact> = None;
    for o in outcomes {
        match &o.result {
            PieceResult::Proved {
                kind: ProofKind::Bound,
                bound,
                ..
            } => {
                if lower_bound.as_ref().is_none_or(|lb| bound < lb) {
                    lower_bound = Some(bound.clone());
                }
            }
            PieceResult::Proved {
                kind: ProofKind::Infeasible,
                ..
            } => {}
            PieceResult::Unproved { .. } => return (None, false),
        }
    }
    // Every piece empty: no behaviour brings the robot near the obstacle at all.
    let lower_bound = lower_bound.unwrap_or_else(|| params.g0.clone());
    let certified = lower_bound > params.clearance;
    (Some(lower_bound), certified)
}

/// Tries to prove that a piece's strict system (guards as the semantics states them) has no
/// solution although its closure has: the solver's Farkas multipliers for the system with
/// strict rows a margin inside, snapped to nearby simple fractions, must give a bound ≥ 0
/// with weight on a strict row ([`Program::proves_empty`]).
pub(crate) fn prove_strictly_empty(
    program: &Program,
    solved: &mut usize,
) -> Option<(Vec<f64>, Exact)> {
    *solved += 1;
    let LpOutcome::Infeasible { z } = lp::solve(program, WITNESS_MARGIN) else {
        return None;
    };
    let scale = z.iter().cloned().fold(0.0, f64::max);
    if scale.is_nan() || scale <= 0.0 {
        return None;
    }
    let snapped: Vec<f64> = z.iter().map(|&zi| snap(zi / scale)).collect();
    program.proves_empty(&snapped).map(|b| (snapped, b))
}

/// The fraction with denominator ≤ 1000 nearest `x` (continued fractions), as a float.
fn snap(x: f64) -> f64 {
    if x <= 1e-9 {
        return 0.0;
    }
    let (mut h0, mut h1, mut k0, mut k1) = (0.0, 1.0, 1.0, 0.0);
    let mut r = x;
    for _ in 0..20 {
        let a = r.floor();
        let (h2, k2) = (a * h1 + h0, a * k1 + k0);
        if k2 > 1000.0 {
            break;
        }
        (h0, h1, k0, k1) = (h1, h2, k1, k2);
        if (r - a).abs() < 1e-12 {
            break;
        }
        r = 1.0 / (r - a);
    }
    h1 / k1
}

/// Finds a proof for one piece: cheap Farkas candidates first, then Clarabel.
pub(crate) fn prove(program: &Program, piece: &Piece, solved: &mut usize) -> PieceResult {
    let rows = program.rows.len();
    let mut farkas_candidates = Vec::new();
    if let Some(i) = program.infeasible_row() {
        let mut z = vec![0.0; rows];
        z[i] = 1.0;
        farkas_candidates.push(z);
    }
    farkas_candidates.push(vec![1.0; rows]);
    for z in farkas_candidates {
        if let Some(b) = program.proves_empty(&z) {
            return PieceResult::Proved {
                kind: ProofKind::Infeasible,
                z,
                bound: b,
                optimum: None,
            };
        }
    }
    *solved += 1;
    match lp::solve(program, 0.0) {
        LpOutcome::Optimal { x, z, value } => {
            if !piece.has_objective() {
                return PieceResult::Unproved {
                    reason: "feasible: the robot never brakes".into(),
                    point: Some(x),
                };
            }
            match program.bound(&z, true) {
                Some(bound) => PieceResult::Proved {
                    kind: ProofKind::Bound,
                    z,
                    bound,
                    optimum: Some((value, x)),
                },
                None => PieceResult::Unproved {
                    reason: "multipliers prove no finite bound".into(),
                    point: Some(x),
                },
            }
        }
        LpOutcome::Infeasible { z } => match program.proves_empty(&z) {
            Some(b) => PieceResult::Proved {
                kind: ProofKind::Infeasible,
                z,
                bound: b,
                optimum: None,
            },
            _ => PieceResult::Unproved {
                reason: "solver's infeasibility certificate does not verify".into(),
                point: None,
            },
        },
        LpOutcome::Failed { status } => PieceResult::Unproved {
            reason: format!("solver: {status}"),
            point: None,
        },
    }
}

/// The (point source, margin) pairs a witness search tries for `piece`, in order: each
/// source of [`lp::point_sources`] with strict rows [`WITNESS_MARGIN`] inside, then a
/// hundredth of that.
pub(crate) fn witness_attempts(piece: &Piece) -> impl Iterator<Item = (PointSource, f64)> {
    lp::point_sources(piece.has_objective())
        .iter()
        .flat_map(|&source| [WITNESS_MARGIN, WITNESS_MARGIN * 1e-2].map(|m| (source, m)))
}

/// Re-solves a piece with strict rows kept inside, turns the point into obstacle speeds and
/// replays them exactly (floats would misplace a guard that lands exactly on its threshold).
/// Returns the witness if the replay realises the piece's optimum (or, for a pass-through,
/// collides without braking).
fn extract_witness(
    dec: &Decomposition,
    piece: &Piece,
    program: &Program,
    value: f64,
    solved: &mut usize,
) -> Option<Witness> {
    for (source, margin) in witness_attempts(piece) {
        *solved += 1;
        let LpOutcome::Optimal { x, .. } = lp::solve_for_point(program, margin, source) else {
            continue;
        };
        let (shift, speeds, first_seen) = speeds_from_point(dec, piece, program, &x);
        let Some(witness) = replay_witness(dec, *piece, shift, margin, speeds, first_seen) else {
            continue;
        };
        let realised = if piece.has_objective() {
            witness
                .separation
                .is_some_and(|s| s >= value - REPLAY_TOLERANCE && s - value <= REPLAY_TOLERANCE)
        } else {
            witness.collides
        };
        if realised {
            return Some(witness);
        }
    }
    None
}

fn clamp(x: Exact, lo: &Exact, hi: &Exact) -> Exact {
    if x < *lo {
        lo.clone()
    } else if x > *hi {
        hi.clone()
    } else {
        x
    }
}

/// The full obstacle speed sequence for a solution point of a piece's program, with its
/// shift and, for an early twin (occlusion), the step at which the obstacle is first seen.
pub(crate) fn speeds_from_point(
    dec: &Decomposition,
    piece: &Piece,
    program: &Program,
    x: &[f64],
) -> (usize, Speeds, Option<usize>) {
    let p = &dec.params;
    let m = dec.anchor(piece);
    let n = piece.brake.saturating_sub(p.L);
    let var = &program.vars[0];
    let u = clamp(exact_float(x[0]), &var.lower.value, &var.upper.value);
    let shift = dec.shift_for(piece, &u);
    let m2 = m + shift;
    let mut speeds = Speeds::default();
    let mut first_seen = None;
    if m2 > 0 {
        let total = p.g0.clone() - dec.position(m2) - u.clone();
        speeds = if piece.early {
            // Scale the fastest approach that respects the area (see fastest_approach), or
            // for an early twin the fastest first seen inside it (occlusion_schedule).
            let (fast, lowest) = if piece.detected {
                let Some((fast, lowest, seen)) = dec.detected_fastest_approach(m2) else {
                    return (shift, speeds, None);
                };
                first_seen = Some(seen);
                (fast, lowest)
            } else {
                dec.fastest_approach(m2)
            };
            let span = p.g0.clone() - dec.position(m2) - lowest;
            let mut lambda = if span > Exact::ZERO {
                total / span
            } else {
                Exact::ZERO
            };
            let near_one = Exact::ONE - exact_float(1e-9);
            if lambda > near_one && !piece.detected {
                // λ = 1 ends a step exactly on ρ at a speed above V_a: stay just outside.
                lambda = near_one;
            }
            let mut speeds = Speeds::default();
            for w in &fast {
                speeds.extend(
                    quantised(&clamp(lambda.clone() * w.clone(), &Exact::ZERO, &p.W)),
                    1,
                );
            }
            speeds
        } else {
            prefix_speeds(p, m2, total)
        };
    }
    for (j, var) in program.vars.iter().enumerate().skip(1).take(n - m) {
        let w = clamp(exact_float(x[j]), &var.lower.value, &var.upper.value);
        speeds.extend(quantised(&w), 1);
    }
    (shift, speeds, first_seen)
}

/// The witness of `speeds` for `piece` shifted by `shift`, if its replay is a run of that
/// piece (the check holds it to that: [`replay_realises`]).
fn replay_witness(
    dec: &Decomposition,
    piece: Piece,
    shift: usize,
    margin: f64,
    mut speeds: Speeds,
    first_seen: Option<usize>,
) -> Option<Witness> {
    let params = &dec.params;
    // A pass-through runs on past its collision to the step T at which the robot sees the
    // obstacle passed, so that its replay shows the schedule it claims.
    let max_steps = if piece.has_objective() {
        piece.brake + shift + simulate::horizon(&params_f64(params))
    } else {
        piece.brake + shift + 1
    };
    // After the program's speeds the obstacle keeps at W (quantised, as every speed).
    let tail = quantised(&params.W);
    let aim = crate::proof::verdict::aim(&piece, shift, first_seen);
    let replay = simulate::replay_segments(
        params,
        speeds.segments(),
        Some(tail),
        aim,
        max_steps,
        false,
        false,
    );
    replay_realises(params, &replay, &piece, shift).ok()?;
    speeds.resize(replay.periods(), tail);
    Some(Witness {
        piece,
        shift,
        margin,
        robot_modes: replay.run.modes.clone(),
        first_seen,
        obstacle_speeds: speeds,
        collides: replay.collided(),
        separation: replay.rest_gap().as_ref().map(f64_at_most),
        // The per-period rows grow with the horizon: only a certificate that asks for
        // them replays them ([`crate::proof::certificate::Certificate::from_analysis_with_steps`]).
        steps: Vec::new(),
    })
}

/// The nearest-float version of exact parameters.
pub fn params_f64(p: &Params<Exact>) -> Params<f64> {
    let (v_max, a, b, b_min, dt) = (
        p.v_max.to_f64().value(),
        p.a.to_f64().value(),
        p.b.to_f64().value(),
        p.b_min.to_f64().value(),
        p.dt.to_f64().value(),
    );
    Params {
        k: crate::core::model::StepConstants::of(&v_max, &a, &b_min, &dt),
        v_max,
        a,
        b,
        b_min,
        v0: p.v0.to_f64().value(),
        dt,
        L: p.L,
        clearance: p.clearance.to_f64().value(),
        V_a: p.V_a.to_f64().value(),
        rho: p.rho.to_f64().value(),
        rule: p.rule,
        buffer: p.buffer.to_f64().value(),
        wrong_assumption_brake: p.wrong_assumption_brake,
        W: p.W.to_f64().value(),
        g0: p.g0.to_f64().value(),
        g0_max: p.g0_max.to_f64().value(),
        sigma_g: p.sigma_g.to_f64().value(),
        sigma_w: p.sigma_w.to_f64().value(),
        d_det: p.d_det.as_ref().map(|d| d.to_f64().value()),
    }
}

/// Witness speeds are multiples of this (m/s): exact in `f64`, at most this far below the
/// speed the program asks for (far inside [`WITNESS_MARGIN`]), and short fractions, so the
/// exact replay's numbers stay a word or two long instead of growing with 53-bit floats.
pub const SPEED_QUANTUM: f64 = 1.0 / (1u64 << 30) as f64;

/// The largest multiple of [`SPEED_QUANTUM`] not above `x` (x ≥ 0).
pub(crate) fn quantised(x: &Exact) -> f64 {
    let scale = Exact::from(1u64 << 30);
    let steps = (x.clone() * scale.clone()).floor();
    f64_at_most(&(Exact::from(steps) / scale))
}

/// Obstacle speeds for the first `m` periods that cover `distance` in total: a constant
/// speed rounded down to a multiple of 2⁻³⁰ m/s, with the remainder in the last period.
/// Short dyadic speeds keep the exact replay's numbers small (a 53-bit float speed held for
/// hundreds of periods makes every later position a long fraction).
fn prefix_speeds(p: &Params<Exact>, m: usize, distance: Exact) -> Speeds {
    let total = clamp(
        distance / p.dt.clone(),
        &Exact::ZERO,
        &(Exact::from(m) * p.W.clone()),
    );
    let scale = Exact::from(1u64 << 30);
    let each = Exact::from((total.clone() * scale.clone() / Exact::from(m)).floor()) / scale;
    let last = total - each.clone() * Exact::from(m - 1);
    let mut speeds = Speeds::default();
    if last <= p.W {
        speeds.extend(quantised(&each), m - 1);
        speeds.extend(quantised(&last), 1);
    } else {
        // Only when the total is within m·2⁻³⁰ of m·W: spread it evenly.
        let w = (each * Exact::from(m - 1) + last) / Exact::from(m);
        speeds.extend(quantised(&clamp(w, &Exact::ZERO, &p.W)), m);
    }
    speeds
}

/// Replays a witness's obstacle speeds exactly (used by `check` and by tests).
pub fn replay(params: &Params<Exact>, speeds: &[f64]) -> simulate::Run<Exact> {
    simulate::replay_exact(params, speeds, speeds.len(), false)
}
