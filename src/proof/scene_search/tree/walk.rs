//! Walking the search tree: from a node, the cells each obstacle can reach, one child per
//! combination the controller tells apart, and the controller's command carried out in
//! each (a leaf when it brakes, else the next step).

use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::core::scene::guards::{Command, scene_guard};
#[cfg(test)]
use crate::core::scene::lateral::LaneChangeEvent;
use crate::core::scene::lateral::Lateral;
use crate::core::semantics::Observation;
use crate::proof::scene_search::cells::{Role, quiet};
use crate::proof::scene_search::chain::Chain;
use crate::proof::scene_search::dominance::{Dominance, NodeView};
use crate::proof::scene_search::interval::Interval;
use crate::proof::scene_search::sense::{Sense, Sight};

use std::rc::Rc;

use super::combinations::{advance, advance_targets, merge_equivalent};
use super::occlusion::{far_cell, hidden_and_far, settle_hidden, undominated};
use super::quiet::{goal_step, nothing_left, quiet_until};
use super::reads::{CellMemo, reach, role, shown_base, thresholds};
use super::{
    Child, Ending, Leaf, LogLink, Node, Options, Profile, Reachable, Reading, SearchOptions,
    ShownCell, TreeError, TreeStats, runs_share_much,
};

/// Walks every run of the scene and hands each finished one to `visit`, searching as
/// `how` asks.
pub fn walk(
    p: &SceneParams<Rational>,
    profile: &mut Profile,
    horizon: usize,
    budget: usize,
    how: SearchOptions,
    visit: impl FnMut(&Leaf, &mut Profile),
) -> Result<TreeStats, TreeError> {
    let dt = p.robot.dt.clone();
    let sense = Sense::of(p);
    let root = Node {
        k: 0,
        lateral: Lateral::start(),
        changes: Vec::new(),
        chains: p
            .obstacles
            .iter()
            .map(|o| {
                Chain::new(
                    Interval::closed(o.start_min.clone(), o.start_max.clone()),
                    o.max_speed.clone(),
                    dt.clone(),
                )
            })
            .collect(),
        sights: vec![sense.initial(); p.obstacles.len()],
        log: None,
    };
    walk_from(p, profile, horizon, budget, how, root, visit)
}

/// A step start, as a search can be started from it (tests search below the nodes that
/// Lemma R9 compares).
#[cfg(test)]
#[derive(Clone, Debug)]
pub(in crate::proof::scene_search) struct Start {
    pub k: usize,
    pub lateral: Lateral,
    pub changes: Vec<LaneChangeEvent>,
    pub chains: Vec<Chain>,
    pub sights: Vec<Sight>,
}

/// [`walk`] over the runs below `start` only.
#[cfg(test)]
pub(in crate::proof::scene_search) fn walk_below(
    p: &SceneParams<Rational>,
    profile: &mut Profile,
    horizon: usize,
    how: SearchOptions,
    start: Start,
    visit: impl FnMut(&Leaf, &mut Profile),
) -> Result<TreeStats, TreeError> {
    let root = Node {
        k: start.k,
        lateral: start.lateral,
        changes: start.changes,
        chains: start.chains,
        sights: start.sights,
        log: None,
    };
    walk_from(p, profile, horizon, usize::MAX, how, root, visit)
}

fn walk_from(
    p: &SceneParams<Rational>,
    profile: &mut Profile,
    horizon: usize,
    budget: usize,
    how: SearchOptions,
    root: Node,
    mut visit: impl FnMut(&Leaf, &mut Profile),
) -> Result<TreeStats, TreeError> {
    let sense = Sense::of(p);
    let periods = p.lane_change_periods();
    let goal_step = goal_step(p, profile, horizon);
    let mut stats = TreeStats::default();
    let mut stack = vec![root];
    let mut known_cells = CellMemo::default();
    let mut searched = Dominance::default();
    let prune = how.prune_dominated && runs_share_much(p);
    while let Some(node) = stack.pop() {
        if prune
            && !searched.admit(
                p,
                &sense,
                profile,
                NodeView {
                    k: node.k,
                    lateral: &node.lateral.at_step(node.k, periods),
                    changes: &node.changes,
                    chains: &node.chains,
                    sights: &node.sights,
                },
            )
        {
            stats.pruned += 1;
            continue;
        }
        stats.nodes += 1;
        if stats.nodes > budget {
            return Err(TreeError::Budget(budget));
        }
        if node.k > horizon {
            return Err(TreeError::Horizon(horizon));
        }
        let k = node.k;
        let lateral = node.lateral.at_step(k, periods);
        let robot = profile.at(p, k).clone();
        let l = p.robot.L;
        if p.goal.is_none() && k >= l && nothing_left(p, &sense, profile, &node, &lateral, k - l) {
            let mut child = Child {
                chains: node.chains.clone(),
                sights: node.sights.clone(),
                log: node.log.clone(),
            };
            if settle_hidden(p, &sense, profile, k, &mut child) {
                stats.leaves += 1;
                visit(
                    &Leaf {
                        ending: Ending::Forever { step: k },
                        changes: node.changes.clone(),
                        chains: child.chains,
                        sights: child.sights,
                        log: child.log,
                    },
                    profile,
                );
            }
            continue;
        }
        if how.jump_quiet_steps
            && let Some(next) = quiet_until(p, &sense, profile, &node, &lateral, goal_step, horizon)
            && next > k + 1
        {
            // Nothing the controller reads can change before `next`: go straight there.
            stack.push(Node { k: next, ..node });
            continue;
        }
        // Per obstacle, the cells it can reach at this step, with its chain in each. A
        // target lane's obstacles are read only when a lane change is being decided, so
        // they are split only then.
        let n = k.checked_sub(l);
        let seen_at = n.map(|n| profile.at(p, n).position.clone());
        let mut options: Vec<Options> = Vec::with_capacity(p.obstacles.len());
        let mut bases: Vec<Option<Chain>> = Vec::with_capacity(p.obstacles.len());
        let mut targets: Vec<usize> = Vec::new();
        for i in 0..p.obstacles.len() {
            let role = role(p, &lateral, i);
            let sight = node.sights[i];
            let base = shown_base(p, &sense, profile, &node.chains[i], sight);
            let cells_here = match (n, &seen_at) {
                (Some(n), Some(seen_at))
                    if role != Role::Ignored
                        && !hidden_and_far(p, &sense, &node, i, n, seen_at) =>
                {
                    let th = thresholds(p, &sense, &robot.speed, &lateral, i, n);
                    let (from, far_only) = match sight {
                        Sight::Shown { from, far_only } => (from, far_only),
                        Sight::Hidden { since } => (since, true),
                    };
                    let mut here: Vec<Reachable> = match &base {
                        Some(base) => known_cells
                            .cells(role, &th)
                            .iter()
                            .cloned()
                            .filter_map(|cell| {
                                let far = far_cell(p, &sense, &cell);
                                let quiet =
                                    far || (sense.d_det.is_some() && quiet(role, &th, &cell));
                                let dominated =
                                    quiet && matches!(sight, Sight::Shown { far_only: true, .. });
                                if far && dominated {
                                    // Dominated: see `far_cell`.
                                    return None;
                                }
                                let after = Sight::Shown {
                                    from,
                                    far_only: far_only && quiet,
                                };
                                let r = reach(base, cell, n, seen_at, &sense, after)?;
                                match dominated {
                                    true => undominated(r, n, seen_at, &sense),
                                    false => Some(r),
                                }
                            })
                            .collect(),
                        None => Vec::new(),
                    };
                    if let Sight::Hidden { .. } = sight {
                        // Hidden at this read: it must stay showable (a true gap ≥ d_det).
                        // Implied by what the first sighting or the leaf asks later (a gap
                        // ≥ d_det at `since` > n; gaps never grow), so it changes no answer
                        // (400 random scenes agree without it): it prunes early (seed-lanes,
                        // d_det = 0.8: 3.4 s with it, 4.6 s without).
                        let still = sense.detectable(seen_at);
                        if let Some(chain) = node.chains[i].constrain(n, &still, &Interval::all()) {
                            here.push(Reachable {
                                seen: None,
                                chain,
                                gap: Interval::all(),
                                speed: Interval::all(),
                                sight: Sight::Hidden { since: n + 1 },
                            });
                        }
                    }
                    here
                }
                _ => vec![Reachable {
                    seen: None,
                    chain: node.chains[i].clone(),
                    gap: Interval::all(),
                    speed: Interval::all(),
                    sight,
                }],
            };
            bases.push(base);
            if role == Role::Target {
                targets.push(i);
            }
            options.push(cells_here);
        }
        if options.iter().any(Vec::is_empty) {
            continue;
        }
        if let (Some(n), Some(seen_at)) = (n, &seen_at) {
            let at = Reading {
                n,
                seen_at,
                sense: &sense,
            };
            merge_equivalent(p, &robot, &lateral, &at, &bases, &mut options, &targets);
        }
        let pushed_from = stack.len();
        let mut choice = vec![0usize; options.len()];
        loop {
            let mut seen: Vec<Option<Observation<Rational>>> = choice
                .iter()
                .enumerate()
                .map(|(i, &c)| options[i][c].seen.clone())
                .collect();
            // Targets unseen: every neighbouring lane free.
            for &t in &targets {
                seen[t] = None;
            }
            // Targets are read only for a lane change: left as they were otherwise.
            let picks: Vec<Option<usize>> = choice
                .iter()
                .enumerate()
                .map(|(i, &c)| (!targets.contains(&i)).then_some(c))
                .collect();
            let base = child_of(&node, &options, &picks, n, sense.noisy());
            let command = scene_guard(p, &robot, &lateral, &seen);
            if matches!(command, Command::ChangeLane(_)) && !targets.is_empty() {
                // The lane change hangs on the targets: one child per combination of theirs.
                let mut tchoice = vec![0usize; targets.len()];
                loop {
                    let mut seen = seen.clone();
                    let mut picks = picks.clone();
                    for (j, &t) in targets.iter().enumerate() {
                        seen[t] = options[t][tchoice[j]].seen.clone();
                        picks[t] = Some(tchoice[j]);
                    }
                    let child = child_of(&node, &options, &picks, n, sense.noisy());
                    let command = scene_guard(p, &robot, &lateral, &seen);
                    follow(
                        &mut stack, &mut stats, &node, lateral, k, command, child, profile,
                        &mut visit, p, &sense,
                    );
                    if !advance_targets(&mut tchoice, &targets, &options) {
                        break;
                    }
                }
            } else {
                follow(
                    &mut stack, &mut stats, &node, lateral, k, command, base, profile, &mut visit,
                    p, &sense,
                );
            }
            if !advance(&mut choice, &options, &targets) {
                break;
            }
        }
        if how.reverse_children {
            stack[pushed_from..].reverse();
        }
    }
    Ok(stats)
}

/// The child that `picks` makes (per obstacle, the option chosen, or None: not read),
/// logging the shown cells when observations are noisy.
fn child_of(
    node: &Node,
    options: &[Options],
    picks: &[Option<usize>],
    n: Option<usize>,
    noisy: bool,
) -> Child {
    let mut child = Child {
        chains: node.chains.clone(),
        sights: node.sights.clone(),
        log: node.log.clone(),
    };
    for (i, pick) in picks.iter().enumerate() {
        let Some(c) = *pick else { continue };
        let option = &options[i][c];
        child.chains[i] = option.chain.clone();
        child.sights[i] = option.sight;
        if let (true, Some(n), Some(_)) = (noisy, n, &option.seen) {
            child.log = Some(Rc::new(LogLink {
                cell: ShownCell {
                    obstacle: i,
                    step: n,
                    gap: option.gap.clone(),
                    speed: option.speed.clone(),
                },
                prev: child.log.take(),
            }));
        }
    }
    child
}

/// Carries out the controller's command in a child: a leaf when it brakes, else the next
/// step (with a lane change begun).
#[allow(clippy::too_many_arguments)]
fn follow(
    stack: &mut Vec<Node>,
    stats: &mut TreeStats,
    node: &Node,
    lateral: Lateral,
    k: usize,
    command: Command,
    mut child: Child,
    profile: &mut Profile,
    visit: &mut impl FnMut(&Leaf, &mut Profile),
    p: &SceneParams<Rational>,
    sense: &Sense,
) {
    let mut next = lateral;
    let mut changes = node.changes.clone();
    match command {
        Command::Go => {}
        Command::ChangeLane(to) => changes.push(next.begin_change(k, to)),
        Command::Brake(reason) => {
            if settle_hidden(p, sense, profile, k, &mut child) {
                stats.leaves += 1;
                visit(
                    &Leaf {
                        ending: Ending::Brake { step: k, reason },
                        changes,
                        chains: child.chains,
                        sights: child.sights,
                        log: child.log,
                    },
                    profile,
                );
            }
            return;
        }
    }
    stack.push(Node {
        k: k + 1,
        lateral: next,
        changes,
        chains: child.chains,
        sights: child.sights,
        log: child.log,
    });
}
