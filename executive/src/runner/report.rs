//! What a run reports when it ends.

use nudge_perception::Prism;

use crate::machine::{Edge, Knowledge};
use crate::state::State;

/// One transition of the run, stamped with robot time.
#[derive(Clone, Debug, PartialEq)]
pub struct TimelineEntry {
    /// Robot-clock time of the transition (s).
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
    /// The obstacles as the executive knew them at the end (pushed ones where they were pushed to).
    pub obstacles: Vec<Prism>,
}

impl RunReport {
    /// True when the robot reached the goal.
    pub fn reached_goal(&self) -> bool {
        matches!(self.outcome, State::Goal)
    }
}
