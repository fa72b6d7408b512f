//! A ROS 2 node over DDS (`ros2-client` on RustDDS): typed publishers and subscriptions on the
//! topics and QoS a [`Ros2Config`](crate::config::Ros2Config) names, and a waiter that sleeps until
//! any of the subscriptions has data.
//!
//! DDS discovery multicasts on every interface the machine has. On a machine whose network must
//! stay local, run the participants inside a network namespace with only loopback (`unshare -rn`,
//! then `ip link set lo up`): discovery and data then stay on 127.0.0.1.

use std::time::Duration;

use ros2_client::dds::rustdds::mio1::{Events, Interest, Poll, Token, event::Source};
use ros2_client::dds::{Context, ContextOptions, Node, Publisher, Subscription};
use ros2_client::qos::{Durability, History, QosProfile, Reliability as DdsReliability, WhenFull};
use ros2_client::{MessageTypeName, Name, NodeName, NodeOptions};

use crate::config::{Qos, Reliability, TopicName};
use crate::msg::RosMessage;

/// Why the DDS side could not be set up or used.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum DdsError {
    /// The participant, node, topic or endpoint could not be created.
    #[error("DDS: cannot create {what}: {reason}")]
    Create {
        /// What was being created (`topic /cmd_vel`).
        what: String,
        /// What DDS said.
        reason: String,
    },
    /// A sample could not be written or read.
    #[error("DDS: {what}: {reason}")]
    Io {
        /// The topic.
        what: String,
        /// What DDS said.
        reason: String,
    },
}

/// One ROS 2 node: its DDS participant and the endpoints made on it.
pub struct RosNode {
    node: Node,
    _context: Context,
    poll: Poll,
    events: Events,
    next_token: usize,
}

impl RosNode {
    /// A node named `name` in the root namespace of DDS domain `domain_id` (`ROS_DOMAIN_ID`).
    pub fn new(name: &str, domain_id: u16) -> Result<Self, DdsError> {
        let context = Context::with_options(ContextOptions::new().domain_id(domain_id))
            .map_err(|e| create("the DDS participant", e))?;
        let node_name = NodeName::new("/", name).map_err(|e| create("the node name", e))?;
        let node = context
            .new_node(node_name, NodeOptions::new().enable_rosout(false))
            .map_err(|e| create("the node", e))?;
        let poll = Poll::new().map_err(|e| create("the waiter", e))?;
        Ok(Self {
            node,
            _context: context,
            poll,
            events: Events::with_capacity(64),
            next_token: 0,
        })
    }

    fn topic<M: RosMessage>(
        &mut self,
        name: &TopicName,
        qos: &QosProfile,
    ) -> Result<ros2_client::dds::rustdds::Topic, DdsError> {
        let (package, rest) = M::TYPE_NAME
            .split_once("/msg/")
            .unwrap_or(("", M::TYPE_NAME));
        let what = format!("topic {}", name.as_str());
        let ros_name = Name::parse(name.as_str()).map_err(|e| create(&what, e))?;
        self.node
            .create_topic(&ros_name, MessageTypeName::new(package, rest), qos)
            .map_err(|e| create(&what, e))
    }

    /// A publisher of `M` on `topic` with `qos`.
    pub fn publisher<M: RosMessage>(
        &mut self,
        topic: &TopicName,
        qos: Qos,
    ) -> Result<RosPublisher<M>, DdsError> {
        let profile = profile(qos);
        let t = self.topic::<M>(topic, &profile)?;
        let inner = self
            .node
            .create_publisher(&t, Some(profile))
            .map_err(|e| create(&format!("a publisher on {}", topic.as_str()), e))?;
        Ok(RosPublisher {
            inner,
            topic: topic.as_str().to_string(),
        })
    }

    /// A subscription to `M` on `topic` with `qos`, registered with this node's waiter.
    pub fn subscription<M: RosMessage + 'static>(
        &mut self,
        topic: &TopicName,
        qos: Qos,
    ) -> Result<RosSubscription<M>, DdsError> {
        let profile = profile(qos);
        let t = self.topic::<M>(topic, &profile)?;
        let mut inner = self
            .node
            .create_subscription(&t, Some(profile))
            .map_err(|e| create(&format!("a subscription to {}", topic.as_str()), e))?;
        let token = Token(self.next_token);
        self.next_token += 1;
        Source::register(&mut inner, self.poll.registry(), token, Interest::READABLE)
            .map_err(|e| create(&format!("a waiter on {}", topic.as_str()), e))?;
        Ok(RosSubscription {
            inner,
            topic: topic.as_str().to_string(),
        })
    }

    /// Sleeps until a subscription has new data or `timeout` passes (wall time).
    pub fn wait(&mut self, timeout: Duration) {
        // A failed poll is a spurious wake-up: every caller takes what is there and waits again.
        let _ = self.poll.poll(&mut self.events, Some(timeout));
    }
}

/// The error of something that could not be created, with what DDS said.
fn create(what: &str, reason: impl std::fmt::Debug) -> DdsError {
    DdsError::Create {
        what: what.to_string(),
        reason: format!("{reason:?}"),
    }
}

/// DDS QoS from a configured profile: volatile, keep last `depth`; a reliable writer waits up to
/// 100 ms for room in its window.
fn profile(qos: Qos) -> QosProfile {
    QosProfile {
        reliability: match qos.reliability {
            Reliability::BestEffort => DdsReliability::BestEffort,
            Reliability::Reliable => DdsReliability::Reliable {
                when_full: WhenFull::DEFAULT,
            },
        },
        durability: Durability::Volatile,
        history: History::KeepLast {
            depth: qos.depth as usize,
        },
        ..QosProfile::subscription_default()
    }
}

/// A typed publisher.
pub struct RosPublisher<M: RosMessage> {
    inner: Publisher<M>,
    topic: String,
}

impl<M: RosMessage> RosPublisher<M> {
    /// Publishes one message.
    pub fn publish(&self, message: M) -> Result<(), DdsError> {
        self.inner.publish(message).map_err(|e| DdsError::Io {
            what: format!("publishing on {}", self.topic),
            reason: match e {
                ros2_client::WriteError::Serialization { reason, .. }
                | ros2_client::WriteError::Poisoned { reason, .. } => reason,
                ros2_client::WriteError::Io(io) => io.to_string(),
                ros2_client::WriteError::WouldBlock { .. } => "the send window stayed full".into(),
                _ => "the writer failed".into(),
            },
        })
    }

    /// The topic's name.
    pub fn topic(&self) -> &str {
        &self.topic
    }
}

/// A typed subscription.
pub struct RosSubscription<M: RosMessage + 'static> {
    inner: Subscription<M>,
    topic: String,
}

impl<M: RosMessage + 'static> RosSubscription<M> {
    /// The oldest message not yet taken, if any.
    pub fn take(&self) -> Result<Option<M>, DdsError> {
        self.inner
            .take()
            .map(|m| m.map(|(message, _)| message))
            .map_err(|e| DdsError::Io {
                what: format!("reading {}", self.topic),
                reason: format!("{e:?}"),
            })
    }

    /// The topic's name.
    pub fn topic(&self) -> &str {
        &self.topic
    }
}
