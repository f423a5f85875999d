//! Where certification ends: the smallest safe reaction radius ρ* for an obstacle speed
//! bound W, and the dual question, the largest certified W for a radius.
//!
//! Both searches rest on two monotonicity laws of the semantics (held by property tests):
//! for a fixed obstacle behaviour a larger radius can only make the robot brake earlier, and
//! braking earlier only raises the gap at rest, so s* and its certified lower bound never
//! fall as ρ grows; a larger W only adds behaviours, so they never rise as W grows. The
//! certified set is therefore an interval, and its end is the root of
//! m(p) = lower bound(p) − clearance.
//!
//! m is piecewise affine. With the multipliers z of the piece that attains the bound held
//! fixed, that piece's bound is an affine function of ρ or W (only right-hand sides, boxes
//! and the objective constant move), valid for every value, so its exact slope — read off
//! the bound's affine form ([`crate::proof::program::Program::bound_affine`]) — gives a Newton step that
//! lands on the root as soon as the attaining piece no longer changes. A bracket
//! [not certified, certified] is kept throughout, and a step that would leave it, or a
//! stretch without a slope (a robot that may never brake has no finite bound), falls back
//! to halving the bracket. A typical search takes a handful of analyses, not the ~35 of a
//! bisection to 1e-10.

use serde::{Deserialize, Serialize};

use crate::analysis::{
    self, Analysis, AnalysisError, Options, PieceResult, Verdict, WitnessPolicy,
};
use crate::core::budget::{Budget, Meter, Work};
use crate::core::model::{DangerRule, Problem};
use crate::core::num::{Exact, exact_decimal};
use crate::core::parameter::Parameter as Named;
use crate::core::semantics::danger_distance;
use crate::core::simulate;
use crate::proof::program::ProofKind;

/// Half-width of the final bracket around the boundary.
pub const TOLERANCE: f64 = 1e-10;
/// Distance from the boundary at which the certificate and the refutation are produced.
pub const PROBE_OFFSET: f64 = 1e-6;

/// Which parameter a search moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Parameter {
    /// `controller.reaction_radius` (certified above the boundary).
    ReactionRadius,
    /// `environment.obstacle_speed` (certified below the boundary).
    ObstacleSpeed,
}

impl Parameter {
    /// The named parameter it moves.
    fn named(self) -> Named {
        match self {
            Parameter::ReactionRadius => Named::ReactionRadius,
            Parameter::ObstacleSpeed => Named::ObstacleSpeed,
        }
    }

    fn get(self, p: &Problem) -> f64 {
        match self {
            Parameter::ReactionRadius => p.controller.reaction_radius,
            Parameter::ObstacleSpeed => p.environment.obstacle_speed,
        }
    }

    fn set(self, p: &Problem, value: f64) -> Problem {
        let mut p = p.clone();
        match self {
            Parameter::ReactionRadius => p.controller.reaction_radius = value,
            Parameter::ObstacleSpeed => p.environment.obstacle_speed = value,
        }
        p
    }
}

/// The answer of a boundary search.
#[derive(Clone, Debug)]
pub struct Boundary {
    /// The parameter searched.
    pub parameter: Parameter,
    /// The certified end of the boundary (ρ* from above, W* from below), within
    /// 3·[`TOLERANCE`] of the root and on its decimal grid; certified itself, its certificate
    /// is [`Boundary::certified`]. None when no value is certified.
    pub value: Option<f64>,
    /// Why there is no boundary, or a remark on it (e.g. it is the end of the range).
    pub reason: Option<String>,
    /// The analysis at `value` (certified, its certificate checked).
    pub certified: Option<Analysis>,
    /// The analysis [`PROBE_OFFSET`] outside it.
    pub refuted: Option<Analysis>,
    /// Analyses run by the search (probes excluded).
    pub analyses: usize,
}

struct Eval {
    margin: Option<Exact>,
    slope: Option<Exact>,
}

impl Eval {
    fn certified(&self) -> bool {
        self.margin.as_ref().is_some_and(|m| *m > Exact::ZERO)
    }
}

/// The exact value a parameter takes in a problem file holding `x`.
fn ex(x: f64) -> Exact {
    exact_decimal(x)
}

fn evaluate(
    base: &Problem,
    param: Parameter,
    x: f64,
    spent: &mut Spent,
) -> Result<Eval, AnalysisError> {
    spent.analyses += 1;
    let problem = param.set(base, x);
    let a = spent.analyse(
        &problem,
        Options {
            witness: WitnessPolicy::ToRefute,
        },
    )?;
    let clearance = ex(problem.robot.clearance);
    let margin = a.lower_bound.as_ref().map(|b| b.clone() - clearance);
    let slope = margin.as_ref().and_then(|_| slope(&a, param));
    Ok(Eval { margin, slope })
}

/// d(bound)/d(parameter) of the piece attaining the lower bound, its multipliers held fixed:
/// read exactly off the bound's affine form (see [`crate::proof::program`]).
fn slope(a: &Analysis, param: Parameter) -> Option<Exact> {
    let (piece, z, _) = a
        .outcomes
        .iter()
        .filter_map(|o| match &o.result {
            PieceResult::Proved {
                kind: ProofKind::Bound,
                z,
                bound,
                ..
            } => Some((o.piece, z, bound)),
            _ => None,
        })
        .min_by(|p, q| p.2.cmp(q.2))?;
    let bound = a.decomposition.program(&piece).bound_affine(z, true)?;
    Some(bound.slope(param.named()))
}

/// Newton root of the affine model at `x`, if it lies strictly inside the bracket.
fn newton(x: f64, e: &Eval, lo: f64, hi: f64) -> Option<f64> {
    let (m, s) = (e.margin.as_ref()?, e.slope.as_ref()?);
    if *s == Exact::ZERO {
        return None;
    }
    let r = (ex(x) - m.clone() / s.clone()).to_f64().value();
    let (a, b) = if lo < hi { (lo, hi) } else { (hi, lo) };
    (r.is_finite() && r > a && r < b).then_some(r)
}

/// Finds the end of the certified interval between `outside` (not certified) and `inside`
/// (certified). Returns the bracket (outside, inside) of width ≤ 2·TOLERANCE.
fn bisect_newton(
    base: &Problem,
    param: Parameter,
    mut outside: (f64, Eval),
    mut inside: (f64, Eval),
    spent: &mut Spent,
) -> Result<(f64, f64), AnalysisError> {
    let mut last_width = f64::INFINITY;
    for _ in 0..200 {
        let width = (inside.0 - outside.0).abs();
        if width <= 2.0 * TOLERANCE {
            break;
        }
        // Newton from the certified side first (its bound is finite), then from the other.
        let guess = newton(inside.0, &inside.1, outside.0, inside.0)
            .or_else(|| newton(outside.0, &outside.1, outside.0, inside.0));
        let x = match guess {
            Some(r) if width < 0.75 * last_width || last_width.is_infinite() => r,
            _ => 0.5 * (inside.0 + outside.0),
        };
        last_width = width;
        let e = evaluate(base, param, x, spent)?;
        let on_root = e
            .margin
            .as_ref()
            .is_some_and(|m| m.clone() * m.clone() < ex(1e-18));
        if e.certified() {
            inside = (x, e);
        } else {
            outside = (x, e);
        }
        if on_root {
            // The affine model put us on the boundary: confirm it from both sides.
            let step = TOLERANCE.max(x.abs() * 1e-15);
            let toward = if inside.0 > outside.0 { 1.0 } else { -1.0 };
            for probe in [x + toward * step, x - toward * step] {
                if (probe - outside.0) * (probe - inside.0) < 0.0 {
                    let e = evaluate(base, param, probe, spent)?;
                    if e.certified() {
                        inside = (probe, e);
                    } else {
                        outside = (probe, e);
                    }
                }
            }
        }
    }
    Ok((outside.0, inside.0))
}

fn summary(a: &Analysis) -> String {
    let clearance = a.problem.robot.clearance;
    match (a.never_stops, a.min_separation) {
        (true, _) => "the robot may never brake (s* = -inf)".into(),
        (_, Some(s)) if s < clearance => format!("s* = {s:.6} m, a collision"),
        (_, Some(s)) => format!("s* = {s:.6} m, not above the clearance ({clearance} m)"),
        _ => "no worst case realised".into(),
    }
}

fn probe(
    base: &Problem,
    param: Parameter,
    x: f64,
    spent: &mut Spent,
) -> Result<Analysis, AnalysisError> {
    spent.analyse(&param.set(base, x), Options::default())
}

/// What a search has spent: the analyses it counts (the final probes beside the boundary
/// are not counted), and every analysis's horizon against the budget of analysed periods.
struct Spent {
    analyses: usize,
    meter: Meter,
}

impl Spent {
    fn new(budget: Budget) -> Spent {
        Spent {
            analyses: 0,
            meter: Meter::new(budget),
        }
    }

    /// Analyses `problem` if its horizon fits in what is left of the budget.
    fn analyse(&mut self, problem: &Problem, options: Options) -> Result<Analysis, AnalysisError> {
        let horizon = simulate::horizon(&problem.params::<f64>()) as u64;
        self.meter.charge_analysis("analysis", horizon)?;
        analysis::analyse_with(problem, options)
    }
}

/// `x` moved onto the decimal grid of [`TOLERANCE`] towards the certified side (up when
/// `toward_inside` is positive): the printed boundary is a short decimal, and monotonicity
/// keeps it certified (the probe at it confirms that).
pub(crate) fn on_grid(x: f64, toward_inside: f64) -> f64 {
    let per_unit = (1.0 / TOLERANCE).round();
    let steps = x * per_unit;
    let steps = if toward_inside > 0.0 {
        steps.ceil()
    } else {
        steps.floor()
    };
    steps / per_unit
}

/// Reports the certified end of `bracket` (outside, inside): the value printed is one the
/// search certified and whose certificate passes the exact check, never the midpoint (which
/// may lie on the unsafe side of the root).
fn finish(
    base: &Problem,
    param: Parameter,
    bracket: (f64, f64),
    spent: &mut Spent,
    reason: Option<String>,
) -> Result<Boundary, AnalysisError> {
    let (outside, inside) = bracket;
    let toward_inside = if inside > outside { 1.0 } else { -1.0 };
    let mut value = on_grid(inside, toward_inside);
    let mut certified = probe(base, param, value, spent)?;
    if certified.verdict != Verdict::Certified && value != inside {
        // The solver's bound is monotone only up to its duality gap: fall back to the end
        // the search itself certified.
        value = inside;
        certified = probe(base, param, value, spent)?;
    }
    if certified.verdict != Verdict::Certified {
        return Err(AnalysisError::Inconsistent(format!(
            "the certified end of the boundary bracket ({value}) is {} on re-analysis",
            certified.verdict.as_str()
        )));
    }
    // Nothing is reported certified unless its certificate passes the exact check.
    if let Err(e) = crate::proof::certificate::check(
        &crate::proof::certificate::Certificate::from_analysis(&certified),
    ) {
        return Err(AnalysisError::Inconsistent(format!(
            "the certificate at the boundary does not verify: {e}"
        )));
    }
    let below = value - toward_inside * PROBE_OFFSET;
    let refuted = if below >= 0.0 {
        Some(probe(base, param, below, spent)?)
    } else {
        None
    };
    Ok(Boundary {
        parameter: param,
        value: Some(value),
        reason,
        certified: Some(certified),
        refuted,
        analyses: spent.analyses,
    })
}

/// The smallest certified reaction radius for the problem's obstacle speed bound, within
/// the default budget of analysed periods.
pub fn safe_radius(problem: &Problem) -> Result<Boundary, AnalysisError> {
    safe_radius_within(problem, Budget::default_for(Work::AnalysedPeriods))
}

/// The smallest certified reaction radius for the problem's obstacle speed bound; a search
/// whose analyses would pass `budget` stops with [`AnalysisError::OverBudget`].
pub fn safe_radius_within(problem: &Problem, budget: Budget) -> Result<Boundary, AnalysisError> {
    let param = Parameter::ReactionRadius;
    let mut spent = Spent::new(budget);
    let p = problem.params::<Exact>();
    // The farthest initial gap (plus the gap noise, by which it may be seen farther): a
    // radius beyond it sees every start from the first observation.
    let g0 = problem.environment.initial_gap.max() + problem.gap_noise();
    // Beyond d_coll(v_max) only the wrong-assumption guard still reacts to a larger radius;
    // beyond the initial gap the obstacle is in the area from the first observation.
    let cap = match danger_distance(&p, &p.v_max) {
        Some(d)
            if !p.wrong_assumption_active()
                && problem.controller.danger_rule != DangerRule::Area =>
        {
            d.to_f64().value().min(g0)
        }
        _ => g0,
    };
    let top = evaluate(problem, param, cap, &mut spent)?;
    if !top.certified() {
        let a = probe(problem, param, cap, &mut spent)?;
        let why = if cap < g0 {
            format!(
                "the robot only reacts within its danger distance d_coll(v_max) = {cap:.6} m, so a larger radius changes nothing, and at that radius {}",
                summary(&a)
            )
        } else {
            format!(
                "even a reaction radius as large as the initial gap ({g0} m) is not certified: {}",
                summary(&a)
            )
        };
        return Ok(Boundary::none(param, why, a, spent.analyses));
    }
    let start = problem.controller.reaction_radius.min(cap);
    let tiny = 1e-9;
    let (outside, inside) = if start < cap {
        let e = evaluate(problem, param, start, &mut spent)?;
        if e.certified() {
            ((tiny, None), (start, e))
        } else {
            ((start, Some(e)), (cap, top))
        }
    } else {
        ((tiny, None), (cap, top))
    };
    let outside = match outside {
        (x, Some(e)) => (x, e),
        (x, None) => {
            let e = evaluate(problem, param, x, &mut spent)?;
            if e.certified() {
                let reason = Some("certified for every positive reaction radius".to_string());
                return finish(problem, param, (0.0, x), &mut spent, reason);
            }
            (x, e)
        }
    };
    let bracket = bisect_newton(problem, param, outside, inside, &mut spent)?;
    finish(problem, param, bracket, &mut spent, None)
}

/// The largest certified obstacle speed bound W for the problem's reaction radius, within
/// the default budget of analysed periods.
pub fn max_speed(problem: &Problem) -> Result<Boundary, AnalysisError> {
    max_speed_within(problem, Budget::default_for(Work::AnalysedPeriods))
}

/// The largest certified obstacle speed bound W for the problem's reaction radius; a search
/// whose analyses would pass `budget` stops with [`AnalysisError::OverBudget`].
pub fn max_speed_within(problem: &Problem, budget: Budget) -> Result<Boundary, AnalysisError> {
    let param = Parameter::ObstacleSpeed;
    let mut spent = Spent::new(budget);
    let zero = evaluate(problem, param, 0.0, &mut spent)?;
    if !zero.certified() {
        let a = probe(problem, param, 0.0, &mut spent)?;
        let why = format!(
            "not even a static obstacle (W = 0) is certified: {}",
            summary(&a)
        );
        return Ok(Boundary::none(param, why, a, spent.analyses));
    }
    // Grow W until certification fails; a fast enough obstacle always jumps the area.
    let mut inside = (0.0, zero);
    let mut x = problem
        .environment
        .obstacle_speed
        .max(problem.robot.max_speed * 0.1);
    let limit = 1e6;
    let outside = loop {
        let e = evaluate(problem, param, x, &mut spent)?;
        if !e.certified() {
            break (x, e);
        }
        inside = (x, e);
        if x >= limit {
            let reason = Some(format!(
                "certified up to the largest speed tried, {limit} m/s"
            ));
            let a = probe(problem, param, x, &mut spent)?;
            return Ok(Boundary {
                parameter: param,
                value: Some(x),
                reason,
                certified: Some(a),
                refuted: None,
                analyses: spent.analyses,
            });
        }
        x *= 2.0;
    };
    let bracket = bisect_newton(problem, param, outside, inside, &mut spent)?;
    finish(problem, param, bracket, &mut spent, None)
}

impl Boundary {
    /// No boundary: even the most favourable value is not certified, for `reason`; `at` is
    /// the analysis there.
    fn none(parameter: Parameter, reason: String, at: Analysis, analyses: usize) -> Self {
        Boundary {
            parameter,
            value: None,
            reason: Some(reason),
            certified: None,
            refuted: Some(at),
            analyses,
        }
    }

    /// A one-line summary for people.
    pub fn describe(&self, problem: &Problem) -> String {
        let (name, unit) = match self.parameter {
            Parameter::ReactionRadius => ("safe radius", "m"),
            Parameter::ObstacleSpeed => ("max obstacle speed", "m/s"),
        };
        let given = match self.parameter {
            Parameter::ReactionRadius => format!("W = {} m/s", problem.environment.obstacle_speed),
            Parameter::ObstacleSpeed => format!("rho = {} m", problem.controller.reaction_radius),
        };
        match self.value {
            Some(v) => {
                // Ten decimals: `value` lies on that grid, so the printed number is the one
                // certified (nine would round it, possibly to the unsafe side).
                let mut s = format!("{given}: {name} {v:.10} {unit}");
                if self.certified.is_some() {
                    s += " (certified";
                    if let Some(r) = &self.refuted {
                        s += &format!(
                            "; at {:.10}: {}{}",
                            Parameter::get(self.parameter, &r.problem),
                            r.verdict.as_str(),
                            if r.verdict == Verdict::Refuted {
                                ", witness collides"
                            } else {
                                ""
                            }
                        );
                    }
                    s += ")";
                }
                if let Some(why) = &self.reason {
                    s += &format!("; {why}");
                }
                s
            }
            None => format!(
                "{given}: no {name}: {}",
                self.reason.as_deref().unwrap_or("not certified")
            ),
        }
    }
}
