//! What each channel of a bag is to the monitor, decided once per channel from its topic,
//! message type and encoding.

use mcap::Channel;

use super::{BagOptionError, BagOptions};

/// The message types the reader decodes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    /// `nav_msgs/msg/Odometry`.
    Odometry,
    /// `autoware_perception_msgs/msg/TrackedObjects`.
    TrackedObjects,
    /// `std_msgs/msg/String`.
    Text,
    /// Anything else, or not CDR.
    Other,
}

impl Kind {
    /// The kind of a channel: its schema's name (`pkg/msg/Type`, or the older `pkg/Type`)
    /// and its message encoding, which must be CDR.
    fn of(channel: &Channel) -> Kind {
        let name = channel.schema.as_ref().map_or("", |s| s.name.as_str());
        if channel.message_encoding != "cdr" {
            return Kind::Other;
        }
        match name.replace("/msg/", "/").as_str() {
            "nav_msgs/Odometry" => Kind::Odometry,
            "autoware_perception_msgs/TrackedObjects" => Kind::TrackedObjects,
            "std_msgs/String" => Kind::Text,
            _ => Kind::Other,
        }
    }
}

/// What a channel's messages are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Role {
    /// The robot's odometry (or a topic of the wrong type, when `Kind` says so).
    Robot(Kind),
    /// Obstacles.
    Obstacles(Kind),
    /// The robot's mode.
    Mode(Kind),
    /// Not used.
    Skipped,
}

/// The topic selection of [`BagOptions`], patterns compiled.
pub(super) struct Topics {
    robot: String,
    obstacles: Vec<glob::Pattern>,
    mode: Option<String>,
}

impl Topics {
    /// Compiles the obstacle patterns.
    pub(super) fn new(options: &BagOptions) -> Result<Topics, BagOptionError> {
        let obstacles = options
            .obstacle_topics
            .iter()
            .map(|p| {
                glob::Pattern::new(p).map_err(|e| BagOptionError::BadPattern {
                    pattern: p.clone(),
                    reason: e.msg.to_string(),
                })
            })
            .collect::<Result<_, _>>()?;
        Ok(Topics {
            robot: options.robot_topic.clone(),
            obstacles,
            mode: options.mode_topic.clone(),
        })
    }

    /// The role of `channel`. The robot and mode topics are matched first, so an obstacle
    /// pattern that also matches them does not take them.
    pub(super) fn role(&self, channel: &Channel) -> Role {
        let kind = Kind::of(channel);
        let topic = channel.topic.as_str();
        if topic == self.robot {
            return Role::Robot(kind);
        }
        if self.mode.as_deref() == Some(topic) {
            return Role::Mode(kind);
        }
        let selected = if self.obstacles.is_empty() {
            kind == Kind::TrackedObjects
        } else {
            self.obstacles.iter().any(|p| p.matches(topic))
        };
        if selected {
            Role::Obstacles(kind)
        } else {
            Role::Skipped
        }
    }
}
