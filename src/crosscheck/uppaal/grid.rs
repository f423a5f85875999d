//! The exact integer grid: one scale D (grid units per metre) chosen so that every number the
//! network computes is an integer and every division in it is exact, and the problem's
//! numbers on that grid — refused, never rounded, when they do not fit UPPAAL's 32-bit `int`
//! (the module docs of `uppaal` give the construction).

use std::collections::BTreeSet;

use dashu_int::ops::Gcd;
use dashu_int::{IBig, UBig};

use super::{INT_MAX, MAX_PROFILE, UppaalError};
use crate::core::model::{DangerRule, Params, Problem};
use crate::core::num::Exact;
use crate::core::semantics::{RobotState, danger_distance, robot_motion};
use crate::crosscheck::explore::{DEFAULT_STARTS, FiniteModel, SpeedSet};

/// The problem's numbers on the integer grid.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Grid {
    /// D: grid units per metre.
    pub scale: UBig,
    /// Latency L in periods.
    pub latency: usize,
    /// Initial gap, g0·D; for a range of initial gaps, the largest start (the bound of the
    /// gap variables).
    pub g0: i64,
    /// The initial gaps (·D) the network starts from, ascending: the problem's one, or the
    /// explorer's starts in its range (`--starts`).
    pub starts: Vec<i64>,
    /// v_max·dt·D.
    pub v_max: i64,
    /// a·dt²·D (speed gained per period while accelerating).
    pub acc: i64,
    /// b·dt²·D: the controller's braking, in its danger distance d_coll.
    pub brk: i64,
    /// b_min·dt²·D: speed the plant loses per period while braking (docs/semantics.md §12:
    /// every engine brakes the plant at b_min, its worst case); `brk` when b_min = b.
    pub brk_min: i64,
    /// v0·dt·D: the robot's speed at t = 0.
    pub v0: i64,
    /// V_a·dt·D.
    pub v_a: i64,
    /// ⌊ρ·D⌋.
    pub rho: i64,
    /// buffer·D.
    pub buffer: i64,
    /// clearance·D.
    pub clearance: i64,
    /// Obstacle speeds × dt·D, ascending.
    pub speeds: Vec<i64>,
    /// σ_g·D: the gap noise (0 without).
    pub sigma_g: i64,
    /// σ_w·dt·D: the speed noise (0 without).
    pub sigma_w: i64,
    /// d_det·D: occlusion's first-detection gap (None: the obstacle is never hidden).
    pub d_det: Option<i64>,
    /// Lowest value a gap variable can take.
    pub gap_min: i64,
    /// The danger rule.
    pub rule: DangerRule,
    /// Whether the wrong-assumption guard is on.
    pub wrong_assumption_brake: bool,
}

pub(super) fn lcm(a: &UBig, b: &UBig) -> UBig {
    let g = a.gcd(b);
    a / &g * b
}

pub(super) fn to_int(x: &Exact, what: &str) -> Result<i64, UppaalError> {
    let n: IBig = x.numerator().clone();
    let v = i64::try_from(&n).ok().filter(|v| v.abs() <= INT_MAX);
    v.ok_or_else(|| {
        UppaalError::Grid(format!(
            "{what} is {n} grid units, beyond UPPAAL's 32-bit int (at most {INT_MAX})"
        ))
    })
}

/// The drive profile of a scene's robot: [`single_drive_profile`], for a robot that starts
/// at rest, brakes at exactly b and observes a visible obstacle exactly (the scene export
/// does not take the other settings yet).
pub(super) fn drive_profile(p: &Params<Exact>) -> Result<Vec<Exact>, UppaalError> {
    if p.noisy() || p.d_det.is_some() {
        return Err(UppaalError::Grid(
            "the UPPAAL export models exact observations of a visible obstacle; \
             the [sensing] settings are not exported yet"
                .into(),
        ));
    }
    if p.v0 != Exact::ZERO || p.b_min != p.b {
        return Err(UppaalError::Grid(
            "the scene UPPAAL export models a robot that starts at rest and brakes at exactly \
             robot.braking; robot.initial_speed and robot.braking_min are not exported for \
             scenes yet"
                .into(),
        ));
    }
    single_drive_profile(p)
}

/// The drive profile's speeds: every speed the robot can brake from (v0, then one per
/// control period until v_max; just v_max for a robot that starts at top speed).
pub(super) fn single_drive_profile(p: &Params<Exact>) -> Result<Vec<Exact>, UppaalError> {
    let mut state = RobotState::initial(p);
    let mut drive = vec![state.speed.clone()];
    while state.speed < p.v_max {
        if drive.len() > MAX_PROFILE {
            return Err(UppaalError::Grid(format!(
                "the robot needs more than {MAX_PROFILE} control periods to reach top speed"
            )));
        }
        state = robot_motion(p, &state).end;
        drive.push(state.speed.clone());
    }
    Ok(drive)
}

/// Every quantity the model's integer arithmetic produces (in metres): D is the least common
/// multiple of their denominators.
fn grid_quantities(
    p: &Params<Exact>,
    drive: &[Exact],
    speeds: &SpeedSet,
    starts: &[Exact],
) -> Vec<Exact> {
    let two = Exact::from(2);
    let dt = p.dt.clone();
    let mut need: Vec<Exact> = starts.to_vec();
    need.extend([
        p.clearance.clone(),
        p.buffer.clone(),
        p.v_max.clone() * dt.clone(),
        p.V_a.clone() * dt.clone(),
        p.a.clone() * dt.clone() * dt.clone() / two.clone(),
        p.b.clone() * dt.clone() * dt.clone() / two.clone(),
        p.b_min.clone() * dt.clone() * dt.clone() / two.clone(),
        p.v0.clone() * dt.clone(),
        p.sigma_g.clone(),
        p.sigma_w.clone() * dt.clone(),
    ]);
    need.extend(p.d_det.clone());
    need.extend(speeds.speeds().iter().map(|w| w.clone() * dt.clone()));
    // The period in which the robot reaches v_max: v_max·dt − (v_max − u)²/(2a) (none for a
    // robot that starts at top speed).
    if drive.len() >= 2 {
        let before_top = drive[drive.len() - 2].clone();
        let gap_to_top = p.v_max.clone() - before_top;
        need.push(gap_to_top.clone() * gap_to_top / (two.clone() * p.a.clone()));
    }
    // The last, partial braking period from every speed the robot can brake from, braking
    // at the plant's b_min.
    let bdt = p.b_min.clone() * dt.clone();
    let mut last: BTreeSet<Exact> = BTreeSet::new();
    for u in drive.iter().filter(|u| **u > Exact::ZERO) {
        let periods = Exact::from((u.clone() / bdt.clone()).ceil());
        last.insert(u.clone() - (periods - Exact::ONE) * bdt.clone());
    }
    for r in &last {
        need.push(r.clone() * r.clone() / (two.clone() * p.b_min.clone()));
        for w in speeds.speeds() {
            need.push(w.clone() * r.clone() / p.b_min.clone());
        }
    }
    need
}

/// With gap noise, the factor by which the grid is refined so that every positive guard
/// threshold θ(v) = min(ρ, d_coll(v)), v on the drive profile, is at least one grid unit:
/// then some *integer* observed gap in [g − σ_g, g + σ_g] fires the guard whenever some real
/// one does (module docs of `uppaal`, "Sensing noise"). 1 without gap noise.
fn noise_refinement(p: &Params<Exact>, drive: &[Exact], scale: &UBig) -> UBig {
    if p.sigma_g == Exact::ZERO {
        return UBig::ONE;
    }
    let d = Exact::from(scale.clone());
    let mut least = p.rho.clone();
    for v in drive {
        if let Some(t) = danger_distance(p, v)
            && t > Exact::ZERO
            && t < least
        {
            least = t;
        }
    }
    let units = least * d;
    if units >= Exact::ONE {
        return UBig::ONE;
    }
    UBig::try_from((Exact::ONE / units).ceil()).expect("a positive factor")
}

impl Grid {
    /// The exact grid of a (validated) problem with obstacle speeds `speeds` (and for a range
    /// of initial gaps, the explorer's default starts).
    pub fn new(problem: &Problem, speeds: &SpeedSet) -> Result<Grid, UppaalError> {
        Self::with_starts(problem, speeds, DEFAULT_STARTS)
    }

    /// As [`Grid::new`], with `n` starts in a range of initial gaps: the explorer's
    /// (`explore --starts n`, [`FiniteModel::with_starts`]), so that both search the same
    /// finite model.
    pub fn with_starts(
        problem: &Problem,
        speeds: &SpeedSet,
        n: usize,
    ) -> Result<Grid, UppaalError> {
        let p: Params<Exact> = problem.params();
        let starts = FiniteModel::from_params(p.clone(), speeds.clone())
            .with_starts(n)
            .map_err(|e| UppaalError::Options(e.to_string()))?
            .starts()
            .to_vec();
        let drive = single_drive_profile(&p)?;
        let need = grid_quantities(&p, &drive, speeds, &starts);
        let scale = need.iter().fold(UBig::ONE, |d, x| lcm(&d, x.denominator()));
        let refine = noise_refinement(&p, &drive, &scale);
        let scale = scale * refine;
        let grid = Self::scaled(&p, speeds, &starts, scale)?;
        grid.check_products()?;
        Ok(grid)
    }

    /// The problem's numbers with `scale` grid units per metre.
    fn scaled(
        p: &Params<Exact>,
        speeds: &SpeedSet,
        starts: &[Exact],
        scale: UBig,
    ) -> Result<Grid, UppaalError> {
        let dt = p.dt.clone();
        let bdt = p.b.clone() * dt.clone();
        let d = Exact::from(scale.clone());
        let on_grid = |x: Exact| x * d.clone();
        let starts = starts
            .iter()
            .map(|g| to_int(&on_grid(g.clone()), "the initial gap"))
            .collect::<Result<Vec<_>, _>>()?;
        let g0 = *starts.last().expect("a problem has a start");
        let v_max = to_int(&on_grid(p.v_max.clone() * dt.clone()), "v_max·dt")?;
        let acc = to_int(&on_grid(p.a.clone() * dt.clone() * dt.clone()), "a·dt²")?;
        let brk = to_int(&on_grid(bdt.clone() * dt.clone()), "b·dt²")?;
        let brk_min = to_int(
            &on_grid(p.b_min.clone() * dt.clone() * dt.clone()),
            "b_min·dt²",
        )?;
        let v0 = to_int(&on_grid(p.v0.clone() * dt.clone()), "v0·dt")?;
        let v_a = to_int(&on_grid(p.V_a.clone() * dt.clone()), "V_a·dt")?;
        let rho_exact = Exact::from(on_grid(p.rho.clone()).floor());
        let rho = to_int(&rho_exact, "the reaction radius")?;
        let buffer = to_int(&on_grid(p.buffer.clone()), "the buffer")?;
        let sigma_g = to_int(&on_grid(p.sigma_g.clone()), "the gap noise")?;
        let sigma_w = to_int(&on_grid(p.sigma_w.clone() * dt.clone()), "σ_w·dt")?;
        let d_det = p
            .d_det
            .clone()
            .map(|d| to_int(&on_grid(d), "the first-detection gap"))
            .transpose()?;
        let clearance = to_int(&on_grid(p.clearance.clone()), "the clearance")?;
        let speeds_int = speeds
            .speeds()
            .iter()
            .map(|w| to_int(&on_grid(w.clone() * dt.clone()), "an obstacle speed"))
            .collect::<Result<Vec<_>, _>>()?;
        let w_max = *speeds_int.last().expect("a speed set is nonempty");
        let gap_min = 0.min(clearance - v_max - w_max);
        Ok(Grid {
            scale,
            latency: p.L,
            g0,
            starts,
            v_max,
            acc,
            brk,
            brk_min,
            v0,
            v_a,
            rho,
            buffer,
            clearance,
            speeds: speeds_int,
            sigma_g,
            sigma_w,
            d_det,
            gap_min,
            rule: p.rule,
            wrong_assumption_brake: p.wrong_assumption_brake,
        })
    }

    /// The largest obstacle speed on the grid.
    pub fn w_max(&self) -> i64 {
        *self.speeds.last().expect("a speed set is nonempty")
    }

    /// Every product the model's functions compute must fit a 32-bit int.
    fn check_products(&self) -> Result<(), UppaalError> {
        let factor = if self.rule == DangerRule::Kinematic {
            2
        } else {
            1
        };
        // Observed gaps are the true ones off by at most σ_g.
        let span =
            (self.g0 + self.sigma_g + self.buffer).max(self.buffer - self.gap_min + self.sigma_g);
        let checks: [(&str, i128); 6] = [
            (
                "the danger guard's left side (observed gap - BUFFER)·BRK",
                i128::from(factor) * i128::from(span) * i128::from(self.brk),
            ),
            (
                "the danger guard's right side v·v + VA·v",
                i128::from(self.v_max) * i128::from(self.v_max)
                    + i128::from(factor) * i128::from(self.v_a) * i128::from(self.v_max),
            ),
            (
                "the rest gap's v·(2·w + v)",
                i128::from(self.brk_min)
                    * (2 * i128::from(self.w_max()) + i128::from(self.brk_min)),
            ),
            (
                "the top-speed step's (VMAX - v)²",
                i128::from(self.acc) * i128::from(self.acc),
            ),
            (
                "a gap plus a period's travel and the noise",
                i128::from(self.g0)
                    + i128::from(self.v_max)
                    + i128::from(self.w_max())
                    + i128::from(self.sigma_g)
                    + i128::from(self.sigma_w),
            ),
            ("2·ACC, 2·BRK", 2 * i128::from(self.acc.max(self.brk))),
        ];
        for (what, value) in checks {
            if value > i128::from(INT_MAX) {
                return Err(UppaalError::Grid(format!(
                    "with 1 unit = 1/{} m, {what} reaches {value}, beyond UPPAAL's 32-bit int \
                     (at most {INT_MAX}); use fewer or rounder speeds, or rounder problem numbers",
                    self.scale
                )));
            }
        }
        Ok(())
    }
}
