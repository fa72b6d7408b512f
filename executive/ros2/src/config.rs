//! How a robot's ROS 2 graph looks to nudge: topic names, frames, head joints, QoS and the clock, from
//! a TOML file. Every field has a default (a common ROS 2 layout), so a file names only what differs
//! on the robot; errors name the file, line, column and field.

use nudge_robot_model::text_place::line_column;
use serde::{Deserialize, Serialize};
use toml::de::{DeTable, DeValue};

/// A topic name as ROS 2 accepts it: `/`-separated tokens of letters, digits and `_`, none starting
/// with a digit, no empty token, no trailing `/` (`~` and substitutions are not taken: the adapter
/// has no node namespace to resolve them against).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub struct TopicName(String);

impl TryFrom<String> for TopicName {
    type Error = String;

    fn try_from(name: String) -> Result<Self, String> {
        let body = name.strip_prefix('/').unwrap_or(&name);
        let token_ok = |t: &str| {
            !t.is_empty()
                && !t.starts_with(|c: char| c.is_ascii_digit())
                && t.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        };
        if body.split('/').all(token_ok) {
            Ok(Self(name))
        } else {
            Err(format!(
                "`{name}` is not a ROS 2 topic name (tokens of letters, digits and _, separated by /)"
            ))
        }
    }
}

impl From<TopicName> for String {
    fn from(name: TopicName) -> String {
        name.0
    }
}

impl TopicName {
    /// The name as written.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

/// A tf frame id: not empty, no leading `/` (tf2 refuses those), no whitespace.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub struct FrameId(String);

impl TryFrom<String> for FrameId {
    type Error = String;

    fn try_from(id: String) -> Result<Self, String> {
        if id.is_empty() || id.starts_with('/') || id.chars().any(char::is_whitespace) {
            Err(format!(
                "`{id}` is not a tf frame id (not empty, no leading /, no spaces)"
            ))
        } else {
            Ok(Self(id))
        }
    }
}

impl From<FrameId> for String {
    fn from(id: FrameId) -> String {
        id.0
    }
}

impl FrameId {
    /// The id as written.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

/// Whether a DDS reader or writer resends lost samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Reliability {
    /// Lost samples are gone: sensor streams, where the next sample is worth more than an old one.
    BestEffort,
    /// Lost samples are resent: commands.
    Reliable,
}

/// A QoS profile: reliability and the history kept (keep last `depth`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Qos {
    /// Reliability.
    pub reliability: Reliability,
    /// Samples kept per topic, 1 to 1000.
    pub depth: u32,
}

/// The topics the adapter reads and writes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Topics {
    /// Organised colour clouds (`sensor_msgs/PointCloud2`, fields x, y, z, rgb).
    pub cloud: TopicName,
    /// The wrist's force/torque (`geometry_msgs/WrenchStamped`), at the sensor's rate.
    pub wrench: TopicName,
    /// The transform tree (`tf2_msgs/TFMessage`): the base in the map, the hand in the base.
    pub tf: TopicName,
    /// The base's velocity command (`geometry_msgs/Twist`).
    pub cmd_vel: TopicName,
    /// The head's joint trajectory command (`trajectory_msgs/JointTrajectory`).
    pub head: TopicName,
    /// The hand's Cartesian velocity command (`geometry_msgs/TwistStamped`, MoveIt Servo's).
    pub hand: TopicName,
    /// Simulated time (`rosgraph_msgs/Clock`), read when `use_sim_time` is set.
    pub clock: TopicName,
    /// The joints' state (`sensor_msgs/JointState`): the head's pan and tilt.
    pub joint_states: TopicName,
    /// Asks a triggered camera for a frame (`std_msgs/Header`, stamped with the request's time); a
    /// streaming camera ignores it, and the adapter takes the first frame stamped at or after it.
    pub camera_trigger: TopicName,
    /// Asks a lock-stepped simulator to run until a time (`rosgraph_msgs/Clock`), published when
    /// `use_sim_time` is set; a free-running simulator ignores it and the adapter waits for
    /// `/clock` all the same.
    pub step: TopicName,
}

impl Default for Topics {
    fn default() -> Self {
        let t = |s: &str| TopicName(s.into());
        Self {
            cloud: t("/camera/depth/color/points"),
            wrench: t("/wrist/wrench"),
            tf: t("/tf"),
            cmd_vel: t("/cmd_vel"),
            head: t("/head_controller/joint_trajectory"),
            hand: t("/servo_node/delta_twist_cmds"),
            clock: t("/clock"),
            joint_states: t("/joint_states"),
            camera_trigger: t("/camera/trigger"),
            step: t("/nudge/step_until"),
        }
    }
}

/// The tf frames the adapter looks up.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Frames {
    /// The fixed frame the base moves in.
    pub map: FrameId,
    /// The base, on the floor between the feet, x ahead.
    pub base: FrameId,
    /// The hand, where the pushes are measured.
    pub hand: FrameId,
    /// The colour range camera's frame, the one its clouds are stamped with (the bridge names its
    /// camera so; the adapter places a cloud by whatever frame it carries).
    pub camera: FrameId,
}

impl Default for Frames {
    fn default() -> Self {
        let f = |s: &str| FrameId(s.into());
        Self {
            map: f("map"),
            base: f("base_link"),
            hand: f("hand"),
            camera: f("camera"),
        }
    }
}

/// The head's joints, by name, as its trajectory controller knows them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HeadJoints {
    /// The pan joint (left positive).
    pub pan: String,
    /// The tilt joint (down positive).
    pub tilt: String,
}

impl Default for HeadJoints {
    fn default() -> Self {
        Self {
            pan: "head_pan".into(),
            tilt: "head_tilt".into(),
        }
    }
}

/// QoS of the two kinds of topic.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct QosProfiles {
    /// Sensor streams (cloud, wrench, tf): ROS 2's sensor-data profile, best effort, depth 5.
    pub sensor: Qos,
    /// Commands (walk, head, hand): reliable, depth 10, ROS 2's default.
    pub command: Qos,
}

impl Default for QosProfiles {
    fn default() -> Self {
        Self {
            sensor: Qos {
                reliability: Reliability::BestEffort,
                depth: 5,
            },
            command: Qos {
                reliability: Reliability::Reliable,
                depth: 10,
            },
        }
    }
}

/// How long the adapter waits before a silent robot is a fault.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Timeouts {
    /// Wall-clock seconds a topic the adapter waits on may stay silent (the clock, a camera frame,
    /// the wrist during a guarded move) before the call fails with a timeout. Two seconds is many
    /// periods of any sensor and of a simulator's step, and short enough that a dead driver ends the
    /// run at once.
    pub quiet: f64,
    /// Robot-clock seconds by which a transform may be older than the data it places (a cloud, a
    /// hand position) before it counts as stale: two of the executive's 50 ms ticks.
    pub stale: f64,
}

impl Default for Timeouts {
    fn default() -> Self {
        Self {
            quiet: 2.0,
            stale: 0.1,
        }
    }
}

/// The robot's ROS 2 graph as the adapter sees it.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Ros2Config {
    /// Take the time from the clock topic (a simulator's), not from the wall clock.
    pub use_sim_time: bool,
    /// The DDS domain (`ROS_DOMAIN_ID`), 0 to 232.
    pub domain_id: u16,
    /// When silence is a fault.
    pub timeouts: Timeouts,
    /// Topic names.
    pub topics: Topics,
    /// Frame ids.
    pub frames: Frames,
    /// The head's joint names.
    pub head_joints: HeadJoints,
    /// QoS profiles.
    pub qos: QosProfiles,
}

/// A fault in a ROS 2 configuration, placed: `origin:line:column: field: message`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{origin}:{line}:{column}: {field}: {message}")]
pub struct ConfigError {
    /// Where the text came from.
    pub origin: String,
    /// 1-based line.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
    /// The field's path (`topics.cloud`), or `(document)`.
    pub field: String,
    /// What is wrong.
    pub message: String,
}

/// The most samples a QoS history keeps: beyond this, a typo.
const MAX_DEPTH: u32 = 1000;

impl Ros2Config {
    /// Parses a configuration; `origin` (a path or a name) starts every error.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, ConfigError> {
        let place = |offset: usize, message: String| {
            let (line, column) = line_column(text, offset);
            let field = DeTable::parse(text)
                .ok()
                .and_then(|doc| key_at(doc.get_ref(), offset, ""))
                .unwrap_or_else(|| "(document)".into());
            ConfigError {
                origin: origin.into(),
                line,
                column,
                field,
                message,
            }
        };
        let config: Self = toml::from_str(text).map_err(|e| {
            let at = e.span().map_or(0, |s| s.start);
            place(at, e.message().trim().to_owned())
        })?;
        for (name, qos) in [
            ("sensor", config.qos.sensor),
            ("command", config.qos.command),
        ] {
            if !(1..=MAX_DEPTH).contains(&qos.depth) {
                let at = span_of(text, &["qos", name, "depth"]);
                return Err(place(
                    at,
                    format!("depth must lie in 1 to {MAX_DEPTH}, got {}", qos.depth),
                ));
            }
        }
        if config.domain_id > MAX_DOMAIN {
            return Err(place(
                span_of(text, &["domain_id"]),
                format!("must lie in 0 to {MAX_DOMAIN}, got {}", config.domain_id),
            ));
        }
        for (name, value) in [
            ("quiet", config.timeouts.quiet),
            ("stale", config.timeouts.stale),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(place(
                    span_of(text, &["timeouts", name]),
                    format!("must be a positive number of seconds, got {value}"),
                ));
            }
        }
        Ok(config)
    }
}

/// The largest DDS domain id ROS 2 maps to ports.
const MAX_DOMAIN: u16 = 232;

/// Where the value at `path` starts in `text` (0 when it is not there).
fn span_of(text: &str, path: &[&str]) -> usize {
    let Ok(doc) = DeTable::parse(text) else {
        return 0;
    };
    let mut table = doc.get_ref();
    for (i, key) in path.iter().enumerate() {
        let Some(value) = table.get(*key) else {
            return 0;
        };
        if i + 1 == path.len() {
            return value.span().start;
        }
        match value.get_ref().as_table() {
            Some(t) => table = t,
            None => return 0,
        }
    }
    0
}

/// The dotted path of the deepest key whose value holds byte `offset`.
fn key_at(table: &DeTable<'_>, offset: usize, prefix: &str) -> Option<String> {
    table.iter().find_map(|(key, value)| {
        let path = if prefix.is_empty() {
            key.get_ref().to_string()
        } else {
            format!("{prefix}.{}", key.get_ref())
        };
        let span = value.span();
        let inside = span.contains(&offset) || key.span().contains(&offset);
        match value.get_ref() {
            DeValue::Table(t) => key_at(t, offset, &path).or(inside.then_some(path)),
            _ => inside.then_some(path),
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(text: &str) -> String {
        Ros2Config::from_toml_str(text, "robot.ros2.toml")
            .expect_err("invalid")
            .to_string()
    }

    #[test]
    fn a_file_names_only_what_differs() {
        // Invariant: an empty file is the default layout; a file that renames one topic and one frame changes those and nothing else.
        let empty = Ros2Config::from_toml_str("", "empty.toml").expect("valid");
        assert_eq!(empty, Ros2Config::default());
        let text = "use_sim_time = true\n[topics]\ncloud = \"/head/points\"\n[frames]\nbase = \"base_footprint\"\n";
        let c = Ros2Config::from_toml_str(text, "robot.toml").expect("valid");
        assert!(c.use_sim_time);
        assert_eq!(c.topics.cloud.as_str(), "/head/points");
        assert_eq!(c.frames.base.as_str(), "base_footprint");
        assert_eq!(c.topics.wrench, Topics::default().wrench);
        assert_eq!(c.qos, QosProfiles::default());
    }

    #[test]
    fn faults_name_the_file_line_column_and_field() {
        // Invariant: a bad topic name, a bad frame, an unknown key, a wrong QoS word and a depth out of range each give origin:line:column: field: message, never a panic.
        assert_eq!(
            error("[topics]\ncloud = \"/camera//points\"\n"),
            "robot.ros2.toml:2:9: topics.cloud: `/camera//points` is not a ROS 2 topic name (tokens of letters, digits and _, separated by /)"
        );
        assert_eq!(
            error("[frames]\nmap = \"/map\"\n"),
            "robot.ros2.toml:2:7: frames.map: `/map` is not a tf frame id (not empty, no leading /, no spaces)"
        );
        assert!(
            error("[topics]\ncloudd = \"/x\"\n")
                .starts_with("robot.ros2.toml:2:1: topics.cloudd: unknown field `cloudd`"),
            "{}",
            error("[topics]\ncloudd = \"/x\"\n")
        );
        assert!(
            error("[qos.sensor]\nreliability = \"sometimes\"\ndepth = 5\n")
                .starts_with("robot.ros2.toml:2:15: qos.sensor.reliability: unknown variant"),
            "{}",
            error("[qos.sensor]\nreliability = \"sometimes\"\ndepth = 5\n")
        );
        assert_eq!(
            error("domain_id = 300\n"),
            "robot.ros2.toml:1:13: domain_id: must lie in 0 to 232, got 300"
        );
        assert_eq!(
            error("[timeouts]\nquiet = -1.0\n"),
            "robot.ros2.toml:2:9: timeouts.quiet: must be a positive number of seconds, got -1"
        );
        assert_eq!(
            error("[qos.command]\nreliability = \"reliable\"\ndepth = 0\n"),
            "robot.ros2.toml:3:9: qos.command.depth: depth must lie in 1 to 1000, got 0"
        );
        for bad in ["2d/points", "/a/", "/a b", "", "/"] {
            assert!(TopicName::try_from(bad.to_string()).is_err(), "{bad:?}");
        }
        for good in ["/cmd_vel", "cmd_vel", "/a1/_b/c_2"] {
            assert!(TopicName::try_from(good.to_string()).is_ok(), "{good:?}");
        }
    }
}
