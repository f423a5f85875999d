//! The scene's step function (DESIGN.md §1.1): the robot, its lateral state and every
//! obstacle, one control period at a time.
//!
//! The robot's longitudinal motion is exactly the single-obstacle one ([`robot_motion`]);
//! lane changes do not change it. Each obstacle keeps its own gap and observation history
//! (latency L, as in [`World`](crate::core::semantics::World)), and its own safety record
//! ([`super::safety`]). With one moving obstacle in lane 0, [`SceneWorld::step`] makes the
//! same decisions and the same numbers as `World::step` (a test holds them equal).

use std::collections::VecDeque;
use std::sync::Arc;

use crate::core::num::Scalar;
use crate::core::semantics::{BrakeReason, Mode, Motion, Observation, RobotState, robot_motion};

use super::guards::{Command, scene_guard};
use super::lateral::{LaneChangeEvent, Lateral};
use super::params::SceneParams;
use super::safety::{MovingSpan, Side, StepSafety, step_safety};

/// One obstacle in one control period.
#[derive(Clone, Debug, PartialEq)]
pub struct ObstacleStep<N> {
    /// Gap at the period's start.
    pub gap: N,
    /// Its speed over the period.
    pub speed: N,
    /// What the robot saw of it at the period's start (None: nothing yet, or beyond the
    /// sensing range).
    pub seen: Option<Observation<N>>,
    /// Gap at the period's end.
    pub end_gap: N,
    /// Gap at the instant the robot came to rest, if it did in this period.
    pub rest_gap: Option<N>,
    /// The robot occupied its lane throughout the period.
    pub occupied: bool,
    /// The period's share of its safety (None: the robot did not move in its lane).
    pub safety: Option<StepSafety<N>>,
}

impl<N> ObstacleStep<N> {
    /// The robot moved in its lane with separation ≤ clearance at some instant of the period.
    pub fn collision(&self) -> bool {
        self.safety.as_ref().is_some_and(|s| s.collision)
    }
}

/// Everything that happened in one control period of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneStepRecord<N> {
    /// Step index k; the period is [k·dt, (k+1)·dt].
    pub k: usize,
    /// The robot at the period's start, with the mode the controller chose for it.
    pub robot: RobotState<N>,
    /// The robot's lateral state over the period (a change begun at its start included).
    pub lateral: Lateral,
    /// Set when the controller commanded Brake at this period's start.
    pub brake: Option<BrakeReason>,
    /// Set when the controller began a lane change at this period's start.
    pub lane_change: Option<LaneChangeEvent>,
    /// The robot's motion over the period.
    pub motion: Motion<N>,
    /// Each obstacle over the period, in the scene's order.
    pub obstacles: Vec<ObstacleStep<N>>,
}

impl<N> SceneStepRecord<N> {
    /// Whether the robot collided with any obstacle in this period.
    pub fn collision(&self) -> bool {
        self.obstacles.iter().any(ObstacleStep::collision)
    }
}

/// One obstacle's state: its gap, what the robot can still observe of its past, and the
/// side of the robot's current occupancy interval of its lane.
#[derive(Clone, Debug)]
struct Track<N> {
    gap: N,
    /// Gaps at the starts of the last L+1 periods, newest last.
    gaps: VecDeque<N>,
    /// Its speeds over the last L+1 periods, newest last.
    speeds: VecDeque<N>,
    /// The side of the occupancy interval the robot is in, if it occupies the lane.
    side: Option<Side>,
}

impl<N: Scalar> Track<N> {
    /// The gap at (k−L)·dt and the speed over period k−L−1 (0 before the first period);
    /// nothing before L·dt. (As `World::observation`.)
    fn observation(&self, k: usize, l: usize) -> Option<Observation<N>> {
        if k < l {
            return None;
        }
        let gap = if l == 0 {
            self.gap.clone()
        } else {
            self.gaps[self.gaps.len() - l].clone()
        };
        let speed = if k < l + 1 {
            N::zero()
        } else {
            self.speeds[self.speeds.len() - l - 1].clone()
        };
        Some(Observation { gap, speed })
    }

    fn remember(&mut self, gap: N, w: N, l: usize) {
        self.gaps.push_back(gap);
        self.speeds.push_back(w);
        while self.gaps.len() > l + 1 {
            self.gaps.pop_front();
        }
        while self.speeds.len() > l + 1 {
            self.speeds.pop_front();
        }
    }
}

/// The robot and a scene's obstacles under the scene semantics.
#[derive(Clone, Debug)]
pub struct SceneWorld<N> {
    /// Shared by every clone: an explorer clones worlds by the million, and the
    /// parameters never change.
    params: Arc<SceneParams<N>>,
    k: usize,
    robot: RobotState<N>,
    lateral: Lateral,
    tracks: Vec<Track<N>>,
}

impl<N: Scalar> SceneWorld<N> {
    /// The scene at t = 0: the robot at rest at x = 0 in lane 0, about to accelerate;
    /// obstacle i at x = `starts[i]` (its number, or the chosen point of its range).
    ///
    /// # Panics
    /// If `starts` does not give one start per obstacle.
    pub fn new(params: SceneParams<N>, starts: Vec<N>) -> Self {
        assert_eq!(
            starts.len(),
            params.obstacles.len(),
            "one start per obstacle"
        );
        let l = params.robot.L;
        SceneWorld {
            k: 0,
            robot: RobotState::initial(&params.robot),
            lateral: Lateral::start(),
            tracks: starts
                .into_iter()
                .map(|gap| Track {
                    gap,
                    gaps: VecDeque::with_capacity(l + 2),
                    speeds: VecDeque::with_capacity(l + 2),
                    side: None,
                })
                .collect(),
            params: Arc::new(params),
        }
    }

    /// The scene's parameters.
    pub fn params(&self) -> &SceneParams<N> {
        &self.params
    }

    /// Index of the next period.
    pub fn k(&self) -> usize {
        self.k
    }

    /// The robot now.
    pub fn robot(&self) -> &RobotState<N> {
        &self.robot
    }

    /// The robot's lateral state at the start of the next period.
    pub fn lateral(&self) -> Lateral {
        self.lateral
            .at_step(self.k, self.params.lane_change_periods())
    }

    /// Obstacle i's gap now.
    pub fn gap(&self, i: usize) -> &N {
        &self.tracks[i].gap
    }

    /// Obstacle i's remembered past, oldest first: the gaps at the starts of the last
    /// periods and its speeds over them (at most L+1 of each; later observations are read
    /// from them). An explorer keys its states on them.
    pub fn history(&self, i: usize) -> (&VecDeque<N>, &VecDeque<N>) {
        let track = &self.tracks[i];
        (&track.gaps, &track.speeds)
    }

    /// The side of the robot's occupancy interval of obstacle i's lane as of the last period
    /// (None: the robot did not occupy that lane in it, or no period has run yet).
    pub fn side(&self, i: usize) -> Option<Side> {
        self.tracks[i].side
    }

    /// Whether the robot has come to rest for good.
    pub fn stopped(&self) -> bool {
        self.robot.mode == Mode::Stop
    }

    /// What the robot sees of obstacle i at the start of the next period: the observation
    /// of §1, unless it shows a gap beyond the sensing range.
    pub fn seen(&self, i: usize) -> Option<Observation<N>> {
        let obs = self.observation_if_shown(i)?;
        self.within_range(obs)
    }

    /// The true observation of obstacle i at the start of the next period (the gap at
    /// (k−L)·dt and its speed over period k−L−1, 0 before the first period; None before
    /// L·dt), before any noise, occlusion or sensing range: what an environment choosing
    /// the robot's observations ([`SceneWorld::step_seeing`]) starts from.
    pub fn observation_if_shown(&self, i: usize) -> Option<Observation<N>> {
        self.tracks[i].observation(self.k, self.params.robot.L)
    }

    /// `obs` unless its gap is beyond the sensing range.
    fn within_range(&self, obs: Observation<N>) -> Option<Observation<N>> {
        match &self.params.sensing_range {
            Some(range) if obs.gap > *range => None,
            _ => Some(obs),
        }
    }

    /// Whether nothing can happen any more: no guard can fire again and no obstacle's
    /// separation can fall further, so running on would change no outcome (the robot would
    /// drive on for ever).
    ///
    /// Guards fire only for a relevant obstacle (in the lane the robot is in or moving
    /// into, observed at a gap in (0, ρ]); the destination guard only with a goal. Observed
    /// gaps never grow, so once every obstacle of that lane has been observed at a gap ≤ 0,
    /// none ever becomes relevant again; with no goal and the robot in Accelerate or Drive
    /// no guard fires again, so the lateral state only completes a change in progress, and
    /// the robot occupies no lane it does not occupy now. Obstacles in the other lanes then
    /// never matter. In an occupied lane, an obstacle whose occupancy interval began beside
    /// or behind the robot has separation −gap, which only grows: it is settled. One whose
    /// interval began ahead is not (its gap still falls while the robot moves: it has been
    /// passed through, a collision, and the run goes on to deepen it).
    pub fn settled(&self) -> bool {
        if self.params.goal.is_some() || !matches!(self.robot.mode, Mode::Accelerate | Mode::Drive)
        {
            return false;
        }
        let lateral = self.lateral();
        let l = self.params.robot.L;
        self.params.obstacles.iter().enumerate().all(|(i, o)| {
            let track = &self.tracks[i];
            let behind = || track.side.unwrap_or_else(|| Side::of(&track.gap)) == Side::Behind;
            if o.lane == lateral.lane {
                // Seen at a gap ≤ 0 whatever the error (a hidden obstacle is first shown at
                // a gap ≥ d_det > 0, so never again).
                let past = track
                    .observation(self.k, l)
                    .is_some_and(|obs| obs.gap <= -self.params.robot.sigma_g.clone());
                past && behind()
            } else if lateral.occupies(o.lane) {
                behind()
            } else {
                true
            }
        })
    }

    /// What the robot sees of each obstacle at the next step start when the environment
    /// shows `shown(i, truth)` (see [`SceneWorld::step_seeing`]), the sensing range applied.
    fn seen_with(
        &self,
        shown: &mut impl FnMut(usize, Observation<N>) -> Option<Observation<N>>,
    ) -> Vec<Option<Observation<N>>> {
        (0..self.tracks.len())
            .map(|i| {
                let truth = self.observation_if_shown(i)?;
                self.within_range(shown(i, truth)?)
            })
            .collect()
    }

    /// The controller's command at the next step start if the environment shows
    /// `shown(i, truth)` (as [`SceneWorld::step_seeing`] would), without stepping: None when
    /// the robot neither accelerates nor drives (no guard is evaluated). An explorer
    /// groups the environment's observation choices by it.
    pub fn command_seeing(
        &self,
        mut shown: impl FnMut(usize, Observation<N>) -> Option<Observation<N>>,
    ) -> Option<Command> {
        if !matches!(self.robot.mode, Mode::Accelerate | Mode::Drive) {
            return None;
        }
        let seen = self.seen_with(&mut shown);
        Some(scene_guard(
            &self.params,
            &self.robot,
            &self.lateral(),
            &seen,
        ))
    }

    /// Advance one control period with obstacle i moving at `speeds[i]` (the caller keeps
    /// 0 ≤ `speeds[i]` ≤ W_i; nothing here checks it).
    ///
    /// # Panics
    /// If `speeds` does not give one speed per obstacle.
    pub fn step(&mut self, speeds: &[N]) -> SceneStepRecord<N> {
        self.step_seeing(speeds, |_, truth| Some(truth))
    }

    /// [`SceneWorld::step`] with the robot's observations chosen by the environment:
    /// `shown(i, truth)` is what the robot is shown of obstacle i when its true observation
    /// is `truth` (None: hidden). Observation noise and occlusion (docs/semantics.md §12)
    /// are such choices; the caller keeps them within the premises (errors within ±σ, a
    /// first sighting at a true gap ≥ d_det), nothing here checks it. The sensing range
    /// applies to what is shown.
    ///
    /// # Panics
    /// If `speeds` does not give one speed per obstacle.
    pub fn step_seeing(
        &mut self,
        speeds: &[N],
        mut shown: impl FnMut(usize, Observation<N>) -> Option<Observation<N>>,
    ) -> SceneStepRecord<N> {
        assert_eq!(speeds.len(), self.tracks.len(), "one speed per obstacle");
        let k = self.k;
        let mut lateral = self.lateral();
        let seen = self.seen_with(&mut shown);
        let mut brake = None;
        let mut lane_change = None;
        if matches!(self.robot.mode, Mode::Accelerate | Mode::Drive) {
            match scene_guard(&self.params, &self.robot, &lateral, &seen) {
                Command::Go => {}
                Command::Brake(reason) => {
                    brake = Some(reason);
                    self.robot.mode = Mode::Brake;
                }
                Command::ChangeLane(to) => lane_change = Some(lateral.begin_change(k, to)),
            }
        }
        if self.robot.mode == Mode::Brake && self.robot.speed <= N::zero() {
            self.robot.mode = Mode::Stop;
        }
        let p = &self.params;
        let start = self.robot.clone();
        let motion = robot_motion(&p.robot, &start);
        let travelled = motion.end.position.clone() - start.position.clone();
        let came_to_rest = motion.came_to_rest();
        let moving = motion.moving_for > N::zero();
        let span = MovingSpan {
            start_speed: &start.speed,
            came_to_rest,
        };
        let mut obstacles = Vec::with_capacity(self.tracks.len());
        for ((track, o), (w, seen)) in self
            .tracks
            .iter_mut()
            .zip(&p.obstacles)
            .zip(speeds.iter().zip(seen))
        {
            let gap = track.gap.clone();
            let end_gap = gap.clone() - w.clone() * p.robot.dt.clone() - travelled.clone();
            let rest_gap = came_to_rest
                .then(|| gap.clone() - w.clone() * motion.moving_for.clone() - travelled.clone());
            let occupied = lateral.occupies(o.lane);
            if occupied {
                track.side.get_or_insert_with(|| Side::of(&gap));
            } else {
                track.side = None;
            }
            let safety = match track.side {
                Some(side) if moving => {
                    let low = rest_gap.as_ref().unwrap_or(&end_gap);
                    Some(step_safety(side, &p.robot.clearance, &gap, low, &span))
                }
                _ => None,
            };
            obstacles.push(ObstacleStep {
                gap: gap.clone(),
                speed: w.clone(),
                seen,
                end_gap: end_gap.clone(),
                rest_gap,
                occupied,
                safety,
            });
            track.remember(gap, w.clone(), p.robot.L);
            track.gap = end_gap;
        }
        let record = SceneStepRecord {
            k,
            robot: start,
            lateral,
            brake,
            lane_change,
            motion: motion.clone(),
            obstacles,
        };
        self.lateral = lateral;
        self.robot = motion.end;
        self.k += 1;
        record
    }
}
