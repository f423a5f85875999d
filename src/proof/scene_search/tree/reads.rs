//! What an obstacle can be shown at a read: how the controller reads it (its role), the
//! thresholds that cut its observation into cells (memoised), and each cell as a
//! constraint on the obstacle.

use crate::core::num::Scalar;
use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::core::scene::lateral::Lateral;
use crate::core::semantics::danger_distance;
use crate::proof::scene_search::cells::{Cell, Role, Thresholds, cells};
use crate::proof::scene_search::chain::Chain;
use crate::proof::scene_search::interval::Interval;
use crate::proof::scene_search::sense::{Sense, Sight};

use std::rc::Rc;

use super::{Profile, Reachable};

/// The cells of the thresholds met so far: they repeat at every step the robot cruises
/// (the same speed, hence the same danger and lane-change distances), so most steps find
/// theirs here instead of sorting and labelling the cuts again.
#[derive(Default)]
pub(super) struct CellMemo {
    known: Vec<(Role, Thresholds, Rc<Vec<Cell>>)>,
}

impl CellMemo {
    /// Most threshold sets kept (a scene meets few: one per obstacle kind, lane-change
    /// state and robot speed while it accelerates).
    const LIMIT: usize = 64;

    pub(super) fn cells(&mut self, role: Role, th: &Thresholds) -> Rc<Vec<Cell>> {
        if let Some((_, _, cs)) = self.known.iter().find(|(r, t, _)| *r == role && t == th) {
            return cs.clone();
        }
        let cs = Rc::new(cells(role, th));
        if self.known.len() == Self::LIMIT {
            self.known.remove(0);
        }
        self.known.push((role, th.clone(), cs.clone()));
        cs
    }
}

/// The chain in which an obstacle is shown at a read: as it is once shown; while hidden,
/// with its first sighting at the first undecided observation (see [`super::super::sense`]).
/// None when it can no longer be shown.
pub(super) fn shown_base(
    p: &SceneParams<Rational>,
    sense: &Sense,
    profile: &mut Profile,
    chain: &Chain,
    sight: Sight,
) -> Option<Chain> {
    match sight {
        Sight::Shown { .. } => Some(chain.clone()),
        Sight::Hidden { since } => {
            let at = profile.at(p, since).position.clone();
            chain.constrain(since, &sense.detectable(&at), &Interval::all())
        }
    }
}

/// The cell as a constraint on the obstacle (its gap is seen from the robot at `seen_at`),
/// with its representative; None when the obstacle cannot be in it.
pub(super) fn reach(
    chain: &Chain,
    cell: Cell,
    n: usize,
    seen_at: &Rational,
    sense: &Sense,
    sight: Sight,
) -> Option<Reachable> {
    let position = sense.positions(&cell.gap, seen_at);
    // The speed seen with X(n) is w_{n−1}; at n = 0 there is none (it reads 0 exactly).
    let speed = if n == 0 {
        Interval::all()
    } else {
        sense.speeds(&cell.speed)
    };
    let chain = chain.constrain(n, &position, &speed)?;
    Some(Reachable {
        seen: cell.seen,
        chain,
        gap: cell.gap,
        speed: cell.speed,
        sight,
    })
}

/// How the controller reads obstacle i with the robot in `lateral`.
pub(super) fn role(p: &SceneParams<Rational>, lateral: &Lateral, i: usize) -> Role {
    let lane = p.obstacles[i].lane;
    if lane == lateral.lane {
        Role::Reference
    } else if p.lane_change.is_some()
        && lateral.change.is_none()
        && (lane == lateral.lane + 1 || lane == lateral.lane - 1)
    {
        Role::Target
    } else {
        Role::Ignored
    }
}

/// The thresholds for obstacle i at a step where the robot drives at `v`.
pub(super) fn thresholds(
    p: &SceneParams<Rational>,
    sense: &Sense,
    v: &Rational,
    lateral: &Lateral,
    i: usize,
    n: usize,
) -> Thresholds {
    let o = &p.obstacles[i];
    let can_change = p.lane_change.is_some() && lateral.change.is_none();
    let lane_change = p.lane_change.as_ref().filter(|_| can_change).map(|lc| {
        let assumed = if o.is_static {
            Rational::zero()
        } else {
            p.robot.V_a.clone()
        };
        (v.clone() + assumed) * Rational::int(lc.periods as i64) * p.robot.dt.clone()
            + p.robot.buffer.clone()
    });
    // Some error shows a speed above V_a iff the true one can be above V_a − σ_w.
    let wrong = p.robot.wrong_assumption_brake
        && !o.is_static
        && o.max_speed.clone() + sense.sigma_w.clone() > p.robot.V_a
        && n >= 1;
    Thresholds {
        rho: p.robot.rho.clone(),
        danger: danger_distance(p.controller_for(i), v),
        lane_change,
        rear_gap: p
            .lane_change
            .as_ref()
            .filter(|_| can_change)
            .map(|lc| lc.rear_gap.clone()),
        wrong_above: wrong.then(|| p.robot.V_a.clone()),
    }
}
