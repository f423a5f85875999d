//! One obstacle's constraints along a run, and what they leave of its position.
//!
//! Obstacle i is at X(n) at the start of step n, with X(0) in its start interval and
//! X(n+1) = X(n) − w_n·dt, w_n ∈ [0, W_i]. A run constrains X(n) (what the robot saw, L
//! steps later) and w_{n−1} (the speed it saw with it). Each constraint is an interval and
//! the steps are independent choices, so the positions still possible at a step, given
//! every constraint, form an interval: forward, the constraints up to the step; backward,
//! the steps after it must stay reachable. Both passes are exact.
//!
//! Chains are persistent (shared tails), so a search tree's children share their parents'
//! constraints.

use std::rc::Rc;

use crate::core::num::Scalar;
use crate::core::rational::Rational;

use super::interval::Interval;

/// One constrained step.
#[derive(Debug)]
struct Link {
    step: usize,
    /// Constraint on X(step).
    position: Interval,
    /// Constraint on w_{step−1} (already within [0, W]).
    speed: Interval,
    /// X(step) given every constraint at steps ≤ step.
    reach: Interval,
    prev: Option<Rc<Link>>,
}

/// A constraint added at a query, outside the chain.
#[derive(Clone, Debug)]
pub struct Extra {
    /// The step.
    pub step: usize,
    /// Constraint on X(step).
    pub position: Interval,
}

/// One obstacle's constraints so far.
#[derive(Clone, Debug)]
pub struct Chain {
    head: Rc<Link>,
    motion: Rc<Motion>,
}

/// How an obstacle may move, shared by every chain of it (a search clones chains per
/// child, so they hold it by reference).
#[derive(Debug)]
struct Motion {
    w_max: Rational,
    dt: Rational,
    /// W_i·dt: the most X falls in one step (kept: every pass needs it).
    fall: Rational,
}

/// A point of a pass: a step with its constraints.
#[derive(Clone, Debug)]
struct Point {
    step: usize,
    position: Interval,
    speed: Interval,
}

impl Chain {
    /// No constraint yet: X(0) ∈ `start`, speeds in [0, `w_max`].
    pub fn new(start: Interval, w_max: Rational, dt: Rational) -> Chain {
        Chain {
            head: Rc::new(Link {
                step: 0,
                position: start.clone(),
                speed: Interval::all(),
                reach: start,
                prev: None,
            }),
            motion: Rc::new(Motion {
                fall: w_max.clone() * dt.clone(),
                w_max,
                dt,
            }),
        }
    }

    /// Which chain this is: the address of its newest row, shared by the clones of one
    /// chain and by no other chain while it lives.
    pub fn identity(&self) -> usize {
        Rc::as_ptr(&self.head) as usize
    }

    /// Whether two chains of the same obstacle put the same constraints on it, row by row.
    pub fn same_constraints(&self, other: &Chain) -> bool {
        let (mut a, mut b) = (Some(&self.head), Some(&other.head));
        loop {
            match (a, b) {
                (None, None) => return true,
                (Some(x), Some(y)) => {
                    if Rc::ptr_eq(x, y) {
                        return true;
                    }
                    if x.step != y.step || x.position != y.position || x.speed != y.speed {
                        return false;
                    }
                    a = x.prev.as_ref();
                    b = y.prev.as_ref();
                }
                _ => return false,
            }
        }
    }

    /// A cheap necessary condition for [`Self::implies`]: what each leaves of the position
    /// after both their rows is a marginal, so it must nest if the chains do.
    pub fn may_imply(&self, other: &Chain) -> bool {
        if Rc::ptr_eq(&self.head, &other.head) {
            return true;
        }
        if self.head.step == other.head.step {
            // The common case, without the drift's arithmetic.
            return self.head.reach.within(&other.head.reach);
        }
        let last = self.last_step().max(other.last_step());
        self.reach_at(last).within(&other.reach_at(last))
    }

    /// Whether every behaviour that meets `self` meets `other` too (chains of the same
    /// obstacle): at each of `other`'s rows, what `self` leaves of the position is inside
    /// the row's interval and the speed `self` sees there (if any) inside the row's.
    /// Exact for positions (`self`'s marginals are exact); for speeds it asks `self` to
    /// state the row, so it can answer false where the sets are nested after all.
    pub fn implies(&self, other: &Chain) -> bool {
        if self.same_constraints(other) {
            return true;
        }
        if !self.may_imply(other) {
            return false;
        }
        let rows: Vec<&Rc<Link>> =
            std::iter::successors(Some(&other.head), |l| l.prev.as_ref()).collect();
        let steps: Vec<usize> = rows.iter().map(|l| l.step).collect();
        let points = self.points(&[], &steps);
        let (forward, backward) = self.passes(&points);
        let speeds = self.speeds();
        rows.iter().all(|row| {
            let j = points
                .binary_search_by_key(&row.step, |p| p.step)
                .expect("every row's step is a point");
            let x = forward[j].intersect(&backward[j]);
            let row_speed = row.speed.intersect(&speeds);
            let speed_ok = row_speed == speeds
                || row.step == 0
                || points[j].speed.intersect(&speeds).within(&row_speed);
            x.within(&row.position) && speed_ok
        })
    }

    /// W_i.
    pub fn w_max(&self) -> &Rational {
        &self.motion.w_max
    }

    /// Speeds the obstacle may hold.
    fn speeds(&self) -> Interval {
        Interval::closed(Rational::zero(), self.motion.w_max.clone())
    }

    /// How far X may fall over `steps` unconstrained steps: [0, W_i·dt·steps].
    fn drift(&self, steps: usize) -> Interval {
        match steps {
            0 => Interval::point(Rational::zero()),
            1 => Interval::closed(Rational::zero(), self.motion.fall.clone()),
            _ => Interval::closed(
                Rational::zero(),
                self.motion.fall.clone() * Rational::int(steps as i64),
            ),
        }
    }

    /// The last constrained step.
    pub fn last_step(&self) -> usize {
        self.head.step
    }

    /// X(n) given every constraint so far, for n at or after the last constrained step.
    pub fn reach_at(&self, n: usize) -> Interval {
        let h = &self.head;
        debug_assert!(n >= h.step);
        h.reach.minus(&self.drift(n - h.step))
    }

    /// The chain with X(n) ∈ `position` and w_{n−1} ∈ `speed` added (n at or after the last
    /// constrained step); None when nothing is left.
    pub fn constrain(&self, n: usize, position: &Interval, speed: &Interval) -> Option<Chain> {
        let speed = speed.intersect(&self.speeds());
        let trivial_speed = speed == self.speeds();
        if position == &Interval::all() && trivial_speed {
            return (!self.reach_at(n).is_empty()).then(|| self.clone());
        }
        let (base, position, speed) = if n == self.head.step {
            match &self.head.prev {
                Some(prev) => (
                    Some(prev.clone()),
                    position.intersect(&self.head.position),
                    speed.intersect(&self.head.speed),
                ),
                // Step 0: nothing before it, and no speed is seen with X(0).
                None => (
                    None,
                    position.intersect(&self.head.position),
                    Interval::all(),
                ),
            }
        } else {
            (Some(self.head.clone()), position.clone(), speed)
        };
        let reach = match &base {
            Some(b) => b
                .reach
                .minus(&self.drift(n - 1 - b.step))
                .minus(&speed.scaled(&self.motion.dt))
                .intersect(&position),
            None => position.clone(),
        };
        if reach.is_empty() {
            return None;
        }
        // A lower bound on X(n) implies every earlier, weaker lower bound (X never grows):
        // drop an implied predecessor so chains of "still far" rows stay short.
        let base = match base {
            Some(b) if implied_by(&b, n, &position, &self.speeds()) => b.prev.clone(),
            b => b,
        };
        Some(Chain {
            head: Rc::new(Link {
                step: n,
                position,
                speed,
                reach,
                prev: base,
            }),
            motion: self.motion.clone(),
        })
    }

    /// The chain's points, oldest first, with `extra` constraints merged in and a point at
    /// every step of `queries`.
    fn points(&self, extra: &[Extra], queries: &[usize]) -> Vec<Point> {
        let mut points = Vec::new();
        let mut link = Some(&self.head);
        while let Some(l) = link {
            points.push(Point {
                step: l.step,
                position: l.position.clone(),
                speed: l.speed.clone(),
            });
            link = l.prev.as_ref();
        }
        points.reverse();
        let mut add = |step: usize, position: Interval| {
            match points.binary_search_by_key(&step, |p| p.step) {
                Ok(i) => points[i].position = points[i].position.intersect(&position),
                Err(i) => points.insert(
                    i,
                    Point {
                        step,
                        position,
                        speed: Interval::all(),
                    },
                ),
            };
        };
        for e in extra {
            add(e.step, e.position.clone());
        }
        for &q in queries {
            add(q, Interval::all());
        }
        points
    }

    /// Forward and backward passes over `points`: (reach given earlier constraints,
    /// feasible given later ones), both including the point's own constraint.
    fn passes(&self, points: &[Point]) -> (Vec<Interval>, Vec<Interval>) {
        let falls: Vec<Interval> = points
            .windows(2)
            .map(|w| self.fall_between(&w[0], &w[1]))
            .collect();
        let mut forward: Vec<Interval> = Vec::with_capacity(points.len());
        for (j, p) in points.iter().enumerate() {
            let f = if j == 0 {
                p.position.clone()
            } else {
                forward[j - 1].minus(&falls[j - 1]).intersect(&p.position)
            };
            forward.push(f);
        }
        let mut backward: Vec<Interval> = vec![Interval::all(); points.len()];
        for j in (0..points.len()).rev() {
            backward[j] = if j + 1 == points.len() {
                points[j].position.clone()
            } else {
                backward[j + 1]
                    .plus(&falls[j])
                    .intersect(&points[j].position)
            };
        }
        (forward, backward)
    }

    /// X(a.step) − X(b.step): the free steps' drift plus the last step's seen speed.
    fn fall_between(&self, a: &Point, b: &Point) -> Interval {
        let free = b.step - 1 - a.step;
        let speeds = self.speeds();
        if b.speed == Interval::all() || b.speed == speeds {
            // No speed seen: one more free step.
            return self.drift(free + 1);
        }
        self.drift(free)
            .plus(&b.speed.intersect(&speeds).scaled(&self.motion.dt))
    }

    /// X(m) over every behaviour that meets the chain and `extra`: exact. Empty when they
    /// cannot all be met.
    pub fn marginal(&self, m: usize, extra: &[Extra]) -> Interval {
        let [x] = self.marginals([m], extra);
        x
    }

    /// [`Self::marginal`] at several steps, from one pair of passes.
    pub fn marginals<const Q: usize>(&self, ms: [usize; Q], extra: &[Extra]) -> [Interval; Q] {
        if self.motion.w_max == Rational::zero() {
            let x = self.standing(extra);
            return ms.map(|_| x.clone());
        }
        let points = self.points(extra, &ms);
        let (forward, backward) = self.passes(&points);
        ms.map(|m| {
            let j = points
                .binary_search_by_key(&m, |p| p.step)
                .expect("the query is a point");
            forward[j].intersect(&backward[j])
        })
    }

    /// The one position of an obstacle that cannot move (W_i = 0) that meets every
    /// constraint: the passes' answer at every step, without them (its seats are static
    /// obstacles, most of a scene's).
    fn standing(&self, extra: &[Extra]) -> Interval {
        let mut x = Interval::all();
        let mut link = Some(&self.head);
        while let Some(l) = link {
            if l.speed.is_empty() {
                // A seen speed it cannot have.
                return Interval::closed(Rational::int(1), Rational::zero());
            }
            x = x.intersect(&l.position);
            link = l.prev.as_ref();
        }
        for e in extra {
            x = x.intersect(&e.position);
        }
        x
    }

    /// A behaviour that meets the chain and `extra`: X(0) and the speeds w_0 … w_{s−1} up to
    /// the last constrained step s (later speeds are free). Chosen away from open ends.
    /// None when the constraints cannot all be met.
    pub fn sample(&self, extra: &[Extra]) -> Option<(Rational, Vec<Rational>)> {
        let points = self.points(extra, &[]);
        let (forward, backward) = self.passes(&points);
        let speeds = self.speeds();
        let mut xs: Vec<Rational> = Vec::with_capacity(points.len());
        let first = forward[0].intersect(&backward[0]).inner_point()?;
        xs.push(first);
        let mut ws: Vec<Rational> = Vec::new();
        for j in 1..points.len() {
            let p = &points[j];
            let gap = p.step - 1 - points[j - 1].step;
            let last_speed = p.speed.intersect(&speeds);
            let from = Interval::point(xs[j - 1].clone());
            let here = from
                .minus(&self.drift(gap))
                .minus(&last_speed.scaled(&self.motion.dt))
                .intersect(&p.position)
                .intersect(&backward[j]);
            let x = here.inner_point()?;
            // Split the fall into the constrained last speed and equal free ones.
            let fall = (xs[j - 1].clone() - x.clone()) / self.motion.dt.clone();
            let free_max = self.motion.w_max.clone() * Rational::int(gap as i64);
            let last = Interval::closed(fall.clone() - free_max, fall.clone())
                .intersect(&last_speed)
                .inner_point()?;
            if gap > 0 {
                let each = (fall - last.clone()) / Rational::int(gap as i64);
                ws.extend(std::iter::repeat_n(each, gap));
            }
            ws.push(last);
            xs.push(x);
        }
        Some((xs.swap_remove(0), ws))
    }
}

/// Whether link `b`'s constraint follows from X(n) ∈ `position` (n > b.step): b bounds X
/// only from below, by no more than `position` does, and sees no speed.
fn implied_by(b: &Link, n: usize, position: &Interval, speeds: &Interval) -> bool {
    if b.prev.is_none() || n <= b.step || b.position.hi.is_some() || b.speed != *speeds {
        return false;
    }
    match (&b.position.lo, &position.lo) {
        (Some(old), Some(new)) => {
            new.at > old.at || (new.at == old.at && (!new.closed || old.closed))
        }
        (None, _) => true,
        (Some(_), None) => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::proof::scene_search::interval::End;

    fn r(n: i64, d: i64) -> Rational {
        Rational::int(n) / Rational::int(d)
    }

    fn below(x: Rational) -> Interval {
        Interval {
            lo: None,
            hi: Some(End::closed(x)),
        }
    }

    fn above(x: Rational) -> Interval {
        Interval {
            lo: Some(End::open(x)),
            hi: None,
        }
    }

    /// Whether the behaviour (X(0), speeds) meets every row of `c`.
    fn meets(c: &Chain, x0: &Rational, ws: &[Rational]) -> bool {
        let mut link = Some(&c.head);
        while let Some(l) = link {
            let mut x = x0.clone();
            for w in &ws[..l.step] {
                x = x - w.clone() * c.motion.dt.clone();
            }
            let speed_ok = l.step == 0 || l.speed.contains(&ws[l.step - 1]);
            if !l.position.contains(&x) || !speed_ok {
                return false;
            }
            link = l.prev.as_ref();
        }
        true
    }

    /// `implies` never claims an inclusion a behaviour contradicts: on random chains of
    /// position and speed rows, every behaviour of a grid (start and each of 5 speeds in
    /// steps of W/2) that meets one chain meets every chain it claims to imply; and it
    /// does claim some (a chain implies itself with a row more, and rows of earlier steps
    /// that its later rows force).
    #[test]
    fn implies_claims_only_inclusions_that_hold() {
        let mut state = 0x5eed_u64;
        let mut draw = |n: i64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as i64
        };
        let grid: Vec<Rational> = (0..=2).map(|i| r(i, 2)).collect();
        let mut behaviours = Vec::new();
        for x0 in 0..=4 {
            for code in 0..3usize.pow(5) {
                let ws: Vec<Rational> = (0..5)
                    .map(|j| grid[(code / 3usize.pow(j)) % 3].clone())
                    .collect();
                behaviours.push((r(20 + x0, 2), ws));
            }
        }
        let mut claimed = 0;
        for _ in 0..300 {
            let mut chains = Vec::new();
            for _ in 0..2 {
                let mut c = Chain::new(Interval::closed(r(10, 1), r(12, 1)), r(1, 1), r(1, 1));
                for step in 1..=5 {
                    if draw(2) == 0 {
                        continue;
                    }
                    let at = r(2 * (12 - step) + draw(5), 2);
                    let position = match draw(3) {
                        0 => below(at),
                        1 => above(at),
                        _ => Interval::all(),
                    };
                    let speed = match draw(3) {
                        0 => below(r(1, 2)),
                        1 => above(r(1, 2)),
                        _ => Interval::all(),
                    };
                    if let Some(next) = c.constrain(step as usize, &position, &speed) {
                        c = next;
                    }
                }
                chains.push(c);
            }
            let (a, b) = (&chains[0], &chains[1]);
            for (x, y) in [(a, b), (b, a)] {
                if x.implies(y) {
                    claimed += 1;
                    for (x0, ws) in &behaviours {
                        assert!(
                            !meets(x, x0, ws) || meets(y, x0, ws),
                            "{x:?} does not imply {y:?}"
                        );
                    }
                }
            }
        }
        assert!(claimed >= 30, "only {claimed} inclusions claimed");
        // A later row forces an earlier one: X(5) ≤ 6 from X(0) = 10 with W·dt = 1 forces
        // X(3) ≤ 8; not X(3) ≤ 7.9.
        let start = Chain::new(Interval::point(r(10, 1)), r(1, 1), r(1, 1));
        let late = start
            .constrain(5, &below(r(6, 1)), &Interval::all())
            .unwrap();
        let forced = start
            .constrain(3, &below(r(8, 1)), &Interval::all())
            .unwrap();
        let too_much = start
            .constrain(3, &below(r(79, 10)), &Interval::all())
            .unwrap();
        assert!(late.implies(&forced) && late.implies(&start));
        assert!(!late.implies(&too_much) && !start.implies(&late));
        // Open and closed ends: (1, 2] is in [1, 2], not the other way round.
        let closed = Interval::closed(r(1, 1), r(2, 1));
        let half_open = Interval {
            lo: Some(End::open(r(1, 1))),
            hi: Some(End::closed(r(2, 1))),
        };
        assert!(half_open.within(&closed) && !closed.within(&half_open));
        assert!(closed.within(&Interval::all()) && !Interval::all().within(&closed));
    }

    /// A later constraint narrows an earlier step's positions (the backward pass), and a
    /// sampled behaviour meets every constraint when replayed by hand.
    #[test]
    fn marginals_see_later_constraints_and_samples_meet_them() {
        // X(0) = 10, W = 1, dt = 1.
        let c = Chain::new(Interval::point(r(10, 1)), r(1, 1), r(1, 1));
        let c = c.constrain(5, &below(r(6, 1)), &Interval::all()).unwrap();
        // X(5) ≤ 6 needs a fall of ≥ 4 in 5 steps, so X(1) ≤ 10 and X(1) ≥ 9 stays, but
        // X(4) ≤ 7: X(4) ∈ [6, 7].
        let m4 = c.marginal(4, &[]);
        assert_eq!(m4, Interval::closed(r(6, 1), r(7, 1)));
        // Beyond the last constraint only the drift applies.
        assert_eq!(c.marginal(7, &[]), Interval::closed(r(3, 1), r(6, 1)));
        let extra = [Extra {
            step: 2,
            position: above(r(17, 2)),
        }];
        let m2 = c.marginal(2, &extra);
        assert!(m2.contains(&r(9, 1)) && !m2.contains(&r(17, 2)));
        let (x0, ws) = c.sample(&extra).unwrap();
        assert_eq!(x0, r(10, 1));
        assert_eq!(ws.len(), 5);
        let mut x = x0;
        for (k, w) in ws.iter().enumerate() {
            assert!(*w >= Rational::zero() && *w <= r(1, 1));
            x = x - w.clone();
            if k + 1 == 2 {
                assert!(x > r(17, 2));
            }
        }
        assert!(x <= r(6, 1));
    }

    /// An obstacle that cannot move: the shortcut gives what the passes give, at every
    /// step, with extras, and nothing when a seen speed excludes standing still.
    #[test]
    fn a_standing_obstacle_is_where_every_constraint_puts_it() {
        let start = Interval::closed(r(4, 1), r(9, 1));
        let c = Chain::new(start, Rational::zero(), r(1, 10));
        let c = c
            .constrain(3, &above(r(5, 1)), &Interval::all())
            .unwrap()
            .constrain(7, &below(r(8, 1)), &Interval::closed(r(0, 1), r(1, 1)))
            .unwrap();
        let extras = [
            vec![],
            vec![Extra {
                step: 5,
                position: below(r(6, 1)),
            }],
            vec![Extra {
                step: 9,
                position: above(r(7, 1)),
            }],
        ];
        for extra in &extras {
            let points = c.points(extra, &[0, 5, 9]);
            let (f, b) = c.passes(&points);
            for m in [0, 5, 9] {
                let j = points.binary_search_by_key(&m, |p| p.step).unwrap();
                assert_eq!(c.marginal(m, extra), f[j].intersect(&b[j]), "step {m}");
            }
        }
        assert_eq!(
            c.marginal(5, &extras[1]),
            Interval {
                lo: Some(End::open(r(5, 1))),
                hi: Some(End::closed(r(6, 1))),
            }
        );
        // Seen moving: either refused at once or nothing left.
        if let Some(moving) = c.constrain(8, &Interval::all(), &above(r(1, 100))) {
            assert!(moving.marginal(8, &[]).is_empty());
        }
    }

    /// Impossible constraints leave nothing; implied "still far" rows do not pile up.
    #[test]
    fn infeasible_and_implied_rows() {
        let c = Chain::new(Interval::point(r(10, 1)), r(1, 1), r(1, 1));
        assert!(c.constrain(2, &below(r(7, 1)), &Interval::all()).is_none());
        let mut far = c.clone();
        for n in 1..50 {
            far = far
                .constrain(n, &above(r(n as i64, 10)), &Interval::all())
                .unwrap();
        }
        assert_eq!(far.points(&[], &[]).len(), 2);
        assert_eq!(
            far.marginal(3, &[]),
            Interval {
                lo: Some(End::closed(r(7, 1))),
                hi: Some(End::closed(r(10, 1))),
            }
        );
    }
}
