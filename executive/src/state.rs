//! The executive's states (Kakiuchi Fig. 2, extended) and the reasons a run ends.

use nudge_perception::ObjectId;

use crate::explain::Explanation;
use crate::push_test::PushIntent;
use crate::view::{Question, Viewpoint};

/// Why the robot is walking to a push pose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Purpose {
    /// To find out whether the object moves (the push test).
    Test,
    /// To push an object already known to be movable out of the way.
    Clear,
}

/// Where the approach to a push pose stands.
#[derive(Clone, Debug, PartialEq)]
pub enum Approach {
    /// Waiting for the push planner's answer.
    Planning,
    /// Waiting for the planner's clearing push of an object a push test has just found movable, the
    /// test's push (held here) not opening the way. A plan that needs a look first is not waited
    /// for: the test's push is finished instead, which takes a box far enough through a doorway for
    /// the next look to see past it.
    AfterTest(PushIntent),
    /// Walking to the stand pose of this plan.
    Walking(PushIntent),
}

/// A state of the executive. The three terminal states end the run.
#[derive(Clone, Debug, PartialEq)]
pub enum State {
    /// Sweeping the head through the look-around views and capturing clouds.
    LookAround,
    /// Turning the look-around clouds into obstacles and updating the grid.
    DetectObjects,
    /// Planning a path to the goal among the known obstacles.
    PlanPath,
    /// Walking the planned path while watching for new obstacles.
    Navigate,
    /// Ranking the obstacles that may be pushed and picking the next one.
    SelectCandidate,
    /// Planning a push of `target` and walking to where the robot stands to push it.
    ApproachPushPose {
        /// The object to push.
        target: ObjectId,
        /// Test it, or clear it out of the way.
        purpose: Purpose,
        /// Planning or walking.
        phase: Approach,
    },
    /// Pushing `target` with a guarded move and measuring what happened.
    PushTest {
        /// The object under test.
        target: ObjectId,
        /// The plan being executed.
        intent: PushIntent,
        /// 1 for the first test, 2 for the retest after an ambiguous result.
        attempt: u8,
    },
    /// Pushing a movable `target` along the planned direction and distance.
    ClearPath {
        /// The object being pushed away.
        target: ObjectId,
        /// The plan being executed.
        intent: PushIntent,
    },
    /// Choosing where to look from to answer `question` (the view planner).
    PlanView {
        /// What the look is meant to answer.
        question: Question,
    },
    /// Walking to a viewpoint and turning to face its heading, to look around there.
    GoToView {
        /// What the look is meant to answer.
        question: Question,
        /// Where to look from.
        view: Viewpoint,
    },
    /// Retracting the arm and stopping the base before ending in `Aborted`.
    Stopping(AbortReason),
    /// Terminal: the robot stands in the goal region.
    Goal,
    /// Terminal: no path exists, no untested obstacle could open one, and no reachable viewpoint could
    /// show floor that would.
    NoPathToGoal(Explanation),
    /// Terminal: the run was stopped, with the reason and what was known then.
    Aborted(AbortReason, Explanation),
}

impl State {
    /// True for `Goal`, `NoPathToGoal` and `Aborted`.
    pub fn is_terminal(&self) -> bool {
        matches!(
            self,
            State::Goal | State::NoPathToGoal(_) | State::Aborted(..)
        )
    }

    /// The state's name as it appears in timelines and recordings.
    pub fn name(&self) -> &'static str {
        match self {
            State::LookAround => "LookAround",
            State::DetectObjects => "DetectObjects",
            State::PlanPath => "PlanPath",
            State::Navigate => "Navigate",
            State::SelectCandidate => "SelectCandidate",
            State::ApproachPushPose { .. } => "ApproachPushPose",
            State::PushTest { .. } => "PushTest",
            State::ClearPath { .. } => "ClearPath",
            State::PlanView { .. } => "PlanView",
            State::GoToView { .. } => "GoToView",
            State::Stopping(_) => "Stopping",
            State::Goal => "Goal",
            State::NoPathToGoal(_) => "NoPathToGoal",
            State::Aborted(..) => "Aborted",
        }
    }
}

/// Why a run was aborted.
#[derive(Clone, Debug, PartialEq)]
pub enum AbortReason {
    /// Cancelled from outside.
    Cancelled,
    /// An adapter call failed.
    Robot(String),
    /// Perception failed on the robot's data.
    Perception(String),
    /// The robot-time budget ran out (s).
    TimeLimit(f64),
    /// More push tests were needed than allowed.
    PushTestLimit(u32),
    /// More replans were needed than allowed.
    ReplanLimit(u32),
    /// The runner fed the machine an event its state does not expect (a bug, reported, never a panic).
    Internal(String),
}

impl std::fmt::Display for AbortReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            AbortReason::Cancelled => write!(f, "cancelled"),
            AbortReason::Robot(e) => write!(f, "robot: {e}"),
            AbortReason::Perception(e) => write!(f, "perception: {e}"),
            AbortReason::TimeLimit(s) => write!(f, "robot-time limit of {s} s reached"),
            AbortReason::PushTestLimit(n) => write!(f, "push-test limit of {n} reached"),
            AbortReason::ReplanLimit(n) => write!(f, "replan limit of {n} reached"),
            AbortReason::Internal(e) => write!(f, "internal: {e}"),
        }
    }
}
