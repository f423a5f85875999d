//! ROS 2 bags (MCAP) as monitor input: odometry and tracked objects read straight from the
//! recording, projected on the lane, and assembled into the samples a text trace would
//! hold (docs/monitor.md, "ROS 2 bags").
//!
//! [`BagReader`] reads an MCAP stream (`mcap`, with its zstd and lz4 chunk decoders) and
//! decodes CDR payloads (`cdr-encoding`) of three message types:
//!
//! - the robot: `nav_msgs/msg/Odometry` on [`BagOptions::robot_topic`]. Each message is one
//!   **instant** (the robot's control step), at its header stamp;
//! - obstacles: `autoware_perception_msgs/msg/TrackedObjects` (one observation per object,
//!   named by its UUID in hex) or `nav_msgs/msg/Odometry` (one obstacle per topic, named by
//!   its `child_frame_id`, or the topic when that is empty), on the topics
//!   [`BagOptions::obstacle_topics`] match — by default every `TrackedObjects` topic;
//! - optionally the robot's mode: `std_msgs/msg/String` (`brake`, `drive`, …) on
//!   [`BagOptions::mode_topic`]. A mode message states the mode from the robot instant
//!   before it on (the controller decides after it sees the state) and holds until the next.
//!
//! An obstacle observation stamped at or before an instant and not yet checked is checked at
//! that instant, with `obstacle_t` its stamp: it is what the controller has then, so latency
//! is monitored and a reaction to it is due at that instant. (A simulator's ground truth is
//! read with [`BagOptions::ground_truth`] instead.) When an obstacle has several such
//! observations, the latest is checked. Observations stamped after the last
//! instant are counted in [`BagStats::unpaired`], not checked.
//!
//! Positions are projected on a [`LaneAxis`]: the one given, or the line through the robot's
//! first pose along its heading. Twists are in the body frame (as both message types define
//! them) and are rotated by the pose before projection; an obstacle's speed towards the
//! robot is minus its velocity along the lane. With [`SpeedSource::Positions`] obstacle
//! twists are ignored and the monitor estimates speeds from successive positions.
//!
//! Everything that cannot be trusted is a fail-safe event ([`BagItem::Malformed`]), never a
//! panic: a payload that is not CDR of its type, a selected topic of a type this reader does
//! not know, a mode that is not a mode, a corrupt or truncated bag (reading stops there).
//! Messages on other topics are skipped and counted.
//!
//! Bags carry no lanes: samples state none (`Lanes::UNKNOWN`), as a text trace without lane
//! columns does.

mod axis;
mod instants;
pub mod messages;
mod reader;
mod topics;

pub use axis::{LaneAxis, world_velocity};
pub use reader::BagReader;

use crate::monitor::planar::{PlanarMonitor, PlanarRobotSample, PlanarSample};
use crate::monitor::trace::Ids;
use crate::monitor::{DEFAULT_MAX_OBSTACLES, Detail, Lanes, Monitor, Outcome, RobotSample, Sample};

/// Where obstacle speeds come from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpeedSource {
    /// The message's twist, projected on the lane: `obstacle_v`, compared exactly.
    #[default]
    Twist,
    /// None given: the monitor estimates each speed from successive positions.
    Positions,
}

/// How a bag is read.
#[derive(Clone, Debug)]
pub struct BagOptions {
    /// The robot's `nav_msgs/msg/Odometry` topic.
    pub robot_topic: String,
    /// Obstacle topics, as glob patterns (`/obstacles/*/odom`); empty: every topic of type
    /// `autoware_perception_msgs/msg/TrackedObjects`.
    pub obstacle_topics: Vec<String>,
    /// The robot's mode (`std_msgs/msg/String`), if recorded.
    pub mode_topic: Option<String>,
    /// Without a mode topic: infer the mode of each instant from the robot's speed at the
    /// next (slower: `brake`, faster: `accelerate`, equal and moving: `drive`). Exact for a
    /// robot that moves as the model does; a real robot's speed jitter would be read as
    /// brief braking, so prefer a mode topic.
    pub infer_mode: bool,
    /// The lane; `None`: through the robot's first pose, along its heading.
    pub lane_axis: Option<LaneAxis>,
    /// Where obstacle speeds come from.
    pub obstacle_speed: SpeedSource,
    /// Obstacle messages are ground truth (a simulator's true positions at their stamps),
    /// not the observations the controller had: samples then carry no `obstacle_t`, and the
    /// monitor takes the controller to see each position the latency L later, as it reads a
    /// `simulate --trace` CSV. Latency is then not monitored.
    pub ground_truth: bool,
    /// Most distinct obstacles (ids beyond are fail-safe events).
    pub max_obstacles: u32,
    /// For a planar certificate: positions and velocities stay in the plane, in the frame
    /// whose origin and x axis are `lane_axis` (default: the odometry frame itself), and
    /// items are [`BagItem::PlanarSample`]s and [`BagItem::PlanarRobot`]s. An observation is
    /// taken as the obstacle's position at the instant it is due at (latency is not
    /// monitored on planar traces); the robot's speed is its velocity's norm.
    pub plane: bool,
}

impl Default for BagOptions {
    fn default() -> BagOptions {
        BagOptions {
            robot_topic: "/odom".to_string(),
            obstacle_topics: Vec::new(),
            mode_topic: None,
            infer_mode: false,
            lane_axis: None,
            obstacle_speed: SpeedSource::Twist,
            ground_truth: false,
            max_obstacles: DEFAULT_MAX_OBSTACLES,
            plane: false,
        }
    }
}

/// A bad [`BagOptions`] value.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BagOptionError {
    /// An obstacle topic pattern is not a glob.
    #[error("obstacle topic pattern {pattern:?} is not a glob: {reason}")]
    BadPattern {
        /// The pattern.
        pattern: String,
        /// Why.
        reason: String,
    },
    /// Both a mode topic and mode inference.
    #[error("a mode topic and mode inference exclude each other: the topic states the mode")]
    TwoModeSources,
}

/// What one step of a bag gives the monitor: one sample, or a fail-safe event. `message` is
/// the 1-based number, in file order, of the message it came from (the obstacle's for a
/// sample, the robot's for a robot-only instant).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum BagItem {
    /// An obstacle observation at a robot instant: feed to the monitor with the obstacle's
    /// name from [`BagReader::ids`].
    Sample {
        /// The sample.
        sample: Sample,
        /// Its message.
        message: u64,
    },
    /// A robot instant at which no obstacle was observed.
    Robot {
        /// The robot.
        sample: RobotSample,
        /// Its message.
        message: u64,
    },
    /// With [`BagOptions::plane`]: an obstacle observation at a robot instant.
    PlanarSample {
        /// The sample.
        sample: PlanarSample,
        /// Its message.
        message: u64,
    },
    /// With [`BagOptions::plane`]: a robot instant at which no obstacle was observed.
    PlanarRobot {
        /// The robot.
        sample: PlanarRobotSample,
        /// Its message.
        message: u64,
    },
    /// A message or part of the bag that cannot be trusted.
    Malformed {
        /// The time, when it could be read.
        t: Option<f64>,
        /// What is wrong.
        detail: Detail,
        /// Its message (the last one read, for a corrupt bag).
        message: u64,
    },
}

impl BagItem {
    /// The 1-based number of the message it came from.
    pub fn message(&self) -> u64 {
        match *self {
            BagItem::Sample { message, .. }
            | BagItem::Robot { message, .. }
            | BagItem::PlanarSample { message, .. }
            | BagItem::PlanarRobot { message, .. }
            | BagItem::Malformed { message, .. } => message,
        }
    }

    /// Its time, when it has one that could be read.
    pub fn t(&self) -> Option<f64> {
        match *self {
            BagItem::Sample { sample, .. } => Some(sample.t),
            BagItem::Robot { sample, .. } => Some(sample.t),
            BagItem::PlanarSample { sample, .. } => Some(sample.t),
            BagItem::PlanarRobot { sample, .. } => Some(sample.t),
            BagItem::Malformed { t, .. } => t,
        }
    }
}

impl Monitor {
    /// Checks one item of a bag: a sample (its obstacle named by `ids`, the reader's
    /// [`BagReader::ids`]), a robot-only instant, or a fail-safe event. Bags state no lanes.
    /// The one way every caller (the command line, Python, the fuzz target) feeds a bag.
    pub fn observe_bag_item(&mut self, ids: &Ids, item: &BagItem) -> Outcome<'_> {
        match *item {
            BagItem::Sample { sample, .. } => self.observe_named(ids, &sample, Lanes::UNKNOWN),
            BagItem::Robot { sample, .. } => self.observe_robot(&sample, Lanes::UNKNOWN),
            BagItem::Malformed { t, detail, .. } => self.malformed(t, detail),
            // A bag read for a planar certificate: not a line's sample.
            BagItem::PlanarSample { sample, .. } => self.malformed(Some(sample.t), PLANAR_ITEM),
            BagItem::PlanarRobot { sample, .. } => self.malformed(Some(sample.t), PLANAR_ITEM),
        }
    }
}

const PLANAR_ITEM: Detail =
    Detail::BadMessage("a planar sample (the bag was read with BagOptions::plane)");

impl PlanarMonitor {
    /// Checks one item of a bag read with [`BagOptions::plane`]: a planar sample (its
    /// obstacle named by `ids` and matched to the certificate's by that name), a robot-only
    /// instant, or a fail-safe event.
    pub fn observe_bag_item(&mut self, ids: &Ids, item: &BagItem) -> Outcome<'_> {
        match *item {
            BagItem::PlanarSample { sample, .. } => {
                self.identify_once(sample.obstacle_id, ids.name(sample.obstacle_id));
                self.observe(&sample)
            }
            BagItem::PlanarRobot { sample, .. } => self.observe_robot(&sample),
            BagItem::Malformed { t, detail, .. } => self.malformed(t, detail),
            BagItem::Sample { sample, .. } => self.malformed(Some(sample.t), LINE_ITEM),
            BagItem::Robot { sample, .. } => self.malformed(Some(sample.t), LINE_ITEM),
        }
    }
}

const LINE_ITEM: Detail =
    Detail::BadMessage("a line's sample (the bag was read without BagOptions::plane)");

/// What was read, for the summary and for users looking for a misnamed topic.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BagStats {
    /// Messages read, on any topic.
    pub messages: u64,
    /// Robot odometry messages (instants).
    pub robot: u64,
    /// Obstacle observations (one per tracked object).
    pub observations: u64,
    /// Mode messages.
    pub modes: u64,
    /// Observations replaced by a later one of the same obstacle before their instant.
    pub superseded: u64,
    /// Observations stamped after the last robot instant: not checked.
    pub unpaired: u64,
    /// Messages on topics the reader does not use.
    pub skipped: u64,
    /// Every topic in the bag, in order of first appearance, with its message type.
    pub topics: Vec<(String, String)>,
}
