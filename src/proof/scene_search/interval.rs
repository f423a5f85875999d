//! Intervals of exact rationals whose ends may be open, closed or infinite: the reachable
//! positions of one obstacle, and the cells of its observed gap that a guard tells apart.

use crate::core::num::Scalar;
use crate::core::rational::Rational;

/// One finite end of an interval.
#[derive(Clone, Debug, PartialEq)]
pub struct End {
    /// Where the interval ends.
    pub at: Rational,
    /// Whether `at` belongs to the interval.
    pub closed: bool,
}

impl End {
    /// A closed end at `at`.
    pub fn closed(at: Rational) -> End {
        End { at, closed: true }
    }

    /// An open end at `at`.
    pub fn open(at: Rational) -> End {
        End { at, closed: false }
    }
}

/// A (possibly empty) interval; `None` ends are infinite.
#[derive(Clone, Debug, PartialEq)]
pub struct Interval {
    /// Lower end (None: −∞).
    pub lo: Option<End>,
    /// Upper end (None: +∞).
    pub hi: Option<End>,
}

impl Interval {
    /// The whole line.
    pub fn all() -> Interval {
        Interval { lo: None, hi: None }
    }

    /// [a, b].
    pub fn closed(a: Rational, b: Rational) -> Interval {
        Interval {
            lo: Some(End::closed(a)),
            hi: Some(End::closed(b)),
        }
    }

    /// The single point a.
    pub fn point(a: Rational) -> Interval {
        Interval::closed(a.clone(), a)
    }

    /// Whether no number lies in it.
    pub fn is_empty(&self) -> bool {
        match (&self.lo, &self.hi) {
            (Some(l), Some(h)) => l.at > h.at || (l.at == h.at && !(l.closed && h.closed)),
            _ => false,
        }
    }

    /// The numbers in both.
    pub fn intersect(&self, other: &Interval) -> Interval {
        Interval {
            lo: tighter(&self.lo, &other.lo, true),
            hi: tighter(&self.hi, &other.hi, false),
        }
    }

    /// {x + y : x ∈ self, y ∈ other}: a sum of independent choices.
    pub fn plus(&self, other: &Interval) -> Interval {
        Interval {
            lo: sum_end(&self.lo, &other.lo),
            hi: sum_end(&self.hi, &other.hi),
        }
    }

    /// {x − y : x ∈ self, y ∈ other}.
    pub fn minus(&self, other: &Interval) -> Interval {
        self.plus(&other.negated())
    }

    /// {−x : x ∈ self}.
    pub fn negated(&self) -> Interval {
        let flip = |e: &Option<End>| {
            e.as_ref().map(|e| End {
                at: -e.at.clone(),
                closed: e.closed,
            })
        };
        Interval {
            lo: flip(&self.hi),
            hi: flip(&self.lo),
        }
    }

    /// {c·x : x ∈ self} for c ≥ 0 (c = 0 gives the point 0 for a nonempty interval).
    pub fn scaled(&self, c: &Rational) -> Interval {
        if *c == Rational::zero() {
            return Interval::point(Rational::zero());
        }
        let times = |e: &Option<End>| {
            e.as_ref().map(|e| End {
                at: e.at.clone() * c.clone(),
                closed: e.closed,
            })
        };
        Interval {
            lo: times(&self.lo),
            hi: times(&self.hi),
        }
    }

    /// {x + c : x ∈ self}.
    pub fn shifted(&self, c: &Rational) -> Interval {
        self.plus(&Interval::point(c.clone()))
    }

    /// Whether `x` lies in it.
    pub fn contains(&self, x: &Rational) -> bool {
        let above = self
            .lo
            .as_ref()
            .is_none_or(|l| *x > l.at || (l.closed && *x == l.at));
        let below = self
            .hi
            .as_ref()
            .is_none_or(|h| *x < h.at || (h.closed && *x == h.at));
        above && below
    }

    /// Whether every number of `self` is in `outer` (an empty interval is in every one).
    pub fn within(&self, outer: &Interval) -> bool {
        if self.is_empty() {
            return true;
        }
        let lo_ok = match (&outer.lo, &self.lo) {
            (None, _) => true,
            (Some(_), None) => false,
            (Some(o), Some(m)) => m.at > o.at || (m.at == o.at && (o.closed || !m.closed)),
        };
        let hi_ok = match (&outer.hi, &self.hi) {
            (None, _) => true,
            (Some(_), None) => false,
            (Some(o), Some(m)) => m.at < o.at || (m.at == o.at && (o.closed || !m.closed)),
        };
        lo_ok && hi_ok
    }

    /// A number inside, away from open ends when it can be: the midpoint of finite ends,
    /// else one unit inside the finite end, else 0. None when empty.
    pub fn inner_point(&self) -> Option<Rational> {
        if self.is_empty() {
            return None;
        }
        Some(match (&self.lo, &self.hi) {
            (Some(l), Some(h)) => (l.at.clone() + h.at.clone()) / Rational::int(2),
            (Some(l), None) => l.at.clone() + Rational::int(1),
            (None, Some(h)) => h.at.clone() - Rational::int(1),
            (None, None) => Rational::zero(),
        })
    }

    /// A number inside, as close to the lower end as `slack` allows: the lower end when it
    /// is closed, else the lower end plus the least of `slack` and half the width.
    pub fn near_lower(&self, slack: &Rational) -> Option<Rational> {
        if self.is_empty() {
            return None;
        }
        let Some(l) = &self.lo else {
            return self.inner_point();
        };
        if l.closed {
            return Some(l.at.clone());
        }
        let step = match &self.hi {
            Some(h) => {
                let half = (h.at.clone() - l.at.clone()) / Rational::int(2);
                if half < *slack { half } else { slack.clone() }
            }
            None => slack.clone(),
        };
        Some(l.at.clone() + step)
    }

    /// A number inside, as close to the upper end as `slack` allows.
    pub fn near_upper(&self, slack: &Rational) -> Option<Rational> {
        self.negated().near_lower(slack).map(|x| -x)
    }
}

/// The tighter of two ends on the same side (`lower`: the larger lower end).
fn tighter(a: &Option<End>, b: &Option<End>, lower: bool) -> Option<End> {
    match (a, b) {
        (None, e) | (e, None) => e.clone(),
        (Some(x), Some(y)) => {
            if x.at == y.at {
                Some(End {
                    at: x.at.clone(),
                    closed: x.closed && y.closed,
                })
            } else if (x.at > y.at) == lower {
                Some(x.clone())
            } else {
                Some(y.clone())
            }
        }
    }
}

/// The end of a Minkowski sum: infinite if either is, closed iff both are.
fn sum_end(a: &Option<End>, b: &Option<End>) -> Option<End> {
    match (a, b) {
        (Some(x), Some(y)) => Some(End {
            at: x.at.clone() + y.at.clone(),
            closed: x.closed && y.closed,
        }),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(n: i64, d: i64) -> Rational {
        Rational::int(n) / Rational::int(d)
    }

    /// Open ends make touching intervals disjoint and sums open; a point survives only
    /// between closed ends.
    #[test]
    fn ends_decide_emptiness_and_sums() {
        let a = Interval {
            lo: Some(End::closed(r(0, 1))),
            hi: Some(End::open(r(1, 1))),
        };
        let b = Interval::closed(r(1, 1), r(2, 1));
        assert!(a.intersect(&b).is_empty());
        assert!(!Interval::point(r(1, 1)).intersect(&b).is_empty());
        let s = a.plus(&b);
        assert_eq!(s.lo, Some(End::closed(r(1, 1))));
        assert_eq!(s.hi, Some(End::open(r(3, 1))));
        assert!(s.contains(&r(29, 10)) && !s.contains(&r(3, 1)));
        assert_eq!(a.minus(&b).lo, Some(End::closed(r(-2, 1))));
        assert_eq!(a.minus(&b).hi, Some(End::open(r(0, 1))));
    }

    /// Points chosen near an end stay inside the interval.
    #[test]
    fn chosen_points_lie_inside() {
        let a = Interval {
            lo: Some(End::open(r(0, 1))),
            hi: Some(End::closed(r(1, 1000))),
        };
        let p = a.near_lower(&r(1, 1)).unwrap();
        assert!(a.contains(&p) && p == r(1, 2000));
        let q = a.near_upper(&r(1, 10_000_000)).unwrap();
        assert_eq!(q, r(1, 1000));
        assert!(a.contains(&a.inner_point().unwrap()));
    }
}
