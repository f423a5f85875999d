//! The multi-period step ([`World::leap`]): as many uniform periods as can be crossed at
//! once with nothing able to happen in them, found by bisection with exact comparisons, and
//! ending exactly where stepping them one by one ends.

use crate::core::num::Scalar;

use super::{Mode, Observation, RobotState, World};

/// What a [`World::leap`] must not jump past beyond what the semantics itself decides
/// (guards, collisions, coming to rest): the first observation within ρ and the first seen
/// passed, which a caller that still watches for them records ([`crate::core::simulate`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Watch {
    /// No observation within ρ may be skipped.
    pub radius: bool,
    /// No observation of a gap ≤ 0 may be skipped.
    pub passed: bool,
}

/// Periods a [`World::leap`] crossed at once, and what the caller needs of them: in each of
/// them the robot kept the mode it had, no guard fired, nothing collided or came to rest,
/// and no observation was within ρ (when watched) or at a gap ≤ 0 (when watched).
#[derive(Clone, Debug, PartialEq)]
pub struct Leap<N> {
    /// The first period crossed.
    pub k: usize,
    /// How many periods were crossed (at least 1).
    pub periods: usize,
    /// The robot's mode at every one of their starts.
    pub mode: Mode,
    /// What the robot would see at the first one's start without noise if it sees anything
    /// there; then it sees something at every one of their starts, else at none.
    pub first_seen: Option<Observation<N>>,
    /// The gap at the last one's end: the lowest gap of the stretch (the robot moved
    /// throughout).
    pub end_gap: N,
}

/// The robot's exact motion over `m` periods of one uniform mode from speed `v`: speed
/// change per period `s` and travel per period `v_i·dt + q`; positions then sum in closed
/// form, Σ_{i<m} (v + i·s)·dt + q = m·v·dt + s·dt·m(m−1)/2 + m·q.
/// Written as m·(v·dt + q) + (s·dt)·m(m−1)/2, with both factors computed once per leap: a
/// leap's bisection evaluates it at many m, and each exact product costs.
struct Uniform<N> {
    v: N,
    s: N,
    /// The first period's travel, v·dt + q.
    step: N,
    /// s·dt.
    sdt: N,
}

/// m(m−1)/2, the number of speed changes summed over the first m periods.
fn pairs<N: Scalar>(m: usize) -> N {
    N::int((m as i64) * (m as i64 - 1) / 2)
}

impl<N: Scalar> Uniform<N> {
    fn new(v: N, s: N, q: N, dt: &N) -> Uniform<N> {
        Uniform {
            step: v.clone() * dt.clone() + q,
            sdt: s.clone() * dt.clone(),
            v,
            s,
        }
    }
    /// Distance travelled over the first `m` periods.
    fn travelled(&self, m: usize) -> N {
        N::int(m as i64) * self.step.clone() + pairs::<N>(m) * self.sdt.clone()
    }
    /// Speed after `m` periods.
    fn speed(&self, m: usize) -> N {
        self.v.clone() + N::int(m as i64) * self.s.clone()
    }
}

/// The gap over a leap with the obstacle at speed w: it closes by w·dt + v·dt + q in the
/// first period and by s·dt more in each later one, so after j periods it is
/// gap − j·(w·dt + step) − (s·dt)·j(j−1)/2 (the same number as gap − j·w·dt − travelled(j)).
struct Closing<N> {
    gap: N,
    per_period: N,
    sdt: N,
}

impl<N: Scalar> Closing<N> {
    fn new(gap: &N, w: &N, dt: &N, uniform: &Uniform<N>) -> Closing<N> {
        Closing {
            gap: gap.clone(),
            per_period: w.clone() * dt.clone() + uniform.step.clone(),
            sdt: uniform.sdt.clone(),
        }
    }
    /// The gap after `j` periods.
    fn after(&self, j: usize) -> N {
        self.gap.clone()
            - N::int(j as i64) * self.per_period.clone()
            - pairs::<N>(j) * self.sdt.clone()
    }
}

impl<N: Scalar> World<N> {
    /// The multi-period step: crosses at once as many of the next `most` periods as can be
    /// crossed, with the obstacle at speed `w` throughout, when every one of them is a period
    /// in which "keep going as you are" is certain — the robot accelerating without reaching
    /// v_max, cruising, or braking without coming to rest; no guard able to fire whatever the
    /// observation error (every observed gap, less σ_g, beyond ρ and above 0); no gap ≤ the
    /// clearance; nothing `watch`ed skipped; not across the first period with an
    /// observation. The world ends exactly as `periods` calls of [`World::step_with`] leave it
    /// (with any error aims: none of them matters there), in exact numbers; None (and the
    /// world unchanged) when not even one period qualifies. Every condition is monotone in
    /// the number of periods (gaps never grow), so the longest stretch is found by bisection
    /// with exact comparisons. Only for exact number types: floats would round differently
    /// from period-by-period arithmetic.
    pub fn leap(&mut self, w: N, most: usize, watch: Watch) -> Option<Leap<N>> {
        let p = &self.params;
        let zero = N::zero();
        if most == 0 || w < zero || self.robot.speed < zero {
            return None;
        }
        let v = self.robot.speed.clone();
        let mode = self.robot.mode;
        let uniform = match mode {
            Mode::Accelerate if v < p.v_max => {
                Uniform::new(v, p.k.a_dt.clone(), p.k.half_a_dt2.clone(), &p.dt)
            }
            Mode::Drive if v <= p.v_max => Uniform::new(v, zero.clone(), zero.clone(), &p.dt),
            Mode::Brake if v > zero => {
                Uniform::new(v, -p.k.b_min_dt.clone(), -p.k.half_b_min_dt2.clone(), &p.dt)
            }
            _ => return None,
        };

        // Observations: from period max(L, hidden_until) on; a leap stays on one side.
        let sighting = p.L.max(self.hidden_until);
        let observed = self.k >= sighting;
        let most = if observed {
            most
        } else {
            most.min(sighting - self.k)
        };
        let limits = Limits {
            mode,
            v: uniform.v.clone(),
            s: uniform.s.clone(),
            closing: Closing::new(&self.gap, &w, &p.dt, &uniform),
            v_max: p.v_max.clone(),
            clearance: p.clearance.clone(),
            sigma_g: p.sigma_g.clone(),
            rho: p.rho.clone(),
            l: p.L,
            history: if observed {
                self.gaps.range(self.gaps.len() - p.L..).cloned().collect()
            } else {
                Vec::new()
            },
            observed,
            watch,
        };
        if !limits.hold(1) {
            return None;
        }
        let m = if limits.hold(most) {
            most
        } else {
            // The boundary in floats first (cheap), then settled exactly around it: every
            // condition is monotone in m, so exact probes at the guess and just past it
            // decide, and a guess off by rounding only narrows the exact bisection.
            let floats = limits.as_f64();
            let guess = last_holding(1, most - 1, |m| floats.hold(m));
            if !limits.hold(guess) {
                last_holding(1, guess - 1, |m| limits.hold(m))
            } else if limits.hold(guess + 1) {
                last_holding(guess + 1, most - 1, |m| limits.hold(m))
            } else {
                guess
            }
        };
        let closing = &limits.closing;
        let first_seen = if observed {
            self.observation_if_shown()
        } else {
            None
        };
        let p = &self.params;
        // History: the last L+1 period starts crossed (older ones stay).
        let keep = m.min(p.L + 1);
        let pushed: Vec<N> = (m - keep..m).map(|j| closing.after(j)).collect();
        let end_gap = closing.after(m);
        let position = self.robot.position.clone() + uniform.travelled(m);
        let speed = uniform.speed(m);
        let cap = p.L + 1;
        for g in pushed {
            self.gaps.push_back(g);
            self.speeds.push_back(w.clone());
        }
        while self.gaps.len() > cap {
            self.gaps.pop_front();
        }
        while self.speeds.len() > cap {
            self.speeds.pop_front();
        }
        let leap = Leap {
            k: self.k,
            periods: m,
            mode,
            first_seen,
            end_gap: end_gap.clone(),
        };
        self.robot = RobotState {
            position,
            speed,
            mode,
        };
        self.gap = end_gap;
        self.k += m;
        Some(leap)
    }
}

/// What decides how far a leap may go ([`World::leap`]), gathered once per leap: the
/// robot's uniform motion, the closing gap, the bounds it is compared with and the gaps the
/// first periods observe from the history. Generic so that the same conditions run on a
/// float copy, which guides the bisection, and exactly, which decides.
struct Limits<M> {
    mode: Mode,
    v: M,
    s: M,
    closing: Closing<M>,
    v_max: M,
    clearance: M,
    sigma_g: M,
    rho: M,
    l: usize,
    /// The last L gaps of the history, oldest first (what periods k … k+L−1 observe).
    history: Vec<M>,
    observed: bool,
    watch: Watch,
}

impl<M: Scalar> Limits<M> {
    /// Whether the next `m` periods can be crossed at once.
    fn hold(&self, m: usize) -> bool {
        let zero = M::zero();
        // The mode's branch of robot_motion in every period: Accelerate stays below
        // v_max − a·dt before its last period (v + m·a·dt < v_max), Brake above b_min·dt
        // (v − m·b_min·dt > 0); Drive at v ≤ v_max keeps v.
        let speed = || self.v.clone() + M::int(m as i64) * self.s.clone();
        let branch = match self.mode {
            Mode::Accelerate => speed() < self.v_max,
            Mode::Brake => speed() > zero,
            _ => true,
        };
        if !branch {
            return false;
        }
        // No collision: gaps fall, so the last end gap is the lowest moving one.
        if self.closing.after(m) <= self.clearance {
            return false;
        }
        if !self.observed {
            return true;
        }
        // Period k observes the gap at (k−L)·dt: from the history while k−L < the first
        // period, then in the stretch; the lowest is the last of each (gaps never grow).
        let mut lowest: Option<M> = None;
        for g in &self.history[..self.l.min(m)] {
            lowest = Some(match lowest {
                Some(x) => M::min_of(x, g.clone()),
                None => g.clone(),
            });
        }
        if m > self.l {
            let g = self.closing.after(m - 1 - self.l);
            lowest = Some(match lowest {
                Some(x) => M::min_of(x, g),
                None => g,
            });
        }
        let Some(lowest) = lowest else {
            return true;
        };
        // Whatever the error within ±σ_g, the observed gap is at least this.
        let seen_low = lowest - self.sigma_g.clone();
        let beyond_radius = seen_low > self.rho;
        let not_passed = seen_low > zero;
        match self.mode {
            // The guard fires only on a gap in (0, ρ].
            Mode::Accelerate | Mode::Drive => beyond_radius && not_passed,
            _ => (!self.watch.radius || beyond_radius) && (!self.watch.passed || not_passed),
        }
    }

    /// The same limits in floats: a guide only (rounding may put its boundary a period or
    /// so off the exact one).
    fn as_f64(&self) -> Limits<f64> {
        let f = |x: &M| x.as_f64();
        Limits {
            mode: self.mode,
            v: f(&self.v),
            s: f(&self.s),
            closing: Closing {
                gap: f(&self.closing.gap),
                per_period: f(&self.closing.per_period),
                sdt: f(&self.closing.sdt),
            },
            v_max: f(&self.v_max),
            clearance: f(&self.clearance),
            sigma_g: f(&self.sigma_g),
            rho: f(&self.rho),
            l: self.l,
            history: self.history.iter().map(f).collect(),
            observed: self.observed,
            watch: self.watch,
        }
    }
}

/// The largest m in [lo, hi] with `hold(m)`, for a condition that holds at `lo` and, past
/// some m, nowhere beyond.
fn last_holding(mut lo: usize, mut hi: usize, hold: impl Fn(usize) -> bool) -> usize {
    while lo < hi {
        let mid = lo + (hi - lo).div_ceil(2);
        if hold(mid) {
            lo = mid;
        } else {
            hi = mid - 1;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::semantics::tests::{Lcg, random_params};

    /// The multi-period step is exactly `periods` ordinary steps: same world after, in
    /// exact numbers, and in every step crossed the mode kept, no guard, no collision, no
    /// rest, observations present all or none (the first as the leap says), nothing watched
    /// skipped, the lowest gap the leap's end gap — on random states of random parameter
    /// sets (noise, latency, occlusion, guards active) with random error aims.
    #[test]
    fn a_leap_is_exactly_its_periods_stepped_one_by_one() {
        use crate::core::rational::Rational;
        let mut rng = Lcg(12);
        let mut leapt = [0usize; 3];
        let mut long = [0usize; 3];
        for _ in 0..400 {
            let p = random_params(&mut rng);
            let eighth = p.W.clone() / Rational::int(8);
            let speed = |rng: &mut Lcg| eighth.clone() * Rational::int(rng.below(9) as i64);
            let gap = Rational::int(rng.below(80) as i64 + 5) / Rational::int(10);
            let mut world = World::with_gap(p.clone(), gap);
            world.hide_until(rng.pick(&[0, 0, 3, 12, 40]));
            let warmup = rng.below(60);
            for _ in 0..warmup {
                if world.stopped() {
                    break;
                }
                let (w, react) = (speed(&mut rng), rng.below(2) == 1);
                world.step_with(w, react);
            }
            for _ in 0..20 {
                if world.stopped() {
                    break;
                }
                let w = speed(&mut rng);
                let most = rng.pick(&[1, 2, 5, 40, 400, 3000]);
                let watch = Watch {
                    radius: rng.below(2) == 1,
                    passed: rng.below(2) == 1,
                };
                let mut stepped = world.clone();
                let Some(leap) = world.leap(w.clone(), most, watch) else {
                    let (w, react) = (speed(&mut rng), rng.below(2) == 1);
                    world.step_with(w, react);
                    continue;
                };
                assert!(leap.periods >= 1 && leap.periods <= most);
                assert_eq!(leap.k, stepped.k);
                let truth = stepped.observation();
                let mut lowest: Option<Rational> = None;
                for i in 0..leap.periods {
                    let rec = stepped.step_with(w.clone(), rng.below(2) == 1);
                    assert_eq!(rec.robot.mode, leap.mode, "mode in period {i}");
                    assert_eq!(rec.brake, None);
                    assert!(!rec.collision && rec.rest_gap.is_none());
                    assert!(rec.motion.moving_for > Rational::zero());
                    assert_eq!(rec.observation.is_some(), leap.first_seen.is_some());
                    if let Some(obs) = &rec.observation {
                        assert!(!watch.radius || obs.gap > p.rho);
                        assert!(!watch.passed || obs.gap > Rational::zero());
                    }
                    lowest = Some(match lowest {
                        Some(x) => Rational::min_of(x, rec.end_gap.clone()),
                        None => rec.end_gap.clone(),
                    });
                }
                if leap.first_seen.is_some() {
                    assert_eq!(leap.first_seen, truth);
                }
                assert_eq!(lowest, Some(leap.end_gap.clone()));
                assert_eq!(stepped.k, world.k);
                assert_eq!(stepped.robot, world.robot);
                assert_eq!(stepped.gap, world.gap);
                assert_eq!(stepped.gaps, world.gaps);
                assert_eq!(stepped.speeds, world.speeds);
                assert_eq!(stepped.hidden_until, world.hidden_until);
                let m = match leap.mode {
                    Mode::Accelerate => 0,
                    Mode::Drive => 1,
                    _ => 2,
                };
                leapt[m] += 1;
                if leap.periods >= 5 {
                    long[m] += 1;
                }
            }
        }
        // Every uniform mode was leapt, and over many periods at once.
        assert!(leapt.iter().all(|&n| n >= 20), "{leapt:?}");
        assert!(long.iter().all(|&n| n >= 5), "{long:?}");
    }
}
