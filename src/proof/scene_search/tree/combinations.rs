//! The combinations of the obstacles' cells at a read: the odometers that list them, what
//! each commands, and the exact merge of neighbouring cells that command the same.

use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::core::scene::guards::{Command, scene_guard};
use crate::core::scene::lateral::Lateral;
use crate::core::semantics::{Observation, RobotState};
use crate::proof::scene_search::chain::Chain;
use crate::proof::scene_search::interval::Interval;

use super::{Options, Reachable, Reading};

/// What a combination of non-target cells commands: the command with every neighbouring
/// lane free, and, when that is a lane change, the command for each combination of the
/// targets' cells.
fn signature(
    p: &SceneParams<Rational>,
    robot: &RobotState<Rational>,
    lateral: &Lateral,
    options: &[Options],
    targets: &[usize],
    choice: &[usize],
) -> Vec<Command> {
    let mut seen: Vec<Option<Observation<Rational>>> = choice
        .iter()
        .enumerate()
        .map(|(i, &c)| options[i][c].seen.clone())
        .collect();
    for &t in targets {
        seen[t] = None;
    }
    let first = scene_guard(p, robot, lateral, &seen);
    let mut out = vec![first];
    if matches!(first, Command::ChangeLane(_)) && !targets.is_empty() {
        let mut tchoice = vec![0usize; targets.len()];
        loop {
            for (j, &t) in targets.iter().enumerate() {
                seen[t] = options[t][tchoice[j]].seen.clone();
            }
            out.push(scene_guard(p, robot, lateral, &seen));
            if !advance_targets(&mut tchoice, targets, options) {
                break;
            }
        }
    }
    out
}

/// Whether two shown cells' union is again a product of intervals: the same speeds and
/// touching gaps, or the same gaps and touching speeds. (Never a hidden option, nor two
/// options that leave the obstacle's sight differently.)
fn touching(a: &Reachable, b: &Reachable) -> Option<(Interval, Interval)> {
    if a.seen.is_none() || b.seen.is_none() || a.sight != b.sight {
        return None;
    }
    let meet = |x: &Interval, y: &Interval| -> Option<Interval> {
        let (Some(h), Some(l)) = (&x.hi, &y.lo) else {
            return None;
        };
        (h.at == l.at && h.closed != l.closed).then(|| Interval {
            lo: x.lo.clone(),
            hi: y.hi.clone(),
        })
    };
    let join = |x: &Interval, y: &Interval| meet(x, y).or_else(|| meet(y, x));
    if a.speed == b.speed {
        return join(&a.gap, &b.gap).map(|gap| (gap, a.speed.clone()));
    }
    if a.gap == b.gap {
        return join(&a.speed, &b.speed).map(|sp| (a.gap.clone(), sp));
    }
    None
}

/// Merges, per non-target obstacle, neighbouring cells that command the same whatever the
/// other obstacles show: the merged cell is one interval constraint (widening by the noise
/// keeps a union of touching cells one interval), and every behaviour in it leads to the
/// same child, so the merge is exact and the tree stays small. `bases[i]` is the chain
/// obstacle i's shown cells constrain.
pub(super) fn merge_equivalent(
    p: &SceneParams<Rational>,
    robot: &RobotState<Rational>,
    lateral: &Lateral,
    at: &Reading<'_>,
    bases: &[Option<Chain>],
    options: &mut [Options],
    targets: &[usize],
) {
    let n = at.n;
    for i in 0..options.len() {
        if targets.contains(&i) {
            continue;
        }
        'retry: loop {
            let len = options[i].len();
            for a in 0..len {
                for b in a + 1..len {
                    let Some((gap, speed)) = touching(&options[i][a], &options[i][b]) else {
                        continue;
                    };
                    if !same_everywhere(p, robot, lateral, options, targets, i, a, b) {
                        continue;
                    }
                    let Some(base) = &bases[i] else { continue };
                    let position = at.sense.positions(&gap, at.seen_at);
                    let constrained = if n == 0 {
                        Interval::all()
                    } else {
                        at.sense.speeds(&speed)
                    };
                    let Some(chain) = base.constrain(n, &position, &constrained) else {
                        continue;
                    };
                    let seen = options[i][a].seen.clone();
                    let sight = options[i][a].sight;
                    options[i][a] = Reachable {
                        seen,
                        chain,
                        gap,
                        speed,
                        sight,
                    };
                    options[i].remove(b);
                    continue 'retry;
                }
            }
            break;
        }
    }
}

/// Whether obstacle i's cells a and b give the same signature for every combination of the
/// other non-target obstacles' cells.
#[allow(clippy::too_many_arguments)]
fn same_everywhere(
    p: &SceneParams<Rational>,
    robot: &RobotState<Rational>,
    lateral: &Lateral,
    options: &[Options],
    targets: &[usize],
    i: usize,
    a: usize,
    b: usize,
) -> bool {
    let mut choice = vec![0usize; options.len()];
    loop {
        choice[i] = a;
        let sa = signature(p, robot, lateral, options, targets, &choice);
        choice[i] = b;
        let sb = signature(p, robot, lateral, options, targets, &choice);
        if sa != sb {
            return false;
        }
        choice[i] = 0;
        // Odometer over the others (i and the targets held at 0).
        let mut moved = false;
        for j in 0..choice.len() {
            if j == i || targets.contains(&j) {
                continue;
            }
            choice[j] += 1;
            if choice[j] < options[j].len() {
                moved = true;
                break;
            }
            choice[j] = 0;
        }
        if !moved {
            return true;
        }
    }
}

/// The next combination of non-target cells (odometer order); false after the last.
pub(super) fn advance(choice: &mut [usize], options: &[Options], targets: &[usize]) -> bool {
    for i in 0..choice.len() {
        if targets.contains(&i) {
            continue;
        }
        choice[i] += 1;
        if choice[i] < options[i].len() {
            return true;
        }
        choice[i] = 0;
    }
    false
}

/// The next combination of the targets' cells; false after the last.
pub(super) fn advance_targets(
    choice: &mut [usize],
    targets: &[usize],
    options: &[Options],
) -> bool {
    for (j, &t) in targets.iter().enumerate() {
        choice[j] += 1;
        if choice[j] < options[t].len() {
            return true;
        }
        choice[j] = 0;
    }
    false
}
