//! Driving a new run from a tape: the [`ReplayRobot`] answers every call with what the recording
//! holds, the [`ReplayObserver`] checks every transition, and the first call or transition that
//! differs is the [`Divergence`].

use std::cell::RefCell;
use std::fmt;
use std::rc::Rc;

use nalgebra::{Isometry2, Point2, Point3};
use nudge_perception::ColourCloud;

use super::call::{Entry, Reply, Request, Transition};
use super::codec::request_bytes;
use crate::machine::Edge;
use crate::record::Observer;
use crate::robot::{
    ActionStatus, Arm, Base, Clock, GuardedMove, HandOutcome, Head, RangeCamera, RobotError,
    Stamped, WalkOutcome, Wrench, WristSensor,
};
use crate::state::State;

/// Where a new run first parted from its recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Divergence {
    /// Index of the tape entry where it parted (calls and transitions counted together, from 0).
    pub index: usize,
    /// Robot time there: the recording's last clock reading before that entry (s).
    pub robot_time: f64,
    /// The state the executive was in: the target of the last transition both runs took (`None`
    /// before the first).
    pub state: Option<String>,
    /// What the recording holds there (`(end of recording)` past its end).
    pub recorded: String,
    /// What the new run did there.
    pub new: String,
}

impl fmt::Display for Divergence {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "divergence at tape entry {}, robot time {:.3} s, state {}",
            self.index,
            self.robot_time,
            self.state.as_deref().unwrap_or("(before the start)")
        )?;
        writeln!(f, "  recorded: {}", self.recorded)?;
        write!(f, "  new:      {}", self.new)
    }
}

#[derive(Debug)]
struct Cursor {
    entries: Vec<Entry>,
    next: usize,
    clock: f64,
    state: Option<String>,
    calls: usize,
    transitions: usize,
    divergence: Option<Divergence>,
}

impl Cursor {
    fn diverge(&mut self, new: String) {
        if self.divergence.is_some() {
            return;
        }
        let recorded = self
            .entries
            .get(self.next)
            .map_or_else(|| "(end of recording)".to_string(), ToString::to_string);
        self.divergence = Some(Divergence {
            index: self.next,
            robot_time: self.clock,
            state: self.state.clone(),
            recorded,
            new,
        });
    }

    /// The recorded reply to `request` when the next entry is the same call, bit for bit.
    fn call(&mut self, request: Request) -> Option<Reply> {
        if self.divergence.is_some() {
            return None;
        }
        let reply = match self.entries.get(self.next) {
            Some(Entry::Call(recorded, reply))
                if request_bytes(recorded) == request_bytes(&request) =>
            {
                reply.clone()
            }
            _ => {
                self.diverge(request.to_string());
                return None;
            }
        };
        self.next += 1;
        self.calls += 1;
        if let Reply::Time(t) = reply {
            self.clock = t;
        }
        Some(reply)
    }

    fn transition(&mut self, t: Transition) {
        if self.divergence.is_some() {
            return;
        }
        match self.entries.get(self.next) {
            Some(Entry::Transition(recorded)) if *recorded == t => {
                self.next += 1;
                self.transitions += 1;
                self.state = Some(t.to);
            }
            _ => self.diverge(t.to_string()),
        }
    }
}

/// A replay of one tape: hand [`Replay::robot`] and [`Replay::observer`] to a runner, run it, then
/// ask [`Replay::finish`] whether it matched.
#[derive(Clone, Debug)]
pub struct Replay(Rc<RefCell<Cursor>>);

impl Replay {
    /// A replay of `entries`, in tape order.
    pub fn new(entries: Vec<Entry>) -> Self {
        Self(Rc::new(RefCell::new(Cursor {
            entries,
            next: 0,
            clock: 0.0,
            state: None,
            calls: 0,
            transitions: 0,
            divergence: None,
        })))
    }

    /// The robot that answers from the tape.
    pub fn robot(&self) -> ReplayRobot {
        ReplayRobot(self.clone())
    }

    /// The observer that checks the new run's transitions against the tape.
    pub fn observer(&self) -> ReplayObserver {
        ReplayObserver(self.clone())
    }

    /// Entries on the tape.
    pub fn len(&self) -> usize {
        self.0.borrow().entries.len()
    }

    /// True when the tape is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Calls that matched so far.
    pub fn calls(&self) -> usize {
        self.0.borrow().calls
    }

    /// Transitions that matched so far.
    pub fn transitions(&self) -> usize {
        self.0.borrow().transitions
    }

    /// The first divergence so far.
    pub fn divergence(&self) -> Option<Divergence> {
        self.0.borrow().divergence.clone()
    }

    /// Ends the replay after the new run ended (`ended`: how, for the report): a run that stopped
    /// before the tape did diverges at the first entry it did not reach. The first divergence, or
    /// `None` when every entry matched.
    pub fn finish(&self, ended: &str) -> Option<Divergence> {
        let mut c = self.0.borrow_mut();
        if c.next < c.entries.len() {
            c.diverge(format!("(the run ended: {ended})"));
        }
        c.divergence.clone()
    }

    fn call(&self, request: Request) -> Option<Reply> {
        self.0.borrow_mut().call(request)
    }
}

/// The error every call returns once the run has parted from the recording, so that it ends.
fn parted() -> RobotError {
    RobotError::Fault {
        capability: "replay",
        reason: "the run parted from the recording".into(),
    }
}

/// A robot that answers every call from a tape (see [`Replay`]). A query returns the recorded
/// reply; a command must have the recorded arguments bit for bit. Any other call, or one past the
/// tape's end, is a divergence, after which every call fails.
#[derive(Clone, Debug)]
pub struct ReplayRobot(Replay);

/// Checks the new run's transitions against the tape (see [`Replay`]).
#[derive(Clone, Debug)]
pub struct ReplayObserver(Replay);

impl Observer for ReplayObserver {
    fn transition(&mut self, _stamp: f64, from: Option<&State>, edge: Edge, to: &State) {
        self.0
            .0
            .borrow_mut()
            .transition(Transition::new(from, edge, to));
    }
}

/// Answers `$request` with the recorded reply of kind `$kind`, or fails after a divergence.
macro_rules! answer {
    ($self:ident, $request:expr, $kind:ident) => {
        match $self.0.call($request) {
            Some(Reply::$kind(r)) => r,
            _ => Err(parted()),
        }
    };
}

impl Clock for ReplayRobot {
    /// The recorded reading; after a divergence, the last one.
    fn now(&self) -> f64 {
        match self.0.call(Request::Now) {
            Some(Reply::Time(t)) => t,
            _ => self.0.0.borrow().clock,
        }
    }

    fn advance(&mut self, dt: f64) -> Result<(), RobotError> {
        answer!(self, Request::Advance(dt), Done)
    }
}

impl Base for ReplayRobot {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        answer!(self, Request::BasePose, Pose)
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        answer!(self, Request::StartWalk(waypoints.to_vec()), Done)
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        answer!(self, Request::StartTurn(yaw), Done)
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        answer!(self, Request::WalkStatus, Walk)
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        answer!(self, Request::StopWalk, Done)
    }
}

impl Head for ReplayRobot {
    fn head_angles(&mut self) -> Result<Stamped<(f64, f64)>, RobotError> {
        answer!(self, Request::HeadAngles, Angles)
    }

    fn start_point_head(&mut self, pan: f64, tilt: f64) -> Result<(), RobotError> {
        answer!(self, Request::StartPointHead(pan, tilt), Done)
    }

    fn head_status(&mut self) -> Result<ActionStatus<()>, RobotError> {
        answer!(self, Request::HeadStatus, Head)
    }
}

impl RangeCamera for ReplayRobot {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        answer!(self, Request::Capture, Cloud)
    }
}

impl WristSensor for ReplayRobot {
    fn tare(&mut self) -> Result<(), RobotError> {
        answer!(self, Request::Tare, Done)
    }

    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        answer!(self, Request::Wrench, Wrench)
    }

    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        answer!(self, Request::DrainWrenches, Wrenches)
    }

    fn discard_wrenches(&mut self) -> Result<(), RobotError> {
        answer!(self, Request::DiscardWrenches, Done)
    }
}

impl Arm for ReplayRobot {
    fn hand_position(&mut self) -> Result<Stamped<Point3<f64>>, RobotError> {
        answer!(self, Request::HandPosition, Hand)
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        answer!(self, Request::StartGuardedMove(motion), Done)
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        answer!(self, Request::StartRetract, Done)
    }

    fn hand_status(&mut self) -> Result<ActionStatus<HandOutcome>, RobotError> {
        answer!(self, Request::HandStatus, HandStatus)
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        answer!(self, Request::StopHand, Done)
    }
}
