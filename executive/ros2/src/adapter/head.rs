//! The head over a joint trajectory command and `/joint_states`.

use nudge_executive::robot::{ActionStatus, Head, RobotError, Stamped};

use super::{Ros2Robot, dds};
use crate::convert::time_from_seconds;
use crate::msg::{Duration, Header, JointTrajectory, JointTrajectoryPoint};

/// The head has arrived when both joints lie this close to the target (rad): far below what a
/// look-around's view changes with, far above a controller's settling error.
const ARRIVED: f64 = 1.0e-3;

impl Head for Ros2Robot {
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        self.pump()?;
        self.check()?;
        self.inbox.head.ok_or_else(|| RobotError::Unavailable {
            capability: "head",
            reason: format!(
                "nothing heard on {}",
                self.config.topics.joint_states.as_str()
            ),
        })
    }

    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        let h = self.model.head.clone();
        let within = |v: f64, [lo, hi]: [f64; 2]| v.is_finite() && (lo..=hi).contains(&v);
        if !(within(pan, h.pan_limits) && within(tilt, h.tilt_limits)) {
            return Err(RobotError::Refused {
                capability: "head",
                reason: format!(
                    "head angles ({pan}, {tilt}) outside pan {:?} tilt {:?}",
                    h.pan_limits, h.tilt_limits
                ),
            });
        }
        let (from_pan, from_tilt) = self.head_angles()?.value;
        // The controller is given the time the head's rate needs for the longer joint.
        let seconds = (pan - from_pan).abs().max((tilt - from_tilt).abs()) / h.rate;
        let t = time_from_seconds(seconds).unwrap_or_default();
        self.io
            .head
            .publish(JointTrajectory {
                header: Header::default(),
                joint_names: vec![
                    self.config.head_joints.pan.clone(),
                    self.config.head_joints.tilt.clone(),
                ],
                points: vec![JointTrajectoryPoint {
                    positions: vec![pan, tilt],
                    velocities: vec![0.0, 0.0],
                    accelerations: vec![],
                    effort: vec![],
                    time_from_start: Duration {
                        sec: t.sec,
                        nanosec: t.nanosec,
                    },
                }],
            })
            .map_err(dds)?;
        self.head_target = Some((pan, tilt));
        Ok(())
    }

    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        let (pan, tilt) = self.head_angles()?.value;
        match self.head_target {
            Some((p, t)) if (pan - p).abs() > ARRIVED || (tilt - t).abs() > ARRIVED => {
                Ok(ActionStatus::Running)
            }
            _ => {
                self.head_target = None;
                Ok(ActionStatus::Done(()))
            }
        }
    }
}
