//! `Taped`: a decorator that puts every adapter call and its result on a tape.

use nalgebra::{Isometry2, Point2, Point3};
use nudge_perception::ColourCloud;

use super::call::{Entry, Reply, Request};
use super::tape_buffer::Tape;
use crate::robot::{
    ActionStatus, Arm, Base, Clock, GuardedMove, HandOutcome, Head, RangeCamera, Robot, RobotError,
    Stamped, WalkOutcome, Wrench, WristSensor,
};

/// Wraps any robot and writes each call the executive makes — the method, its arguments, and the
/// result, errors included — onto a [`Tape`], then hands the result back unchanged. Without a tape
/// ([`Taped::untaped`]) it only forwards, so a caller can keep one robot type whether it records
/// or not.
#[derive(Debug)]
pub struct Taped<R> {
    inner: R,
    tape: Option<Tape>,
}

impl<R: Robot> Taped<R> {
    /// Wraps `inner`, taping every call onto `tape`.
    pub fn new(inner: R, tape: Tape) -> Self {
        Self {
            inner,
            tape: Some(tape),
        }
    }

    /// Wraps `inner` without a tape: every call is only forwarded.
    pub fn untaped(inner: R) -> Self {
        Self { inner, tape: None }
    }

    /// The wrapped robot (calls made on it directly are not taped).
    pub fn inner(&self) -> &R {
        &self.inner
    }

    /// Unwraps the decorator.
    pub fn into_inner(self) -> R {
        self.inner
    }

    /// Puts a call on the tape, if there is one; `call` builds it only then.
    fn tape(&self, call: impl FnOnce() -> (Request, Reply)) {
        if let Some(tape) = &self.tape {
            let (request, reply) = call();
            tape.write(Entry::Call(request, reply));
        }
    }
}

impl<R: Robot> Clock for Taped<R> {
    fn now(&self) -> f64 {
        let t = self.inner.now();
        self.tape(|| (Request::Now, Reply::Time(t)));
        t
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        let r = self.inner.advance(dt);
        self.tape(|| (Request::Advance(dt), Reply::Done(r.clone())));
        r
    }
}

impl<R: Robot> Base for Taped<R> {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        let r = self.inner.base_pose();
        self.tape(|| (Request::BasePose, Reply::Pose(r.clone())));
        r
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        let r = self.inner.start_walk(waypoints);
        self.tape(|| {
            (
                Request::StartWalk(waypoints.to_vec()),
                Reply::Done(r.clone()),
            )
        });
        r
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        let r = self.inner.start_turn(yaw);
        self.tape(|| (Request::StartTurn(yaw), Reply::Done(r.clone())));
        r
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        let r = self.inner.walk_status();
        self.tape(|| (Request::WalkStatus, Reply::Walk(r.clone())));
        r
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        let r = self.inner.stop_walk();
        self.tape(|| (Request::StopWalk, Reply::Done(r.clone())));
        r
    }
}

impl<R: Robot> Head for Taped<R> {
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        let r = self.inner.head_angles();
        self.tape(|| (Request::HeadAngles, Reply::Angles(r.clone())));
        r
    }

    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        let r = self.inner.start_point_head(pan, tilt);
        self.tape(|| (Request::StartPointHead(pan, tilt), Reply::Done(r.clone())));
        r
    }

    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        let r = self.inner.head_status();
        self.tape(|| (Request::HeadStatus, Reply::Head(r.clone())));
        r
    }
}

impl<R: Robot> RangeCamera for Taped<R> {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        let r = self.inner.capture();
        self.tape(|| (Request::Capture, Reply::Cloud(r.clone())));
        r
    }
}

impl<R: Robot> WristSensor for Taped<R> {
    fn tare(&mut self) -> Result<(), RobotError> {
        let r = self.inner.tare();
        self.tape(|| (Request::Tare, Reply::Done(r.clone())));
        r
    }

    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        let r = self.inner.wrench();
        self.tape(|| (Request::Wrench, Reply::Wrench(r.clone())));
        r
    }

    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        let r = self.inner.drain_wrenches();
        self.tape(|| (Request::DrainWrenches, Reply::Wrenches(r.clone())));
        r
    }

    fn discard_wrenches(&mut self) -> Result<(), RobotError> {
        let r = self.inner.discard_wrenches();
        self.tape(|| (Request::DiscardWrenches, Reply::Done(r.clone())));
        r
    }
}

impl<R: Robot> Arm for Taped<R> {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        let r = self.inner.hand_position();
        self.tape(|| (Request::HandPosition, Reply::Hand(r.clone())));
        r
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        let request = self.tape.is_some().then(|| motion.clone());
        let r = self.inner.start_guarded_move(motion);
        if let Some(motion) = request {
            self.tape(|| (Request::StartGuardedMove(motion), Reply::Done(r.clone())));
        }
        r
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        let r = self.inner.start_retract();
        self.tape(|| (Request::StartRetract, Reply::Done(r.clone())));
        r
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        let r = self.inner.hand_status();
        self.tape(|| (Request::HandStatus, Reply::HandStatus(r.clone())));
        r
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        let r = self.inner.stop_hand();
        self.tape(|| (Request::StopHand, Reply::Done(r.clone())));
        r
    }
}
