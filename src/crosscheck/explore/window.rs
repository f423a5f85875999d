//! The last few entries of a state's history, shared with every state along its path: a
//! persistent list, newest first, of which a state sees its first `len` entries. A step
//! pushes one entry in front of its parent's list, so a successor costs one node whatever
//! the latency (a state of latency 999 used to copy its 999 pending observations into
//! itself and again into its key: 60 KB a state).

use std::hash::{Hash, Hasher};
use std::sync::Arc;

/// One entry and the older ones.
#[derive(Debug)]
struct Node<T> {
    entry: T,
    older: Option<Arc<Node<T>>>,
}

/// The newest `len` entries of a shared history (cloning is a pointer copy).
#[derive(Debug)]
pub(super) struct Window<T> {
    newest: Option<Arc<Node<T>>>,
    len: usize,
}

impl<T> Clone for Window<T> {
    fn clone(&self) -> Self {
        Window {
            newest: self.newest.clone(),
            len: self.len,
        }
    }
}

impl<T> Window<T> {
    /// No entries.
    pub(super) fn empty() -> Self {
        Window {
            newest: None,
            len: 0,
        }
    }

    /// The window with `entry` pushed as the newest, keeping at most `cap` entries.
    pub(super) fn pushed(&self, entry: T, cap: usize) -> Self {
        Window {
            newest: Some(Arc::new(Node {
                entry,
                older: self.newest.clone(),
            })),
            len: (self.len + 1).min(cap),
        }
    }

    /// Number of entries.
    pub(super) fn len(&self) -> usize {
        self.len
    }

    /// The entries, newest first.
    pub(super) fn newest_first(&self) -> impl Iterator<Item = &T> {
        let mut node = self.newest.as_deref();
        (0..self.len).map_while(move |_| {
            let n = node?;
            node = n.older.as_deref();
            Some(&n.entry)
        })
    }

    /// The entries, oldest first.
    pub(super) fn oldest_first(&self) -> impl Iterator<Item = &T> {
        let mut all: Vec<&T> = self.newest_first().collect();
        all.reverse();
        all.into_iter()
    }

    /// The oldest entry.
    pub(super) fn oldest(&self) -> Option<&T> {
        self.newest_first().last()
    }

    /// Whether the two windows show the same entries by `same` (equal lengths), stopping
    /// early where they share the rest of their nodes.
    pub(super) fn same_by(&self, other: &Self, same: impl Fn(&T, &T) -> bool) -> bool {
        if self.len != other.len {
            return false;
        }
        let (mut a, mut b) = (self.newest.as_ref(), other.newest.as_ref());
        for _ in 0..self.len {
            match (a, b) {
                (Some(x), Some(y)) if Arc::ptr_eq(x, y) => return true,
                (Some(x), Some(y)) => {
                    if !same(&x.entry, &y.entry) {
                        return false;
                    }
                    (a, b) = (x.older.as_ref(), y.older.as_ref());
                }
                _ => return false,
            }
        }
        true
    }

    /// Hashes the length, then each entry by `hash_entry`, newest first.
    pub(super) fn hash_by<H: Hasher>(&self, state: &mut H, hash_entry: impl Fn(&T, &mut H)) {
        self.len.hash(state);
        for e in self.newest_first() {
            hash_entry(e, state);
        }
    }

    /// The nodes of this window that `other` does not share (what storing it costs beyond
    /// `other`).
    #[cfg(test)]
    pub(super) fn nodes_not_in(&self, other: &Self) -> usize {
        let theirs: Vec<*const Node<T>> = {
            let mut v = Vec::new();
            let mut n = other.newest.as_ref();
            while let Some(x) = n {
                v.push(Arc::as_ptr(x));
                n = x.older.as_ref();
            }
            v
        };
        let mut count = 0;
        let mut n = self.newest.as_ref();
        while let Some(x) = n {
            if theirs.contains(&Arc::as_ptr(x)) {
                break;
            }
            count += 1;
            n = x.older.as_ref();
        }
        count
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn window(entries: &[u32], cap: usize) -> Window<u32> {
        entries
            .iter()
            .fold(Window::empty(), |w, &e| w.pushed(e, cap))
    }

    #[test]
    fn a_window_holds_its_newest_entries_up_to_its_cap() {
        let w = window(&[1, 2, 3, 4, 5], 3);
        assert_eq!(w.len(), 3);
        assert_eq!(w.oldest_first().copied().collect::<Vec<_>>(), [3, 4, 5]);
        assert_eq!(w.newest_first().copied().collect::<Vec<_>>(), [5, 4, 3]);
        assert_eq!(w.oldest(), Some(&3));
        assert_eq!(Window::<u32>::empty().oldest(), None);
    }

    #[test]
    fn windows_compare_by_what_they_show_not_by_their_nodes() {
        let (a, b) = (window(&[9, 1, 2, 3], 3), window(&[7, 1, 2, 3], 3));
        assert!(a.same_by(&b, |x, y| x == y));
        assert!(!a.same_by(&window(&[1, 2, 4], 3), |x, y| x == y));
        assert!(!a.same_by(&window(&[2, 3], 3), |x, y| x == y));
        let parent = window(&[1, 2], 5);
        let child = parent.pushed(3, 5);
        assert!(
            child
                .pushed(4, 5)
                .same_by(&child.pushed(4, 5), |x, y| x == y)
        );
    }

    #[test]
    fn a_push_costs_one_node_whatever_the_cap() {
        for cap in [1, 3, 999] {
            let parent = window(&(0..2000).collect::<Vec<_>>(), cap);
            let child = parent.pushed(7, cap);
            assert_eq!(child.nodes_not_in(&parent), 1, "cap {cap}");
            assert_eq!(child.len(), cap);
        }
    }
}
