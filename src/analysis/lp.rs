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
