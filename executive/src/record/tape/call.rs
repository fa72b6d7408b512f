//! What a tape holds: adapter calls (a [`Request`] and its [`Reply`]) and transitions.

use std::fmt;

use nalgebra::{Isometry2, Point2, Point3};
use nudge_perception::ColourCloud;

use crate::machine::Edge;
use crate::robot::{
    ActionStatus, GuardedMove, HandOutcome, RobotError, Stamped, WalkOutcome, Wrench,
};
use crate::state::State;

/// An adapter call as the executive made it: the method and, for commands, its arguments.
#[derive(Clone, Debug, PartialEq)]
pub enum Request {
    /// `Clock::now`.
    Now,
    /// `Clock::advance(dt)`.
    Advance(f64),
    /// `Base::base_pose`.
    BasePose,
    /// `Base::start_walk(waypoints)`.
    StartWalk(Vec<Point2<f64>>),
    /// `Base::start_turn(yaw)`.
    StartTurn(f64),
    /// `Base::walk_status`.
    WalkStatus,
    /// `Base::stop_walk`.
    StopWalk,
    /// `Head::head_angles`.
    HeadAngles,
    /// `Head::start_point_head(pan, tilt)`.
    StartPointHead(f64, f64),
    /// `Head::head_status`.
    HeadStatus,
    /// `RangeCamera::capture`.
    Capture,
    /// `WristSensor::tare`.
    Tare,
    /// `WristSensor::wrench`.
    Wrench,
    /// `WristSensor::drain_wrenches`.
    DrainWrenches,
    /// `WristSensor::discard_wrenches`.
    DiscardWrenches,
    /// `Arm::hand_position`.
    HandPosition,
    /// `Arm::start_guarded_move(motion)`.
    StartGuardedMove(GuardedMove),
    /// `Arm::start_retract`.
    StartRetract,
    /// `Arm::hand_status`.
    HandStatus,
    /// `Arm::stop_hand`.
    StopHand,
}

/// What the robot answered a [`Request`]; each request has one kind of reply.
#[derive(Clone, Debug, PartialEq)]
pub enum Reply {
    /// The clock's reading (`now`).
    Time(f64),
    /// A command's result (`advance`, `start_*`, `stop_*`, `tare`).
    Done(Result<(), RobotError>),
    /// `base_pose`.
    Pose(Result<Stamped<Isometry2<f64>>, RobotError>),
    /// `walk_status`.
    Walk(Result<ActionStatus<WalkOutcome>, RobotError>),
    /// `head_angles`.
    Angles(Result<Stamped<(f64, f64)>, RobotError>),
    /// `head_status`.
    Head(Result<ActionStatus<()>, RobotError>),
    /// `capture`.
    Cloud(Result<ColourCloud, RobotError>),
    /// `wrench`.
    Wrench(Result<Stamped<Wrench>, RobotError>),
    /// `drain_wrenches`.
    Wrenches(Result<Vec<Stamped<Wrench>>, RobotError>),
    /// `hand_position`.
    Hand(Result<Stamped<Point3<f64>>, RobotError>),
    /// `hand_status`.
    HandStatus(Result<ActionStatus<HandOutcome>, RobotError>),
}

/// A transition of the executive, as the observer saw it: state names and the edge.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Transition {
    /// The state left (`(start)` for the run's first step).
    pub from: String,
    /// The edge taken (its `Debug` name).
    pub edge: String,
    /// The state entered.
    pub to: String,
}

impl Transition {
    /// The transition an observer is told of.
    pub fn new(from: Option<&State>, edge: Edge, to: &State) -> Self {
        Self {
            from: from.map_or("(start)", State::name).to_string(),
            edge: format!("{edge:?}"),
            to: to.name().to_string(),
        }
    }
}

/// One thing on a tape.
#[derive(Clone, Debug, PartialEq)]
pub enum Entry {
    /// An adapter call and the robot's answer.
    Call(Request, Reply),
    /// A transition of the executive.
    Transition(Transition),
}

impl fmt::Display for Transition {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "transition {} -> {} ({})", self.from, self.to, self.edge)
    }
}

impl fmt::Display for Entry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Entry::Call(request, _) => request.fmt(f),
            Entry::Transition(t) => t.fmt(f),
        }
    }
}

/// `(x, y, z)` with every digit the float needs to be read back exactly.
fn p3(p: &Point3<f64>) -> String {
    format!("({}, {}, {})", p.x, p.y, p.z)
}

impl fmt::Display for Request {
    /// The call as code would write it, floats printed exactly (shortest round-trip form).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Request::Now => write!(f, "now()"),
            Request::Advance(dt) => write!(f, "advance({dt})"),
            Request::BasePose => write!(f, "base_pose()"),
            Request::StartWalk(waypoints) => {
                let points: Vec<String> = waypoints
                    .iter()
                    .map(|p| format!("({}, {})", p.x, p.y))
                    .collect();
                write!(f, "start_walk([{}])", points.join(", "))
            }
            Request::StartTurn(yaw) => write!(f, "start_turn({yaw})"),
            Request::WalkStatus => write!(f, "walk_status()"),
            Request::StopWalk => write!(f, "stop_walk()"),
            Request::HeadAngles => write!(f, "head_angles()"),
            Request::StartPointHead(pan, tilt) => write!(f, "start_point_head({pan}, {tilt})"),
            Request::HeadStatus => write!(f, "head_status()"),
            Request::Capture => write!(f, "capture()"),
            Request::Tare => write!(f, "tare()"),
            Request::Wrench => write!(f, "wrench()"),
            Request::DrainWrenches => write!(f, "drain_wrenches()"),
            Request::DiscardWrenches => write!(f, "discard_wrenches()"),
            Request::HandPosition => write!(f, "hand_position()"),
            Request::StartGuardedMove(m) => write!(
                f,
                "start_guarded_move(from {}, to {}, speed {}, force_limit {}, acceleration {:?})",
                p3(&m.from),
                p3(&m.to),
                m.speed,
                m.force_limit,
                m.acceleration
            ),
            Request::StartRetract => write!(f, "start_retract()"),
            Request::HandStatus => write!(f, "hand_status()"),
            Request::StopHand => write!(f, "stop_hand()"),
        }
    }
}
