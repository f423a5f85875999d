//! Branch and bound over one problem's leaves (docs/reductions.md Lemmas P3, P4): every
//! piece starts as one leaf per quarter arc (one leaf without an anchor); the leaf with
//! the lowest exact bound is split — its time interval or its arc, whichever loses more —
//! until the lowest bound is above the goal (proved), or the lowest leaf is finer than the
//! tolerance (its bound is then the relaxation's minimum, and it is not above the goal), or
//! the budget of programs is spent.
//!
//! The bound returned is always the least exact bound over leaves that together cover
//! every piece: refinement replaces a leaf by two that cover it (halves of an interval, of
//! an arc), so it is a lower bound on s* at every stage.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::core::num::Exact;
use crate::core::planar::PlanarParams;
use crate::proof::planar::cover::Arc;
use crate::proof::planar::domain::{DomainError, ObstacleDomain, PieceKind};

use super::leaf_solve::{LeafBound, bound_leaf};

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
    /// The solver's point there: distance, p, x, y, ...
    pub point: Vec<f64>,
}

/// A proved lower bound on the planar s*.
#[derive(Clone, Debug, PartialEq)]
pub struct LowerBound {
    /// Every behaviour's separation is at least this (exact).
    pub lower: Exact,
    /// The least leaf (None: every leaf was empty, no obstacle can come near).
    pub worst: Option<WorstLeaf>,
    /// Programs solved.
    pub programs: usize,
    /// The budget ran out before the stop rule held.
    pub exhausted: bool,
}

/// Why no bound was proved.
#[derive(Clone, Debug, PartialEq)]
pub enum LowerBoundError {
    /// The problem has a setting the bound does not cover (or no finite horizon).
    Domain(DomainError),
    /// A program the bound needs was not solved (its status, and which leaf).
    Solver(String),
}

struct Node {
    lower: Exact,
    value: f64,
    point: Vec<f64>,
    piece: usize,
    from: Exact,
    to: Exact,
    arc: Option<Arc>,
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
        programs: 0,
        exhausted: false,
    };
    for i in 0..params.obstacles.len() {
        let one = obstacle_bound(params, i, goal, options)?;
        total.programs += one.programs;
        total.exhausted |= one.exhausted;
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
    let pieces = domain.pieces.clone();
    let solve = |domain: &mut ObstacleDomain<'_>,
                 piece: usize,
                 from: Exact,
                 to: Exact,
                 arc: Option<Arc>,
                 heap: &mut BinaryHeap<Node>|
     -> Result<(), LowerBoundError> {
        programs.set(programs.get() + 1);
        let leaf = domain.leaf(&pieces[piece], &from, &to, arc.as_ref());
        match bound_leaf(&leaf) {
            LeafBound::Empty => Ok(()),
            LeafBound::Lower {
                lower,
                value,
                point,
            } => {
                heap.push(Node {
                    lower,
                    value,
                    point,
                    piece,
                    from,
                    to,
                    arc,
                });
                Ok(())
            }
            LeafBound::Failed(status) => Err(LowerBoundError::Solver(format!(
                "obstacle {index}, {:?}, instants [{}, {}]: {status}",
                pieces[piece].kind,
                from.to_f64().value(),
                to.to_f64().value()
            ))),
        }
    };
    for (p, piece) in pieces.iter().enumerate() {
        let arcs: Vec<Option<Arc>> = match piece.anchor {
            Some(_) => Arc::quarters().into_iter().map(Some).collect(),
            None => vec![None],
        };
        for arc in arcs {
            solve(
                &mut domain,
                p,
                piece.from.clone(),
                piece.to.clone(),
                arc,
                &mut heap,
            )?;
        }
    }
    let mut exhausted = false;
    while let Some(node) = heap.peek() {
        if node.lower > *goal {
            break;
        }
        let piece = &pieces[node.piece];
        let time_loss = {
            let mut d = domain_chord(&mut domain, node.piece, &node.from, &node.to);
            d += &w * &(&node.to - &node.from);
            d
        };
        let arc_loss = match (&node.arc, &piece.anchor) {
            (Some(arc), Some(a)) => arc.loss(&a.radius),
            _ => Exact::ZERO,
        };
        if time_loss <= options.tolerance && arc_loss <= options.tolerance {
            break;
        }
        if programs.get() + 2 > options.budget {
            exhausted = true;
            break;
        }
        let node = heap.pop().expect("peeked");
        if time_loss >= arc_loss {
            let mid = (&node.from + &node.to) / Exact::from(2);
            solve(
                &mut domain,
                node.piece,
                node.from.clone(),
                mid.clone(),
                node.arc.clone(),
                &mut heap,
            )?;
            solve(
                &mut domain,
                node.piece,
                mid,
                node.to.clone(),
                node.arc.clone(),
                &mut heap,
            )?;
        } else {
            let [a, b] = node
                .arc
                .as_ref()
                .expect("an arc loss needs an arc")
                .halves();
            solve(
                &mut domain,
                node.piece,
                node.from.clone(),
                node.to.clone(),
                Some(a),
                &mut heap,
            )?;
            solve(
                &mut domain,
                node.piece,
                node.from.clone(),
                node.to.clone(),
                Some(b),
                &mut heap,
            )?;
        }
    }
    Ok(match heap.peek() {
        Some(node) => LowerBound {
            lower: node.lower.clone(),
            worst: Some(WorstLeaf {
                obstacle: index,
                kind: pieces[node.piece].kind,
                from: node.from.clone(),
                to: node.to.clone(),
                value: node.value,
                point: node.point.clone(),
            }),
            programs: programs.get(),
            exhausted,
        },
        None => LowerBound {
            lower: Exact::from(i64::MAX),
            worst: None,
            programs: programs.get(),
            exhausted,
        },
    })
}

/// s(t₂) − s(t₁) on a piece: the chord loss of Lemma P4.
fn domain_chord(domain: &mut ObstacleDomain<'_>, piece: usize, from: &Exact, to: &Exact) -> Exact {
    domain.arc_length_gain(piece, from, to)
}
