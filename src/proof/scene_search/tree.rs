//! The search tree: every way a scene's run can go, as far as the controller can tell.
//!
//! A node is a step start k at which the robot still accelerates or drives: its lateral
//! state, the lane changes so far, and per obstacle the constraints the run has put on it
//! ([`Chain`]). Until it brakes the robot follows the drive profile whatever happens, so
//! the node fixes the robot's whole past. At k ≥ L the robot sees every obstacle's position
//! at step n = k − L; the cells of each observation ([`super::cells`]) are the only
//! distinctions the controller makes, so one child per combination of cells (those the
//! obstacles can reach) covers every behaviour, and [`scene_guard`] on a representative of
//! the combination is the controller's command for all of it. A child either goes on to
//! k + 1, begins a lane change and goes on, or brakes: a leaf. A run in which nothing can
//! happen any more (no goal, and every obstacle of the robot's lane already seen at a gap
//! ≤ 0) is a leaf too: the robot drives on for ever.

use crate::core::num::Scalar;
use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::core::scene::guards::{Command, scene_guard};
use crate::core::scene::lateral::{LaneChangeEvent, Lateral};
use crate::core::semantics::{BrakeReason, Observation, RobotState, danger_distance, robot_motion};

use std::rc::Rc;

use super::cells::{Cell, Role, Thresholds, cells, quiet};
use super::chain::Chain;
use super::dominance::{Dominance, NodeView};
use super::interval::Interval;
use super::sense::{Sense, Sight};

/// The robot along the drive profile, extended as the search needs it.
#[derive(Clone, Debug)]
pub struct Profile {
    states: Vec<RobotState<Rational>>,
}

impl Profile {
    /// The profile's first state: the robot at t = 0.
    pub fn new(p: &SceneParams<Rational>) -> Profile {
        Profile {
            states: vec![RobotState::initial(&p.robot)],
        }
    }

    /// The robot at step k's start if it has not braked.
    pub fn at(&mut self, p: &SceneParams<Rational>, k: usize) -> &RobotState<Rational> {
        while self.states.len() <= k {
            let last = self.states.last().expect("never empty");
            let next = robot_motion(&p.robot, last).end;
            self.states.push(next);
        }
        &self.states[k]
    }
}

/// How a run ends.
#[derive(Clone, Debug, PartialEq)]
pub enum Ending {
    /// The controller commands Brake at this step's start.
    Brake {
        /// T.
        step: usize,
        /// Why.
        reason: BrakeReason,
    },
    /// From this step on no guard can fire again: the robot drives on for ever.
    Forever {
        /// The first step at which nothing can happen any more.
        step: usize,
    },
}

/// A finished run, as far as the controller can tell.
#[derive(Clone, Debug)]
pub struct Leaf {
    /// How it ends.
    pub ending: Ending,
    /// Lane changes begun, in order.
    pub changes: Vec<LaneChangeEvent>,
    /// Per obstacle, what the run requires of it.
    pub chains: Vec<Chain>,
    /// Per obstacle, whether the run has shown it (occlusion).
    pub sights: Vec<Sight>,
    log: Log,
}

impl Leaf {
    /// The cells the run was shown at its reads, oldest first (kept only with noise: a
    /// witness picks each of those observations' errors to land in its cell).
    pub fn shown_cells(&self) -> Vec<ShownCell> {
        let mut out = Vec::new();
        let mut link = self.log.as_ref();
        while let Some(l) = link {
            out.push(l.cell.clone());
            link = l.prev.as_ref();
        }
        out.reverse();
        out
    }
}

/// One read observation and the cell the run was shown of it.
#[derive(Clone, Debug, PartialEq)]
pub struct ShownCell {
    /// The obstacle.
    pub obstacle: usize,
    /// Its observation step n (the gap at n·dt, read at step n + L).
    pub step: usize,
    /// The gaps shown.
    pub gap: Interval,
    /// The speeds shown.
    pub speed: Interval,
}

/// A persistent list of shown cells, newest first (children share their parent's).
#[derive(Debug)]
struct LogLink {
    cell: ShownCell,
    prev: Log,
}

type Log = Option<Rc<LogLink>>;

/// A step start at which the robot still accelerates or drives.
#[derive(Clone, Debug)]
struct Node {
    k: usize,
    lateral: Lateral,
    changes: Vec<LaneChangeEvent>,
    chains: Vec<Chain>,
    sights: Vec<Sight>,
    log: Log,
}

/// What a child of a node requires of the obstacles.
#[derive(Clone, Debug)]
struct Child {
    chains: Vec<Chain>,
    sights: Vec<Sight>,
    log: Log,
}

/// Whether runs of the scene share much: at least two obstacles move, so runs can differ
/// in their past (Lemma R9 merges them) and siblings share the chains of the obstacles
/// they did not split (worst cases are kept by chain). With one moving obstacle runs differ
/// in their brake step, and both cost more than they save (the seed's picture: 43 M
/// instructions without, 53 M with).
pub fn runs_share_much(p: &SceneParams<Rational>) -> bool {
    p.obstacles
        .iter()
        .filter(|o| o.max_speed > Rational::zero())
        .count()
        >= 2
}

/// Why the search stopped without an answer.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TreeError {
    /// A run went on past the horizon.
    #[error("a run is still undecided after {0} control periods")]
    Horizon(usize),
    /// Too many runs to list.
    #[error("more than {0} runs; the scene is too large for the search")]
    Budget(usize),
}

/// Counts of what the search did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TreeStats {
    /// Step starts expanded.
    pub nodes: usize,
    /// Finished runs.
    pub leaves: usize,
    /// Step starts left out as dominated by one searched ([`SearchOptions::prune_dominated`]).
    pub pruned: usize,
}

/// How to search: the exact shortcuts, each of which can be turned off (the same answers,
/// slower: tests check each against the search without it), and the order of children.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SearchOptions {
    /// Search a node's children last first (the answers do not depend on the order; a test
    /// turns it so that pruning cannot owe its answers to which run it met first).
    pub reverse_children: bool,
    /// Jump over the steps at which nothing can happen (Lemma R7, `quiet_until`) in one
    /// go instead of step by step.
    pub jump_quiet_steps: bool,
    /// Leave out a step start whose every run is worth no less, obstacle by obstacle, than
    /// a run from one already searched (Lemma R9, `scene_search::dominance`); taken when at
    /// least two obstacles move.
    pub prune_dominated: bool,
}

impl Default for SearchOptions {
    fn default() -> SearchOptions {
        SearchOptions {
            reverse_children: false,
            jump_quiet_steps: true,
            prune_dominated: true,
        }
    }
}

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
pub(super) struct Start {
    pub k: usize,
    pub lateral: Lateral,
    pub changes: Vec<LaneChangeEvent>,
    pub chains: Vec<Chain>,
    pub sights: Vec<Sight>,
}

/// [`walk`] over the runs below `start` only.
#[cfg(test)]
pub(super) fn walk_below(
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

/// The cells of the thresholds met so far: they repeat at every step the robot cruises
/// (the same speed, hence the same danger and lane-change distances), so most steps find
/// theirs here instead of sorting and labelling the cuts again.
#[derive(Default)]
struct CellMemo {
    known: Vec<(Role, Thresholds, Rc<Vec<Cell>>)>,
}

impl CellMemo {
    /// Most threshold sets kept (a scene meets few: one per obstacle kind, lane-change
    /// state and robot speed while it accelerates).
    const LIMIT: usize = 64;

    fn cells(&mut self, role: Role, th: &Thresholds) -> Rc<Vec<Cell>> {
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

/// One cell an obstacle can be shown in (or, with occlusion, hidden): its representative
/// (None: nothing shown), the chain in it, the cell of shown gaps and speeds, and the
/// obstacle's sight after it.
#[derive(Clone, Debug)]
struct Reachable {
    seen: Option<Observation<Rational>>,
    chain: Chain,
    gap: Interval,
    speed: Interval,
    sight: Sight,
}

/// A read at a step: its observation step n, where the robot was then, and the noise.
struct Reading<'a> {
    n: usize,
    seen_at: &'a Rational,
    sense: &'a Sense,
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

/// The chain in which an obstacle is shown at a read: as it is once shown; while hidden,
/// with its first sighting at the first undecided observation (see [`super::sense`]).
/// None when it can no longer be shown.
fn shown_base(
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

/// Whether `cell` shows the obstacle beyond ρ, where no guard reads it (as if hidden), and
/// every truth it allows is showable (ρ − σ_g ≥ d_det; never without occlusion).
///
/// An obstacle first shown in such a cell at read m and read only in such cells since
/// (`far_only`) needs nothing from the run that the lineage hiding it at m and showing it
/// first at the next read does not also allow: hidden at m asks a true gap ≥ d_det, which
/// the far cell implies, and showing it first later asks a true gap ≥ d_det at an
/// observation where the far cell is read again. The commands are the same, so a
/// `far_only` obstacle's far cell at its next read is dominated and left out: exact for
/// s* (every behaviour left out is in a run kept, with the same robot motion), and it keeps
/// a hidden obstacle from starting a new lineage of runs at every read.
fn far_cell(p: &SceneParams<Rational>, sense: &Sense, cell: &Cell) -> bool {
    let Some(d) = &sense.d_det else {
        return false;
    };
    let beyond_rho = cell.gap.hi.is_none()
        && cell
            .gap
            .lo
            .as_ref()
            .is_some_and(|lo| lo.at >= p.robot.rho && !(lo.at == p.robot.rho && lo.closed));
    beyond_rho && *d <= p.robot.rho.clone() - sense.sigma_g.clone()
}

/// Quiet cells (`cells::quiet`: the guards read them as nothing) generalise far cells,
/// with a split. Let an obstacle be first shown at read m′ and read only in quiet cells
/// since (`far_only`), and let a behaviour B of that lineage read it at read m + 1 in a
/// quiet cell Q′ with a true gap ≥ d_det there. Then the behaviour B′ with the same motion
/// that hides it through read m and first shows it at m + 1 in Q′ is a behaviour of the
/// sibling lineage hidden at m′: its first sighting has a true gap ≥ d_det, every hidden
/// read before has one too (gaps never grow), and every command is B's (B's reads were
/// quiet, B′'s unseen). From m + 1 on the two are the same. So the lineage keeps of Q′
/// only the truths below d_det (for a far cell, whose truths are all showable, nothing:
/// `far_cell`), exactly for s*; a hidden obstacle inside a large ρ then starts new runs
/// only where showing it changes a command.
fn undominated(mut r: Reachable, n: usize, seen_at: &Rational, sense: &Sense) -> Option<Reachable> {
    r.chain = r
        .chain
        .constrain(n, &sense.undetectable(seen_at), &Interval::all())?;
    Some(r)
}

/// Whether obstacle i is still hidden at read n while every error would show it beyond ρ
/// (a true gap > ρ + σ_g whatever it did): showing it then could not change any command,
/// and it is showable (ρ + σ_g ≥ d_det), so the read is as if unread and its sight stays
/// undecided (see [`super::sense`]). Exact, and it keeps far hidden obstacles from
/// splitting the run at every read of a near one.
fn hidden_and_far(
    p: &SceneParams<Rational>,
    sense: &Sense,
    node: &Node,
    i: usize,
    n: usize,
    seen_at: &Rational,
) -> bool {
    let Sight::Hidden { .. } = node.sights[i] else {
        return false;
    };
    let chain = &node.chains[i];
    let far = p.robot.rho.clone() + sense.sigma_g.clone() + seen_at.clone();
    let showable = sense
        .d_det
        .as_ref()
        .is_some_and(|d| *d <= p.robot.rho.clone() + sense.sigma_g.clone());
    showable && n >= chain.last_step() && chain.reach_at(n).lo.is_some_and(|lo| lo.at > far)
}

/// At a leaf reached at step k: every obstacle still undecided was first shown at its
/// first undecided observation or is hidden through k, and either needs a true gap ≥ d_det
/// at that observation (see [`super::sense`]). False when some obstacle cannot.
fn settle_hidden(
    p: &SceneParams<Rational>,
    sense: &Sense,
    profile: &mut Profile,
    k: usize,
    child: &mut Child,
) -> bool {
    let now = k.saturating_sub(p.robot.L);
    for i in 0..child.chains.len() {
        let Sight::Hidden { since } = child.sights[i] else {
            continue;
        };
        if since > now {
            continue;
        }
        let at = profile.at(p, since).position.clone();
        match child.chains[i].constrain(since, &sense.detectable(&at), &Interval::all()) {
            Some(chain) => child.chains[i] = chain,
            None => return false,
        }
    }
    true
}

/// Per obstacle, the cells it can reach.
type Options = Vec<Reachable>;

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
fn merge_equivalent(
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
fn advance(choice: &mut [usize], options: &[Options], targets: &[usize]) -> bool {
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
fn advance_targets(choice: &mut [usize], targets: &[usize], options: &[Options]) -> bool {
    for (j, &t) in targets.iter().enumerate() {
        choice[j] += 1;
        if choice[j] < options[t].len() {
            return true;
        }
        choice[j] = 0;
    }
    false
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

/// The first step after `node.k` at which the controller might do anything but go on, when
/// it can be told without branching: no obstacle of the robot's lane can be shown where a
/// guard reads it before then (observed gaps fall no faster than the robot's travel plus
/// W_i per period), and the destination does not fire before it. Where only danger can
/// fire ([`only_danger_fires`]) that is within min(ρ, d_i(v)), else within ρ: an obstacle
/// in the area but not dangerous moves nothing (`scene_guard`). Lane changes need danger,
/// so none begins before it either; obstacles of other lanes are read only for lane
/// changes. None when the robot might react now.
#[allow(clippy::too_many_arguments)]
fn quiet_until(
    p: &SceneParams<Rational>,
    sense: &Sense,
    profile: &mut Profile,
    node: &Node,
    lateral: &Lateral,
    goal_step: Option<usize>,
    horizon: usize,
) -> Option<usize> {
    let k = node.k;
    let l = p.robot.L;
    let mut next = goal_step.unwrap_or(horizon + 1).min(horizon + 1);
    if k < l {
        // From step L on a lane without obstacles has nothing left to decide.
        next = next.min(l);
    }
    if next <= k {
        return None;
    }
    for (i, o) in p.obstacles.iter().enumerate() {
        if o.lane != lateral.lane {
            continue;
        }
        let chain = &node.chains[i];
        let first = k.saturating_sub(l).max(chain.last_step());
        let lowest = chain.reach_at(chain.last_step()).lo?.at;
        let guarded = only_danger_fires(p, sense, i);
        // First n ≥ first with lowest − W·dt·(n − last) − P_n ≤ θ_n (monotone in n: the
        // left side falls, θ_n = ρ or min(ρ, d(v_{n+L})) grows with the robot's speed).
        let near = |n: usize, profile: &mut Profile| {
            let fall = chain.w_max().clone()
                * p.robot.dt.clone()
                * Rational::int((n - chain.last_step()) as i64);
            // Some error shows it within θ_n iff its true gap is ≤ θ_n + σ_g.
            let gap =
                lowest.clone() - fall - profile.at(p, n).position.clone() - sense.sigma_g.clone();
            // θ_n ≤ ρ: beyond ρ there is no need to ask for d_i.
            gap <= p.robot.rho
                && (!guarded || gap <= fires_within(p, i, &profile.at(p, n + l).speed))
        };
        if near(first, profile) {
            return None;
        }
        // Only steps k' = n + L < next matter.
        let last = match next.checked_sub(l + 1) {
            Some(last) if last > first => last,
            _ => continue,
        };
        if !near(last, profile) {
            continue;
        }
        // near(lo) is false, near(hi) true: bisect for the first near step.
        let (mut lo, mut hi) = (first, last);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if near(mid, profile) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        next = next.min(hi + l);
    }
    (next > k).then_some(next)
}

/// Whether obstacle i, seen within ρ, can move the controller only by danger: it is never
/// seen faster than V_a (static, the guard off, or W_i + σ_w ≤ V_a) and no occlusion
/// decides its sight at a read (a read of a hidden obstacle is a choice of the run).
fn only_danger_fires(p: &SceneParams<Rational>, sense: &Sense, i: usize) -> bool {
    let o = &p.obstacles[i];
    let wrong = p.robot.wrong_assumption_brake
        && !o.is_static
        && o.max_speed.clone() + sense.sigma_w.clone() > p.robot.V_a;
    sense.d_det.is_none() && !wrong
}

/// min(ρ, d_i(v)): the largest shown gap at which obstacle i is dangerous to a robot at
/// speed v (ρ under the area rule).
fn fires_within(p: &SceneParams<Rational>, i: usize, v: &Rational) -> Rational {
    match danger_distance(p.controller_for(i), v) {
        Some(d) if d < p.robot.rho => d,
        _ => p.robot.rho.clone(),
    }
}

/// The cell as a constraint on the obstacle (its gap is seen from the robot at `seen_at`),
/// with its representative; None when the obstacle cannot be in it.
fn reach(
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
fn role(p: &SceneParams<Rational>, lateral: &Lateral, i: usize) -> Role {
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
fn thresholds(
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

/// Whether no guard can fire again at or after this step: every obstacle of the lane the
/// robot is in (or moving into) is already at a true gap ≤ −σ_g whatever it did, so it is
/// shown at a gap ≤ 0 whatever the error (true gaps never grow), and there is no goal.
fn nothing_left(
    p: &SceneParams<Rational>,
    sense: &Sense,
    profile: &mut Profile,
    node: &Node,
    lateral: &Lateral,
    n: usize,
) -> bool {
    let seen_at = profile.at(p, n).position.clone();
    p.obstacles.iter().enumerate().all(|(i, o)| {
        o.lane != lateral.lane
            || node.chains[i]
                .reach_at(n.max(node.chains[i].last_step()))
                .hi
                .is_some_and(|h| h.at <= seen_at.clone() - sense.sigma_g.clone())
    })
}

/// G: the first step at whose start the robot, driving on, has x + v²/(2b) ≥ goal (None:
/// no goal, or not within the horizon).
fn goal_step(p: &SceneParams<Rational>, profile: &mut Profile, horizon: usize) -> Option<usize> {
    let goal = p.goal.as_ref()?;
    let two_b = Rational::int(2) * p.robot.b.clone();
    (0..=horizon).find(|&k| {
        let s = profile.at(p, k);
        s.position.clone() + s.speed.clone() * s.speed.clone() / two_b.clone() >= *goal
    })
}
