//! A walk that stops short and says it arrived.

use nalgebra::{Isometry2, Point2};

use super::FaultWindow;
use super::forward::{fault, forward};
use crate::robot::{ActionStatus, Base, Clock, Robot, RobotError, Stamped, WalkOutcome};

/// A walk (or turn) that stops short of its end and reports [`WalkOutcome::Arrived`]: a base
/// controller that reaches its step budget, or localisation that jumps onto the goal. Once a walk or
/// turn has run `after` seconds of robot time, each poll of its status while it still runs is a
/// chance; when the window fires, the wrapped base is stopped where it stands and the poll answers
/// `Done(Arrived)`. The base pose stays true: an executive that checks where it stands finds out.
/// Every other call is forwarded.
#[derive(Debug)]
pub struct ShortWalk<R> {
    inner: R,
    window: FaultWindow,
    after: f64,
    /// Robot time the walk or turn under way has run (s), counted from what [`Clock::advance`]
    /// lets pass.
    walking: Option<f64>,
}

impl<R: Robot> ShortWalk<R> {
    /// Wraps `inner`; a walk or turn that has run `after` seconds is cut short whenever `window`
    /// fires.
    pub fn new(inner: R, window: FaultWindow, after: f64) -> Self {
        Self {
            inner,
            window,
            after,
            walking: None,
        }
    }
}

fault!(ShortWalk);
forward!(ShortWalk: Head, RangeCamera, WristSensor, Arm);

impl<R: Robot> Clock for ShortWalk<R> {
    fn now(&self) -> f64 {
        self.inner.now()
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        self.inner.advance(dt)?;
        if let Some(t) = self.walking.as_mut() {
            *t += dt;
        }
        Ok(())
    }
}

impl<R: Robot> Base for ShortWalk<R> {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        self.inner.base_pose()
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        self.inner.start_walk(waypoints)?;
        self.walking = Some(0.0);
        Ok(())
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        self.inner.start_turn(yaw)?;
        self.walking = Some(0.0);
        Ok(())
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        let status = self.inner.walk_status()?;
        if let ActionStatus::Done(_) = status {
            self.walking = None;
            return Ok(status);
        }
        let long_enough = self.walking.is_some_and(|t| t >= self.after);
        if long_enough && self.window.fires(self.inner.now()) {
            self.inner.stop_walk()?;
            self.walking = None;
            return Ok(ActionStatus::Done(WalkOutcome::Arrived));
        }
        Ok(status)
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        self.walking = None;
        self.inner.stop_walk()
    }
}
