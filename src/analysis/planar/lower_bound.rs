//! Branch and bound over one problem's leaves (docs/reductions.md Lemmas P3, P4): every
//! piece starts as one leaf per quarter arc (one leaf without an anchor); the leaf with
//! the lowest exact bound is split — its time interval or its arc, whichever loses more —
//! until the lowest bound is above the goal (proved), or the lowest leaf is finer than the
//! tolerance (its bound is then the relaxation's minimum, and it is not above the goal), or
//! the budget of programs is spent.
//!
//! Before a leaf is split its middle instant is solved alone (no time loss): that value,
//! plus the arc's loss, estimates from above the relaxation's value at that instant, so the
//! least such *probe* estimates the relaxation's minimum; the search also stops when the
//! lowest bound is within the tolerance of it. Without this, a plateau — an obstacle that
//! can touch the robot over an interval of instants — would be refined leaf by leaf to the
//! tolerance. The estimate only decides when to stop, never what is proved.
//!
//! A distance is never negative, so every leaf's bound is at least −(r_R + r_i + D).
//!
//! The bound returned is always the least exact bound over leaves that together cover
//! every piece: refinement replaces a leaf by two that cover it (halves of an interval, of
//! an arc), so it is a lower bound on s* at every stage.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::core::num::{Exact, f64_at_most};
use crate::core::planar::PlanarParams;
use crate::proof::planar::certificate::{LeafProof, ObstacleLeaves};
use crate::proof::planar::domain::{CoverPiece, DomainError, ObstacleDomain, PieceKind};
use crate::proof::planar::tiling::{self, Split};

use super::leaf_solve::{LeafBound, bound_leaf, strictly_empty};

/// How many of each obstacle's lowest leaves are kept for witnesses.
const LOW_LEAVES: usize = 6;

/// How far to refine.
#[derive(Clone, Debug)]
pub struct BoundOptions {
    /// At most this many programs per obstacle.
    pub budget: usize,
    /// A leaf whose time and arc losses are both below this (m) is not split.
    pub tolerance: Exact,
    /// At most this many steps to look for the horizon.
    pub step_limit: usize,
}

impl Default for BoundOptions {
    fn default() -> Self {
        BoundOptions {
            budget: 200_000,
            tolerance: Exact::from(1) / Exact::from(10_000_000),
            step_limit: 100_000,
        }
    }
}

/// The least leaf when the search stopped.
#[derive(Clone, Debug, PartialEq)]
pub struct WorstLeaf {
    /// The obstacle's index.
    pub obstacle: usize,
    /// Its piece.
    pub kind: PieceKind,
    /// The leaf's instants.
    pub from: Exact,
    /// The leaf's last instant.
    pub to: Exact,
    /// The solver's optimum there (float).
    pub value: f64,
    /// The solver's point there: distance, p, x, y, ... (empty: the solver failed there).
    pub point: Vec<f64>,
    /// The anchor's observed instant index j (None: the leaf has no anchor).
    pub anchor_instant: Option<usize>,
}

/// A proved lower bound on the planar s*.
#[derive(Clone, Debug, PartialEq)]
pub struct LowerBound {
    /// Every behaviour's separation is at least this (exact).
    pub lower: Exact,
    /// The least leaf (None: every leaf was empty, no obstacle can come near).
    pub worst: Option<WorstLeaf>,
    /// The lowest leaves, least first (at most a few per obstacle): where witnesses are
    /// looked for.
    pub low: Vec<WorstLeaf>,
    /// Programs solved.
    pub programs: usize,
    /// The budget ran out before the stop rule held.
    pub exhausted: bool,
    /// Leaves the solver could not bound, each given the floor −(r_R + r_i + D) instead
    /// and split further (sound; the bound is loose only if one of them stays lowest).
    pub unsolved: usize,
    /// Every obstacle's final leaves with their proofs, in the problem's order: what a
    /// planar certificate stores for `check`.
    pub proofs: Vec<ObstacleLeaves>,
}

/// Why no bound was proved.
#[derive(Clone, Debug, PartialEq)]
pub enum LowerBoundError {
    /// The problem has a setting the bound does not cover (or no finite horizon).
    Domain(DomainError),
}

impl std::fmt::Display for LowerBoundError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LowerBoundError::Domain(DomainError::Unsupported(key)) => {
                write!(
                    f,
                    "{key} is not analysed by the planar engine yet (issue 36)"
                )
            }
            LowerBoundError::Domain(DomainError::Unbounded) => write!(
                f,
                "the path has no end and an obstacle can keep up with the robot without a \
                 bounded region: no finite horizon (give the robot a path that ends, or the \
                 obstacle a region)"
            ),
        }
    }
}

struct Node {
    lower: Exact,
    value: f64,
    point: Vec<f64>,
    piece: usize,
    from: Exact,
    to: Exact,
    cover: CoverPiece,
    time_loss: Exact,
    arc_loss: Exact,
    /// The index of the piece's initial cover set it refines, and the halvings since.
    root: usize,
    splits: Vec<Split>,
    multipliers: Vec<f64>,
}

impl Node {
    fn proof(&self) -> LeafProof {
        LeafProof {
            piece: self.piece,
            cover: self.root,
            splits: tiling::write(&self.splits),
            empty: false,
            multipliers: self.multipliers.clone(),
            bound: Some(f64_at_most(&self.lower)),
        }
    }
}

/// An empty leaf's proof.
fn empty_proof(piece: usize, root: usize, splits: &[Split], multipliers: Vec<f64>) -> LeafProof {
    LeafProof {
        piece,
        cover: root,
        splits: tiling::write(splits),
        empty: true,
        multipliers,
        bound: None,
    }
}

impl PartialEq for Node {
    fn eq(&self, other: &Self) -> bool {
        self.lower == other.lower
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Node {
    /// Reversed, so that the max-heap pops the lowest bound.
    fn cmp(&self, other: &Self) -> Ordering {
        other.lower.cmp(&self.lower)
    }
}

/// The proved lower bound on the separation of every obstacle of `params`, refined until
/// it is above `goal` or cannot rise (see the module docs).
pub fn lower_bound(
    params: &PlanarParams,
    goal: &Exact,
    options: &BoundOptions,
) -> Result<LowerBound, LowerBoundError> {
    let mut total = LowerBound {
        lower: Exact::from(i64::MAX),
        worst: None,
        low: Vec::new(),
        programs: 0,
        exhausted: false,
        unsolved: 0,
        proofs: Vec::new(),
    };
    for i in 0..params.obstacles.len() {
        let one = obstacle_bound(params, i, goal, options)?;
        total.programs += one.programs;
        total.exhausted |= one.exhausted;
        total.unsolved += one.unsolved;
        total.low.extend(one.low.iter().cloned());
        total.proofs.extend(one.proofs);
        if one.lower < total.lower {
            total.lower = one.lower;
            total.worst = one.worst;
        }
    }
    Ok(total)
}

fn obstacle_bound(
    params: &PlanarParams,
    index: usize,
    goal: &Exact,
    options: &BoundOptions,
) -> Result<LowerBound, LowerBoundError> {
    let mut domain = ObstacleDomain::new(params, index, goal, options.step_limit)
        .map_err(LowerBoundError::Domain)?;
    let w = params.obstacles[index].max_speed.clone();
    let mut heap = BinaryHeap::new();
    let programs = std::cell::Cell::new(0usize);
    let unsolved = std::cell::Cell::new(0usize);
    // The least probe estimate: the relaxation's minimum is at most this.
    let mut above: Option<Exact> = None;
    let pieces = domain.pieces.clone();
    let floor = -domain.radii.clone();
    // Leaves proved empty: they stay part of the tiling a certificate states.
    let mut emptied: Vec<LeafProof> = Vec::new();
    let solve = |domain: &mut ObstacleDomain<'_>,
                 piece: usize,
                 (from, to, cover): (Exact, Exact, CoverPiece),
                 (root, splits): (usize, Vec<Split>),
                 heap: &mut BinaryHeap<Node>,
                 emptied: &mut Vec<LeafProof>| {
        programs.set(programs.get() + 1);
        let leaf = domain.leaf(&pieces[piece], &from, &to, &cover);
        let (lower, value, point, multipliers) = match bound_leaf(&leaf) {
            LeafBound::Empty(z) => {
                emptied.push(empty_proof(piece, root, &splits, z));
                return;
            }
            LeafBound::Lower {
                lower,
                value,
                point,
                multipliers,
            } => (lower, value, point, multipliers),
            LeafBound::Failed(_) => {
                unsolved.set(unsolved.get() + 1);
                (
                    floor.clone(),
                    floor.to_f64().value(),
                    Vec::new(),
                    Vec::new(),
                )
            }
        };
        // A distance is never negative: no separation is below −(r_R + r_i).
        let lower = if lower < floor { floor.clone() } else { lower };
        // Lemma P4's loss: the chord plus the obstacle's travel over the interval.
        let mut time_loss = domain.arc_length_gain(piece, &from, &to);
        time_loss += &w * &(&to - &from);
        let arc_loss = match (&cover, &pieces[piece].anchor) {
            (CoverPiece::Arc(arc), Some(a)) => {
                a.radius.as_ref().map_or(Exact::ZERO, |r| arc.loss(r))
            }
            _ => Exact::ZERO,
        };
        heap.push(Node {
            lower,
            value,
            point,
            piece,
            from,
            to,
            cover,
            time_loss,
            arc_loss,
            root,
            splits,
            multipliers,
        });
    };
    for (p, piece) in pieces.iter().enumerate() {
        for (root, cover) in domain.initial_covers(piece).into_iter().enumerate() {
            let cell = (piece.from.clone(), piece.to.clone(), cover);
            solve(
                &mut domain,
                p,
                cell,
                (root, Vec::new()),
                &mut heap,
                &mut emptied,
            );
        }
    }
    let mut exhausted = false;
    while let Some(node) = heap.peek() {
        if node.lower > *goal {
            break;
        }
        let (time_loss, arc_loss) = (node.time_loss.clone(), node.arc_loss.clone());
        let converged = time_loss <= options.tolerance && arc_loss <= options.tolerance;
        if converged
            || above
                .as_ref()
                .is_some_and(|a| &node.lower + &options.tolerance >= *a)
        {
            // About to stop on this leaf: drop it if only its closure is feasible.
            let leaf = domain.leaf(&pieces[node.piece], &node.from, &node.to, &node.cover);
            programs.set(programs.get() + 1);
            if let Some(z) = strictly_empty(&leaf) {
                let node = heap.pop().expect("peeked");
                emptied.push(empty_proof(node.piece, node.root, &node.splits, z));
                continue;
            }
        }
        if converged {
            break;
        }
        // The probe (module docs): the middle instant alone, an estimate from above.
        let middle = (&node.from + &node.to) / Exact::from(2);
        let probe = domain.leaf(&pieces[node.piece], &middle, &middle, &node.cover);
        programs.set(programs.get() + 1);
        if let LeafBound::Lower { lower, .. } = bound_leaf(&probe) {
            let lower = if lower < floor { floor.clone() } else { lower };
            let estimate = lower + &arc_loss;
            if above.as_ref().is_none_or(|a| estimate < *a) {
                above = Some(estimate);
            }
        }
        if above
            .as_ref()
            .is_some_and(|a| &node.lower + &options.tolerance >= *a)
        {
            break;
        }
        if programs.get() + 2 > options.budget {
            exhausted = true;
            break;
        }
        let node = heap.pop().expect("peeked");
        // The halves as the certificate's checker rebuilds them (`tiling::Cell::child`).
        let split: fn(u8) -> Split = if time_loss >= arc_loss {
            Split::Time
        } else {
            Split::Arc
        };
        let parent = tiling::Cell {
            from: node.from.clone(),
            to: node.to.clone(),
            cover: node.cover.clone(),
        };
        for half in [0, 1] {
            let cell = parent
                .child(split(half))
                .expect("only an arc has an arc loss");
            let mut splits = node.splits.clone();
            splits.push(split(half));
            let cell = (cell.from, cell.to, cell.cover);
            solve(
                &mut domain,
                node.piece,
                cell,
                (node.root, splits),
                &mut heap,
                &mut emptied,
            );
        }
    }
    let leaf = |node: &Node| WorstLeaf {
        obstacle: index,
        kind: pieces[node.piece].kind,
        from: node.from.clone(),
        to: node.to.clone(),
        value: node.value,
        point: node.point.clone(),
        anchor_instant: pieces[node.piece].anchor.as_ref().map(|a| a.instant),
    };
    let lower = heap
        .peek()
        .map_or(Exact::from(i64::MAX), |n| n.lower.clone());
    let obstacle_lower = heap.peek().map(|n| f64_at_most(&n.lower));
    let mut low = Vec::new();
    let mut leaves = emptied;
    while let Some(node) = heap.pop() {
        if low.len() < LOW_LEAVES {
            low.push(leaf(&node));
        }
        leaves.push(node.proof());
    }
    leaves.sort_by(|a, b| (a.piece, a.cover, &a.splits).cmp(&(b.piece, b.cover, &b.splits)));
    let proofs = vec![ObstacleLeaves {
        name: params.obstacles[index].name.clone(),
        lower_bound: obstacle_lower,
        leaves,
    }];
    Ok(LowerBound {
        lower,
        worst: low.first().cloned(),
        low,
        programs: programs.get(),
        exhausted,
        unsolved: unsolved.get(),
        proofs,
    })
}
