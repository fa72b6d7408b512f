//! What a run reports when it ends.

use nudge_perception::Prism;
use nudge_perception::grid::ObstacleGrid;

use crate::machine::{Edge, Knowledge};
use crate::state::State;

/// One transition of the run, stamped with robot time.
#[derive(Clone, Debug, PartialEq)]
pub struct TimelineEntry {
    /// Robot-clock time of the transition (s).
    pub stamp: f64,
    /// The state left (`None` for the run's start, [`Edge::Start`]).
    pub from: Option<&'static str>,
    /// The edge taken.
    pub edge: Edge,
    /// The state entered.
    pub to: &'static str,
}

/// The outcome of a run with its evidence and timeline.
#[derive(Clone, Debug)]
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
    /// The obstacle-type grid at the end (`None` if it could not be made).
    pub grid: Option<ObstacleGrid>,
}

/// Two reports are equal when everything they say is: the grids compare by placement and by every cell's
/// class (their scratch buffers do not count).
impl PartialEq for RunReport {
    fn eq(&self, other: &Self) -> bool {
        let grid = |r: &Self| {
            r.grid
                .as_ref()
                .map(|g| (*g.geometry(), g.class_codes().to_vec()))
        };
        self.outcome == other.outcome
            && self.knowledge == other.knowledge
            && self.robot_time.to_bits() == other.robot_time.to_bits()
            && self.timeline == other.timeline
            && self.obstacles == other.obstacles
            && grid(self) == grid(other)
    }
}

impl RunReport {
    /// True when the robot reached the goal.
    pub fn reached_goal(&self) -> bool {
        matches!(self.outcome, State::Goal)
    }
}
