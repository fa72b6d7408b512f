//! The harness side of a fault test: a run that cannot hang.

use std::cell::Cell;

use nalgebra::{Isometry2, Point2, Point3};
use nudge_perception::ColourCloud;

use crate::robot::{
    ActionStatus, Arm, Base, Clock, GuardedMove, HandOutcome, Head, RangeCamera, Robot, RobotError,
    Stamped, WalkOutcome, Wrench, WristSensor,
};

/// Ends a run that goes on too long, so that a hang in a test is a failure and not a stuck test.
/// It counts every adapter call and the robot time [`Clock::advance`] lets pass (not the clock's
/// reading, which a [`super::ClockJump`] may have moved); once either passes its bound, every call
/// but [`Clock::now`] fails with [`RobotError::Fault`] of capability `"bound"`, which ends any run
/// (the runner aborts, its safe stop fails too), and [`Bounded::exceeded`] says so. Below the bounds
/// every call is forwarded untouched. Put it outermost, around the faults.
#[derive(Debug)]
pub struct Bounded<R> {
    inner: R,
    max_time: f64,
    max_calls: u64,
    time: f64,
    calls: Cell<u64>,
}

impl<R: Robot> Bounded<R> {
    /// Wraps `inner`, allowing `max_time` seconds of robot time and `max_calls` adapter calls.
    pub fn new(inner: R, max_time: f64, max_calls: u64) -> Self {
        Self {
            inner,
            max_time,
            max_calls,
            time: 0.0,
            calls: Cell::new(0),
        }
    }

    /// True once a bound was passed.
    pub fn exceeded(&self) -> bool {
        self.time > self.max_time || self.calls.get() > self.max_calls
    }

    /// Robot time let pass so far (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Adapter calls so far.
    pub fn calls(&self) -> u64 {
        self.calls.get()
    }

    /// The wrapped robot.
    pub fn inner(&self) -> &R {
        &self.inner
    }

    /// Unwraps it.
    pub fn into_inner(self) -> R {
        self.inner
    }

    /// Counts a call of `capability`; an error once a bound is passed.
    fn count(&self, capability: &'static str) -> Result<(), RobotError> {
        self.calls.set(self.calls.get() + 1);
        if self.exceeded() {
            return Err(RobotError::Fault {
                capability: "bound",
                reason: format!(
                    "{capability} called past the test's bound ({} s of robot time, {} calls)",
                    self.max_time, self.max_calls
                ),
            });
        }
        Ok(())
    }
}

impl<R: Robot> Clock for Bounded<R> {
    fn now(&self) -> f64 {
        self.calls.set(self.calls.get() + 1);
        self.inner.now()
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        self.count("clock")?;
        self.time += dt;
        self.inner.advance(dt)
    }
}

impl<R: Robot> Base for Bounded<R> {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        self.count("base")?;
        self.inner.base_pose()
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        self.count("base")?;
        self.inner.start_walk(waypoints)
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        self.count("base")?;
        self.inner.start_turn(yaw)
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        self.count("base")?;
        self.inner.walk_status()
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        self.count("base")?;
        self.inner.stop_walk()
    }
}

impl<R: Robot> Head for Bounded<R> {
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        self.count("head")?;
        self.inner.head_angles()
    }

    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        self.count("head")?;
        self.inner.start_point_head(pan, tilt)
    }

    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        self.count("head")?;
        self.inner.head_status()
    }
}

impl<R: Robot> RangeCamera for Bounded<R> {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        self.count("camera")?;
        self.inner.capture()
    }
}

impl<R: Robot> WristSensor for Bounded<R> {
    fn tare(&mut self) -> Result<(), RobotError> {
        self.count("wrist")?;
        self.inner.tare()
    }

    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        self.count("wrist")?;
        self.inner.wrench()
    }

    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        self.count("wrist")?;
        self.inner.drain_wrenches()
    }

    fn discard_wrenches(&mut self) -> Result<(), RobotError> {
        self.count("wrist")?;
        self.inner.discard_wrenches()
    }
}

impl<R: Robot> Arm for Bounded<R> {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        self.count("arm")?;
        self.inner.hand_position()
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        self.count("arm")?;
        self.inner.start_guarded_move(motion)
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        self.count("arm")?;
        self.inner.start_retract()
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        self.count("arm")?;
        self.inner.hand_status()
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.count("arm")?;
        self.inner.stop_hand()
    }
}
