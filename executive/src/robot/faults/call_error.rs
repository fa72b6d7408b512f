//! An adapter call that fails.

use nalgebra::{Isometry2, Point2, Point3};
use nudge_perception::ColourCloud;

use super::FaultWindow;
use super::forward::fault;
use crate::robot::{
    ActionStatus, Arm, Base, Clock, GuardedMove, HandOutcome, Head, RangeCamera, Robot, RobotError,
    Stamped, WalkOutcome, Wrench, WristSensor,
};

/// How the failing call fails.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ErrorKind {
    /// [`RobotError::Fault`]: the hardware or the driver reported a fault.
    Fault,
    /// [`RobotError::Timeout`]: the adapter gave up waiting for the hardware after `seconds`.
    Timeout {
        /// How long the adapter says it waited (s).
        seconds: f64,
    },
}

/// An adapter call that fails: every call but [`Clock::now`] (which cannot fail) is a chance, and
/// when the window fires the call returns the error `kind` says without reaching the wrapped robot —
/// a dropped connection, a driver restart, a controller that did not answer in time. Whichever call
/// the executive makes next is the one that fails, so a trigger on a state fails that state's next
/// call, whatever it is.
#[derive(Debug)]
pub struct CallError<R> {
    inner: R,
    window: FaultWindow,
    kind: ErrorKind,
}

impl<R: Robot> CallError<R> {
    /// Wraps `inner`; a call fails as `kind` says whenever `window` fires.
    pub fn new(inner: R, window: FaultWindow, kind: ErrorKind) -> Self {
        Self {
            inner,
            window,
            kind,
        }
    }

    /// A chance: the error for `call` of `capability` when the window fires.
    fn check(&self, capability: &'static str, call: &str) -> Result<(), RobotError> {
        if !self.window.fires(self.inner.now()) {
            return Ok(());
        }
        Err(match self.kind {
            ErrorKind::Fault => RobotError::Fault {
                capability,
                reason: format!("{call} failed (injected)"),
            },
            ErrorKind::Timeout { seconds } => RobotError::Timeout {
                capability,
                seconds,
            },
        })
    }
}

fault!(CallError);

impl<R: Robot> Clock for CallError<R> {
    fn now(&self) -> f64 {
        self.inner.now()
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        self.check("clock", "advance")?;
        self.inner.advance(dt)
    }
}

impl<R: Robot> Base for CallError<R> {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        self.check("base", "base_pose")?;
        self.inner.base_pose()
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        self.check("base", "start_walk")?;
        self.inner.start_walk(waypoints)
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        self.check("base", "start_turn")?;
        self.inner.start_turn(yaw)
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        self.check("base", "walk_status")?;
        self.inner.walk_status()
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        self.check("base", "stop_walk")?;
        self.inner.stop_walk()
    }
}

impl<R: Robot> Head for CallError<R> {
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        self.check("head", "head_angles")?;
        self.inner.head_angles()
    }

    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        self.check("head", "start_point_head")?;
        self.inner.start_point_head(pan, tilt)
    }

    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        self.check("head", "head_status")?;
        self.inner.head_status()
    }
}

impl<R: Robot> RangeCamera for CallError<R> {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        self.check("camera", "capture")?;
        self.inner.capture()
    }
}

impl<R: Robot> WristSensor for CallError<R> {
    fn tare(&mut self) -> Result<(), RobotError> {
        self.check("wrist", "tare")?;
        self.inner.tare()
    }

    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        self.check("wrist", "wrench")?;
        self.inner.wrench()
    }

    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        self.check("wrist", "drain_wrenches")?;
        self.inner.drain_wrenches()
    }

    fn discard_wrenches(&mut self) -> Result<(), RobotError> {
        self.check("wrist", "discard_wrenches")?;
        self.inner.discard_wrenches()
    }
}

impl<R: Robot> Arm for CallError<R> {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        self.check("arm", "hand_position")?;
        self.inner.hand_position()
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        self.check("arm", "start_guarded_move")?;
        self.inner.start_guarded_move(motion)
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        self.check("arm", "start_retract")?;
        self.inner.start_retract()
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        self.check("arm", "hand_status")?;
        self.inner.hand_status()
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.check("arm", "stop_hand")?;
        self.inner.stop_hand()
    }
}
