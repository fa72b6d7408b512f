//! A clock that jumps.

use std::cell::Cell;

use nalgebra::{Isometry2, Point2, Point3};
use nudge_perception::ColourCloud;

use super::FaultWindow;
use super::forward::fault;
use crate::robot::{
    ActionStatus, Arm, Base, Clock, GuardedMove, HandOutcome, Head, RangeCamera, Robot, RobotError,
    Stamped, WalkOutcome, Wrench, WristSensor,
};

/// A robot clock that steps by `offset` seconds (forwards or backwards) and stays stepped: an NTP
/// correction, a clock source switched over, a simulation restarted under a running executive.
/// Every call is a chance, [`Clock::now`] included; from the first that fires on, `now` and every
/// stamp the robot returns (poses, head angles, hand positions, wrenches, clouds) carry the offset.
/// Time itself passes as before: [`Clock::advance`] is forwarded unchanged.
#[derive(Debug)]
pub struct ClockJump<R> {
    inner: R,
    window: FaultWindow,
    offset: f64,
    jumped: Cell<bool>,
}

impl<R: Robot> ClockJump<R> {
    /// Wraps `inner`; the clock steps by `offset` (s) when `window` first fires.
    pub fn new(inner: R, window: FaultWindow, offset: f64) -> Self {
        Self {
            inner,
            window,
            offset,
            jumped: Cell::new(false),
        }
    }

    /// A chance, then the offset in force (0 before the jump).
    fn shift(&self) -> f64 {
        if !self.jumped.get() && self.window.fires(self.inner.now()) {
            self.jumped.set(true);
        }
        if self.jumped.get() { self.offset } else { 0.0 }
    }

    fn stamped<T>(&self, mut value: Stamped<T>) -> Stamped<T> {
        value.stamp += self.shift();
        value
    }
}

fault!(ClockJump);

impl<R: Robot> Clock for ClockJump<R> {
    fn now(&self) -> f64 {
        self.inner.now() + self.shift()
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        self.shift();
        self.inner.advance(dt)
    }
}

impl<R: Robot> Base for ClockJump<R> {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        let pose = self.inner.base_pose()?;
        Ok(self.stamped(pose))
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        self.shift();
        self.inner.start_walk(waypoints)
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        self.shift();
        self.inner.start_turn(yaw)
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        self.shift();
        self.inner.walk_status()
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        self.shift();
        self.inner.stop_walk()
    }
}

impl<R: Robot> Head for ClockJump<R> {
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        let angles = self.inner.head_angles()?;
        Ok(self.stamped(angles))
    }

    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        self.shift();
        self.inner.start_point_head(pan, tilt)
    }

    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        self.shift();
        self.inner.head_status()
    }
}

impl<R: Robot> RangeCamera for ClockJump<R> {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        let cloud = self.inner.capture()?;
        let shift = self.shift();
        if shift == 0.0 {
            return Ok(cloud);
        }
        ColourCloud::organised(
            cloud.width(),
            cloud.height(),
            cloud.xs().to_vec(),
            cloud.ys().to_vec(),
            cloud.zs().to_vec(),
            cloud.colours().to_vec(),
            cloud.frame(),
            *cloud.sensor_pose(),
            cloud.stamp() + shift,
        )
        .map_err(|e| RobotError::Fault {
            capability: "camera",
            reason: e.to_string(),
        })
    }
}

impl<R: Robot> WristSensor for ClockJump<R> {
    fn tare(&mut self) -> Result<(), RobotError> {
        self.shift();
        self.inner.tare()
    }

    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        let reading = self.inner.wrench()?;
        Ok(self.stamped(reading))
    }

    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        let samples = self.inner.drain_wrenches()?;
        Ok(samples.into_iter().map(|s| self.stamped(s)).collect())
    }
}

impl<R: Robot> Arm for ClockJump<R> {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        let at = self.inner.hand_position()?;
        Ok(self.stamped(at))
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        self.shift();
        self.inner.start_guarded_move(motion)
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        self.shift();
        self.inner.start_retract()
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        let status = self.inner.hand_status()?;
        Ok(match status {
            ActionStatus::Done(HandOutcome::ForceLimit { wrench, at }) => {
                ActionStatus::Done(HandOutcome::ForceLimit {
                    wrench: self.stamped(wrench),
                    at,
                })
            }
            other => {
                self.shift();
                other
            }
        })
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.shift();
        self.inner.stop_hand()
    }
}
