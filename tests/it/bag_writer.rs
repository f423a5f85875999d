//! ROS 2 bags written by the tests: MCAP files (the `mcap` crate's writer) whose payloads are
//! CDR encoded here by hand, field by field from the message definitions — independent of
//! the serde decoder the monitor reads them with, so a field-order or alignment mistake on
//! either side shows up as a disagreement.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use mcap::records::MessageHeader;
use mcap::{Compression, WriteOptions, Writer};

/// A CDR payload under construction: the little-endian encapsulation header, then fields
/// aligned to their size, counted from the end of the header.
pub struct Cdr(Vec<u8>);

impl Cdr {
    pub fn new() -> Cdr {
        Cdr(vec![0, 1, 0, 0])
    }
    fn align(&mut self, n: usize) {
        while !(self.0.len() - 4).is_multiple_of(n) {
            self.0.push(0);
        }
    }
    pub fn u8(&mut self, v: u8) -> &mut Self {
        self.0.push(v);
        self
    }
    pub fn u32(&mut self, v: u32) -> &mut Self {
        self.align(4);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    pub fn i32(&mut self, v: i32) -> &mut Self {
        self.align(4);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    pub fn f32(&mut self, v: f32) -> &mut Self {
        self.align(4);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    pub fn f64(&mut self, v: f64) -> &mut Self {
        self.align(8);
        self.0.extend_from_slice(&v.to_le_bytes());
        self
    }
    /// A string: its length with the terminating NUL, its bytes, the NUL.
    pub fn string(&mut self, s: &str) -> &mut Self {
        self.u32(s.len() as u32 + 1);
        self.0.extend_from_slice(s.as_bytes());
        self.0.push(0);
        self
    }
    pub fn bytes(self) -> Vec<u8> {
        self.0
    }
}

/// A stamp from a time written in decimal (`2.1`): whole seconds and nanoseconds, exactly.
pub fn stamp(text: &str) -> (i32, u32) {
    let (sec, frac) = text.split_once('.').unwrap_or((text, ""));
    assert!(frac.len() <= 9, "{text}: more than nanosecond precision");
    let nanos = format!("{frac:0<9}");
    (sec.parse().unwrap(), nanos.parse().unwrap())
}

/// A planar pose and body-frame velocity.
#[derive(Clone, Copy, Debug)]
pub struct Body {
    pub position: [f64; 2],
    /// Quaternion (x, y, z, w).
    pub orientation: [f64; 4],
    /// Body-frame linear velocity (x forward, y left).
    pub velocity: [f64; 2],
}

/// A yaw as a quaternion; exact at 0 and π (the test lanes' headings).
pub fn yaw(angle: f64) -> [f64; 4] {
    if angle == 0.0 {
        return [0.0, 0.0, 0.0, 1.0];
    }
    if angle == std::f64::consts::PI {
        return [0.0, 0.0, 1.0, 0.0];
    }
    [0.0, 0.0, (angle / 2.0).sin(), (angle / 2.0).cos()]
}

fn header(c: &mut Cdr, (sec, nanosec): (i32, u32), frame: &str) {
    c.i32(sec).u32(nanosec).string(frame);
}

fn pose_twist(c: &mut Cdr, b: &Body) {
    // geometry_msgs/PoseWithCovariance: Point, Quaternion, float64[36].
    c.f64(b.position[0]).f64(b.position[1]).f64(0.0);
    for q in b.orientation {
        c.f64(q);
    }
    for k in 0..36 {
        c.f64(k as f64 * 0.5);
    }
    // geometry_msgs/TwistWithCovariance: linear, angular, float64[36].
    c.f64(b.velocity[0]).f64(b.velocity[1]).f64(0.0);
    c.f64(0.0).f64(0.0).f64(0.01);
    for _ in 0..36 {
        c.f64(0.0);
    }
}

/// `nav_msgs/msg/Odometry`.
pub fn odometry(stamp: (i32, u32), child_frame_id: &str, b: &Body) -> Vec<u8> {
    let mut c = Cdr::new();
    header(&mut c, stamp, "odom");
    c.string(child_frame_id);
    pose_twist(&mut c, b);
    c.bytes()
}

/// `autoware_perception_msgs/msg/TrackedObjects`.
pub fn tracked_objects(stamp: (i32, u32), objects: &[([u8; 16], Body)]) -> Vec<u8> {
    let mut c = Cdr::new();
    header(&mut c, stamp, "map");
    c.u32(objects.len() as u32);
    for (uuid, b) in objects {
        for byte in uuid {
            c.u8(*byte);
        }
        c.f32(0.9); // existence_probability
        c.u32(2); // classification: two entries
        c.u8(1).f32(0.7).u8(7).f32(0.3);
        // TrackedObjectKinematics: pose, twist, acceleration (a twist-shaped record), then
        // orientation_availability and is_stationary.
        pose_twist(&mut c, b);
        for _ in 0..6 {
            c.f64(0.0);
        }
        for _ in 0..36 {
            c.f64(0.0);
        }
        c.u8(2).u8(0);
        // Shape: type, footprint (geometry_msgs/Polygon of Point32), dimensions.
        c.u8(0);
        c.u32(3);
        for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            c.f32(p[0]).f32(p[1]).f32(p[2]);
        }
        c.f64(4.5).f64(1.8).f64(1.5);
    }
    c.bytes()
}

/// `std_msgs/msg/String`.
pub fn text(data: &str) -> Vec<u8> {
    let mut c = Cdr::new();
    c.string(data);
    c.bytes()
}

/// The message types' definitions, as `ros2 bag record` stores them (abridged to the top
/// level: the reader never parses them).
fn definition(kind: &str) -> &'static str {
    match kind {
        "nav_msgs/msg/Odometry" => {
            "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\ngeometry_msgs/TwistWithCovariance twist\n"
        }
        "autoware_perception_msgs/msg/TrackedObjects" => {
            "std_msgs/Header header\nautoware_perception_msgs/TrackedObject[] objects\n"
        }
        "std_msgs/msg/String" => "string data\n",
        _ => "float64 x\n",
    }
}

/// An MCAP bag being written.
pub struct Bag {
    writer: Writer<BufWriter<File>>,
    channels: BTreeMap<String, u16>,
    sequence: u32,
}

impl Bag {
    pub fn create(path: &Path, compression: Option<Compression>) -> Bag {
        let options = WriteOptions::new()
            .compression(compression)
            .profile("ros2")
            .chunk_size(Some(64 * 1024));
        Bag::with_options(path, options)
    }

    /// A bag for the fuzzer's corpus: uncompressed and without CRCs (0 means "not computed"),
    /// so that a mutated byte reaches the CDR decoder instead of failing a checksum.
    pub fn for_fuzzing(path: &Path) -> Bag {
        let options = WriteOptions::new()
            .compression(None)
            .profile("ros2")
            .calculate_chunk_crcs(false)
            .calculate_data_section_crc(false)
            .calculate_summary_section_crc(false)
            .emit_summary_records(false)
            .emit_message_indexes(false)
            .emit_chunk_indexes(false);
        Bag::with_options(path, options)
    }

    fn with_options(path: &Path, options: WriteOptions) -> Bag {
        let file = BufWriter::new(File::create(path).unwrap());
        Bag {
            writer: options.create(file).unwrap(),
            channels: BTreeMap::new(),
            sequence: 0,
        }
    }

    /// Writes `data` on `topic` (of message type `kind`, declared at first use) at `log_ns`.
    pub fn write(&mut self, topic: &str, kind: &str, log_ns: u64, data: &[u8]) {
        self.write_encoded(topic, kind, "cdr", log_ns, data);
    }

    pub fn write_encoded(
        &mut self,
        topic: &str,
        kind: &str,
        encoding: &str,
        log_ns: u64,
        data: &[u8],
    ) {
        let channel = match self.channels.get(topic) {
            Some(&c) => c,
            None => {
                let schema = self
                    .writer
                    .add_schema(kind, "ros2msg", definition(kind).as_bytes())
                    .unwrap();
                let c = self
                    .writer
                    .add_channel(schema, topic, encoding, &BTreeMap::new())
                    .unwrap();
                self.channels.insert(topic.to_string(), c);
                c
            }
        };
        self.sequence += 1;
        let header = MessageHeader {
            channel_id: channel,
            sequence: self.sequence,
            log_time: log_ns,
            publish_time: log_ns,
        };
        self.writer.write_to_known_channel(&header, data).unwrap();
    }

    pub fn finish(mut self) {
        self.writer.finish().unwrap();
    }
}

/// One row of a `simulate --trace` CSV, with its time as written.
pub struct Row {
    pub t: String,
    pub robot_x: f64,
    pub robot_v: f64,
    pub robot_mode: String,
    pub obstacle_id: String,
    pub obstacle_x: f64,
    pub obstacle_v: f64,
}

/// The rows of a `simulate --trace` CSV (its columns in their usual order).
pub fn rows(csv: &str) -> Vec<Row> {
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,robot_x,robot_v,robot_mode,obstacle_id,obstacle_x,obstacle_v"
    );
    lines
        .map(|line| {
            let f: Vec<&str> = line.split(',').collect();
            Row {
                t: f[0].to_string(),
                robot_x: f[1].parse().unwrap(),
                robot_v: f[2].parse().unwrap(),
                robot_mode: f[3].to_string(),
                obstacle_id: f[4].to_string(),
                obstacle_x: f[5].parse().unwrap(),
                obstacle_v: f[6].parse().unwrap(),
            }
        })
        .collect()
}

/// How [`seed_bag`] lays the trace out.
#[derive(Clone, Copy)]
pub struct Layout {
    pub compression: Option<Compression>,
    /// Write the robot's mode on `/mode`.
    pub mode_topic: bool,
    /// Obstacles in one `TrackedObjects` message on `/perception/tracked_objects` (named by
    /// a UUID), instead of `nav_msgs/Odometry` on `/obstacles/<id>/odom`.
    pub tracked: bool,
    /// The lane's heading (rad) and origin in the odometry frame.
    pub heading: f64,
    pub origin: [f64; 2],
    /// Write each instant's obstacle message before the robot's.
    pub obstacle_first: bool,
}

impl Default for Layout {
    fn default() -> Layout {
        Layout {
            compression: Some(Compression::Zstd),
            mode_topic: true,
            tracked: false,
            heading: 0.0,
            origin: [0.0, 0.0],
            obstacle_first: false,
        }
    }
}

/// The UUID a tracked obstacle gets, from its trace id.
pub fn uuid_of(id: &str) -> [u8; 16] {
    let mut u = [0u8; 16];
    for (k, b) in id.bytes().enumerate().take(16) {
        u[k] = b;
    }
    u[15] = 0xab;
    u
}

/// The hex name the monitor gives that UUID.
pub fn uuid_name(id: &str) -> String {
    uuid_of(id).iter().map(|b| format!("{b:02x}")).collect()
}

/// A simulator trace as a ROS 2 bag: per row the robot's odometry on `/odom` (driving along
/// the lane), its mode on `/mode`, and the obstacle facing the robot, moving at its
/// `obstacle_v` towards it — all at the row's time.
pub fn seed_bag(rows: &[Row], path: &Path, layout: Layout) {
    let mut bag = Bag::create(path, layout.compression);
    let (c, s) = if layout.heading == 0.0 {
        (1.0, 0.0)
    } else {
        (layout.heading.cos(), layout.heading.sin())
    };
    let at = |x: f64| {
        if layout.heading == 0.0 && layout.origin == [0.0, 0.0] {
            [x, 0.0]
        } else {
            [layout.origin[0] + x * c, layout.origin[1] + x * s]
        }
    };
    for (k, row) in rows.iter().enumerate() {
        let stamp = stamp(&row.t);
        let log = 1_000_000 * k as u64;
        let robot = Body {
            position: at(row.robot_x),
            orientation: yaw(layout.heading),
            velocity: [row.robot_v, 0.0],
        };
        let obstacle = Body {
            position: at(row.obstacle_x),
            orientation: yaw(layout.heading + std::f64::consts::PI),
            velocity: [row.obstacle_v, 0.0],
        };
        let write_obstacle = |bag: &mut Bag| {
            if layout.tracked {
                let data = tracked_objects(stamp, &[(uuid_of(&row.obstacle_id), obstacle)]);
                bag.write(
                    "/perception/tracked_objects",
                    "autoware_perception_msgs/msg/TrackedObjects",
                    log,
                    &data,
                );
            } else {
                let topic = format!("/obstacles/{}/odom", row.obstacle_id);
                let data = odometry(stamp, &row.obstacle_id, &obstacle);
                bag.write(&topic, "nav_msgs/msg/Odometry", log, &data);
            }
        };
        if layout.obstacle_first {
            write_obstacle(&mut bag);
        }
        bag.write(
            "/odom",
            "nav_msgs/msg/Odometry",
            log,
            &odometry(stamp, "base_link", &robot),
        );
        if layout.mode_topic {
            bag.write("/mode", "std_msgs/msg/String", log, &text(&row.robot_mode));
        }
        if !layout.obstacle_first {
            write_obstacle(&mut bag);
        }
    }
    bag.finish();
}
