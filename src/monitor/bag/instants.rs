//! Robot instants assembled from a bag's messages: each robot odometry message is an
//! instant, checked once the next one has arrived (the mode of an instant may be stated, or
//! inferred, only after it), with the obstacle observations stamped at or before it.

use std::collections::VecDeque;

use crate::core::semantics::Mode;
use crate::monitor::planar::{PlanarRobotSample, PlanarSample};
use crate::monitor::{ObstacleId, RobotSample, Sample};

use super::axis::LaneAxis;
use super::{BagItem, BagOptions, SpeedSource};

/// A robot odometry message, in the odometry frame.
#[derive(Clone, Copy, Debug)]
pub(super) struct Robot {
    /// Header stamp (s).
    pub t: f64,
    /// Position (m).
    pub position: [f64; 2],
    /// Velocity (m/s); `None` when the pose's orientation is not a rotation.
    pub velocity: Option<[f64; 2]>,
    /// Its message number.
    pub message: u64,
}

/// One obstacle observation, in the odometry frame.
#[derive(Clone, Copy, Debug)]
pub(super) struct Observation {
    /// The obstacle.
    pub id: ObstacleId,
    /// Header stamp (s): when it was observed.
    pub t: f64,
    /// Position (m).
    pub position: [f64; 2],
    /// Velocity (m/s); `None` when unknown.
    pub velocity: Option<[f64; 2]>,
    /// Its message number.
    pub message: u64,
}

/// Observations waiting for an instant, at most one per obstacle (a later one replaces an
/// earlier), in arrival order.
#[derive(Default)]
struct Pool {
    list: Vec<Observation>,
    /// Each obstacle's index in `list`, or `NONE`.
    slot: Vec<u32>,
}

const NONE: u32 = u32::MAX;

impl Pool {
    /// Adds `o`; true when it replaced an observation of the same obstacle.
    fn put(&mut self, o: Observation) -> bool {
        let id = o.id as usize;
        if id >= self.slot.len() {
            self.slot.resize(id + 1, NONE);
        }
        match self.slot[id] {
            NONE => {
                self.slot[id] = self.list.len() as u32;
                self.list.push(o);
                false
            }
            k => {
                self.list[k as usize] = o;
                true
            }
        }
    }

    fn clear(&mut self) {
        for o in &self.list {
            self.slot[o.id as usize] = NONE;
        }
        self.list.clear();
    }
}

/// Whether an observation stamped `t` is due at the instant `at`. A NaN stamp is due at
/// once: the monitor rejects it as non-finite rather than it waiting for ever.
#[inline]
fn due(t: f64, at: f64) -> bool {
    t <= at || t.is_nan()
}

/// The assembly of instants.
pub(super) struct Instants {
    pub axis: Option<LaneAxis>,
    /// Keep the plane (a planar certificate's samples).
    pub plane: bool,
    infer_mode: bool,
    speeds: SpeedSource,
    ground_truth: bool,
    /// The last robot message, waiting for the next.
    current: Option<Robot>,
    /// The mode the mode topic stated last.
    pub mode: Option<Mode>,
    /// Observations due at `current`.
    assigned: Pool,
    /// Observations stamped after `current` (or before any robot message).
    future: Pool,
    /// Items ready for the monitor.
    pub out: VecDeque<BagItem>,
    /// Observations replaced before being checked.
    pub superseded: u64,
    /// Observations after the last instant.
    pub unpaired: u64,
}

impl Instants {
    pub(super) fn new(options: &BagOptions) -> Self {
        Instants {
            axis: options.lane_axis,
            plane: options.plane,
            infer_mode: options.infer_mode,
            speeds: options.obstacle_speed,
            ground_truth: options.ground_truth,
            current: None,
            mode: None,
            assigned: Pool::default(),
            future: Pool::default(),
            out: VecDeque::new(),
            superseded: 0,
            unpaired: 0,
        }
    }

    /// An obstacle observation: due at the waiting instant when stamped at or before it,
    /// else at the first later instant at or after its stamp.
    pub(super) fn observe(&mut self, o: Observation) {
        let pool = match self.current {
            Some(r) if due(o.t, r.t) => &mut self.assigned,
            _ => &mut self.future,
        };
        self.superseded += u64::from(pool.put(o));
    }

    /// A robot message: the previous instant is complete now, and observations stamped up
    /// to this one are due at it.
    pub(super) fn robot(&mut self, r: Robot) {
        if let Some(previous) = self.current.replace(r) {
            self.emit(previous, Some(r));
        }
        let future = std::mem::take(&mut self.future.list);
        for o in &future {
            self.future.slot[o.id as usize] = NONE;
        }
        for o in future {
            let pool = if due(o.t, r.t) {
                &mut self.assigned
            } else {
                &mut self.future
            };
            self.superseded += u64::from(pool.put(o));
        }
    }

    /// The end of the bag: the last instant is checked, later observations are not.
    pub(super) fn finish(&mut self) {
        if let Some(last) = self.current.take() {
            self.emit(last, None);
        }
        self.unpaired += self.future.list.len() as u64;
        self.future.clear();
    }

    /// Checks the instant `r`, whose successor is `next`: its robot state, and the
    /// observations due at it.
    fn emit(&mut self, r: Robot, next: Option<Robot>) {
        let Some(axis) = self.axis else {
            self.assigned.clear();
            return;
        };
        if self.plane {
            return self.emit_planar(axis, r, next);
        }
        let along = |v: Option<[f64; 2]>| v.map_or(f64::NAN, |v| axis.along(v));
        let robot_v = along(r.velocity);
        let robot_mode = if self.infer_mode {
            next.and_then(|n| inferred(robot_v, along(n.velocity)))
        } else {
            self.mode
        };
        let robot_x = axis.position(r.position);
        if self.assigned.list.is_empty() {
            self.out.push_back(BagItem::Robot {
                sample: RobotSample {
                    t: r.t,
                    robot_x,
                    robot_v,
                    robot_mode,
                },
                message: r.message,
            });
            return;
        }
        for o in &self.assigned.list {
            let obstacle_v = match self.speeds {
                SpeedSource::Twist => o.velocity.map(|v| -axis.along(v)),
                SpeedSource::Positions => None,
            };
            self.out.push_back(BagItem::Sample {
                sample: Sample {
                    t: r.t,
                    robot_x,
                    robot_v,
                    robot_mode,
                    obstacle_id: o.id,
                    obstacle_x: axis.position(o.position),
                    obstacle_v,
                    obstacle_t: (!self.ground_truth).then_some(o.t),
                },
                message: o.message,
            });
        }
        self.assigned.clear();
    }
}

impl Instants {
    /// [`Instants::emit`] in the plane: positions and velocities in the axis's frame, the
    /// robot's speed its velocity's norm.
    fn emit_planar(&mut self, axis: LaneAxis, r: Robot, next: Option<Robot>) {
        let speed = |v: Option<[f64; 2]>| v.map_or(f64::NAN, |v| v[0].hypot(v[1]));
        let robot_v = speed(r.velocity);
        let robot_mode = if self.infer_mode {
            next.and_then(|n| inferred(robot_v, speed(n.velocity)))
        } else {
            self.mode
        };
        let [robot_x, robot_y] = axis.local(r.position);
        let robot = PlanarRobotSample {
            t: r.t,
            robot_x,
            robot_y,
            robot_v,
            robot_mode,
        };
        if self.assigned.list.is_empty() {
            self.out.push_back(BagItem::PlanarRobot {
                sample: robot,
                message: r.message,
            });
            return;
        }
        for o in &self.assigned.list {
            let [obstacle_x, obstacle_y] = axis.local(o.position);
            let obstacle_velocity = match self.speeds {
                SpeedSource::Twist => o.velocity.map(|v| {
                    let [x, y] = axis.rotate(v);
                    (x, y)
                }),
                SpeedSource::Positions => None,
            };
            self.out.push_back(BagItem::PlanarSample {
                sample: PlanarSample {
                    t: r.t,
                    robot_x,
                    robot_y,
                    robot_v,
                    robot_mode,
                    obstacle_id: o.id,
                    obstacle_x,
                    obstacle_y,
                    obstacle_velocity,
                },
                message: o.message,
            });
        }
        self.assigned.clear();
    }
}

/// The mode of an instant at speed `v` whose next instant has speed `next`, for a robot
/// that moves as the model does: slower is braking, faster accelerating, the same speed
/// and moving is driving. At rest it states nothing (the monitor counts a robot at rest as
/// passive either way).
fn inferred(v: f64, next: f64) -> Option<Mode> {
    if !(v.is_finite() && next.is_finite()) {
        return None;
    }
    if next < v {
        Some(Mode::Brake)
    } else if next > v {
        Some(Mode::Accelerate)
    } else if v > 0.0 {
        Some(Mode::Drive)
    } else {
        None
    }
}
