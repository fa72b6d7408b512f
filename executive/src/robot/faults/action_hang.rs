//! An action whose status never says done.

use nalgebra::{Isometry2, Point2, Point3};

use super::FaultWindow;
use super::forward::{fault, forward};
use crate::robot::{
    ActionStatus, Arm, Base, GuardedMove, HandOutcome, Head, Robot, RobotError, Stamped,
    WalkOutcome,
};

/// Which action hangs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Action {
    Walk,
    Head,
    Hand,
}

/// An action (a walk or turn, a head motion, a hand motion) whose completion never arrives: its
/// status answers `Running` forever, whatever the wrapped robot did — a lost "done" message, a
/// driver that stopped publishing. Each status poll is a chance; when the window fires, the action
/// polled hangs until the executive stops it or starts another of its kind (a head has no stop: only
/// a new head motion ends it). The polls still reach the wrapped robot. Every other call is
/// forwarded.
#[derive(Debug)]
pub struct ActionHang<R> {
    inner: R,
    window: FaultWindow,
    hung: Option<Action>,
}

impl<R: Robot> ActionHang<R> {
    /// Wraps `inner`; the action polled hangs when `window` fires.
    pub fn new(inner: R, window: FaultWindow) -> Self {
        Self {
            inner,
            window,
            hung: None,
        }
    }

    /// `status`, or `Running` when `action` hangs or starts hanging now.
    fn answer<T>(&mut self, action: Action, status: ActionStatus<T>) -> ActionStatus<T> {
        if self.hung == Some(action) || (self.hung.is_none() && self.window.fires(self.inner.now()))
        {
            self.hung = Some(action);
            return ActionStatus::Running;
        }
        status
    }

    fn release(&mut self, action: Action) {
        if self.hung == Some(action) {
            self.hung = None;
        }
    }
}

fault!(ActionHang);
forward!(ActionHang: Clock, RangeCamera, WristSensor);

impl<R: Robot> Base for ActionHang<R> {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        self.inner.base_pose()
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        self.release(Action::Walk);
        self.inner.start_walk(waypoints)
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        self.release(Action::Walk);
        self.inner.start_turn(yaw)
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        let status = self.inner.walk_status()?;
        Ok(self.answer(Action::Walk, status))
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        self.release(Action::Walk);
        self.inner.stop_walk()
    }
}

impl<R: Robot> Head for ActionHang<R> {
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        self.inner.head_angles()
    }

    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        self.release(Action::Head);
        self.inner.start_point_head(pan, tilt)
    }

    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        let status = self.inner.head_status()?;
        Ok(self.answer(Action::Head, status))
    }
}

impl<R: Robot> Arm for ActionHang<R> {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        self.inner.hand_position()
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        self.release(Action::Hand);
        self.inner.start_guarded_move(motion)
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        self.release(Action::Hand);
        self.inner.start_retract()
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        let status = self.inner.hand_status()?;
        Ok(self.answer(Action::Hand, status))
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.release(Action::Hand);
        self.inner.stop_hand()
    }
}
