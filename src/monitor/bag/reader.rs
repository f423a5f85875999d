//! [`BagReader`]: an MCAP stream in, monitor samples out.

use std::io::Read;
use std::panic::AssertUnwindSafe;

use mcap::sans_io::LinearReaderOptions;
use mcap::{McapError, Message};

use crate::core::semantics::Mode;
use crate::monitor::Detail;
use crate::monitor::trace::Ids;

use super::axis::{LaneAxis, world_velocity};
use super::instants::{Instants, Observation, Robot};
use super::messages::{Odometry, Text, TrackedObjects, decode};
use super::topics::{Kind, Role, Topics};
use super::{BagItem, BagOptionError, BagOptions, BagStats};

/// Reads a ROS 2 bag (MCAP) from any byte stream — a file, standard input — and yields the
/// monitor's samples one at a time ([module docs](super)). Memory is bounded by the bag's
/// largest chunk and the number of obstacles, not by its length.
pub struct BagReader<R: Read> {
    messages: mcap::io::MessageReader<R>,
    topics: Topics,
    /// Each channel's role, by channel id, decided at its first message.
    roles: Vec<Option<Role>>,
    ids: Ids,
    instants: Instants,
    stats: BagStats,
    done: bool,
}

impl<R: Read> BagReader<R> {
    /// A reader of `source` with `options`; fails only on bad options.
    pub fn new(source: R, options: &BagOptions) -> Result<BagReader<R>, BagOptionError> {
        if options.infer_mode && options.mode_topic.is_some() {
            return Err(BagOptionError::TwoModeSources);
        }
        Ok(BagReader {
            messages: mcap::io::MessageReader::new_with_options(source, reader_options()),
            topics: Topics::new(options)?,
            roles: Vec::new(),
            ids: Ids::new(options.max_obstacles),
            instants: Instants::new(options),
            stats: BagStats::default(),
            done: false,
        })
    }

    /// The obstacles' names (a tracked object's UUID in hex, an odometry topic's
    /// `child_frame_id` or topic), by the ids samples carry.
    pub fn ids(&self) -> &Ids {
        &self.ids
    }

    /// What was read so far.
    pub fn stats(&self) -> &BagStats {
        &self.stats
    }

    /// The byte stream, given back.
    pub fn into_inner(self) -> R {
        self.messages.into_inner()
    }

    /// The lane axis in use, once known (given, or from the robot's first pose).
    pub fn lane_axis(&self) -> Option<LaneAxis> {
        self.instants.axis
    }

    /// The next sample or fail-safe event; `None` at the end of the bag (or after a
    /// corrupt part of it).
    pub fn next_item(&mut self) -> Option<BagItem> {
        loop {
            if let Some(item) = self.instants.out.pop_front() {
                return Some(item);
            }
            if self.done {
                return None;
            }
            // A malformed record can make the MCAP reader panic where it subtracts lengths
            // unchecked (mcap 0.26.0, builds with overflow checks on; see
            // fuzz/src/bag.rs): caught, it is a corrupt bag like any other.
            let Ok(next) = std::panic::catch_unwind(AssertUnwindSafe(|| self.messages.next()))
            else {
                self.stop("a record's length overruns its chunk");
                continue;
            };
            match next {
                Some(Ok(message)) => self.message(&message),
                Some(Err(e)) => self.stop(corruption(&e)),
                None => {
                    self.done = true;
                    self.finish();
                }
            }
        }
    }

    /// Stops at a damaged part of the bag: what was read before it is still checked, first,
    /// then the damage is one fail-safe event.
    fn stop(&mut self, what: &'static str) {
        self.done = true;
        self.finish();
        self.instants.out.push_back(BagItem::Malformed {
            t: None,
            detail: Detail::CorruptBag(what),
            message: self.stats.messages,
        });
    }

    fn finish(&mut self) {
        self.instants.finish();
        self.stats.superseded = self.instants.superseded;
        self.stats.unpaired = self.instants.unpaired;
    }

    fn message(&mut self, m: &Message) {
        self.stats.messages += 1;
        let number = self.stats.messages;
        let id = usize::from(m.channel.id);
        if id >= self.roles.len() {
            self.roles.resize(id + 1, None);
        }
        let role = match self.roles[id] {
            Some(role) => role,
            None => {
                let role = self.topics.role(&m.channel);
                self.roles[id] = Some(role);
                let kind = m.channel.schema.as_ref().map_or("", |s| s.name.as_str());
                self.stats
                    .topics
                    .push((m.channel.topic.clone(), kind.to_string()));
                role
            }
        };
        let malformed = |detail| BagItem::Malformed {
            t: None,
            detail,
            message: number,
        };
        let item = match role {
            Role::Skipped => {
                self.stats.skipped += 1;
                return;
            }
            Role::Robot(Kind::Odometry) => match decode::<Odometry>(&m.data) {
                Ok(odom) => return self.robot(&odom, number),
                Err(why) => malformed(Detail::BadMessage(why)),
            },
            Role::Obstacles(Kind::Odometry) => match decode::<Odometry>(&m.data) {
                Ok(odom) => {
                    let name = if odom.child_frame_id.is_empty() {
                        m.channel.topic.as_str()
                    } else {
                        odom.child_frame_id.as_str()
                    };
                    let Some(id) = self.ids.get_or_insert(name.as_bytes()) else {
                        return self.too_many(number);
                    };
                    self.stats.observations += 1;
                    let pose = &odom.pose.pose;
                    return self.instants.observe(Observation {
                        id,
                        t: odom.header.stamp.seconds(),
                        position: [pose.position.x, pose.position.y],
                        velocity: world_velocity(pose, &odom.twist.twist),
                        message: number,
                    });
                }
                Err(why) => malformed(Detail::BadMessage(why)),
            },
            Role::Obstacles(Kind::TrackedObjects) => match decode::<TrackedObjects>(&m.data) {
                Ok(tracked) => return self.tracked(&tracked, number),
                Err(why) => malformed(Detail::BadMessage(why)),
            },
            Role::Mode(Kind::Text) => match decode::<Text>(&m.data) {
                Ok(text) => match Mode::from_name(text.data.trim().as_bytes()) {
                    Some(mode) => {
                        self.stats.modes += 1;
                        self.instants.mode = Some(mode);
                        return;
                    }
                    None => malformed(Detail::BadMode),
                },
                Err(why) => malformed(Detail::BadMessage(why)),
            },
            Role::Robot(_) | Role::Obstacles(_) | Role::Mode(_) => {
                malformed(Detail::UnknownMessageType)
            }
        };
        self.instants.out.push_back(item);
    }

    fn robot(&mut self, odom: &Odometry, number: u64) {
        let pose = &odom.pose.pose;
        if self.instants.axis.is_none() && self.instants.plane {
            // The plane's frame is the odometry frame unless an axis says otherwise.
            self.instants.axis = Some(LaneAxis::new([0.0, 0.0], 0.0));
        }
        if self.instants.axis.is_none() {
            self.instants.axis = LaneAxis::from_pose(pose);
            if self.instants.axis.is_none() {
                self.instants.out.push_back(BagItem::Malformed {
                    t: Some(odom.header.stamp.seconds()),
                    detail: Detail::NoLaneAxis,
                    message: number,
                });
                return;
            }
        }
        self.stats.robot += 1;
        self.instants.robot(Robot {
            t: odom.header.stamp.seconds(),
            position: [pose.position.x, pose.position.y],
            velocity: world_velocity(pose, &odom.twist.twist),
            message: number,
        });
    }

    fn tracked(&mut self, tracked: &TrackedObjects, number: u64) {
        let t = tracked.header.stamp.seconds();
        for object in &tracked.objects {
            let name = hex(&object.object_id.uuid);
            let Some(id) = self.ids.get_or_insert(&name) else {
                return self.too_many(number);
            };
            self.stats.observations += 1;
            let pose = &object.kinematics.pose_with_covariance.pose;
            self.instants.observe(Observation {
                id,
                t,
                position: [pose.position.x, pose.position.y],
                velocity: world_velocity(pose, &object.kinematics.twist_with_covariance.twist),
                message: number,
            });
        }
    }

    fn too_many(&mut self, number: u64) {
        self.instants.out.push_back(BagItem::Malformed {
            t: None,
            detail: Detail::TooManyObstacles {
                limit: self.ids.limit,
            },
            message: number,
        });
    }
}

/// A UUID in lowercase hex, as ROS tools print it without dashes (a table lookup per byte:
/// formatting it took more time than decoding the object).
fn hex(uuid: &[u8; 16]) -> [u8; 32] {
    const DIGITS: &[u8; 16] = b"0123456789abcdef";
    let mut out = [0u8; 32];
    for (k, b) in uuid.iter().enumerate() {
        out[2 * k] = DIGITS[usize::from(b >> 4)];
        out[2 * k + 1] = DIGITS[usize::from(b & 15)];
    }
    out
}

/// Longest record the reader accepts (and most chunk data it buffers): rosbag2 writes chunks
/// of about 1 MiB, so this only stops a corrupt length field from exhausting memory.
const RECORD_LIMIT: usize = 256 << 20;

/// Every CRC the bag carries is checked, and a chunk's before any of its messages is used:
/// data from a damaged chunk never reaches the monitor.
fn reader_options() -> LinearReaderOptions {
    LinearReaderOptions::default()
        .with_prevalidate_chunk_crcs(true)
        .with_validate_data_section_crc(true)
        .with_record_length_limit(RECORD_LIMIT)
}

/// What is wrong with a bag, in words.
fn corruption(e: &McapError) -> &'static str {
    match e {
        McapError::BadMagic => {
            "it does not start (or end) with the MCAP magic bytes: not an MCAP file"
        }
        McapError::UnexpectedEof | McapError::UnexpectedEoc => {
            "it ends inside a record (truncated, e.g. the recorder was stopped hard)"
        }
        McapError::BadChunkCrc { .. } | McapError::BadDataCrc { .. } => {
            "a chunk fails its CRC check"
        }
        McapError::UnsupportedCompression(_) => "a chunk uses a compression other than zstd or lz4",
        McapError::DecompressionError(_) => "a chunk cannot be decompressed",
        McapError::Io(_) => "reading or decompressing it failed",
        McapError::RecordTooLarge { .. } | McapError::ChunkTooLarge(_) => {
            "a record states a length over 256 MiB"
        }
        _ => "a record is not valid MCAP",
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;
    use std::io::Cursor;

    use super::*;

    /// A bag of `n` std_msgs/String messages on `/mode`, uncompressed and without CRCs.
    fn bag(n: u32) -> Vec<u8> {
        let options = mcap::WriteOptions::new()
            .compression(None)
            .calculate_chunk_crcs(false)
            .calculate_data_section_crc(false)
            .calculate_summary_section_crc(false);
        let mut w = options.create(Cursor::new(Vec::new())).unwrap();
        let schema = w
            .add_schema("std_msgs/msg/String", "ros2msg", b"string data")
            .unwrap();
        let channel = w
            .add_channel(schema, "/mode", "cdr", &BTreeMap::new())
            .unwrap();
        for k in 0..n {
            let header = mcap::records::MessageHeader {
                channel_id: channel,
                sequence: k,
                log_time: u64::from(k),
                publish_time: u64::from(k),
            };
            w.write_to_known_channel(
                &header,
                &[0, 1, 0, 0, 6, 0, 0, 0, b'd', b'r', b'i', b'v', b'e', 0],
            )
            .unwrap();
        }
        w.finish().unwrap();
        w.into_inner().into_inner()
    }

    fn items(data: &[u8]) -> Vec<BagItem> {
        let options = BagOptions {
            mode_topic: Some("/mode".into()),
            ..BagOptions::default()
        };
        let mut reader = BagReader::new(data, &options).unwrap();
        std::iter::from_fn(|| reader.next_item()).collect()
    }

    #[test]
    fn a_clean_bag_of_modes_has_no_items() {
        // No robot: no instant, nothing to check, and nothing wrong.
        assert_eq!(items(&bag(5)), vec![]);
    }

    #[test]
    fn records_the_mcap_reader_panics_on_are_a_corrupt_bag() {
        // Found by the bag fuzz target: a record inside an uncompressed chunk claims more
        // bytes than the chunk has left. mcap 0.26.0 subtracts unchecked there, which panics
        // with overflow checks on (`cargo test` without --release) and wraps without them.
        // Either way: one corrupt-bag event, last.
        // The second: an attachment record too short for its own header, where mcap
        // 0.26.0 slices out of range (a panic in every build).
        for data in [
            &include_bytes!("../../../fuzz/corpus/bag/finding-record-overruns-chunk.mcap")[..],
            &include_bytes!("../../../fuzz/corpus/bag/finding-short-attachment.mcap")[..],
        ] {
            let items = items(data);
            let corrupt = matches!(
                items.last(),
                Some(BagItem::Malformed {
                    detail: Detail::CorruptBag(_),
                    ..
                })
            );
            assert!(corrupt, "{items:?}");
        }
    }
}
