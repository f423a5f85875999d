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
//!
//! The pieces, one idea a file: walking the tree and expanding a node into its children
//! ([`walk()`]), the robot along the drive profile ([`Profile`]), what an obstacle can be
//! shown at a read (`reads`), the exact shortcuts for hidden and far obstacles
//! (`occlusion`), the combinations of the obstacles' cells and the merge of those that
//! command the same (`combinations`), and the steps at which nothing can happen (`quiet`).
//! This file holds what they share: the nodes, children and options of the tree, and the
//! runs, counts and options of a search.
//!
//! [`scene_guard`]: crate::core::scene::guards::scene_guard

mod combinations;
mod occlusion;
mod profile;
mod quiet;
mod reads;
mod walk;

pub use profile::Profile;
pub use walk::walk;
#[cfg(test)]
pub(super) use walk::{Start, walk_below};

use crate::core::num::Scalar;
use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::core::scene::lateral::{LaneChangeEvent, Lateral};
use crate::core::semantics::{BrakeReason, Observation};

use std::rc::Rc;

use super::chain::Chain;
use super::interval::Interval;
use super::sense::{Sense, Sight};

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

/// Per obstacle, the cells it can reach.
type Options = Vec<Reachable>;
