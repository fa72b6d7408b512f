//! What the adapter has heard from the robot: the clock, the transform tree, the head's joints, the
//! wrist's readings and the latest camera frame, each checked as it arrives. A message that cannot
//! be right (a NaN, a clock that runs backwards) is kept as the fault the next call reports.

use std::collections::{HashMap, VecDeque};

use nalgebra::Isometry3;
use nudge_executive::robot::{RobotError, Stamped, Wrench};

use crate::config::Ros2Config;
use crate::convert::{nudge_wrench, pose, seconds};
use crate::msg::{Clock, JointState, PointCloud2, TFMessage, WrenchStamped};

/// One edge of the transform tree: the child's pose in its parent at a stamp.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Edge {
    pub parent: String,
    pub stamp: f64,
    pub pose: Isometry3<f64>,
}

/// Everything received so far.
#[derive(Debug, Default)]
pub(crate) struct Inbox {
    /// The latest `/clock` (s), when one came.
    pub clock: Option<f64>,
    /// The latest transform of each child frame.
    pub tf: HashMap<String, Edge>,
    /// The head's (pan, tilt), stamped.
    pub head: Option<Stamped<(f64, f64)>>,
    /// Raw (untared) wrist readings since the last drain, oldest first.
    pub wrenches: VecDeque<Stamped<Wrench>>,
    /// The latest raw wrist reading.
    pub latest_wrench: Option<Stamped<Wrench>>,
    /// The latest camera frame.
    pub cloud: Option<PointCloud2>,
    /// The first fault seen and not yet reported.
    pub fault: Option<RobotError>,
}

/// The most raw readings kept between drains: a minute at 1 kHz. A walk that nobody drains does not
/// grow without bound; a push test drains long before.
const MAX_KEPT: usize = 60_000;

impl Inbox {
    fn fault(&mut self, capability: &'static str, reason: String) {
        if self.fault.is_none() {
            self.fault = Some(RobotError::Fault { capability, reason });
        }
    }

    pub fn on_clock(&mut self, msg: &Clock) {
        let t = seconds(&msg.clock);
        match self.clock {
            Some(now) if t < now => {
                self.fault("clock", format!("/clock jumped back from {now} s to {t} s"));
            }
            _ => self.clock = Some(t),
        }
    }

    pub fn on_tf(&mut self, msg: &TFMessage) {
        for t in &msg.transforms {
            match pose(&t.transform) {
                Some(p) => {
                    self.tf.insert(
                        t.child_frame_id.clone(),
                        Edge {
                            parent: t.header.frame_id.clone(),
                            stamp: seconds(&t.header.stamp),
                            pose: p,
                        },
                    );
                }
                None => self.fault(
                    "tf",
                    format!(
                        "transform {} → {} is not a pose (a NaN or a zero rotation)",
                        t.header.frame_id, t.child_frame_id
                    ),
                ),
            }
        }
    }

    pub fn on_joints(&mut self, msg: &JointState, config: &Ros2Config) {
        let at = |name: &str| {
            msg.name
                .iter()
                .position(|n| n == name)
                .and_then(|i| msg.position.get(i).copied())
        };
        if let (Some(pan), Some(tilt)) = (at(&config.head_joints.pan), at(&config.head_joints.tilt))
        {
            if pan.is_finite() && tilt.is_finite() {
                self.head = Some(Stamped {
                    stamp: seconds(&msg.header.stamp),
                    value: (pan, tilt),
                });
            } else {
                self.fault("head", format!("joint state ({pan}, {tilt}) is not finite"));
            }
        }
    }

    pub fn on_wrench(&mut self, msg: &WrenchStamped) {
        let w = nudge_wrench(&msg.wrench);
        if !(w.force.iter().chain(w.torque.iter()).all(|v| v.is_finite())) {
            self.fault(
                "wrist",
                format!("a reading with a NaN or an infinity: {w:?}"),
            );
            return;
        }
        let reading = Stamped {
            stamp: seconds(&msg.header.stamp),
            value: w,
        };
        if self.wrenches.len() >= MAX_KEPT {
            self.wrenches.pop_front();
        }
        self.wrenches.push_back(reading);
        self.latest_wrench = Some(reading);
    }

    pub fn on_cloud(&mut self, msg: PointCloud2) {
        self.cloud = Some(msg);
    }

    /// The pose of `child` in `root`, chained through the tree, and the oldest stamp on the way.
    pub fn lookup(&self, root: &str, child: &str) -> Result<(Isometry3<f64>, f64), RobotError> {
        let mut pose = Isometry3::identity();
        let mut oldest = f64::INFINITY;
        let mut frame = child;
        for _ in 0..32 {
            if frame == root {
                return Ok((pose, oldest));
            }
            let edge = self.tf.get(frame).ok_or_else(|| RobotError::Unavailable {
                capability: "tf",
                reason: format!("no transform from {root} to {child} (nothing for {frame})"),
            })?;
            pose = edge.pose * pose;
            oldest = oldest.min(edge.stamp);
            frame = &edge.parent;
        }
        Err(RobotError::Fault {
            capability: "tf",
            reason: format!("the tree from {root} to {child} has a loop"),
        })
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Translation3, UnitQuaternion};

    use super::*;
    use crate::convert::{time_from_seconds, transform, wrench};
    use crate::msg::{Header, TransformStamped};

    fn header(frame: &str, t: f64) -> Header {
        Header {
            stamp: time_from_seconds(t).expect("a time"),
            frame_id: frame.into(),
        }
    }

    fn clock(t: f64) -> Clock {
        Clock {
            clock: time_from_seconds(t).expect("a time"),
        }
    }

    #[test]
    fn a_clock_that_runs_backwards_is_a_fault_and_is_not_taken() {
        // Invariant: /clock going back is kept as a clock fault naming both times, and the inbox's time stays where it was.
        let mut inbox = Inbox::default();
        inbox.on_clock(&clock(10.0));
        inbox.on_clock(&clock(9.5));
        assert_eq!(inbox.clock, Some(10.0));
        let fault = inbox.fault.expect("a fault").to_string();
        assert!(
            fault.contains("clock") && fault.contains("10 s to 9.5 s"),
            "{fault}"
        );
    }

    #[test]
    fn a_wrench_with_a_nan_is_a_fault_and_never_a_reading() {
        // Invariant: a WrenchStamped with a NaN is reported as a wrist fault and reaches neither the latest reading nor the drained trace.
        let mut inbox = Inbox::default();
        let mut w = nudge_executive::robot::Wrench::default();
        w.force.x = f64::NAN;
        inbox.on_wrench(&WrenchStamped {
            header: header("hand", 1.0),
            wrench: wrench(&w),
        });
        assert!(inbox.latest_wrench.is_none() && inbox.wrenches.is_empty());
        assert!(
            inbox
                .fault
                .expect("a fault")
                .to_string()
                .contains("wrist fault")
        );
    }

    #[test]
    fn transforms_chain_from_the_map_and_report_their_oldest_stamp() {
        // Invariant: map → base → camera composes the two poses, the stamp returned is the older edge's, a missing edge is Unavailable and a NaN transform a fault.
        let mut inbox = Inbox::default();
        let base = Isometry3::from_parts(
            Translation3::new(1.0, 2.0, 0.0),
            UnitQuaternion::from_euler_angles(0.0, 0.0, 0.5),
        );
        let camera = Isometry3::translation(0.0, 0.0, 1.4);
        let edge = |parent: &str, child: &str, t: f64, p: &Isometry3<f64>| TransformStamped {
            header: header(parent, t),
            child_frame_id: child.into(),
            transform: transform(p),
        };
        inbox.on_tf(&TFMessage {
            transforms: vec![
                edge("map", "base_link", 3.0, &base),
                edge("base_link", "camera", 2.5, &camera),
            ],
        });
        let (pose, stamp) = inbox.lookup("map", "camera").expect("a chain");
        assert!((pose.translation.vector - (base * camera).translation.vector).norm() < 1e-12);
        assert_eq!(stamp, 2.5);
        assert!(matches!(
            inbox.lookup("map", "hand"),
            Err(RobotError::Unavailable { .. })
        ));
        let mut bad = transform(&base);
        bad.translation.x = f64::NAN;
        inbox.on_tf(&TFMessage {
            transforms: vec![TransformStamped {
                header: header("map", 4.0),
                child_frame_id: "base_link".into(),
                transform: bad,
            }],
        });
        assert!(inbox.fault.is_some());
        assert_eq!(inbox.lookup("map", "base_link").expect("kept").1, 3.0);
    }
}
