//! What a run reports when it ends.

use nudge_perception::grid::ObstacleGrid;
use nudge_perception::{ObjectId, Prism};

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

/// What a verdict was about: the obstacle as the robot knew it when the push test that led to
/// the verdict began (its first attempt), before the test's strokes or any later push moved things.
#[derive(Clone, Debug, PartialEq)]
pub struct Decision {
    /// Robot-clock time the test began (s).
    pub stamp: f64,
    /// The obstacle then.
    pub prism: Prism,
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
    /// Obstacles a later look showed to be part of another, with the id of the obstacle they joined:
    /// a verdict about one of them is about that obstacle (see [`Self::obstacle`]).
    pub joined: std::collections::BTreeMap<ObjectId, ObjectId>,
    /// The push sequences the last sequence search considered when no single push opened the way,
    /// each with what stopped it (empty when none was searched, or the last search found one).
    pub sequences: Vec<nudge_motion::PairRecord>,
    /// Per obstacle with a verdict, what its latest verdict was about (see [`Decision`]).
    pub decisions: std::collections::BTreeMap<ObjectId, Decision>,
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
            && self.joined == other.joined
            && self.sequences == other.sequences
            && self.decisions == other.decisions
            && grid(self) == grid(other)
    }
}

impl RunReport {
    /// The obstacle `id` is at the end of the run, following the obstacles it joined; `None` when it
    /// was forgotten (moved away unseen, or never there).
    pub fn obstacle(&self, id: ObjectId) -> Option<&Prism> {
        let mut id = id;
        // Each join points at an obstacle older or judged; the bound only guards a cycle.
        for _ in 0..=self.joined.len() {
            match self.obstacles.iter().find(|p| p.id == id) {
                Some(p) => return Some(p),
                None => id = *self.joined.get(&id)?,
            }
        }
        None
    }

    /// True when the robot reached the goal.
    pub fn reached_goal(&self) -> bool {
        matches!(self.outcome, State::Goal)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Point2};
    use nudge_perception::{CloudFrame, ColourCloud};

    fn square(id: u32) -> Prism {
        Prism {
            id: ObjectId(id),
            footprint: vec![
                Point2::new(0.0, 0.0),
                Point2::new(1.0, 0.0),
                Point2::new(1.0, 1.0),
                Point2::new(0.0, 1.0),
            ],
            z_min: 0.0,
            z_max: 1.0,
            points: ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0),
        }
    }

    #[test]
    fn an_obstacle_is_found_through_the_ones_it_joined() {
        // Invariant: a verdict's id leads to the obstacle it is now part of, through any chain of joins; an id that joined nothing present leads nowhere, and a cycle of joins ends.
        let report = RunReport {
            outcome: State::Goal,
            knowledge: Knowledge::default(),
            robot_time: 1.0,
            timeline: Vec::new(),
            obstacles: vec![square(1)],
            grid: None,
            joined: [(ObjectId(36), ObjectId(40)), (ObjectId(40), ObjectId(1))]
                .into_iter()
                .chain([(ObjectId(7), ObjectId(8)), (ObjectId(8), ObjectId(7))])
                .collect(),
            sequences: Vec::new(),
            decisions: Default::default(),
        };
        assert_eq!(
            report.obstacle(ObjectId(36)).map(|p| p.id),
            Some(ObjectId(1))
        );
        assert_eq!(
            report.obstacle(ObjectId(1)).map(|p| p.id),
            Some(ObjectId(1))
        );
        assert!(report.obstacle(ObjectId(5)).is_none());
        assert!(report.obstacle(ObjectId(7)).is_none());
    }
}
