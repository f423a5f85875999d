//! The exact integer grid of a scene: the single-obstacle grid's scale D ([`super::Grid`])
//! extended to every obstacle's starts and speeds, the goal and the lane-change rear gap, and
//! the scene's numbers on it — refused, never rounded, when they do not fit UPPAAL's 32-bit
//! `int`. The d_lc test (v + V_i)·P + BUFFER and the destination guard are products of grid
//! numbers, so they need nothing more.

use std::collections::BTreeSet;

use dashu_int::UBig;

use super::grid::{drive_profile, lcm, to_int};
use super::{INT_MAX, UppaalError};
use crate::core::model::DangerRule;
use crate::core::num::Exact;
use crate::core::scene::SceneParams;
use crate::core::scene::simulate::horizon;
use crate::crosscheck::explore::scene::SceneSpeeds;

/// One obstacle on the grid.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ObstacleGrid {
    /// Its lane.
    pub lane: i32,
    /// Its starts x_i(0)·D: its position, or both ends of its range (as the scene explorer).
    pub starts: Vec<i64>,
    /// Its speeds × dt·D, ascending.
    pub speeds: Vec<i64>,
    /// Known to the robot as static (V_i = 0 in its danger and lane-change distances).
    pub is_static: bool,
}

/// A scene's numbers on the integer grid.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneGrid {
    /// D: grid units per metre.
    pub scale: UBig,
    /// Latency L in periods.
    pub latency: usize,
    /// v_max·dt·D.
    pub v_max: i64,
    /// a·dt²·D.
    pub acc: i64,
    /// b·dt²·D.
    pub brk: i64,
    /// V_a·dt·D.
    pub v_a: i64,
    /// ⌊ρ·D⌋.
    pub rho: i64,
    /// buffer·D.
    pub buffer: i64,
    /// clearance·D.
    pub clearance: i64,
    /// The danger rule.
    pub rule: DangerRule,
    /// Whether the wrong-assumption guard is on.
    pub wrong_assumption_brake: bool,
    /// The lanes that exist, ascending.
    pub lanes: Vec<i32>,
    /// Lane changes: P (periods) and rear_gap·D.
    pub lane_change: Option<(usize, i64)>,
    /// goal·D.
    pub goal: Option<i64>,
    /// The obstacles, in the scene's order.
    pub obstacles: Vec<ObstacleGrid>,
    /// Periods within which every run of the network has ended (the scene explorer's
    /// horizon, plus one): it bounds how far the gaps can fall.
    pub periods: usize,
    /// Lowest value a gap can take.
    pub gap_min: i64,
    /// Highest value a gap can take (the farthest start).
    pub gap_max: i64,
    /// Highest robot position (with a goal: the robot brakes for it and rests past it by
    /// less than one period's travel).
    pub xr_max: i64,
}

/// Every quantity (in metres) the scene network's integer arithmetic produces: D is the
/// least common multiple of their denominators (as for one obstacle, `grid`).
fn scene_quantities(p: &SceneParams<Exact>, drive: &[Exact], speeds: &SceneSpeeds) -> Vec<Exact> {
    let r = &p.robot;
    let two = Exact::from(2);
    let dt = r.dt.clone();
    let mut need: Vec<Exact> = vec![
        r.clearance.clone(),
        r.buffer.clone(),
        r.v_max.clone() * dt.clone(),
        r.V_a.clone() * dt.clone(),
        r.a.clone() * dt.clone() * dt.clone() / two.clone(),
        r.b.clone() * dt.clone() * dt.clone() / two.clone(),
    ];
    need.extend(p.goal.iter().cloned());
    need.extend(p.lane_change.iter().map(|lc| lc.rear_gap.clone()));
    for o in &p.obstacles {
        need.push(o.start_min.clone());
        need.push(o.start_max.clone());
    }
    let all_speeds: BTreeSet<Exact> = speeds
        .sets()
        .iter()
        .flat_map(|s| s.speeds().iter().cloned())
        .collect();
    need.extend(all_speeds.iter().map(|w| w.clone() * dt.clone()));
    let before_top = drive[drive.len() - 2].clone();
    let gap_to_top = r.v_max.clone() - before_top;
    need.push(gap_to_top.clone() * gap_to_top / (two.clone() * r.a.clone()));
    let bdt = r.b.clone() * dt.clone();
    let mut last: BTreeSet<Exact> = BTreeSet::new();
    for u in drive.iter().filter(|u| **u > Exact::ZERO) {
        let periods = Exact::from((u.clone() / bdt.clone()).ceil());
        last.insert(u.clone() - (periods - Exact::ONE) * bdt.clone());
    }
    for rest in &last {
        need.push(rest.clone() * rest.clone() / (two.clone() * r.b.clone()));
        for w in &all_speeds {
            need.push(w.clone() * rest.clone() / r.b.clone());
        }
    }
    need
}

impl SceneGrid {
    /// The exact grid of a (validated) scene's numbers with each obstacle's speeds from
    /// `speeds`.
    pub fn new(p: &SceneParams<Exact>, speeds: &SceneSpeeds) -> Result<SceneGrid, UppaalError> {
        if speeds.sets().len() != p.obstacles.len() {
            return Err(UppaalError::Options(format!(
                "{} speed sets for {} obstacles",
                speeds.sets().len(),
                p.obstacles.len()
            )));
        }
        let drive = drive_profile(&p.robot)?;
        let need = scene_quantities(p, &drive, speeds);
        let scale = need.iter().fold(UBig::ONE, |d, x| lcm(&d, x.denominator()));
        let grid = Self::scaled(p, speeds, scale)?;
        grid.check_products()?;
        Ok(grid)
    }

    fn scaled(
        p: &SceneParams<Exact>,
        speeds: &SceneSpeeds,
        scale: UBig,
    ) -> Result<SceneGrid, UppaalError> {
        let r = &p.robot;
        let dt = r.dt.clone();
        let d = Exact::from(scale.clone());
        let on = |x: Exact, what: &str| to_int(&(x * d.clone()), what);
        let v_max = on(r.v_max.clone() * dt.clone(), "v_max·dt")?;
        let acc = on(r.a.clone() * dt.clone() * dt.clone(), "a·dt²")?;
        let brk = on(r.b.clone() * dt.clone() * dt.clone(), "b·dt²")?;
        let rho = to_int(
            &Exact::from((r.rho.clone() * d.clone()).floor()),
            "the reaction radius",
        )?;
        let mut obstacles = Vec::with_capacity(p.obstacles.len());
        for (i, o) in p.obstacles.iter().enumerate() {
            let what = format!("obstacle {i}'s position");
            let mut starts = vec![on(o.start_min.clone(), &what)?];
            if o.start_max != o.start_min {
                starts.push(on(o.start_max.clone(), &what)?);
            }
            let speeds = speeds
                .of(i)
                .speeds()
                .iter()
                .map(|w| on(w.clone() * dt.clone(), &format!("obstacle {i}'s speed")))
                .collect::<Result<Vec<_>, _>>()?;
            obstacles.push(ObstacleGrid {
                lane: o.lane,
                starts,
                speeds,
                is_static: o.is_static,
            });
        }
        let w_max = obstacles
            .iter()
            .flat_map(|o| o.speeds.iter().copied())
            .max()
            .unwrap_or(0);
        let gap_max = obstacles
            .iter()
            .flat_map(|o| o.starts.iter().copied())
            .max()
            .unwrap_or(0);
        let nearest = obstacles.iter().map(|o| o.starts[0]).min().unwrap_or(0);
        let periods = horizon(&p.map(|x| x.to_f64().value())) + 2;
        let clearance = on(r.clearance.clone(), "the clearance")?;
        let travel = (periods as i128 + 1) * i128::from(v_max + w_max);
        let gap_min = (i128::from(nearest) - travel)
            .min(i128::from(clearance - v_max - w_max))
            .min(0);
        let gap_min = i64::try_from(gap_min)
            .ok()
            .filter(|g| g.abs() <= INT_MAX)
            .ok_or_else(|| {
                UppaalError::Grid(format!(
                    "the gaps fall to {gap_min} grid units within the {periods} periods a run \
                     lasts, beyond UPPAAL's 32-bit int"
                ))
            })?;
        let goal = p.goal.clone().map(|g| on(g, "the goal")).transpose()?;
        let xr_max = match goal {
            // Rests at x + v²/(2b) with x ≤ goal + VMAX: the guard fired at the first step start
            // where x + v²/(2b) ≥ goal.
            Some(g) => g + v_max + (v_max * v_max + 2 * brk - 1) / (2 * brk),
            None => 0,
        };
        Ok(SceneGrid {
            scale,
            latency: r.L,
            v_max,
            acc,
            brk,
            v_a: on(r.V_a.clone() * dt.clone(), "V_a·dt")?,
            rho,
            buffer: on(r.buffer.clone(), "the buffer")?,
            clearance,
            rule: r.rule,
            wrong_assumption_brake: r.wrong_assumption_brake,
            lanes: p.lanes.clone(),
            lane_change: p
                .lane_change
                .as_ref()
                .map(|lc| Ok((lc.periods, on(lc.rear_gap.clone(), "the rear gap")?)))
                .transpose()?,
            goal,
            obstacles,
            periods,
            gap_min,
            gap_max,
            xr_max,
        })
    }

    /// The largest obstacle speed on the grid.
    pub fn w_max(&self) -> i64 {
        self.obstacles
            .iter()
            .flat_map(|o| o.speeds.iter().copied())
            .max()
            .unwrap_or(0)
    }

    /// The most speeds any obstacle has.
    pub fn speeds_max(&self) -> usize {
        self.obstacles
            .iter()
            .map(|o| o.speeds.len())
            .max()
            .unwrap_or(1)
    }

    /// Lowest separation share: a gap, or minus one.
    pub fn sep_min(&self) -> i64 {
        self.gap_min.min(-self.gap_max)
    }

    /// Highest separation share.
    pub fn sep_max(&self) -> i64 {
        self.gap_max.max(-self.gap_min)
    }

    /// Every product the network's functions compute must fit a 32-bit int.
    fn check_products(&self) -> Result<(), UppaalError> {
        let w = |x: i64| i128::from(x);
        let factor = if self.rule == DangerRule::Kinematic {
            2
        } else {
            1
        };
        let span = w(self.gap_max.max(-self.gap_min)) + w(self.buffer);
        let periods = w(self.lane_change.map_or(0, |(p, _)| p as i64));
        let goal_span = self
            .goal
            .map_or(0, |g| w(g.max(self.xr_max - g)) * 2 * w(self.brk));
        let checks: [(&str, i128); 8] = [
            (
                "the danger guard's left side (observed gap - BUFFER)·BRK",
                factor * span * w(self.brk),
            ),
            (
                "the danger guard's right side v·v + VI·v",
                w(self.v_max) * w(self.v_max) + factor * w(self.v_a) * w(self.v_max),
            ),
            (
                "the rest gap's v·(2·w + v)",
                w(self.brk) * (2 * w(self.w_max()) + w(self.brk)),
            ),
            (
                "the top-speed step's (VMAX - v)²",
                w(self.acc) * w(self.acc),
            ),
            (
                "a gap minus a period's travel",
                span + w(self.v_max) + w(self.w_max()),
            ),
            (
                "the lane-change distance (v + VI)·P + BUFFER",
                (w(self.v_max) + w(self.v_a)) * periods + w(self.buffer),
            ),
            ("the destination guard's 2·BRK·(GOAL - xr)", goal_span),
            ("2·ACC, 2·BRK", 2 * w(self.acc.max(self.brk))),
        ];
        for (what, value) in checks {
            if value > w(INT_MAX) {
                return Err(UppaalError::Grid(format!(
                    "with 1 unit = 1/{} m, {what} reaches {value}, beyond UPPAAL's 32-bit int \
                     (at most {INT_MAX}); use fewer or rounder speeds, or rounder scene numbers",
                    self.scale
                )));
            }
        }
        Ok(())
    }
}
