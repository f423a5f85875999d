//! Where a leaf sits in its piece: the splits that led to it from one of the piece's
//! initial cover sets, and the test that a certificate's leaves tile every piece.
//!
//! The refinement only ever halves a leaf's time interval or its arc (docs/reductions.md
//! Lemma P3), so a leaf is named by its root — the piece and the index of its initial cover
//! set — and its splits, `t0`/`t1` (first or second half of the interval) and `a0`/`a1`
//! (of the arc), written in order (`"t1a0t0"`; the root itself is `""`). The checker
//! rebuilds each leaf from that name exactly, and a set of names covers its root exactly
//! when, recursively, it is the root alone or both halves of one split, each covered.

use crate::core::num::Exact;

use super::domain::CoverPiece;

/// One halving.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Split {
    /// Half (0: first, 1: second) of the time interval.
    Time(u8),
    /// Half (0, 1: as [`Arc::halves`](super::cover::Arc::halves)) of the arc.
    Arc(u8),
}

/// A leaf's instants and cover set.
#[derive(Clone, Debug, PartialEq)]
pub struct Cell {
    /// The first instant.
    pub from: Exact,
    /// The last instant.
    pub to: Exact,
    /// The cover set.
    pub cover: CoverPiece,
}

impl Cell {
    /// The half `split` names, or None (an arc split of a cover set that is not an arc).
    pub fn child(&self, split: Split) -> Option<Cell> {
        match split {
            Split::Time(h) => {
                let mid = (&self.from + &self.to) / Exact::from(2);
                let (from, to) = if h == 0 {
                    (self.from.clone(), mid)
                } else {
                    (mid, self.to.clone())
                };
                Some(Cell {
                    from,
                    to,
                    cover: self.cover.clone(),
                })
            }
            Split::Arc(h) => match &self.cover {
                CoverPiece::Arc(arc) => {
                    let [a, b] = arc.halves();
                    Some(Cell {
                        from: self.from.clone(),
                        to: self.to.clone(),
                        cover: CoverPiece::Arc(if h == 0 { a } else { b }),
                    })
                }
                _ => None,
            },
        }
    }

    /// The cell `splits` lead to from this one, or None.
    pub fn descend(&self, splits: &[Split]) -> Option<Cell> {
        splits
            .iter()
            .try_fold(self.clone(), |cell, s| cell.child(*s))
    }
}

/// `splits` as text.
pub fn write(splits: &[Split]) -> String {
    splits
        .iter()
        .map(|s| match s {
            Split::Time(h) => format!("t{h}"),
            Split::Arc(h) => format!("a{h}"),
        })
        .collect()
}

/// The splits `text` names, or None.
pub fn read(text: &str) -> Option<Vec<Split>> {
    let bytes = text.as_bytes();
    if !bytes.len().is_multiple_of(2) {
        return None;
    }
    bytes
        .chunks(2)
        .map(|c| {
            let half = match c[1] {
                b'0' => 0,
                b'1' => 1,
                _ => return None,
            };
            match c[0] {
                b't' => Some(Split::Time(half)),
                b'a' => Some(Split::Arc(half)),
                _ => None,
            }
        })
        .collect()
}

/// Whether the leaves named by `names` cover their root exactly once (see the module docs):
/// Err names what is missing or doubled.
pub fn tiles(names: &[&[Split]]) -> Result<(), String> {
    match names {
        [] => return Err("a part of it has no leaf".into()),
        [[]] => return Ok(()),
        _ => {}
    }
    if names.iter().any(|n| n.is_empty()) {
        return Err("a leaf overlaps another".into());
    }
    let first = names[0][0];
    let kind = |s: Split| matches!(s, Split::Time(_));
    if names.iter().any(|n| kind(n[0]) != kind(first)) {
        return Err("its leaves split it two ways at once".into());
    }
    for half in [0u8, 1] {
        let side: Vec<&[Split]> = names
            .iter()
            .filter(|n| match n[0] {
                Split::Time(h) | Split::Arc(h) => h == half,
            })
            .map(|n| &n[1..])
            .collect();
        tiles(&side).map_err(|e| {
            let s = match first {
                Split::Time(_) => Split::Time(half),
                Split::Arc(_) => Split::Arc(half),
            };
            format!("{} {e}", write(&[s]))
        })?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::proof::planar::cover::Arc;

    fn names(texts: &[&str]) -> Vec<Vec<Split>> {
        texts.iter().map(|t| read(t).expect("names")).collect()
    }

    fn check(texts: &[&str]) -> Result<(), String> {
        let n = names(texts);
        let refs: Vec<&[Split]> = n.iter().map(|v| v.as_slice()).collect();
        tiles(&refs)
    }

    #[test]
    fn complete_split_trees_tile_and_gaps_overlaps_and_mixed_splits_do_not() {
        assert_eq!(check(&[""]), Ok(()));
        assert_eq!(check(&["t0", "t1a0", "t1a1t0", "t1a1t1"]), Ok(()));
        assert!(check(&["t0", "t1a0"]).is_err(), "t1a1 is missing");
        assert!(check(&["t0", "t1", "t1a0"]).is_err(), "t1 doubled");
        assert!(check(&["t0", "a1"]).is_err(), "two splits at once");
        assert!(check(&[]).is_err());
        assert!(check(&["", "t0"]).is_err());
        assert_eq!(read("t2"), None);
        assert_eq!(read("t"), None);
        assert_eq!(write(&read("t0a1").unwrap()), "t0a1");
    }

    #[test]
    fn descending_halves_the_interval_and_the_arc_as_the_refinement_does() {
        let arc = Arc::quarters().remove(0);
        let root = Cell {
            from: Exact::ZERO,
            to: Exact::ONE,
            cover: CoverPiece::Arc(arc.clone()),
        };
        let cell = root.descend(&read("t1a0").unwrap()).expect("a cell");
        assert_eq!(cell.from, Exact::from(1) / Exact::from(2));
        assert_eq!(cell.to, Exact::ONE);
        assert_eq!(cell.cover, CoverPiece::Arc(arc.halves()[0].clone()));
        let whole = Cell {
            cover: CoverPiece::Whole,
            ..root
        };
        assert_eq!(whole.descend(&[Split::Arc(0)]), None);
    }
}
