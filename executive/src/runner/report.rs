//! What a run reports when it ends.

use crate::machine::{Edge, Knowledge};
use crate::state::State;

/// One transition of the run, stamped with robot time.
#[derive(Clone, Debug, PartialEq)]
pub struct TimelineEntry {
    /// Robot time (s) since the run started... as read from the robot clock.
    pub stamp: f64,
    /// The state left.
    pub from: &'static str,
    /// The edge taken.
    pub edge: Edge,
    /// The state entered.
    pub to: &'static str,
}

/// The outcome of a run with its evidence and timeline.
#[derive(Clone, Debug, PartialEq)]
pub struct RunReport {
    /// The terminal state: Goal, NoPathToGoal or Aborted (with the explanation).
    pub outcome: State,
    /// Everything learnt: push tests, verdicts, replans.
    pub knowledge: Knowledge,
    /// Robot time the run took (s).
    pub robot_time: f64,
    /// Every transition in order.
    pub timeline: Vec<TimelineEntry>,
}

impl RunReport {
    /// True when the robot reached the goal.
    pub fn reached_goal(&self) -> bool {
        matches!(self.outcome, State::Goal)
    }
}
