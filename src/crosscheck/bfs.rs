//! One breadth-first search for both engines of this layer: the explorer's finite model
//! ([`crate::crosscheck::explore`]) and the interpreter of the exported UPPAAL network
//! ([`crate::crosscheck::uppaal`]). Both ask what is reachable and by which shortest path, and
//! both back verdicts, so the search keeps every stored state's key *in full* in a hash map
//! (keys are compared, never only their 64-bit hashes) and a parent link per stored state,
//! from which the shortest path to it is read back.
//!
//! The engines differ only in what they watch while the search runs — the explorer watches
//! transitions, the interpreter watches states — so the search hands each dequeued state to
//! the engine's `expand` closure, which computes its successors in a fixed order, watches
//! whatever it needs, and offers each successor with [`Successors::offer`]. A successor is
//! stored only if its key is new and the state budget allows; once the budget is reached the
//! offer answers [`ControlFlow::Break`], the engine stops offering, and the search ends
//! incomplete. The order is first in, first out, so every state is first reached along a path
//! with the fewest transitions, and the search is deterministic: the same graph gives the
//! same states in the same order, whatever the hasher.

use std::collections::VecDeque;
use std::collections::hash_map::Entry;
use std::hash::Hash;
use std::ops::ControlFlow;

use rustc_hash::FxHashMap;

/// The id of a stored state: its position in storage order (the init states first).
pub(crate) type NodeId = u32;

/// Most states one search can store (ids are 32-bit); larger budgets are capped to it.
pub(crate) const MAX_NODES: usize = NodeId::MAX as usize;

/// The search's tables: the visited keys, the parent links and the queue.
struct Store<S, K, A> {
    /// Every stored state's key, with its id.
    visited: FxHashMap<K, NodeId>,
    /// For each stored state that is not an init state (id − `roots`): its parent and the
    /// action that first reached it.
    parents: Vec<(NodeId, A)>,
    /// Stored states still to expand, oldest first.
    queue: VecDeque<(NodeId, S)>,
    /// Number of init states (ids 0..roots).
    roots: usize,
    /// The state budget.
    limit: usize,
    /// The budget was reached: a new state was refused.
    full: bool,
}

/// Where the engine's `expand` closure hands the successors of the state being expanded.
pub(crate) struct Successors<'a, S, K, A> {
    store: &'a mut Store<S, K, A>,
    parent: NodeId,
}

impl<S, K: Hash + Eq, A> Successors<'_, S, K, A> {
    /// Offers the successor with key `key`, reached by `action`: if the key is new it is
    /// stored and the state `make(&key)` is queued for expansion. [`ControlFlow::Break`] when
    /// the budget is reached (the successor is then not stored): offer nothing more.
    pub(crate) fn offer(
        &mut self,
        action: A,
        key: K,
        make: impl FnOnce(&K) -> S,
    ) -> ControlFlow<()> {
        self.store(action, key, Some(make))
    }

    /// As [`Successors::offer`] for a state with no successors: only its key is stored.
    pub(crate) fn offer_leaf(&mut self, action: A, key: K) -> ControlFlow<()> {
        self.store(action, key, None::<fn(&K) -> S>)
    }

    fn store(&mut self, action: A, key: K, make: Option<impl FnOnce(&K) -> S>) -> ControlFlow<()> {
        let store = &mut *self.store;
        if store.full {
            return ControlFlow::Break(());
        }
        let id = store.visited.len();
        let Entry::Vacant(slot) = store.visited.entry(key) else {
            return ControlFlow::Continue(());
        };
        if id >= store.limit {
            store.full = true;
            return ControlFlow::Break(());
        }
        let id = id as NodeId;
        if let Some(make) = make {
            store.queue.push_back((id, make(slot.key())));
        }
        slot.insert(id);
        store.parents.push((self.parent, action));
        ControlFlow::Continue(())
    }
}

/// What a search reached.
pub(crate) struct Reached<A> {
    /// Every reachable state was stored (false: the budget was reached).
    pub(crate) complete: bool,
    /// Distinct states stored (init states included).
    pub(crate) states: usize,
    roots: usize,
    parents: Vec<(NodeId, A)>,
}

impl<A: Copy> Reached<A> {
    /// The actions of the path by which `node` was first reached (a shortest one), with
    /// the id of the init state it starts from (init states are numbered in the order
    /// given, repeated keys left out).
    pub(crate) fn rooted_path_to(&self, node: NodeId) -> (NodeId, Vec<A>) {
        let mut actions = Vec::new();
        let mut id = node as usize;
        while id >= self.roots {
            let (parent, action) = self.parents[id - self.roots];
            actions.push(action);
            id = parent as usize;
        }
        actions.reverse();
        (id as NodeId, actions)
    }
}

/// Searches breadth first from the init states (`(key, state)` pairs; repeated keys are
/// stored once, and init states are stored whatever the budget), storing at most `limit`
/// states (capped at [`MAX_NODES`]). `expand(id, state, successors)` is called once for
/// every stored state that was queued, in the order they were stored; an error from it ends
/// the search.
pub(crate) fn search<S, K: Hash + Eq, A, E>(
    init: impl IntoIterator<Item = (K, S)>,
    limit: usize,
    mut expand: impl FnMut(NodeId, &S, &mut Successors<'_, S, K, A>) -> Result<(), E>,
) -> Result<Reached<A>, E> {
    let mut store = Store {
        visited: FxHashMap::default(),
        parents: Vec::new(),
        queue: VecDeque::new(),
        roots: 0,
        limit: limit.min(MAX_NODES),
        full: false,
    };
    for (key, state) in init {
        let id = store.visited.len() as NodeId;
        if let Entry::Vacant(slot) = store.visited.entry(key) {
            slot.insert(id);
            store.queue.push_back((id, state));
        }
    }
    store.roots = store.visited.len();
    while let Some((id, state)) = store.queue.pop_front() {
        let mut successors = Successors {
            store: &mut store,
            parent: id,
        };
        expand(id, &state, &mut successors)?;
        if store.full {
            break;
        }
    }
    Ok(Reached {
        complete: !store.full,
        states: store.visited.len(),
        roots: store.roots,
        parents: store.parents,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The numbers 1..=n, each stepping to its double and its successor.
    fn numbers(n: u32, limit: usize) -> (Reached<char>, Vec<u32>) {
        let mut order = Vec::new();
        let reached = search([(1u32, 1u32)], limit, |_, &x, next| {
            order.push(x);
            for (action, y) in [('d', 2 * x), ('s', x + 1)] {
                if y <= n && next.offer(action, y, |&y| y).is_break() {
                    break;
                }
            }
            Ok::<(), ()>(())
        })
        .unwrap();
        (reached, order)
    }

    #[test]
    fn states_are_expanded_once_in_breadth_first_order() {
        let (reached, order) = numbers(10, usize::MAX);
        assert!(reached.complete);
        assert_eq!(reached.states, 10);
        assert_eq!(order, [1, 2, 4, 3, 8, 5, 6, 9, 10, 7]);
    }

    #[test]
    fn paths_are_shortest_and_read_back_from_the_parents() {
        let (reached, order) = numbers(10, usize::MAX);
        let id = |x: u32| order.iter().position(|&y| y == x).unwrap() as NodeId;
        assert_eq!(reached.rooted_path_to(id(1)).1, Vec::<char>::new());
        assert_eq!(reached.rooted_path_to(id(10)).1, ['d', 'd', 's', 'd']);
        assert_eq!(reached.rooted_path_to(id(7)).1, ['d', 's', 'd', 's']);
    }

    #[test]
    fn the_budget_stops_the_search_incomplete() {
        let (reached, order) = numbers(10, 4);
        assert!(!reached.complete);
        assert_eq!(reached.states, 4);
        assert_eq!(order, [1, 2, 4]);
    }

    #[test]
    fn leaves_are_stored_but_not_expanded() {
        let mut expanded = 0;
        let reached = search([(0u8, ())], 10, |_, _, next| {
            expanded += 1;
            let _ = next.offer_leaf((), 1);
            let _ = next.offer_leaf((), 1);
            Ok::<(), ()>(())
        })
        .unwrap();
        assert_eq!((reached.states, expanded), (2, 1));
    }
}
