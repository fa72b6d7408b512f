//! The hand over a Cartesian velocity command (MoveIt Servo's `TwistStamped` in the base frame),
//! the wrist over a `WrenchStamped` stream, and the force guard between them: every reading that
//! arrives during a guarded move is checked, and the hand is stopped the moment one reaches the
//! move's limit.

use nalgebra::{Point3, Vector3};
use nudge_executive::robot::{
    ActionStatus, Arm, GuardedMove, HandOutcome, RobotError, Stamped, Wrench, WristSensor,
};

use super::{Ros2Robot, dds};
use crate::convert::time_from_seconds;
use crate::msg::{Header, Twist, TwistStamped, Vector3 as RosVector3};

/// How much of the wrist's latest stream a tare averages (s): ten samples at HRP-2's 1 kHz, enough
/// to average out the sensor's noise while the hand stands still.
const TARE_WINDOW: f64 = 0.01;

fn tared(raw: Stamped<Wrench>, tare: &Wrench) -> Stamped<Wrench> {
    Stamped {
        stamp: raw.stamp,
        value: Wrench {
            force: raw.value.force - tare.force,
            torque: raw.value.torque - tare.torque,
        },
    }
}

impl Ros2Robot {
    /// Checks the newest reading against the guarded move's limit; stops the hand when it is reached.
    pub(super) fn guard(&mut self) -> Result<(), RobotError> {
        let (Some(limit), Some(raw)) = (self.hand.guard(), self.inbox.latest_wrench) else {
            self.pressed_since = None;
            return Ok(());
        };
        let reading = tared(raw, &self.tare);
        let pressing = self.hand.guarded_line().is_some()
            && reading.value.force_norm() >= self.model.force.contact_threshold;
        self.pressed_since = pressing.then(|| self.pressed_since.unwrap_or(reading.stamp));
        if reading.value.force_norm() >= limit {
            let at = self
                .hand_in_base()
                .map_or(self.hand.command, |(position, _)| position);
            self.hand.force_limit_reached(reading, at);
            self.send_hand(Vector3::zeros())?;
        }
        Ok(())
    }

    /// Sends the hand's next `dt` seconds as a velocity.
    pub(super) fn command_hand(&mut self, dt: f64) -> Result<(), RobotError> {
        let before = self.hand.command;
        self.hand.step(dt);
        let velocity = (self.hand.command - before) / dt;
        self.send_hand(velocity)
    }

    fn send_hand(&mut self, velocity: Vector3<f64>) -> Result<(), RobotError> {
        let moving = velocity != Vector3::zeros();
        if moving || self.hand_moving {
            let stamp =
                time_from_seconds(nudge_executive::robot::Clock::now(self)).unwrap_or_default();
            self.io
                .hand
                .publish(TwistStamped {
                    header: Header {
                        stamp,
                        frame_id: self.config.frames.base.as_str().into(),
                    },
                    twist: Twist {
                        linear: RosVector3 {
                            x: velocity.x,
                            y: velocity.y,
                            z: velocity.z,
                        },
                        angular: RosVector3::default(),
                    },
                })
                .map_err(dds)?;
        }
        self.hand_moving = moving;
        Ok(())
    }
}

impl Arm for Ros2Robot {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        self.pump()?;
        self.check()?;
        let (value, stamp) = self.hand_in_base()?;
        Ok(Stamped { stamp, value })
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        self.hand
            .start_guarded(motion)
            .map_err(|reason| RobotError::Refused {
                capability: "arm",
                reason,
            })
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        self.hand.start_retract();
        Ok(())
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        self.check()?;
        Ok(self.hand.status())
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.hand.stop();
        self.send_hand(Vector3::zeros())
    }
}

impl WristSensor for Ros2Robot {
    fn tare(&mut self) -> Result<(), RobotError> {
        self.pump()?;
        self.check()?;
        let readings = ((self.model.wrist.rate_hz * TARE_WINDOW).ceil() as usize).max(1);
        let recent: Vec<_> = self.inbox.wrenches.iter().rev().take(readings).collect();
        if recent.is_empty() {
            return Err(RobotError::Unavailable {
                capability: "wrist",
                reason: format!("nothing heard on {}", self.config.topics.wrench.as_str()),
            });
        }
        let n = recent.len() as f64;
        self.tare = Wrench {
            force: recent.iter().map(|w| w.value.force).sum::<Vector3<f64>>() / n,
            torque: recent.iter().map(|w| w.value.torque).sum::<Vector3<f64>>() / n,
        };
        Ok(())
    }

    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        self.pump()?;
        self.check()?;
        self.inbox
            .latest_wrench
            .map(|w| tared(w, &self.tare))
            .ok_or_else(|| RobotError::Unavailable {
                capability: "wrist",
                reason: format!("nothing heard on {}", self.config.topics.wrench.as_str()),
            })
    }

    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        self.pump()?;
        self.check()?;
        let tare = self.tare;
        Ok(self
            .inbox
            .wrenches
            .drain(..)
            .map(|w| tared(w, &tare))
            .collect())
    }

    fn discard_wrenches(&mut self) -> Result<(), RobotError> {
        self.pump()?;
        self.inbox.wrenches.clear();
        self.check()
    }
}
