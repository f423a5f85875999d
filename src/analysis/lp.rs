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

use crate::proof::program::Program;

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
    let n = program.n();
    let f = |x: &crate::core::num::Exact| x.to_f64().value();
    // Fixed variables become equality rows (a box with no interior stalls an interior-point
    // method); they come first, in Clarabel's zero cone.
    let fixed: Vec<usize> = (0..n)
        .filter(|&j| program.vars[j].lower == program.vars[j].upper)
        .collect();
    let free: Vec<usize> = (0..n)
        .filter(|&j| program.vars[j].lower != program.vars[j].upper)
        .collect();
    let mut dense: Vec<Vec<f64>> = Vec::new();
    let mut rhs: Vec<f64> = Vec::new();
    for &j in &fixed {
        let mut row = vec![0.0; n];
        row[j] = 1.0;
        dense.push(row);
        rhs.push(f(&program.vars[j].lower));
    }
    let structural = dense.len();
    for row in &program.rows {
        dense.push(row.a.iter().map(f).collect());
        let b = f(&row.b);
        rhs.push(if row.strict { b - margin } else { b });
    }
    for &j in &free {
        let mut up = vec![0.0; n];
        up[j] = 1.0;
        dense.push(up);
        rhs.push(f(&program.vars[j].upper));
        let mut low = vec![0.0; n];
        low[j] = -1.0;
        dense.push(low);
        rhs.push(-f(&program.vars[j].lower));
    }
    let m = dense.len();
    let a = csc(&dense, m, n);
    let p = CscMatrix::zeros((n, n));
    let q: Vec<f64> = match &program.objective {
        Some(c) => c.iter().map(f).collect(),
        None => vec![0.0; n],
    };
    let mut cones = Vec::new();
    if structural > 0 {
        cones.push(SupportedConeT::ZeroConeT(structural));
    }
    cones.push(SupportedConeT::NonnegativeConeT(m - structural));
    let mut solver = match DefaultSolver::new(&p, &q, &a, &rhs, &cones, settings(tight)) {
        Ok(s) => s,
        Err(e) => {
            return LpOutcome::Failed {
                status: format!("setup: {e}"),
            };
        }
    };
    solver.solve();
    let sol = &solver.solution;
    let rows = structural..structural + program.rows.len();
    match sol.status {
        SolverStatus::Solved => {
            let value = sol.obj_val + f(&program.constant);
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
