//! The worst separation of each obstacle over the behaviours of one finished run.
//!
//! A leaf fixes the robot's whole motion (the drive profile until T, then braking to rest;
//! or driving for ever) and its lanes over time. Obstacle i counts on each occupancy
//! interval J = [s, e) of its lane (docs/semantics.md §11.6): when it is ahead at J's start
//! its measure is the gap, lowest where the robot's moving instants in J end (the exit at
//! e·dt, or the rest instant, or never: −∞); when it is beside or behind, the measure is
//! −gap, lowest at J's start. Which side it is on is one more interval constraint on
//! X(s), so each case is an exact marginal of its chain (`Chain::marginal`).

use crate::core::num::Scalar;
use crate::core::rational::Rational;
use crate::core::scene::SceneParams;
use crate::core::scene::lateral::LaneChangeEvent;
use crate::core::semantics::{Mode, RobotState, robot_motion};

use std::collections::HashMap;

use super::chain::{Chain, Extra};
use super::interval::{End, Interval};
use super::tree::{Ending, Leaf, Profile, runs_share_much};

/// An occupancy interval of a lane: from step `start` to step `end` (None: never left).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Occupancy {
    /// The lane.
    pub lane: i32,
    /// The step at whose start the robot entered it (0 for lane 0).
    pub start: usize,
    /// The step at whose start the robot had left it.
    pub end: Option<usize>,
}

/// The occupancy intervals of a run's lane changes (maximal: a change back into the lane
/// just left, at the instant the first change completes, continues the old interval).
pub fn occupancies(changes: &[LaneChangeEvent], periods: usize) -> Vec<Occupancy> {
    let mut out = vec![Occupancy {
        lane: 0,
        start: 0,
        end: None,
    }];
    for c in changes {
        match out
            .iter_mut()
            .find(|o| o.lane == c.to && o.end == Some(c.step))
        {
            Some(o) => o.end = None,
            None => out.push(Occupancy {
                lane: c.to,
                start: c.step,
                end: None,
            }),
        }
        if let Some(o) = out.iter_mut().find(|o| o.lane == c.from && o.end.is_none()) {
            o.end = Some(c.step + periods);
        }
    }
    out
}

/// Where obstacle i's worst separation in a leaf is reached.
#[derive(Clone, Debug, PartialEq)]
pub enum Objective {
    /// Ahead at the interval's start: the gap at the end of its moving instants, the
    /// instant `at` (seconds), reached at step `step` plus `into` seconds.
    Ahead {
        /// The interval.
        interval: Occupancy,
        /// Step whose start precedes the instant.
        step: usize,
        /// Seconds into that step.
        into: Rational,
    },
    /// Ahead at the interval's start, which the robot never leaves while moving: −∞.
    Unbounded {
        /// The interval.
        interval: Occupancy,
    },
    /// Beside or behind at the interval's start: −gap there.
    Behind {
        /// The interval.
        interval: Occupancy,
    },
}

/// Obstacle i's worst case in one leaf.
#[derive(Clone, Debug)]
pub struct Worst {
    /// The infimum of its separation over the leaf's behaviours (None: −∞).
    pub value: Option<Rational>,
    /// Where it is reached.
    pub objective: Objective,
}

impl Worst {
    /// Whether `self` is below `other`.
    pub fn below(&self, other: &Worst) -> bool {
        match (&self.value, &other.value) {
            (None, None) => false,
            (None, Some(_)) => true,
            (Some(_), None) => false,
            (Some(a), Some(b)) => a < b,
        }
    }

    /// The constraint that puts the obstacle on the objective's side.
    pub fn side(&self, robot_at_start: &Rational) -> Extra {
        let (interval, ahead) = match &self.objective {
            Objective::Ahead { interval, .. } | Objective::Unbounded { interval } => {
                (interval, true)
            }
            Objective::Behind { interval } => (interval, false),
        };
        Extra {
            step: interval.start,
            position: side(robot_at_start, ahead),
        }
    }
}

/// The robot's motion in a leaf, exactly.
#[derive(Clone, Debug)]
pub struct Motion {
    /// Brake step T (None: never brakes).
    pub brake: Option<usize>,
    /// States at step starts after T until rest (index 0 is step T+1).
    braking: Vec<RobotState<Rational>>,
    /// The rest instant (s) and the step whose start precedes it.
    pub rest: Option<(Rational, usize)>,
}

/// Braking to rest from a speed, from position 0: the states at the step starts after the
/// brake step, and the rest as (seconds after the brake step's start, steps after it). A
/// braking step moves the robot by an amount its position does not enter, so braking from
/// x is this curve shifted by x, exactly.
#[derive(Clone, Debug)]
pub struct BrakeCurve {
    speed: Rational,
    states: Vec<RobotState<Rational>>,
    rest: (Rational, usize),
}

impl BrakeCurve {
    fn from_speed(p: &SceneParams<Rational>, speed: &Rational) -> BrakeCurve {
        let dt = p.robot.dt.clone();
        let mut state = RobotState {
            position: Rational::zero(),
            speed: speed.clone(),
            mode: Mode::Brake,
        };
        let mut states = Vec::new();
        if state.speed <= Rational::zero() {
            return BrakeCurve {
                speed: speed.clone(),
                states,
                rest: (Rational::zero(), 0),
            };
        }
        let mut j = 0;
        loop {
            let m = robot_motion(&p.robot, &state);
            if m.came_to_rest() {
                let at = dt.clone() * Rational::int(j as i64) + m.moving_for.clone();
                return BrakeCurve {
                    speed: speed.clone(),
                    states,
                    rest: (at, j),
                };
            }
            state = m.end;
            states.push(state.clone());
            j += 1;
        }
    }
}

/// Brake curves met so far, by the speed they start from (a search brakes from few
/// speeds: those of the acceleration and the cruise).
pub type BrakeCurves = Vec<BrakeCurve>;

impl Motion {
    /// The robot's motion in a leaf, its braking taken from `curves` (new ones kept there).
    pub fn of_with(
        p: &SceneParams<Rational>,
        profile: &mut Profile,
        ending: &Ending,
        curves: &mut BrakeCurves,
    ) -> Motion {
        let Ending::Brake { step, .. } = ending else {
            return Motion::driving_on();
        };
        let start = profile.at(p, *step).clone();
        let curve = match curves.iter().position(|c| c.speed == start.speed) {
            Some(i) => &curves[i],
            None => {
                curves.push(BrakeCurve::from_speed(p, &start.speed));
                curves.last().expect("just pushed")
            }
        };
        let braking = curve
            .states
            .iter()
            .map(|s| RobotState {
                position: start.position.clone() + s.position.clone(),
                speed: s.speed.clone(),
                mode: s.mode,
            })
            .collect();
        let (after, steps) = &curve.rest;
        let t0 = p.robot.dt.clone() * Rational::int(*step as i64);
        Motion {
            brake: Some(*step),
            braking,
            rest: Some((t0 + after.clone(), step + steps)),
        }
    }

    /// The motion of a robot that never brakes: the drive profile for ever.
    pub fn driving_on() -> Motion {
        Motion {
            brake: None,
            braking: Vec::new(),
            rest: None,
        }
    }

    /// The robot's position at step k's start.
    pub fn position(&self, p: &SceneParams<Rational>, profile: &mut Profile, k: usize) -> Rational {
        match self.brake {
            Some(t) if k > t => match self.braking.get(k - t - 1) {
                Some(s) => s.position.clone(),
                // Past the rest instant it stays where it rested.
                None => self.rest_position(p, profile),
            },
            _ => profile.at(p, k).position.clone(),
        }
    }

    /// Where the robot rests.
    pub fn rest_position(&self, p: &SceneParams<Rational>, profile: &mut Profile) -> Rational {
        let t = self.brake.expect("only a braking run rests");
        let last = self.braking.last().cloned().unwrap_or_else(|| {
            let mut s = profile.at(p, t).clone();
            s.mode = Mode::Brake;
            s
        });
        if last.speed <= Rational::zero() {
            return last.position;
        }
        robot_motion(&p.robot, &last).end.position
    }
}

/// X(s) ahead of (`ahead`) or at/behind the robot at `robot`.
fn side(robot: &Rational, ahead: bool) -> Interval {
    if ahead {
        Interval {
            lo: Some(End::open(robot.clone())),
            hi: None,
        }
    } else {
        Interval {
            lo: None,
            hi: Some(End::closed(robot.clone())),
        }
    }
}

/// Worst cases already computed, by all they depend on: the obstacle's chain (runs share
/// the chains of the obstacles they did not split, by reference), the robot's stays in its
/// lane and its brake step. Sibling runs differ in one or two obstacles, so with many
/// obstacles most of a leaf's worst cases are found here (8 oncoming obstacles: 86% of the
/// search was recomputing them).
pub struct WorstMemo {
    /// Off: every worst case is computed (cheaper where runs share little: one moving
    /// obstacle, whose runs differ in their brake step).
    on: bool,
    /// By chain and brake step.
    known: HashMap<(usize, Option<usize>), Known>,
}

/// One chain's worst cases: the chain (kept, so that its address is not reused while it is
/// a key) and the worst case per list of stays in its lane.
type Known = (Chain, Vec<(Vec<Occupancy>, Option<Worst>)>);

impl WorstMemo {
    /// A memo for a scene's search: kept when its runs share much ([`runs_share_much`]).
    pub fn for_scene(p: &SceneParams<Rational>) -> WorstMemo {
        WorstMemo {
            on: runs_share_much(p),
            known: HashMap::new(),
        }
    }

    /// Every obstacle's worst case in a leaf ([`worst`] for each).
    pub fn of_leaf(
        &mut self,
        p: &SceneParams<Rational>,
        profile: &mut Profile,
        leaf: &Leaf,
        motion: &Motion,
    ) -> Vec<Option<Worst>> {
        if !self.on {
            return (0..leaf.chains.len())
                .map(|i| worst(p, profile, leaf, motion, i))
                .collect();
        }
        let stays = occupancies(&leaf.changes, p.lane_change_periods());
        let mut by_lane: Vec<(i32, Vec<Occupancy>)> = Vec::new();
        (0..leaf.chains.len())
            .map(|i| {
                let chain = &leaf.chains[i];
                let lane = p.obstacles[i].lane;
                let at = match by_lane.iter().position(|(l, _)| *l == lane) {
                    Some(at) => at,
                    None => {
                        let mine = stays.iter().filter(|o| o.lane == lane).cloned().collect();
                        by_lane.push((lane, mine));
                        by_lane.len() - 1
                    }
                };
                let mine = &by_lane[at].1;
                let (_, known) = self
                    .known
                    .entry((chain.identity(), motion.brake))
                    .or_insert_with(|| (chain.clone(), Vec::new()));
                if let Some((_, w)) = known.iter().find(|(s, _)| s == mine) {
                    return w.clone();
                }
                let w = worst(p, profile, leaf, motion, i);
                known.push((mine.clone(), w.clone()));
                w
            })
            .collect()
    }
}

/// Obstacle i's worst case in a leaf (None: the robot never moves in its lane).
pub fn worst(
    p: &SceneParams<Rational>,
    profile: &mut Profile,
    leaf: &Leaf,
    motion: &Motion,
    i: usize,
) -> Option<Worst> {
    worst_of(
        p,
        profile,
        &leaf.changes,
        &leaf.chains[i],
        p.obstacles[i].lane,
        motion,
    )
}

/// The worst case of an obstacle in `lane` with constraints `chain`, for a robot that
/// makes lane changes `changes` and moves as `motion` (None: never in the lane).
pub fn worst_of(
    p: &SceneParams<Rational>,
    profile: &mut Profile,
    changes: &[LaneChangeEvent],
    chain: &Chain,
    lane: i32,
    motion: &Motion,
) -> Option<Worst> {
    let dt = p.robot.dt.clone();
    let w = chain.w_max().clone();
    let mut best: Option<Worst> = None;
    for interval in occupancies(changes, p.lane_change_periods()) {
        if interval.lane != lane {
            continue;
        }
        let start_time = dt.clone() * Rational::int(interval.start as i64);
        if let Some((rest, _)) = &motion.rest
            && start_time >= *rest
        {
            continue;
        }
        let at_start = motion.position(p, profile, interval.start);
        let ahead = [Extra {
            step: interval.start,
            position: side(&at_start, true),
        }];
        let behind = [Extra {
            step: interval.start,
            position: side(&at_start, false),
        }];
        let mut candidates: Vec<Worst> = Vec::new();
        // Ahead: the gap where the moving instants end.
        let exit = interval
            .end
            .map(|e| (dt.clone() * Rational::int(e as i64), e));
        let end = match (&exit, &motion.rest) {
            (Some((te, e)), Some((tr, r))) => Some(if te <= tr {
                (*e, Rational::zero())
            } else {
                (*r, tr.clone() - dt.clone() * Rational::int(*r as i64))
            }),
            (Some((_, e)), None) => Some((*e, Rational::zero())),
            (None, Some((tr, r))) => Some((*r, tr.clone() - dt.clone() * Rational::int(*r as i64))),
            (None, None) => None,
        };
        // The marginals at the start and where the moving instants end, in one pass.
        let end_step = end.as_ref().map_or(interval.start, |(step, _)| *step);
        let [at_start_ahead, at_end] = chain.marginals([interval.start, end_step], &ahead);
        if !at_start_ahead.is_empty() {
            match end {
                None => candidates.push(Worst {
                    value: None,
                    objective: Objective::Unbounded {
                        interval: interval.clone(),
                    },
                }),
                Some((step, into)) => {
                    let x = at_end;
                    let low = x.lo.expect("positions are bounded").at - w.clone() * into.clone();
                    let robot = if into == Rational::zero() {
                        motion.position(p, profile, step)
                    } else {
                        motion.rest_position(p, profile)
                    };
                    candidates.push(Worst {
                        value: Some(low - robot),
                        objective: Objective::Ahead {
                            interval: interval.clone(),
                            step,
                            into,
                        },
                    });
                }
            }
        }
        // Beside or behind: −gap at the start.
        let x = chain.marginal(interval.start, &behind);
        if !x.is_empty() {
            let high = x.hi.expect("bounded above by the robot").at;
            candidates.push(Worst {
                value: Some(at_start.clone() - high),
                objective: Objective::Behind {
                    interval: interval.clone(),
                },
            });
        }
        for c in candidates {
            if best.as_ref().is_none_or(|b| c.below(b)) {
                best = Some(c);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::core::scene::Scene;

    /// Braking taken from a shared curve is braking stepped from where the robot is, at
    /// every brake step of the seed's drive profile (accelerating and cruising): the same
    /// states, the same rest instant and step.
    #[test]
    fn a_shared_brake_curve_is_the_braking_from_each_step() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/problems/seed-lanes.toml"
        ))
        .unwrap();
        let scene = Scene::from_toml_str(&text, "seed-lanes.toml").unwrap();
        let p: SceneParams<Rational> = scene
            .params::<crate::core::num::Exact>()
            .map(Rational::from_exact);
        let mut profile = Profile::new(&p);
        let mut curves = BrakeCurves::new();
        for step in [0, 1, 3, 7, 19, 20, 21, 60, 61, 400] {
            let ending = Ending::Brake {
                step,
                reason: crate::core::semantics::BrakeReason::CollisionDanger,
            };
            let shared = Motion::of_with(&p, &mut profile, &ending, &mut curves);
            // Stepped from the robot's own state.
            let mut state = profile.at(&p, step).clone();
            state.mode = Mode::Brake;
            let mut k = step;
            let mut braking = Vec::new();
            let rest = loop {
                if state.speed <= Rational::zero() {
                    // At rest already (the robot starts at 0 m/s).
                    break (p.robot.dt.clone() * Rational::int(k as i64), k);
                }
                let m = robot_motion(&p.robot, &state);
                if m.came_to_rest() {
                    break (
                        p.robot.dt.clone() * Rational::int(k as i64) + m.moving_for,
                        k,
                    );
                }
                state = m.end;
                braking.push(state.clone());
                k += 1;
            };
            assert_eq!(shared.braking, braking, "step {step}");
            assert_eq!(shared.rest, Some(rest), "step {step}");
        }
        // The cruise is one speed: one curve for every cruising step.
        assert!(curves.len() < 10, "{} curves", curves.len());
    }

    fn change(step: usize, from: i32, to: i32) -> LaneChangeEvent {
        LaneChangeEvent { step, from, to }
    }

    /// Lane 0 from t = 0; a change opens the target at its start and closes the source P
    /// periods later; a change straight back continues the interval just closed.
    #[test]
    fn occupancy_intervals_follow_the_changes() {
        let o = occupancies(&[change(10, 0, 1), change(20, 1, 0)], 4);
        assert_eq!(
            o,
            vec![
                Occupancy {
                    lane: 0,
                    start: 0,
                    end: Some(14)
                },
                Occupancy {
                    lane: 1,
                    start: 10,
                    end: Some(24)
                },
                Occupancy {
                    lane: 0,
                    start: 20,
                    end: None
                },
            ]
        );
        let back = occupancies(&[change(10, 0, 1), change(14, 1, 0)], 4);
        assert_eq!(
            back[0],
            Occupancy {
                lane: 0,
                start: 0,
                end: None
            }
        );
        assert_eq!(
            back[1],
            Occupancy {
                lane: 1,
                start: 10,
                end: Some(18)
            }
        );
    }
}
