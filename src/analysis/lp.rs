//! Clarabel, wrapped: a [`Program`] in, an [`LpOutcome`] out, every solver status named.
//!
//! The solver is only ever a source of *candidates*: optimal points become witnesses that
//! are replayed exactly, and multipliers become bounds that [`Program::bound`] recomputes
//! exactly. An `AlmostSolved` or stalled run is reported as [`LpOutcome::Failed`], never
//! read as an answer.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
};

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
/// Tries tight tolerances first, then Clarabel's defaults.
pub fn solve(program: &Program, margin: f64) -> LpOutcome {
    let first = solve_with(program, margin, true);
    match first {
        LpOutcome::Failed { .. } => solve_with(program, margin, false),
        done => done,
    }
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

    #[test]
    fn malformed_programs_are_refused_before_the_solver() {
        let mut program = cone_program(true);
        program.cones[0].rows = 2;
        assert!(matches!(solve(&program, 0.0), LpOutcome::Failed { .. }));
    }
}
