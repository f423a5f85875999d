//! What the controller can tell apart about one obstacle at one step: the cells of its
//! observed gap (and speed) between the thresholds its guards compare them with.
//!
//! Within a cell every guard that reads the obstacle answers the same, so one
//! representative observation per cell decides the controller's command for the whole
//! cell ([`scene_guard`](crate::core::scene::guards) is run on it, not a copy of it).
//! Adjacent cells that no guard tells apart are merged.

use crate::core::num::Scalar;
use crate::core::rational::Rational;
use crate::core::semantics::Observation;

use super::interval::{End, Interval};

/// How the controller reads an obstacle at a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Role {
    /// In the lane the robot is in or moving into: relevance, danger, the lane change's
    /// time test and the wrong assumption read it.
    Reference,
    /// In a lane a lane change could go to now: the free-lane test reads it.
    Target,
    /// No guard reads it at this step.
    Ignored,
}

/// The numbers the guards compare one obstacle's observation with at one step.
#[derive(Clone, Debug, PartialEq)]
pub struct Thresholds {
    /// ρ.
    pub rho: Rational,
    /// The danger distance d_i(v) (None: the area rule, always dangerous when relevant).
    pub danger: Option<Rational>,
    /// The lane change's time test d_lc,i(v) (None: no lane change can start now).
    pub lane_change: Option<Rational>,
    /// The free-lane test's rear gap (None: no lane change can start now).
    pub rear_gap: Option<Rational>,
    /// V_a, when the wrong-assumption guard can fire for this obstacle (on, moving, and
    /// W_i > V_a) and a speed is seen with the gap.
    pub wrong_above: Option<Rational>,
}

/// One cell: the observed gap and speed it covers, and a representative observation.
#[derive(Clone, Debug)]
pub struct Cell {
    /// Observed gaps in the cell.
    pub gap: Interval,
    /// Observed speeds in the cell (all: not read).
    pub speed: Interval,
    /// A point of the cell, as the robot would see it.
    pub seen: Option<Observation<Rational>>,
}

/// A cut of the gap line: `(t, inclusive)` separates gap ≤ t from gap > t when inclusive,
/// gap < t from gap ≥ t otherwise.
type Cut = (Rational, bool);

/// The cells of one obstacle in `role`.
pub fn cells(role: Role, th: &Thresholds) -> Vec<Cell> {
    let mut cuts: Vec<Cut> = Vec::new();
    match role {
        Role::Ignored => {
            return vec![Cell {
                gap: Interval::all(),
                speed: Interval::all(),
                seen: None,
            }];
        }
        Role::Reference => {
            cuts.push((Rational::zero(), true));
            cuts.push((th.rho.clone(), true));
            if let Some(d) = &th.danger {
                cuts.push((d.clone(), true));
            }
            if let Some(d) = &th.lane_change {
                cuts.push((d.clone(), true));
            }
        }
        Role::Target => {
            if let Some(rg) = &th.rear_gap {
                cuts.push((-rg.clone(), false));
            }
            cuts.push((th.rho.clone(), true));
        }
    }
    // Order by position; at one position gap < t comes before gap ≤ t.
    cuts.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap().then(a.1.cmp(&b.1)));
    cuts.dedup();
    let mut gaps: Vec<Interval> = Vec::new();
    let mut lo: Option<End> = None;
    for (t, inclusive) in &cuts {
        let cell = Interval {
            lo: lo.clone(),
            hi: Some(End {
                at: t.clone(),
                closed: *inclusive,
            }),
        };
        if !cell.is_empty() {
            gaps.push(cell);
        }
        lo = Some(End {
            at: t.clone(),
            closed: !*inclusive,
        });
    }
    gaps.push(Interval { lo, hi: None });
    // Merge neighbours that no guard tells apart.
    let label = |g: &Interval| labels(role, th, &g.inner_point().expect("cells are not empty"));
    let mut merged: Vec<Interval> = Vec::new();
    for g in gaps {
        match merged.last_mut() {
            Some(last) if label(last) == label(&g) => last.hi = g.hi,
            _ => merged.push(g),
        }
    }
    let mut out = Vec::new();
    for gap in merged {
        let rep = gap.inner_point().expect("cells are not empty");
        let relevant = labels(role, th, &rep).0;
        match (&th.wrong_above, relevant && role == Role::Reference) {
            (Some(va), true) => {
                // Shown speeds: with noise a shown speed may be below 0.
                let slow = Interval {
                    lo: None,
                    hi: Some(End::closed(va.clone())),
                };
                let fast = Interval {
                    lo: Some(End::open(va.clone())),
                    hi: None,
                };
                for speed in [slow, fast] {
                    let s = speed_point(&speed, va);
                    out.push(Cell {
                        gap: gap.clone(),
                        speed,
                        seen: Some(Observation {
                            gap: rep.clone(),
                            speed: s,
                        }),
                    });
                }
            }
            _ => out.push(Cell {
                gap,
                speed: Interval::all(),
                seen: Some(Observation {
                    gap: rep,
                    speed: Rational::zero(),
                }),
            }),
        }
    }
    out
}

/// Whether the guards read `cell` of an obstacle in `role` as they read nothing: in the
/// robot's lane, not dangerous and not seen faster than V_a (or not relevant at all). No
/// other obstacle's reading changes that (danger, the lane change's time test and the
/// wrong assumption are read per obstacle). Only the reference role: a target's cells are
/// read by the free-lane test, which the search treats apart.
pub fn quiet(role: Role, th: &Thresholds, cell: &Cell) -> bool {
    let Some(seen) = &cell.seen else {
        return true;
    };
    if role != Role::Reference {
        return false;
    }
    let (relevant, dangerous, _, _) = labels(role, th, &seen.gap);
    let fast = th.wrong_above.as_ref().is_some_and(|va| seen.speed > *va);
    !(dangerous || relevant && fast)
}

/// A representative speed of a speed cell: V_a/2 for [0, V_a], V_a + 1 above it (a speed
/// cell is cut by V_a alone, so any point on the right side represents it).
fn speed_point(speed: &Interval, va: &Rational) -> Rational {
    match &speed.hi {
        Some(_) => va.clone() / Rational::int(2),
        None => va.clone() + Rational::int(1),
    }
}

/// What the guards read from an observed gap in a role: (relevant, dangerous, too close
/// for a lane change, occupies a target lane).
fn labels(role: Role, th: &Thresholds, gap: &Rational) -> (bool, bool, bool, bool) {
    match role {
        Role::Ignored => (false, false, false, false),
        Role::Reference => {
            let relevant = *gap > Rational::zero() && *gap <= th.rho;
            let dangerous = relevant && th.danger.as_ref().is_none_or(|d| gap <= d);
            let blocking = dangerous && th.lane_change.as_ref().is_some_and(|d| gap <= d);
            (relevant, dangerous, blocking, false)
        }
        Role::Target => {
            let above_rear = th.rear_gap.as_ref().is_none_or(|rg| *gap >= -rg.clone());
            (false, false, false, above_rear && *gap <= th.rho)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(n: i64, d: i64) -> Rational {
        Rational::int(n) / Rational::int(d)
    }

    /// The reference cells cover the line, in order, without overlap, and split exactly at
    /// 0, d_lc, d and ρ.
    #[test]
    fn reference_cells_partition_the_gap_line() {
        let th = Thresholds {
            rho: r(14, 10),
            danger: Some(r(9, 10)),
            lane_change: Some(r(5, 10)),
            rear_gap: Some(r(1, 2)),
            wrong_above: None,
        };
        let cs = cells(Role::Reference, &th);
        let probes = [
            r(-1, 1),
            r(0, 1),
            r(1, 10),
            r(5, 10),
            r(6, 10),
            r(9, 10),
            r(1, 1),
            r(14, 10),
            r(2, 1),
        ];
        for p in &probes {
            let hits: Vec<_> = cs.iter().filter(|c| c.gap.contains(p)).collect();
            assert_eq!(hits.len(), 1, "gap {p:?}");
        }
        // (−∞,0], (0,0.5], (0.5,0.9], (0.9,1.4], (1.4,∞)
        assert_eq!(cs.len(), 5);
        // With ρ below d the band (ρ, d] is not relevant and merges with (d, ∞).
        let th2 = Thresholds {
            danger: Some(r(2, 1)),
            ..th
        };
        assert_eq!(cells(Role::Reference, &th2).len(), 4);
    }

    /// A target lane is occupied exactly on [−rear_gap, ρ].
    #[test]
    fn target_cells_split_at_the_rear_gap_and_rho() {
        let th = Thresholds {
            rho: r(1, 1),
            danger: None,
            lane_change: None,
            rear_gap: Some(r(1, 2)),
            wrong_above: None,
        };
        let cs = cells(Role::Target, &th);
        assert_eq!(cs.len(), 3);
        assert!(cs[1].gap.contains(&r(-1, 2)) && cs[1].gap.contains(&r(1, 1)));
        assert!(cs[0].gap.contains(&r(-6, 10)) && cs[2].gap.contains(&r(11, 10)));
    }
}
