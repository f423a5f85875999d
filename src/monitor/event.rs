//! What the monitor reports: an [`Event`] per violation (which check, at which sample, by how
//! much, what to do), the [`Detail`] of unreadable input, and the standing [`Verdict`].
//!
//! Checks describe a violation with the small [`Violation`] builder; the monitor stamps it
//! with the sample's index and the action and keeps it as an [`Event`].

use std::fmt;

use serde::{Deserialize, Serialize};

use super::{Check, Field, ObstacleId, Sample};

/// What a violation asks the robot to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Action {
    /// Enter the passive safe state: brake to a stop.
    Brake,
}

impl Action {
    /// The word used in output.
    pub fn as_str(self) -> &'static str {
        match self {
            Action::Brake => "brake",
        }
    }
}

/// Why a sample was malformed or non-finite, without allocating.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum Detail {
    /// The value of this field is NaN or infinite (or JSON `null` in a required field).
    NonFinite(Field),
    /// The obstacle id is beyond the monitor's table.
    ObstacleIdOutOfRange {
        /// Ids must be below this.
        limit: u32,
    },
    /// A new obstacle, but the reader's table of obstacle ids is full.
    TooManyObstacles {
        /// Most obstacles a trace may have.
        limit: u32,
    },
    /// The robot's position, speed or mode differs from the first sample of the same instant.
    RobotStateDiffers,
    /// A required field is missing.
    MissingField(Field),
    /// A field is not a number.
    BadNumber(Field),
    /// `robot_mode` is not one of idle, accelerate, drive, brake, stop.
    BadMode,
    /// `obstacle_id` is neither a string nor an integer.
    BadId,
    /// A lane column holds something other than an integer.
    BadLane(Field),
    /// A CSV row with a different number of fields than the header.
    FieldCount {
        /// Fields in the row.
        found: u32,
        /// Columns in the header.
        expected: u32,
    },
    /// The CSV header lacks a required column.
    MissingColumn(Field),
    /// The CSV header names a column twice.
    DuplicateColumn(Field),
    /// A CSV data line with no usable header before it.
    NoHeader,
    /// The first CSV line is data (it starts with a number), not a header.
    HeaderIsData,
    /// A line longer than the reader accepts.
    LineTooLong {
        /// Longest accepted line (bytes).
        limit: u32,
    },
    /// A CSV syntax error (quoting).
    Csv(&'static str),
    /// A JSON syntax error.
    Json(&'static str),
    /// A JSON object with the same key twice.
    DuplicateKey(Field),
    /// `controller_reaction`: the observation showed collision danger.
    Danger,
    /// `controller_reaction`: the observation showed an obstacle faster than V_a.
    WrongAssumption,
    /// `robot_envelope`: the robot's speed (m/s) above v_max.
    AboveTopSpeed,
    /// `robot_envelope`: the robot's acceleration (m/s²) above a.
    AboveAcceleration,
    /// `observation_dropout`: the obstacle was last seen inside the reaction area.
    Dropout,
    /// `observation_dropout` (planar): the obstacle was last seen where it stays in view
    /// until the next instant (all-round sensing, within range).
    DropoutInView,
    /// `uncertified_obstacle`: the certificate has no obstacle of the object's name.
    NotInCertificate,
    /// `controller_reaction` (planar): the robot drives on where braking at b no longer
    /// stops it before its path's end (the destination guard).
    Destination,
    /// `robot_motion`: the robot moved (m) while its mode (`stop` or `idle`) says it stands.
    MovedWhileStanding,
    /// `robot_motion`: the robot moved (m) farther than its speeds and mode allow.
    MovedTooFar,
    /// `robot_motion`: the robot moved (m) less far than its speeds and mode allow.
    MovedTooLittle,
    /// `collision`: the least separation the premises allow within the step that ended at
    /// the sample, while the robot still moved.
    WithinStep,
    /// A bag message that is not CDR of its topic's type (what is wrong).
    BadMessage(&'static str),
    /// A bag topic the monitor was told to read, of a type it does not read.
    UnknownMessageType,
    /// The robot's first pose has no heading, so the lane's direction is unknown.
    NoLaneAxis,
    /// The bag itself is corrupt or truncated (what is wrong); reading stops.
    CorruptBag(&'static str),
}

impl Detail {
    /// How observed and bound compare, where this detail says it differently from its
    /// check's [`Check::relation`] (`robot_motion` below its least: `<`).
    pub fn relation(self) -> Option<&'static str> {
        match self {
            Detail::MovedTooLittle => Some("<"),
            _ => None,
        }
    }
}

impl fmt::Display for Detail {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Detail::NonFinite(field) => write!(f, "{field} is not a finite number"),
            Detail::ObstacleIdOutOfRange { limit } => {
                write!(
                    f,
                    "obstacle id beyond the monitor's table (ids must be < {limit})"
                )
            }
            Detail::TooManyObstacles { limit } => {
                write!(f, "more than {limit} distinct obstacle ids")
            }
            Detail::RobotStateDiffers => f.write_str(
                "robot state differs from the first sample of the same instant (same t)",
            ),
            Detail::MissingField(field) => write!(f, "{field} is missing"),
            Detail::BadNumber(field) => write!(f, "{field} is not a number"),
            Detail::BadMode => {
                f.write_str("robot_mode is not one of idle, accelerate, drive, brake, stop")
            }
            Detail::BadId => f.write_str("obstacle_id is neither a string nor an integer"),
            Detail::BadLane(field) => write!(f, "{field} is not a lane (an integer)"),
            Detail::FieldCount { found, expected } => {
                write!(f, "{found} fields, but the header has {expected} columns")
            }
            Detail::MissingColumn(field) => {
                write!(
                    f,
                    "the header has no column {field} (required: t, robot_x, robot_v, obstacle_id, obstacle_x)"
                )
            }
            Detail::DuplicateColumn(field) => write!(f, "the header names {field} twice"),
            Detail::NoHeader => f.write_str("no usable CSV header before this line"),
            Detail::HeaderIsData => f.write_str(
                "the first line is data, not a header: name the columns of a CSV without a \
                 header with --columns (e.g. --columns t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v)",
            ),
            Detail::LineTooLong { limit } => write!(f, "line longer than {limit} bytes"),
            Detail::Csv(what) => write!(f, "not a CSV row: {what}"),
            Detail::Json(what) => write!(f, "not a JSON sample: {what}"),
            Detail::DuplicateKey(field) => write!(f, "key {field} given twice"),
            Detail::Danger => f.write_str(
                "the observed gap (m) was within the danger distance min(rho, d(v)) and the robot was not braking",
            ),
            Detail::WrongAssumption => f.write_str(
                "an obstacle in the reaction area (gap, bound rho, m) was seen faster than the assumed V_a and the robot was not braking",
            ),
            Detail::AboveTopSpeed => f.write_str("robot speed (m/s) above v_max"),
            Detail::AboveAcceleration => f.write_str("robot acceleration (m/s^2) above a"),
            Detail::Dropout => f.write_str(
                "last observed gap (m) inside the reaction radius rho, and the next instant came without this obstacle",
            ),
            Detail::DropoutInView => f.write_str(
                "last observed separation (m) where the obstacle stays in view (all-round sensing, within range) until the next instant, which came without it",
            ),
            Detail::NotInCertificate => f.write_str(
                "the certificate has no obstacle of this name, so its proof says nothing about this object",
            ),
            Detail::Destination => f.write_str(
                "the arc length (m) at which braking at b stops the robot is at or beyond its path's end, and it did not brake",
            ),
            Detail::MovedWhileStanding => f.write_str(
                "robot displacement (m) since the previous instant, in mode stop or idle, which stands still",
            ),
            Detail::MovedTooFar => f.write_str(
                "robot displacement (m) since the previous instant beyond the most its speeds and mode allow \
                 (speed up to v_max, speeding up at most at a, slowing at least at b while braking)",
            ),
            Detail::MovedTooLittle => f.write_str(
                "robot displacement (m) since the previous instant below the least its speeds and mode allow \
                 (speeding up at most at a, slowing at least at b while braking)",
            ),
            Detail::WithinStep => f.write_str(
                "the least separation (m) the premises allow while the robot moved within the step \
                 before this sample (the robot moving on to where this sample shows it, for as long as \
                 braking at b from its last speed allows; the obstacle approaching at up to its bound)",
            ),
            Detail::BadMessage(what) => write!(f, "unreadable bag message: {what}"),
            Detail::UnknownMessageType => f.write_str(
                "the topic's message type is not one the monitor reads (nav_msgs/msg/Odometry, \
                 autoware_perception_msgs/msg/TrackedObjects; std_msgs/msg/String for the mode) \
                 or is not CDR-encoded",
            ),
            Detail::NoLaneAxis => f.write_str(
                "the robot's first pose has no heading (zero or non-finite orientation), so the \
                 lane's direction is unknown: give --lane-axis X,Y,YAW",
            ),
            Detail::CorruptBag(what) => write!(f, "the bag is corrupt: {what}; reading stopped"),
        }
    }
}

/// A violation: which check failed at which sample, by how much, and what to do.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Event {
    /// Index of the sample that raised it (0-based count of samples fed to the monitor,
    /// malformed ones included).
    pub sample: u64,
    /// Time of the sample (s); `None` when it could not be read.
    pub t: Option<f64>,
    /// The obstacle of the sample, when known.
    pub obstacle_id: Option<ObstacleId>,
    /// The check that failed.
    #[serde(rename = "premise")]
    pub check: Check,
    /// The observed value (in [`Check::unit`]); `None` for malformed and non-finite input.
    pub observed: Option<f64>,
    /// The bound it broke.
    pub bound: Option<f64>,
    /// What the robot must do.
    pub action: Action,
    /// For malformed and non-finite input: what is wrong.
    #[serde(serialize_with = "serialize_detail")]
    #[cfg_attr(feature = "schema", schemars(with = "Option<String>"))]
    pub detail: Option<Detail>,
}

fn serialize_detail<S: serde::Serializer>(d: &Option<Detail>, s: S) -> Result<S::Ok, S::Error> {
    match d {
        Some(d) => s.collect_str(d),
        None => s.serialize_none(),
    }
}

impl fmt::Display for Event {
    /// `premise observed X > bound Y unit -> brake`, or `premise: detail -> brake`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.check)?;
        if let (Some(o), Some(b)) = (self.observed, self.bound) {
            let unit = self.check.unit();
            let sep = if unit.is_empty() { "" } else { " " };
            let relation = self.detail.and_then(Detail::relation);
            write!(
                f,
                " observed {o}{sep}{unit} {} bound {b}{sep}{unit}",
                relation.unwrap_or(self.check.relation())
            )?;
        } else if let Some(o) = self.observed {
            write!(f, " observed {o} {}", self.check.unit())?;
        }
        if let Some(d) = &self.detail {
            write!(f, ": {d}")?;
        }
        write!(f, " -> {}", self.action.as_str())
    }
}

/// The standing verdict.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Every premise has held on every sample so far.
    Held,
    /// Some sample violated a premise (latched: it never returns to `Held`).
    Violated,
}

impl Verdict {
    /// The word used in output.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Held => "held",
            Verdict::Violated => "violated",
        }
    }
}

/// What one sample produced.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome<'a> {
    /// The standing verdict after this sample.
    pub verdict: Verdict,
    /// The violations this sample raised (usually none), in the order the checks ran.
    pub events: &'a [Event],
}

/// A violation as a check describes it, before the monitor stamps it with the sample's index
/// and the action: `Violation::at(check, sample).observed(x).bound(b)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Violation {
    pub(crate) check: Check,
    pub(crate) t: Option<f64>,
    pub(crate) obstacle_id: Option<ObstacleId>,
    pub(crate) observed: Option<f64>,
    pub(crate) bound: Option<f64>,
    pub(crate) detail: Option<Detail>,
}

impl Violation {
    /// A violation of `check` by sample `s` (its time and obstacle).
    #[inline]
    pub(crate) fn at(check: Check, s: &Sample) -> Violation {
        Violation {
            check,
            t: Some(s.t),
            obstacle_id: (s.obstacle_id != super::ROBOT_ONLY).then_some(s.obstacle_id),
            observed: None,
            bound: None,
            detail: None,
        }
    }

    /// A violation of `check` by input that may have no time or obstacle.
    #[inline]
    pub(crate) fn of_input(
        check: Check,
        t: Option<f64>,
        obstacle_id: Option<ObstacleId>,
    ) -> Violation {
        Violation {
            check,
            t,
            obstacle_id,
            observed: None,
            bound: None,
            detail: None,
        }
    }

    /// The value observed.
    #[inline]
    pub(crate) fn observed(self, observed: f64) -> Violation {
        Violation {
            observed: Some(observed),
            ..self
        }
    }

    /// The bound it broke.
    #[inline]
    pub(crate) fn bound(self, bound: f64) -> Violation {
        Violation {
            bound: Some(bound),
            ..self
        }
    }

    /// What is wrong with the input.
    #[inline]
    pub(crate) fn detail(self, detail: Detail) -> Violation {
        Violation {
            detail: Some(detail),
            ..self
        }
    }

    /// The event of sample number `sample`.
    #[inline]
    pub(crate) fn event(self, sample: u64) -> Event {
        Event {
            sample,
            t: self.t,
            obstacle_id: self.obstacle_id,
            check: self.check,
            observed: self.observed,
            bound: self.bound,
            action: Action::Brake,
            detail: self.detail,
        }
    }
}
