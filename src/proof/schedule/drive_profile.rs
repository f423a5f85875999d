//! The drive profile: the robot's exact states when it never brakes, shared across
//! decompositions of one robot, and where it is, how fast, and where it comes to rest after
//! braking at any step (in closed form past the cruise onset).

use std::sync::{Arc, Mutex};

use super::Decomposition;
use crate::core::model::Params;
use crate::core::num::{Exact, Scalar};
use crate::core::rational::Rational;
use crate::core::semantics::{Mode, RobotState, robot_motion};

/// Time and distance the robot needs to stop when it brakes from speed `v`: v/b_min and
/// v²/(2·b_min), exactly. The step function brakes at the constant rate b_min — a full
/// period from speed u covers u·dt − b_min·dt²/2 = (u² − (u − b_min·dt)²)/(2·b_min), the last
/// one, from u ≤ b_min·dt, covers u²/(2·b_min) in u/b_min — so the periods telescope to the
/// closed form (held equal to iterating the step function by a test). Iterating cost one
/// exact step per period per piece: 9 minutes for an accelerating robot at dt = 0.1 ms.
pub(super) fn stopping(p: &Params<Exact>, v: Exact) -> (Exact, Exact) {
    if v <= Exact::zero() {
        return (Exact::zero(), Exact::zero());
    }
    let time = v.clone() / p.b_min.clone();
    let distance = v * time.clone() / Exact::from(2);
    (time, distance)
}

/// A drive profile: its states up to the cruise onset.
pub(super) type Profile = Arc<Vec<RobotState<Exact>>>;

/// Profiles already stepped, by the numbers the drive depends on (v_max, a, dt, v0): a sweep
/// or a region map asks for one robot's profile thousands of times (2,000 exact steps at
/// 1 kHz). A few robots are kept; the list starts over when full.
static PROFILES: Mutex<Vec<([Exact; 4], Profile)>> = Mutex::new(Vec::new());

/// The longest profile [`PROFILES`] keeps (10,000 steps: v_max/a of 1 s at 0.1 ms).
const MAX_SHARED_STEPS: usize = 10_000;

/// The drive profile of `params`'s robot, stepped once per robot ([`PROFILES`]).
pub(super) fn shared_drive_profile(params: &Params<Exact>) -> Profile {
    let key = [
        params.v_max.clone(),
        params.a.clone(),
        params.dt.clone(),
        params.v0.clone(),
    ];
    let known = PROFILES.lock().ok().and_then(|list| {
        list.iter()
            .find(|(k, _)| *k == key)
            .map(|(_, profile)| profile.clone())
    });
    if let Some(profile) = known {
        return profile;
    }
    let profile = Arc::new(drive_profile(params));
    // (A long profile is not kept past its use: its memory would outlive the analysis.)
    if profile.len() <= MAX_SHARED_STEPS
        && let Ok(mut list) = PROFILES.lock()
    {
        if list.len() >= 8 {
            list.clear();
        }
        list.push((key, profile.clone()));
    }
    profile
}

/// The drive profile up to the cruise onset, through the step function (in [`Rational`]).
fn drive_profile(params: &Params<Exact>) -> Vec<RobotState<Exact>> {
    let p: Params<Rational> = params.map(Rational::from_exact);
    let mut state = RobotState::initial(&p);
    let mut profile = Vec::new();
    loop {
        profile.push(RobotState {
            position: state.position.to_exact(),
            speed: state.speed.to_exact(),
            mode: state.mode,
        });
        if state.speed >= p.v_max {
            return profile;
        }
        state = robot_motion(&p, &state).end;
    }
}

impl Decomposition {
    /// The first index k ≥ 0 where `reached(k)` holds, for a predicate that is monotone in k
    /// and, past the cruise onset, holds from `cruise_from + ceil(steps)` on (`steps` is the
    /// exact number of cruise steps still needed, as computed from the cruise state). Up to
    /// the cruise onset it is found by bisection (the onset is v_max/(a·dt) steps away: 2,000
    /// at 1 kHz), which monotonicity makes the first index a scan would find.
    pub(crate) fn first_index(
        &self,
        reached: impl Fn(usize, &Self) -> bool,
        steps: Exact,
    ) -> usize {
        let c = self.cruise_from;
        if reached(c, self) {
            // The first reached index in [0, c]: reached(hi), and lo is unreached or 0.
            if reached(0, self) {
                return 0;
            }
            let (mut lo, mut hi) = (0, c);
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if reached(mid, self) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            return hi;
        }
        let k = self.cruise_from + usize::try_from(steps.ceil()).unwrap_or(usize::MAX).max(1);
        debug_assert!(reached(k, self) && !reached(k - 1, self));
        k
    }

    /// Position along the drive profile at step k's start.
    pub fn position(&self, k: usize) -> Exact {
        match self.profile.get(k) {
            Some(s) => s.position.clone(),
            None => {
                self.profile[self.cruise_from].position.clone()
                    + Exact::from(k - self.cruise_from) * &self.cruise_step
            }
        }
    }

    /// Speed along the drive profile at step k's start.
    pub(super) fn speed(&self, k: usize) -> &Exact {
        self.profile.get(k).map_or(&self.params.v_max, |s| &s.speed)
    }

    /// The drive-profile state at step k's start. Past the cruise onset the robot drives
    /// at v_max, so the state is the cruise state moved k − cruise_from steps (what
    /// iterating [`robot_motion`] in Drive gives; a test holds the two equal).
    pub(crate) fn drive(&self, k: usize) -> RobotState<Exact> {
        match self.profile.get(k) {
            Some(s) => s.clone(),
            None => RobotState {
                position: self.position(k),
                speed: self.params.v_max.clone(),
                mode: Mode::Drive,
            },
        }
    }

    /// Time and position at which the robot comes to rest after braking at step T's start.
    pub fn rest(&self, t: usize) -> (Exact, Exact) {
        let start = self.drive(t);
        let (time, distance) = if t >= self.cruise_from {
            self.cruise_stop.clone()
        } else {
            stopping(&self.params, start.speed)
        };
        (
            Exact::from(t) * self.params.dt.clone() + time,
            start.position + distance,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::proof::schedule::tests::problem;

    /// Decompositions share drive profiles by robot, never across robots: interleaved robots
    /// that differ in one number each (a, v_max, dt, v0) get their own profile.
    #[test]
    fn shared_drive_profiles_belong_to_their_robot() {
        let robots = [
            (0.2, 0.1, 0.1, None),
            (0.2, 0.05, 0.1, None),
            (0.3, 0.1, 0.1, None),
            (0.2, 0.1, 0.05, None),
            (0.2, 0.1, 0.1, Some(0.1)),
        ];
        for _ in 0..2 {
            for (v, a, dt, v0) in robots {
                let mut pr = problem(v, a, 0.05, dt);
                pr.robot.initial_speed = v0;
                let d = Decomposition::new(&pr);
                assert_eq!(
                    *d.profile,
                    drive_profile(&d.params),
                    "robot {v} {a} {dt} {v0:?}"
                );
            }
        }
    }

    /// The closed-form stop equals braking period by period through the step function,
    /// exactly: speeds that are whole multiples of b·dt, that stop inside the first period,
    /// that stop mid-period, zero, and a plant braking weaker than the controller assumes.
    #[test]
    fn stopping_in_closed_form_is_the_step_function_iterated() {
        for (v, b, dt, b_min) in [
            (0.2, 0.05, 0.1, None),
            (0.2, 0.5, 0.1, None),
            (0.37, 0.3, 0.07, None),
            (0.8, 0.5, 0.07, Some(0.13)),
        ] {
            let mut pr = problem(v, 0.1, b, dt);
            pr.robot.braking_min = b_min;
            let p = Decomposition::new(&pr).params;
            let v_max = p.v_max.clone();
            let b_dt = p.b_min.clone() * p.dt.clone();
            for speed in [
                v_max.clone(),
                v_max.clone() / Exact::from(3),
                b_dt.clone() * Exact::from(2),
                b_dt / Exact::from(2),
                Exact::ZERO,
            ] {
                let mut s = RobotState {
                    position: Exact::ZERO,
                    speed: speed.clone(),
                    mode: Mode::Brake,
                };
                let mut time = Exact::ZERO;
                while s.mode != Mode::Stop {
                    let m = robot_motion(&p, &s);
                    time += m.moving_for.clone();
                    s = m.end;
                }
                assert_eq!(
                    stopping(&p, speed.clone()),
                    (time, s.position),
                    "v_max {v}, b {b}, dt {dt}, b_min {b_min:?}, from {speed}"
                );
            }
        }
    }

    /// Bisection up to the cruise onset finds the index a scan finds, for thresholds on the
    /// drive profile's position before, at and past the onset.
    #[test]
    fn first_index_bisects_as_a_scan_finds() {
        for (v, a, b, dt) in [
            (0.2, 0.1, 0.05, 0.1),
            (0.8, 0.3, 0.5, 0.007),
            (0.2, 0.1, 0.05, 0.001),
        ] {
            let dec = Decomposition::new(&problem(v, a, b, dt));
            let c = dec.cruise_from;
            let end = dec.position(c + 5);
            for i in 0..=40 {
                let x = end.clone() * Exact::from(i) / Exact::from(40);
                let reached = |k: usize, d: &Decomposition| d.position(k) >= x;
                let steps = (x.clone() - dec.position(c))
                    / (dec.params.v_max.clone() * dec.params.dt.clone());
                let scan = (0..).find(|&k| reached(k, &dec)).unwrap();
                assert_eq!(dec.first_index(reached, steps), scan, "{dt} {i}");
            }
        }
    }

    /// `drive(k)` past the cruise onset is the cruise state moved on: exactly what iterating
    /// the step function gives. `rest(t)` is exactly braking through the step function.
    #[test]
    fn drive_profile_and_rest_are_the_step_function() {
        for (v, a, b, dt) in [
            (0.2, 0.1, 0.05, 0.1),
            (0.8, 0.3, 0.5, 0.07),
            (1.3, 2.9, 0.7, 0.2),
        ] {
            let dec = Decomposition::new(&problem(v, a, b, dt));
            let p = &dec.params;
            let mut state = RobotState {
                position: Exact::ZERO,
                speed: Exact::ZERO,
                mode: Mode::Accelerate,
            };
            for k in 0..dec.cruise_from + 60 {
                let d = dec.drive(k);
                assert_eq!(
                    (&d.position, &d.speed),
                    (&state.position, &state.speed),
                    "step {k}"
                );
                if k > 0 && k % 7 == 0 {
                    let (t_rest, p_rest) = dec.rest(k);
                    let mut s = RobotState {
                        mode: Mode::Brake,
                        ..state.clone()
                    };
                    let mut time = Exact::from(k) * p.dt.clone();
                    while s.mode != Mode::Stop {
                        let m = robot_motion(p, &s);
                        time += m.moving_for.clone();
                        s = m.end;
                    }
                    assert_eq!(
                        (t_rest, p_rest),
                        (time, s.position),
                        "rest after braking at {k}"
                    );
                }
                state = robot_motion(p, &state).end;
            }
        }
    }
}
