//! The colour range camera over `PointCloud2`: a capture asks for a frame (a triggered camera
//! answers, a streaming one ignores it) and takes the first one stamped at or after the request,
//! placed by the transform from the map to its frame.

use nudge_executive::robot::{Clock, RangeCamera, RobotError};
use nudge_perception::ColourCloud;

use super::{Ros2Robot, dds};
use crate::convert::{colour_cloud, seconds, time_from_seconds};
use crate::msg::Header;

impl RangeCamera for Ros2Robot {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        self.pump()?;
        self.check()?;
        let asked = self.now();
        let stamp = time_from_seconds(asked).unwrap_or_default();
        self.inbox.cloud = None;
        self.io
            .trigger
            .publish(Header {
                stamp,
                frame_id: String::new(),
            })
            .map_err(dds)?;
        if self.config.use_sim_time {
            // A lock-stepped simulator takes commands when asked to step: a zero-length step.
            self.ask_step(asked)?;
        }
        let fresh = asked - 1e-9;
        self.wait_for("camera", Some(asked), |r| {
            r.inbox
                .cloud
                .as_ref()
                .is_some_and(|c| seconds(&c.header.stamp) >= fresh)
        })?;
        let msg = self
            .inbox
            .cloud
            .take()
            .ok_or_else(|| RobotError::Unavailable {
                capability: "camera",
                reason: "the frame went missing".into(),
            })?;
        let at = seconds(&msg.header.stamp);
        let (sensor, tf_stamp) = self
            .inbox
            .lookup(self.config.frames.map.as_str(), &msg.header.frame_id)?;
        if (at - tf_stamp).abs() > self.config.timeouts.stale {
            return Err(RobotError::Fault {
                capability: "tf",
                reason: format!(
                    "the transform from {} to {} is stamped {tf_stamp} s, the frame {at} s: stale",
                    self.config.frames.map.as_str(),
                    msg.header.frame_id
                ),
            });
        }
        colour_cloud(&msg, sensor, at).map_err(|e| RobotError::Fault {
            capability: "camera",
            reason: e.to_string(),
        })
    }
}
