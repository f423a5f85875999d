//! The LP solvers, wrapped: a [`Program`] in, an [`LpOutcome`] out. Small linear programs
//! go to the dense simplex ([`simplex`]), everything else to Clarabel, every solver status
//! named.
//!
//! A solver is only ever a source of *candidates*: optimal points become witnesses that
//! are replayed exactly, and multipliers become bounds that [`Program::bound`] recomputes
//! exactly. An `AlmostSolved` or stalled run is reported as [`LpOutcome::Failed`], never
//! read as an answer.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};

use crate::analysis::simplex::{self, DenseLp, SimplexOutcome};
use crate::core::num::Exact;
use crate::proof::program::{Cone, Program};

/// What the solver said about a program.
#[derive(Clone, Debug, PartialEq)]
pub enum LpOutcome {
    /// Solved to tolerance.
    Optimal {
        /// Primal point, one entry per variable.
        x: Vec<f64>,
        /// Multipliers, one per row of the program (box rows excluded).
        z: Vec<f64>,
        /// Objective value at `x` (including the constant).
        value: f64,
    },
    /// Primal infeasible; `z` is the solver's Farkas certificate, one entry per row.
    Infeasible {
        /// Farkas multipliers.
        z: Vec<f64>,
    },
    /// Anything else: no conclusion may be drawn.
    Failed {
        /// The solver's status, by name.
        status: String,
    },
}

fn settings(tight: bool) -> DefaultSettings<f64> {
    let mut b = DefaultSettingsBuilder::default();
    b.verbose(false).max_iter(200);
    if tight {
        // Measured: ~15% slower, dual-bound gap from ~1e-9 down to ~1e-13 (CRATES.md).
        b.tol_gap_abs(1e-12).tol_gap_rel(1e-12).tol_feas(1e-12);
    }
    b.build().expect("static solver settings are valid")
}

/// Solves `program` with every strict row moved `margin` inside (margin 0: the closure).
/// A small linear program goes to the dense simplex ([`simplex`]); a cone, a larger program
/// or anything the simplex gives up on goes to Clarabel, tight tolerances first, then its
/// defaults.
pub fn solve(program: &Program, margin: f64) -> LpOutcome {
    if program.is_well_formed()
        && let Some(dense) = dense_lp(program, margin)
    {
        match simplex::solve(&dense) {
            SimplexOutcome::Optimal { x, z, value } => {
                return LpOutcome::Optimal {
                    x,
                    z,
                    value: value + f(&program.constant.value),
                };
            }
            SimplexOutcome::Infeasible { z } => return LpOutcome::Infeasible { z },
            SimplexOutcome::GaveUp => {}
        }
    }
    solve_by_clarabel(program, margin)
}

/// Which solver proposes the point a witness is read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PointSource {
    /// The simplex's vertex (Clarabel's point if the simplex finds none): for an optimum,
    /// which a vertex attains.
    Vertex,
    /// Clarabel's point, which an interior-point method leaves inside the region, away from
    /// box ends the semantics may leave open.
    Interior,
}

/// The sources a witness search tries, in order, for a piece with or without an objective.
/// A piece without one (can the robot collide without braking?) wants any point of its
/// region, and a vertex sits on box ends where the exact replay may fall the other way
/// (measured: 126 of 10,600 never-stopping cases lost their witness to vertices), so it
/// goes to Clarabel alone; an optimum tries the cheap vertex first.
pub fn point_sources(has_objective: bool) -> &'static [PointSource] {
    if has_objective {
        &[PointSource::Vertex, PointSource::Interior]
    } else {
        &[PointSource::Interior]
    }
}

/// A point of `program` with strict rows `margin` inside, for a witness to be replayed.
/// From a vertex, when the shrunk program has none, Clarabel is asked too: it stops within
/// its tolerance, so on a guard's very threshold (a program empty by less than the margin)
/// its point can lie just outside the shrunk rows yet replay exactly as the worst case. The
/// exact replay is the judge either way.
pub fn solve_for_point(program: &Program, margin: f64, source: PointSource) -> LpOutcome {
    match source {
        PointSource::Vertex => match solve(program, margin) {
            found @ LpOutcome::Optimal { .. } => found,
            _ => solve_by_clarabel(program, margin),
        },
        PointSource::Interior => solve_by_clarabel(program, margin),
    }
}

/// Solves `program` with Clarabel alone (what [`solve`] falls back to).
pub fn solve_by_clarabel(program: &Program, margin: f64) -> LpOutcome {
    let first = solve_with(program, margin, true);
    match first {
        LpOutcome::Failed { .. } => solve_with(program, margin, false),
        done => done,
    }
}

/// `program` as a dense linear program in floats, strict rows `margin` inside; `None` if it
/// has a second-order block or is too large for a dense tableau.
fn dense_lp(program: &Program, margin: f64) -> Option<DenseLp> {
    let n = program.n();
    let m = program.rows.len();
    if (m + n + 1) * (2 * n + 2 * m + 1) > simplex::MAX_TABLEAU {
        return None;
    }
    let mut equality = Vec::with_capacity(m);
    for block in &program.cones {
        let eq = match block.cone {
            Cone::Zero => true,
            Cone::Nonnegative => false,
            Cone::SecondOrder => return None,
        };
        equality.extend(std::iter::repeat_n(eq, block.rows));
    }
    Some(DenseLp {
        rows: program
            .rows
            .iter()
            .map(|row| row.a.iter().map(f).collect())
            .collect(),
        rhs: program
            .rows
            .iter()
            .map(|row| {
                let b = f(&row.b.value);
                if row.strict { b - margin } else { b }
            })
            .collect(),
        equality,
        lower: program.vars.iter().map(|v| f(&v.lower.value)).collect(),
        upper: program.vars.iter().map(|v| f(&v.upper.value)).collect(),
        cost: match &program.objective {
            Some(c) => c.iter().map(f).collect(),
            None => vec![0.0; n],
        },
    })
}

fn solve_with(program: &Program, margin: f64, tight: bool) -> LpOutcome {
    if !program.is_well_formed() {
        return LpOutcome::Failed {
            status: "malformed program: cone blocks do not cover its rows".into(),
        };
    }
    let data = ConicData::of(program, margin);
    let n = program.n();
    let a = csc(&data.rows, data.rows.len(), n);
    let p = CscMatrix::zeros((n, n));
    let q: Vec<f64> = match &program.objective {
        Some(c) => c.iter().map(f).collect(),
        None => vec![0.0; n],
    };
    let mut solver = match DefaultSolver::new(&p, &q, &a, &data.rhs, &data.cones, settings(tight)) {
        Ok(s) => s,
        Err(e) => {
            return LpOutcome::Failed {
                status: format!("setup: {e}"),
            };
        }
    };
    solver.solve();
    let sol = &solver.solution;
    let rows = data.structural..data.structural + program.rows.len();
    match sol.status {
        SolverStatus::Solved => {
            let value = sol.obj_val + f(&program.constant.value);
            LpOutcome::Optimal {
                x: sol.x.clone(),
                z: sol.z[rows].to_vec(),
                value,
            }
        }
        SolverStatus::PrimalInfeasible => LpOutcome::Infeasible {
            z: sol.z[rows].to_vec(),
        },
        SolverStatus::Unsolved
        | SolverStatus::DualInfeasible
        | SolverStatus::AlmostSolved
        | SolverStatus::AlmostPrimalInfeasible
        | SolverStatus::AlmostDualInfeasible
        | SolverStatus::MaxIterations
        | SolverStatus::MaxTime
        | SolverStatus::NumericalError
        | SolverStatus::InsufficientProgress
        | SolverStatus::CallbackTerminated => LpOutcome::Failed {
            status: format!("{:?}", sol.status),
        },
    }
}

fn f(x: &Exact) -> f64 {
    x.to_f64().value()
}

/// A program in Clarabel's form `A·x + s = b, s ∈ K`, as floats: fixed variables first (a
/// box with no interior stalls an interior-point method, so they become equalities in the
/// zero cone), then the program's rows in their cone blocks (strict rows moved `margin`
/// inside), then the boxes of the free variables as nonnegative rows.
struct ConicData {
    rows: Vec<Vec<f64>>,
    rhs: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
    /// Index of the program's first row.
    structural: usize,
}

impl ConicData {
    fn of(program: &Program, margin: f64) -> Self {
        let n = program.n();
        let unit = |j: usize, sign: f64| {
            let mut row = vec![0.0; n];
            row[j] = sign;
            row
        };
        let fixed = |j: &usize| program.vars[*j].lower == program.vars[*j].upper;
        let mut data = ConicData {
            rows: Vec::new(),
            rhs: Vec::new(),
            cones: Vec::new(),
            structural: 0,
        };
        for j in (0..n).filter(fixed) {
            data.rows.push(unit(j, 1.0));
            data.rhs.push(f(&program.vars[j].lower.value));
        }
        data.structural = data.rows.len();
        if data.structural > 0 {
            data.cones.push(SupportedConeT::ZeroConeT(data.structural));
        }
        for row in &program.rows {
            data.rows.push(row.a.iter().map(f).collect());
            let b = f(&row.b.value);
            data.rhs.push(if row.strict { b - margin } else { b });
        }
        for block in &program.cones {
            data.push_cone(match block.cone {
                Cone::Zero => SupportedConeT::ZeroConeT(block.rows),
                Cone::Nonnegative => SupportedConeT::NonnegativeConeT(block.rows),
                Cone::SecondOrder => SupportedConeT::SecondOrderConeT(block.rows),
            });
        }
        let boxes = data.rows.len();
        for j in (0..n).filter(|j| !fixed(j)) {
            data.rows.push(unit(j, 1.0));
            data.rhs.push(f(&program.vars[j].upper.value));
            data.rows.push(unit(j, -1.0));
            data.rhs.push(-f(&program.vars[j].lower.value));
        }
        if data.rows.len() > boxes {
            data.push_cone(SupportedConeT::NonnegativeConeT(data.rows.len() - boxes));
        }
        data
    }

    /// Appends a cone, merging consecutive nonnegative blocks into one (what Clarabel is
    /// handed does not depend on how the program happened to group its rows).
    fn push_cone(&mut self, cone: SupportedConeT<f64>) {
        if let (Some(SupportedConeT::NonnegativeConeT(k)), SupportedConeT::NonnegativeConeT(more)) =
            (self.cones.last_mut(), &cone)
        {
            *k += more;
            return;
        }
        self.cones.push(cone);
    }
}

fn csc(dense: &[Vec<f64>], m: usize, n: usize) -> CscMatrix<f64> {
    let mut colptr = vec![0];
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    for j in 0..n {
        for (i, row) in dense.iter().enumerate() {
            if row[j] != 0.0 {
                rowval.push(i);
                nzval.push(row[j]);
            }
        }
        colptr.push(rowval.len());
    }
    CscMatrix::new(m, n, colptr, rowval, nzval)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::parameter::ParamAffine;
    use crate::proof::program::{ConeBlock, Row, Var};

    fn c(x: i64) -> ParamAffine {
        ParamAffine::constant(Exact::from(x))
    }

    /// min t s.t. t ≥ ‖(x − 3, y − 4)‖ with x, y ∈ [0, 10] free: optimum 0 at (3, 4), and
    /// with x fixed at 0, y at 0 by their boxes: optimum 5. Slacks (t, x − 3, y − 4) ∈ SOC,
    /// written b − A·(t, x, y) with A = −I and b = (0, −3, −4).
    fn cone_program(fixed: bool) -> Program {
        let hi = if fixed { 0 } else { 10 };
        let var = |name: &str, lo: i64, up: i64| Var {
            name: name.into(),
            lower: c(lo),
            upper: c(up),
        };
        let row = |a: [i64; 3], b: i64| Row {
            label: String::new(),
            a: a.iter().map(|&x| Exact::from(x)).collect(),
            b: c(b),
            strict: false,
        };
        Program {
            vars: vec![var("t", 0, 100), var("x", 0, hi), var("y", 0, hi)],
            rows: vec![row([-1, 0, 0], 0), row([0, -1, 0], -3), row([0, 0, -1], -4)],
            cones: vec![ConeBlock {
                cone: Cone::SecondOrder,
                rows: 3,
            }],
            objective: Some(vec![Exact::ONE, Exact::ZERO, Exact::ZERO]),
            constant: c(0),
        }
    }

    #[test]
    fn second_order_blocks_reach_clarabel_and_their_duals_prove_the_optimum() {
        for (fixed, optimum) in [(true, 5.0), (false, 0.0)] {
            let program = cone_program(fixed);
            let LpOutcome::Optimal { z, value, .. } = solve(&program, 0.0) else {
                panic!("the cone program solves");
            };
            assert!(
                (value - optimum).abs() < 1e-6,
                "optimum {value}, expected {optimum}"
            );
            // The exact bound from the solver's multipliers, moved into the cone, is a valid
            // lower bound within the solver's gap of the optimum.
            let bound = program.bound(&z, true).expect("usable multipliers");
            let b = bound.to_f64().value();
            assert!(
                b <= optimum + 1e-12 && b > optimum - 1e-6,
                "bound {b} vs {optimum}"
            );
        }
    }

    /// Random small linear programs: boxes, an equality block built through a point of the
    /// box, inequality rows some of which cut that point off (so some programs are empty).
    fn random_program(seed: &mut u64) -> Program {
        let mut next = |k: i64| -> i64 {
            *seed ^= *seed << 13;
            *seed ^= *seed >> 7;
            *seed ^= *seed << 17;
            (*seed % k as u64) as i64
        };
        let n = 1 + next(5) as usize;
        let (eqs, ineqs) = (next(2) as usize, 1 + next(9) as usize);
        let lower: Vec<i64> = (0..n).map(|_| next(7) - 3).collect();
        let upper: Vec<i64> = lower.iter().map(|l| l + next(6)).collect();
        let point: Vec<i64> = (0..n)
            .map(|j| lower[j] + next(upper[j] - lower[j] + 1))
            .collect();
        let slacks: Vec<i64> = (0..ineqs).map(|_| next(7) - 3).collect();
        let mut row = |slack: i64| {
            let a: Vec<i64> = (0..n).map(|_| next(9) - 4).collect();
            let b = a.iter().zip(&point).map(|(a, x)| a * x).sum::<i64>() + slack;
            Row {
                label: String::new(),
                a: a.into_iter().map(Exact::from).collect(),
                b: c(b),
                strict: false,
            }
        };
        let mut rows: Vec<Row> = (0..eqs).map(|_| row(0)).collect();
        rows.extend(slacks.iter().map(|&s| row(s)));
        let mut cones = Vec::new();
        if eqs > 0 {
            cones.push(ConeBlock {
                cone: Cone::Zero,
                rows: eqs,
            });
        }
        cones.push(ConeBlock {
            cone: Cone::Nonnegative,
            rows: ineqs,
        });
        let mut program = Program {
            vars: (0..n)
                .map(|j| Var {
                    name: format!("x{j}"),
                    lower: c(lower[j]),
                    upper: c(upper[j]),
                })
                .collect(),
            rows,
            cones,
            objective: None,
            constant: c(0),
        };
        if next(5) > 0 {
            program.objective = Some((0..n).map(|_| Exact::from(next(11) - 5)).collect());
        }
        program
    }

    /// The simplex's answers hold on their own: an optimal point satisfies every row and box
    /// and its multipliers' exact bound is within 1e-9 of its objective (so both are optimal,
    /// whatever any other solver says); an empty program's Farkas multipliers verify exactly.
    /// Clarabel, on the same programs, must not contradict either.
    #[test]
    fn the_dense_simplex_proves_what_it_claims_and_agrees_with_clarabel() {
        let (mut seed, mut optimal, mut empty) = (0x5eed_u64, 0, 0);
        for _ in 0..600 {
            let program = random_program(&mut seed);
            let dense = dense_lp(&program, 0.0).expect("small linear programs take the simplex");
            match simplex::solve(&dense) {
                SimplexOutcome::Optimal { x, z, value } => {
                    optimal += 1;
                    for (i, row) in dense.rows.iter().enumerate() {
                        let ax: f64 = row.iter().zip(&x).map(|(a, x)| a * x).sum();
                        let slack = dense.rhs[i] - ax;
                        assert!(
                            slack > -1e-9 && (!dense.equality[i] || slack < 1e-9),
                            "{program:?}: row {i} violated at {x:?}"
                        );
                    }
                    let bound = program.bound(&z, true).expect("usable multipliers");
                    let bound = bound.to_f64().value();
                    assert!(
                        (bound - value).abs() < 1e-9,
                        "{program:?}: bound {bound} vs value {value}"
                    );
                    match solve_by_clarabel(&program, 0.0) {
                        LpOutcome::Optimal { value: v, .. } => {
                            assert!((v - value).abs() < 1e-6, "Clarabel {v}, simplex {value}")
                        }
                        LpOutcome::Infeasible { z } => {
                            assert!(program.proves_empty(&z).is_none(), "{program:?}")
                        }
                        LpOutcome::Failed { .. } => {}
                    }
                }
                SimplexOutcome::Infeasible { z } => {
                    empty += 1;
                    assert!(program.proves_empty(&z).is_some(), "{program:?}: {z:?}");
                    assert!(
                        !matches!(solve_by_clarabel(&program, 0.0), LpOutcome::Optimal { .. }),
                        "{program:?}"
                    );
                }
                SimplexOutcome::GaveUp => panic!("{program:?}: simplex gave up"),
            }
        }
        assert!(
            optimal > 150 && empty > 150,
            "{optimal} optimal, {empty} empty"
        );
    }

    #[test]
    fn malformed_programs_are_refused_before_the_solver() {
        let mut program = cone_program(true);
        program.cones[0].rows = 2;
        assert!(matches!(solve(&program, 0.0), LpOutcome::Failed { .. }));
    }
}
