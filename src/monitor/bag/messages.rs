//! The ROS 2 messages the monitor reads from a bag, as serde types for the CDR decoder of
//! `cdr-encoding`: fields in the order of their `.msg` definitions, since CDR is a plain
//! sequence of aligned values with no field names. Values the monitor does not use
//! (covariances, frame ids, shapes) are still decoded, because the next field's offset
//! depends on them, but into types that keep nothing.

use std::fmt;
use std::marker::PhantomData;

use byteorder::{BigEndian, LittleEndian};
use serde::Deserialize;
use serde::de::{self, Deserializer, SeqAccess, Visitor};

/// `builtin_interfaces/msg/Time`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Time {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds, `0..1e9`.
    pub nanosec: u32,
}

impl Time {
    /// The time in seconds: the nanosecond count divided once, so a stamp written from a
    /// decimal time (`2.1` → 2 s 100000000 ns) reads back as the double nearest that decimal,
    /// exactly as a text trace's `2.1` does. (Exact up to 2⁵³ ns, about 104 days, past any
    /// robot's bag; beyond, correctly rounded all the same.)
    pub fn seconds(self) -> f64 {
        let ns = i64::from(self.sec) * 1_000_000_000 + i64::from(self.nanosec);
        ns as f64 / 1e9
    }
}

/// `std_msgs/msg/Header`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Header {
    /// When the data was taken.
    pub stamp: Time,
    /// The frame of the data (unused: positions are projected on the lane axis).
    pub frame_id: Ignored<String>,
}

/// `geometry_msgs/msg/Point` and `geometry_msgs/msg/Vector3`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Vector3 {
    /// x (m, or m/s in a twist).
    pub x: f64,
    /// y.
    pub y: f64,
    /// z (unused: the lane is planar).
    pub z: f64,
}

/// `geometry_msgs/msg/Quaternion`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Quaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

/// `geometry_msgs/msg/Pose`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Pose {
    /// Position (m).
    pub position: Vector3,
    /// Orientation.
    pub orientation: Quaternion,
}

/// `geometry_msgs/msg/Twist` and `geometry_msgs/msg/Accel`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Twist {
    /// Linear velocity (m/s) or acceleration (m/s²).
    pub linear: Vector3,
    /// Angular velocity (unused).
    pub angular: Vector3,
}

/// A 6×6 covariance (`float64[36]`), read and dropped.
#[derive(Clone, Copy, Debug)]
pub struct Covariance;

impl<'de> Deserialize<'de> for Covariance {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Skip;
        impl<'de> Visitor<'de> for Skip {
            type Value = Covariance;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("36 float64 values")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Covariance, A::Error> {
                for k in 0..36 {
                    if seq.next_element::<f64>()?.is_none() {
                        return Err(de::Error::invalid_length(k, &self));
                    }
                }
                Ok(Covariance)
            }
        }
        // A fixed-size array: CDR writes no length.
        d.deserialize_tuple(36, Skip)
    }
}

/// `geometry_msgs/msg/PoseWithCovariance`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct PoseWithCovariance {
    /// The pose.
    pub pose: Pose,
    /// Its covariance (dropped).
    pub covariance: Covariance,
}

/// `geometry_msgs/msg/TwistWithCovariance` and `geometry_msgs/msg/AccelWithCovariance`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct TwistWithCovariance {
    /// The twist (or acceleration).
    pub twist: Twist,
    /// Its covariance (dropped).
    pub covariance: Covariance,
}

/// `nav_msgs/msg/Odometry`: the robot's, or one obstacle's. The twist is in the child frame
/// (the body), as the message definition says.
#[derive(Clone, Debug, Deserialize)]
pub struct Odometry {
    /// Stamp and frame of the pose.
    pub header: Header,
    /// The body frame: names an obstacle published on its own topic.
    pub child_frame_id: String,
    /// Pose in the header's frame.
    pub pose: PoseWithCovariance,
    /// Velocity in the child frame.
    pub twist: TwistWithCovariance,
}

/// `unique_identifier_msgs/msg/UUID`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Uuid {
    /// The 16 bytes.
    pub uuid: [u8; 16],
}

/// `autoware_perception_msgs/msg/ObjectClassification` (dropped).
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct ObjectClassification {
    /// Class label.
    pub label: u8,
    /// Its probability.
    pub probability: f32,
}

/// `autoware_perception_msgs/msg/TrackedObjectKinematics`. The twist is in the object's
/// frame (its pose's orientation), as Autoware's trackers write it.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct TrackedObjectKinematics {
    /// Pose in the message header's frame.
    pub pose_with_covariance: PoseWithCovariance,
    /// Velocity in the object's frame.
    pub twist_with_covariance: TwistWithCovariance,
    /// Acceleration (dropped).
    pub acceleration_with_covariance: TwistWithCovariance,
    /// Whether the orientation is known (dropped).
    pub orientation_availability: u8,
    /// The tracker's stationary flag (dropped: the monitor judges motion itself).
    pub is_stationary: bool,
}

/// `geometry_msgs/msg/Point32`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Point32 {
    /// x.
    pub x: f32,
    /// y.
    pub y: f32,
    /// z.
    pub z: f32,
}

/// `autoware_perception_msgs/msg/Shape` (dropped).
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct Shape {
    /// Bounding box, cylinder or polygon.
    #[serde(rename = "type")]
    pub kind: u8,
    /// `geometry_msgs/msg/Polygon`: its points.
    pub footprint: Ignored<Vec<Point32>>,
    /// Size (m).
    pub dimensions: Vector3,
}

/// `autoware_perception_msgs/msg/TrackedObject`.
#[derive(Clone, Copy, Debug, Deserialize)]
pub struct TrackedObject {
    /// The tracker's id of the object, stable over its track.
    pub object_id: Uuid,
    /// Existence probability (dropped: every tracked object is checked).
    pub existence_probability: f32,
    /// Classes (dropped).
    pub classification: Ignored<Vec<ObjectClassification>>,
    /// Pose and velocity.
    pub kinematics: TrackedObjectKinematics,
    /// Shape (dropped).
    pub shape: Shape,
}

/// `autoware_perception_msgs/msg/TrackedObjects`.
#[derive(Clone, Debug, Deserialize)]
pub struct TrackedObjects {
    /// Stamp and frame of every object's pose.
    pub header: Header,
    /// The objects.
    pub objects: Vec<TrackedObject>,
}

/// `std_msgs/msg/String`: the robot's mode on the mode topic.
#[derive(Clone, Debug, Deserialize)]
pub struct Text {
    /// The text.
    pub data: String,
}

/// A value decoded (its bytes must be consumed to reach the next field) and not kept: a
/// sequence is read element by element, a string is checked for UTF-8 and dropped, and
/// neither allocates.
#[derive(Debug)]
pub struct Ignored<T>(PhantomData<T>);

// By hand: derived, they would ask `T` to be `Copy`, and nothing of `T` is kept.
impl<T> Clone for Ignored<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for Ignored<T> {}

impl<'de> Deserialize<'de> for Ignored<String> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Drop;
        impl Visitor<'_> for Drop {
            type Value = Ignored<String>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a string")
            }
            fn visit_str<E: de::Error>(self, _: &str) -> Result<Self::Value, E> {
                Ok(Ignored(PhantomData))
            }
        }
        d.deserialize_str(Drop)
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Ignored<Vec<T>> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Drop<T>(PhantomData<T>);
        impl<'de, T: Deserialize<'de>> Visitor<'de> for Drop<T> {
            type Value = Ignored<Vec<T>>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a sequence")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                while seq.next_element::<T>()?.is_some() {}
                Ok(Ignored(PhantomData))
            }
        }
        d.deserialize_seq(Drop(PhantomData))
    }
}

/// Why a message payload could not be decoded, in words a log reader understands.
pub(crate) fn why(e: &cdr_encoding::Error) -> &'static str {
    match e {
        cdr_encoding::Error::Eof => "the message ends before its last field",
        cdr_encoding::Error::BadBoolean(_) => "a boolean that is neither 0 nor 1",
        cdr_encoding::Error::BadUTF8(_) => "a string that is not UTF-8",
        _ => "not CDR of the topic's message type",
    }
}

/// Decodes a ROS 2 payload: a 4-byte encapsulation header (plain CDR, little- or big-endian;
/// the options bytes are ignored), then the message, aligned from the end of the header.
/// Bytes after the message (padding, or fields of a newer definition) are ignored.
pub fn decode<'a, T: Deserialize<'a>>(payload: &'a [u8]) -> Result<T, &'static str> {
    let [0, kind, _, _, body @ ..] = payload else {
        return Err("not CDR: the 4-byte encapsulation header is missing or not plain CDR");
    };
    let decoded = match kind {
        0 => cdr_encoding::from_bytes::<T, BigEndian>(body),
        1 => cdr_encoding::from_bytes::<T, LittleEndian>(body),
        _ => return Err("encapsulated as something other than plain CDR (e.g. XCDR2)"),
    };
    decoded.map(|(value, _)| value).map_err(|e| why(&e))
}
