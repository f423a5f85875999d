//! The exact replay of one planar behaviour (docs/semantics.md §13): the controller's
//! guards at every step start, the robot's motion along its path, and every obstacle's
//! least separation over the moving instants, inside steps included ([`run`],
//! [`PlanarReplay`]).
//!
//! One step k, in the order of §13 and the line's `World::step`:
//! 1. while the robot accelerates or drives, the guards are evaluated: the destination guard
//!    on its own state (the path ends and s + v²/(2b) ≥ its length); from k ≥ L every
//!    visible obstacle (range, field of view, occlusion at the observed instant j = k − L)
//!    is seen at its centre at j·dt plus the error of observation k, relative to the
//!    robot's centre then and in its frame then, with the velocity it held in step j − 1
//!    (0 for j = 0) plus the velocity error. Danger, then wrong assumption, then destination
//!    name the guard; the first obstacle in file order names the obstacle;
//! 2. a guard that fires latches Brake; a Brake at speed 0 is Stop at once;
//! 3. the robot moves as on the line (`robot_motion`: the plant brakes at b_min), each
//!    obstacle along its velocity, and each obstacle's separation over the step's moving
//!    instants is bracketed exactly ([`super::separation`]).
//!
//! Occlusion (an obstacle that hides): it stays unseen at observation k until its
//! separation has fallen to d_det at some instant ≤ j·dt — on a whole earlier step, decided
//! by Sturm sequences, or at j·dt itself. The replay stops once the robot is at rest for
//! good, or after the asked number of steps.

use crate::core::num::Exact;
use crate::core::plane::point::Point;
use crate::core::semantics::{Mode, RobotState, robot_motion};

use super::behaviour::{BehaviourError, ObstacleBehaviour, PlanarBehaviour, velocity_allowed};
use super::observe::{dangerous, visible, wrong_assumption};
use super::params::PlanarParams;
use super::phases::motion_phases;
use super::pieces::path_pieces;
use super::separation::{Separation, Track};

/// Which guard braked the robot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PlanarGuard {
    /// This obstacle was seen in the danger zone.
    Danger {
        /// Its index.
        obstacle: usize,
    },
    /// This obstacle was seen within ρ and faster than V_a.
    WrongAssumption {
        /// Its index.
        obstacle: usize,
    },
    /// Braking now brings the robot to rest at the path's end or beyond.
    Destination,
}

/// When and why the robot braked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BrakeEvent {
    /// The step at whose start the guard fired.
    pub step: usize,
    /// Which guard.
    pub guard: PlanarGuard,
}

/// A finished replay.
#[derive(Clone, Debug)]
pub struct PlanarRun {
    /// Steps replayed.
    pub steps: usize,
    /// The brake, if a guard fired.
    pub brake: Option<BrakeEvent>,
    /// The instant the robot came to rest (s), if it did (a Brake at speed 0 rests at once).
    pub rest: Option<Exact>,
    tracks: Vec<Track>,
}

impl PlanarRun {
    /// Obstacle `i`'s least separation over the moving instants (None: the robot never
    /// moved).
    pub fn separation(&self, i: usize) -> Option<Separation> {
        self.tracks[i].separation()
    }

    /// The obstacle with the least separation (by the bracket's upper end) and its bracket.
    pub fn closest(&self) -> Option<(usize, Separation)> {
        (0..self.tracks.len())
            .filter_map(|i| self.separation(i).map(|s| (i, s)))
            .min_by(|a, b| a.1.upper.cmp(&b.1.upper))
    }

    /// Whether some obstacle's separation is ≤ `clearance` at some moving instant (§13.5),
    /// decided exactly; None only where a surd vertex crossing's bound leaves it open.
    pub fn collides(&self, clearance: &Exact) -> Option<bool> {
        let mut unsure = false;
        for t in &self.tracks {
            match t.collides(clearance) {
                Some(true) => return Some(true),
                Some(false) => {}
                None => unsure = true,
            }
        }
        (!unsure).then_some(false)
    }
}

/// What each obstacle does in one step: its velocity and the errors of the observation
/// made at the step's start.
#[derive(Clone, Debug, PartialEq)]
pub struct StepChoice {
    /// The velocity over the step.
    pub velocity: Point,
    /// The seen centre's error at this step's observation.
    pub position_error: Point,
    /// The seen velocity's error at this step's observation.
    pub velocity_error: Point,
}

impl StepChoice {
    /// Moving at `velocity`, seen exactly.
    pub fn moving(velocity: Point) -> Self {
        StepChoice {
            velocity,
            position_error: Point::origin(),
            velocity_error: Point::origin(),
        }
    }
}

/// A replay in progress, one step at a time (clone it to branch: the brute-force oracle
/// shares prefixes so).
#[derive(Clone, Debug)]
pub struct PlanarReplay<'a> {
    params: &'a PlanarParams,
    k: usize,
    robot: RobotState<Exact>,
    /// The robot's arc length at each step start so far.
    arcs: Vec<Exact>,
    /// Per obstacle: its centre at each step start so far.
    centres: Vec<Vec<Point>>,
    /// Per obstacle: its velocity in each step so far.
    velocities: Vec<Vec<Point>>,
    /// Per obstacle: hiding, with the first step (if any) whose instants brought it to d_det.
    hiding: Vec<Option<Option<usize>>>,
    brake: Option<BrakeEvent>,
    rest: Option<Exact>,
    tracks: Vec<Track>,
}

impl<'a> PlanarReplay<'a> {
    /// The replay at t = 0 with these starts and hiding choices (velocities and errors come
    /// step by step).
    pub fn new(
        params: &'a PlanarParams,
        starts: &[Point],
        hides: &[bool],
    ) -> Result<Self, BehaviourError> {
        let probe = PlanarBehaviour {
            obstacles: starts
                .iter()
                .zip(hides.iter().chain(std::iter::repeat(&false)))
                .map(|(s, h)| ObstacleBehaviour {
                    hide: *h,
                    ..ObstacleBehaviour::moving(s.clone(), Vec::new())
                })
                .collect(),
        };
        probe.validate(params)?;
        let replay = PlanarReplay {
            params,
            k: 0,
            robot: RobotState::initial(&params.motion),
            arcs: vec![Exact::ZERO],
            centres: starts.iter().map(|s| vec![s.clone()]).collect(),
            velocities: vec![Vec::new(); starts.len()],
            hiding: probe
                .obstacles
                .iter()
                .map(|o| o.hide.then_some(None))
                .collect(),
            brake: None,
            rest: None,
            tracks: params
                .obstacles
                .iter()
                .map(|o| Track::new(&params.robot_radius + &o.radius))
                .collect(),
        };
        for i in 0..starts.len() {
            replay.confined(i, 0)?;
        }
        Ok(replay)
    }

    /// Steps replayed so far.
    pub fn k(&self) -> usize {
        self.k
    }

    /// The robot's state at the current step start (arc length along the path, speed,
    /// mode).
    pub fn robot(&self) -> &RobotState<Exact> {
        &self.robot
    }

    /// The robot's centre at the current step start.
    pub fn robot_centre(&self) -> Point {
        self.params.path.point_at(&self.robot.position)
    }

    /// Whether the robot is at rest for good (nothing later can move it).
    pub fn stopped(&self) -> bool {
        self.robot.mode == Mode::Stop
    }

    /// The brake so far.
    pub fn brake(&self) -> Option<BrakeEvent> {
        self.brake
    }

    /// Obstacle `i`'s separation bracket so far.
    pub fn separation(&self, i: usize) -> Option<Separation> {
        self.tracks[i].separation()
    }

    /// Obstacle `i`'s centre now.
    pub fn centre(&self, i: usize) -> &Point {
        self.centres[i].last().expect("never empty")
    }

    /// Replays one step with these choices, one per obstacle.
    pub fn step(&mut self, choices: &[StepChoice]) -> Result<(), BehaviourError> {
        let p = self.params;
        let k = self.k;
        if choices.len() != p.obstacles.len() {
            return Err(BehaviourError::ObstacleCount {
                expected: p.obstacles.len(),
                found: choices.len(),
            });
        }
        for (i, (c, o)) in choices.iter().zip(&p.obstacles).enumerate() {
            velocity_allowed(o, &c.velocity).map_err(|off| off.at(i, k))?;
            let s = &p.sensing;
            let noise = BehaviourError::Noise {
                obstacle: i,
                step: k,
            };
            if c.position_error.norm_squared() > &s.position_noise * &s.position_noise
                || c.velocity_error.norm_squared() > &s.velocity_noise * &s.velocity_noise
            {
                return Err(noise);
            }
        }
        let (robot, fired) = self.decided(choices);
        if let Some(guard) = fired {
            self.brake = Some(BrakeEvent { step: k, guard });
        }
        let t0 = Exact::from(k) * &p.motion.dt;
        if robot.mode == Mode::Stop && self.robot.mode != Mode::Stop {
            self.rest.get_or_insert(t0.clone());
        }
        self.robot = robot;
        let phases = motion_phases(&p.motion, &self.robot);
        let pieces = path_pieces(&p.path, &phases);
        for (i, c) in choices.iter().enumerate() {
            let fall = match self.hiding[i] {
                Some(None) => p.sensing.first_detection.as_ref().map(|d| {
                    let reach = d + &p.robot_radius + &p.obstacles[i].radius;
                    &reach * &reach
                }),
                _ => None,
            };
            let x = self.centre(i).clone();
            let fell =
                self.tracks[i].add_period(&p.path, &pieces, &t0, &x, &c.velocity, fall.as_ref());
            if fell {
                self.hiding[i] = Some(Some(k));
            }
            self.centres[i].push(&x + &(&c.velocity * &p.motion.dt));
            self.velocities[i].push(c.velocity.clone());
            self.confined(i, k + 1)?;
        }
        let motion = robot_motion(&p.motion, &self.robot);
        if motion.came_to_rest() {
            self.rest = Some(&t0 + &motion.moving_for);
        }
        self.robot = motion.end;
        self.arcs.push(self.robot.position.clone());
        self.k += 1;
        Ok(())
    }

    /// The robot's centre at the end of the step that `choices` would replay, without
    /// replaying it: the robot's motion in a step depends on the obstacles only through the
    /// guards at its start (observations of earlier instants and these choices' errors).
    pub fn robot_centre_after(&self, choices: &[StepChoice]) -> Point {
        let (robot, _) = self.decided(choices);
        let motion = robot_motion(&self.params.motion, &robot);
        self.params.path.point_at(&motion.end.position)
    }

    /// The robot's state for this step after the guards at its start, and the guard that
    /// fired (a brake latches; braking at speed 0 is rest).
    fn decided(&self, choices: &[StepChoice]) -> (RobotState<Exact>, Option<PlanarGuard>) {
        let mut robot = self.robot.clone();
        let mut fired = None;
        if matches!(robot.mode, Mode::Accelerate | Mode::Drive)
            && let Some(guard) = self.guards(choices)
        {
            fired = Some(guard);
            robot.mode = Mode::Brake;
        }
        if robot.mode == Mode::Brake && robot.speed <= Exact::ZERO {
            robot.mode = Mode::Stop;
        }
        (robot, fired)
    }

    /// The guard that fires at this step's start, if any (module docs, item 1).
    fn guards(&self, choices: &[StepChoice]) -> Option<PlanarGuard> {
        let p = self.params;
        let m = &p.motion;
        let (mut danger, mut wrong) = (None, None);
        if self.k >= m.L {
            let j = self.k - m.L;
            let centre = p.path.point_at(&self.arcs[j]);
            let heading = p.path.heading_at(&self.arcs[j]).unit();
            for (i, c) in choices.iter().enumerate() {
                let rel = &self.centres[i][j] - &centre;
                if !visible(p, &rel, heading) || self.hidden(i, j, &rel) {
                    continue;
                }
                let seen = &rel + &c.position_error;
                let moved = match j {
                    0 => Point::origin(),
                    _ => self.velocities[i][j - 1].clone(),
                };
                let velocity = &moved + &c.velocity_error;
                if danger.is_none() && dangerous(p, i, &seen, heading, &self.robot.speed) {
                    danger = Some(i);
                }
                if wrong.is_none() && wrong_assumption(p, i, &seen, &velocity) {
                    wrong = Some(i);
                }
            }
        }
        let destination = p.path_ends && {
            let v = &self.robot.speed;
            &self.robot.position + &(v * v / (Exact::from(2) * &m.b)) >= p.path.length()
        };
        match (danger, wrong) {
            (Some(obstacle), _) => Some(PlanarGuard::Danger { obstacle }),
            (None, Some(obstacle)) => Some(PlanarGuard::WrongAssumption { obstacle }),
            (None, None) => destination.then_some(PlanarGuard::Destination),
        }
    }

    /// Whether hiding obstacle `i` is still unseen at observed instant j (true centre `rel`
    /// from the robot's then): its separation has not yet fallen to d_det.
    fn hidden(&self, i: usize, j: usize, rel: &Point) -> bool {
        let Some(fell) = self.hiding[i] else {
            return false;
        };
        if fell.is_some_and(|m| m < j) {
            return false;
        }
        let p = self.params;
        let d = p.sensing.first_detection.as_ref().expect("validated");
        let reach = d + &p.robot_radius + &p.obstacles[i].radius;
        rel.norm_squared() > &reach * &reach
    }

    /// Obstacle `i` is in its region at the start of step k.
    fn confined(&self, i: usize, k: usize) -> Result<(), BehaviourError> {
        match &self.params.obstacles[i].region {
            Some(q) if !q.contains(&self.centres[i][k]) => Err(BehaviourError::LeavesRegion {
                obstacle: i,
                step: k,
            }),
            _ => Ok(()),
        }
    }

    /// The replay so far, finished.
    pub fn finish(self) -> PlanarRun {
        PlanarRun {
            steps: self.k,
            brake: self.brake,
            rest: self.rest,
            tracks: self.tracks,
        }
    }
}

/// Replays `behaviour` on `params` exactly for at most `steps` steps, stopping once the robot
/// is at rest for good (module docs).
pub fn run(
    params: &PlanarParams,
    behaviour: &PlanarBehaviour,
    steps: usize,
) -> Result<PlanarRun, BehaviourError> {
    run_observed(params, behaviour, steps, |_| {})
}

/// [`run`], showing `observe` the replay at every step start (and at the end): for traces.
pub fn run_observed(
    params: &PlanarParams,
    behaviour: &PlanarBehaviour,
    steps: usize,
    mut observe: impl FnMut(&PlanarReplay<'_>),
) -> Result<PlanarRun, BehaviourError> {
    behaviour.validate(params)?;
    let starts: Vec<Point> = behaviour
        .obstacles
        .iter()
        .map(|o| o.start.clone())
        .collect();
    let hides: Vec<bool> = behaviour.obstacles.iter().map(|o| o.hide).collect();
    let mut replay = PlanarReplay::new(params, &starts, &hides)?;
    while replay.k() < steps && !replay.stopped() {
        let k = replay.k();
        let choices: Vec<StepChoice> = behaviour
            .obstacles
            .iter()
            .map(|o| StepChoice {
                velocity: o.velocity(k),
                position_error: o.position_error(k),
                velocity_error: o.velocity_error(k),
            })
            .collect();
        observe(&replay);
        replay.step(&choices)?;
    }
    observe(&replay);
    Ok(replay.finish())
}
