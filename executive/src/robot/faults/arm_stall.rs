//! An arm that stalls: the hand stops, its status says running.

use nalgebra::Point3;

use super::FaultWindow;
use super::forward::{fault, forward};
use crate::robot::{
    ActionStatus, Arm, Clock, GuardedMove, HandOutcome, Robot, RobotError, Stamped,
};

/// A hand motion that stalls: the hand stops where it is (the wrapped arm is stopped) while
/// [`Arm::hand_status`] keeps answering `Running` — a joint at its current limit, a controller
/// waiting on a trajectory it will never finish. Once a motion has run `after` seconds of robot
/// time (so the hand is out, not still at its start), each poll of it while it runs is a chance;
/// once the window fires, the stall holds until the executive stops the hand ([`Arm::stop_hand`], which
/// then reports `Stopped`) or starts another motion: the arm still obeys commands, it only never
/// finishes this one. Every other call is forwarded.
#[derive(Debug)]
pub struct ArmStall<R> {
    inner: R,
    window: FaultWindow,
    after: f64,
    /// Robot time the motion under way has run (s), counted from what [`Clock::advance`] lets pass.
    moving: Option<f64>,
    stalled: bool,
}

impl<R: Robot> ArmStall<R> {
    /// Wraps `inner`; a hand motion that has run `after` seconds stalls when `window` fires.
    pub fn new(inner: R, window: FaultWindow, after: f64) -> Self {
        Self {
            inner,
            window,
            after,
            moving: None,
            stalled: false,
        }
    }
}

fault!(ArmStall);
forward!(ArmStall: Base, Head, RangeCamera, WristSensor);

impl<R: Robot> Clock for ArmStall<R> {
    fn now(&self) -> f64 {
        self.inner.now()
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        self.inner.advance(dt)?;
        if let Some(t) = self.moving.as_mut() {
            *t += dt;
        }
        Ok(())
    }
}

impl<R: Robot> Arm for ArmStall<R> {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        self.inner.hand_position()
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        self.stalled = false;
        self.inner.start_guarded_move(motion)?;
        self.moving = Some(0.0);
        Ok(())
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        self.stalled = false;
        self.inner.start_retract()?;
        self.moving = Some(0.0);
        Ok(())
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        if self.stalled {
            return Ok(ActionStatus::Running);
        }
        let status = self.inner.hand_status()?;
        match status {
            ActionStatus::Running
                if self.moving.is_some_and(|t| t >= self.after)
                    && self.window.fires(self.inner.now()) =>
            {
                self.inner.stop_hand()?;
                self.stalled = true;
                Ok(ActionStatus::Running)
            }
            ActionStatus::Running => Ok(status),
            ActionStatus::Done(_) => {
                self.moving = None;
                Ok(status)
            }
        }
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.stalled = false;
        self.moving = None;
        self.inner.stop_hand()
    }
}
