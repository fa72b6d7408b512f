//! Events: what the runner reports back to the machine after executing its commands.

use nudge_perception::ObjectId;

use crate::push_test::{PushEvidence, PushIntent};
use crate::view::{UnseenRegion, Viewpoint};

/// An obstacle the runner offers as a push candidate, in the order of the policy.
#[derive(Clone, Debug, PartialEq)]
pub struct Candidate {
    /// The obstacle.
    pub id: ObjectId,
    /// The obstacle-type grid already knows it as movable from passive evidence (it was seen moving).
    pub passively_movable: bool,
    /// The grid saw it (or something where it stands) moving lately, in a look or a walk: it may be a
    /// person, who may walk on.
    pub moved_lately: bool,
    /// The grid or a look saw motion where it stands at some time in the run: it came there since,
    /// by itself or carried. Unless passive evidence or a push test calls it movable, it may be a
    /// person who stopped (for the robot, perhaps), and is never push-tested.
    pub seen_moving: bool,
}

/// An obstacle in the robot's way that ranking left out, and why: a partition, a long sideboard, the
/// room's walls, or an object found movable whose outline now takes in what it was pushed against.
#[derive(Clone, Debug, PartialEq)]
pub struct SetAside {
    /// The obstacle.
    pub id: ObjectId,
    /// Why it is no candidate.
    pub why: SetAsideWhy,
}

/// Why ranking left an obstacle out.
#[derive(Clone, Debug, PartialEq)]
pub enum SetAsideWhy {
    /// Wider than anything the robot pushes.
    TooLarge {
        /// Its footprint's largest extent (m).
        extent: f64,
        /// The largest the robot pushes (m).
        limit: f64,
    },
    /// Taken for room structure: at the edge of everything seen, with its top out of the camera's
    /// view from every place a look showed it from (a wall). A low thing at the edge, its top in
    /// view, is a candidate like any other, whatever stands beyond it.
    Structure,
}

/// Something that happened, fed to the machine by the runner.
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    /// Every look-around view was captured.
    LookedAround {
        /// How many clouds.
        views: usize,
    },
    /// Perception turned the clouds into obstacles and updated the grid.
    ObjectsDetected {
        /// How many obstacles.
        count: usize,
        /// How many obstacles the world model forgot since the last detection because the look saw
        /// through where they stood: pushes they stood in the way of may now be made.
        gone: usize,
    },
    /// The planner found a path to the goal.
    PathFound {
        /// Its length (m).
        length: f64,
    },
    /// The planner found no path to the goal.
    NoPath {
        /// The planner's reason.
        reason: String,
    },
    /// The walk under way reached its last waypoint (for `Navigate`: the goal region).
    Arrived,
    /// The robot reported its walk blocked and stopped.
    WalkBlocked,
    /// The grid's replanning flag rose, or a new obstacle lies on the path.
    PathInvalidated {
        /// What the grid or perception saw.
        reason: String,
    },
    /// Push candidates ranked by the configured policy, best first, and the obstacles in the way
    /// left out for their size.
    CandidatesRanked {
        /// The candidates, best first.
        ranked: Vec<Candidate>,
        /// Obstacles in the way too large to push.
        set_aside: Vec<SetAside>,
    },
    /// The push planner produced a plan for the target.
    PushPlanned(PushIntent),
    /// No push of the target could be planned.
    NoPushPlan {
        /// The push planner's reason.
        reason: String,
        /// Floor that matters to the push (around and under the object) is still unseen: a look from
        /// elsewhere might find a push.
        unseen: bool,
    },
    /// A push of the target was planned, but something that may be a person stands within the
    /// safety distance of the object or its sweep: the push waits for them to leave.
    PersonNearPush {
        /// Who stands where, for the explanation.
        reason: String,
    },
    /// The walk stopped before floor under the path that the walking camera could not see in time.
    UnseenAhead {
        /// How far ahead along the path the first such cell lies (m).
        distance: f64,
    },
    /// The view planner chose where to look from.
    ViewPlanned(Viewpoint),
    /// No reachable viewpoint would show enough of the floor that matters.
    NoView {
        /// The view planner's reason.
        reason: String,
        /// The regions that matter and stay unseen, with why.
        unseen: Vec<UnseenRegion>,
    },
    /// The push test finished with this evidence.
    PushTestDone(PushEvidence),
    /// The clearing push moved the object as planned.
    Cleared {
        /// How far the object moved (m).
        moved: f64,
    },
    /// The clearing push stopped before its end: the object, re-located between strokes, turned or
    /// slid off the push line so far that the rest of its sweep would run into something.
    OffLine {
        /// How far the object moved along the push (m).
        moved: f64,
        /// How far its centre lies off the push line (m).
        lateral: f64,
        /// How far it turned (deg).
        yaw_deg: f64,
        /// What the rest of the sweep would run into; `None` for the room's walls.
        blocked_by: Option<ObjectId>,
    },
    /// The clearing push stopped at the force limit.
    Jammed {
        /// Peak force (N).
        peak_force: f64,
        /// How far the object moved before it jammed (m).
        moved: f64,
    },
    /// The safe stop (arm retracted, base stopped) finished.
    Stopped,
    /// Cancel requested from outside.
    Cancel,
    /// An adapter call failed.
    RobotFailed(String),
    /// Perception failed on the robot's data.
    PerceptionFailed(String),
    /// The robot-time budget ran out at this robot time (s).
    TimeUp(f64),
}

impl Event {
    /// The event's name for logs and coverage.
    pub fn name(&self) -> &'static str {
        match self {
            Event::LookedAround { .. } => "LookedAround",
            Event::ObjectsDetected { .. } => "ObjectsDetected",
            Event::PathFound { .. } => "PathFound",
            Event::NoPath { .. } => "NoPath",
            Event::Arrived => "Arrived",
            Event::WalkBlocked => "WalkBlocked",
            Event::PathInvalidated { .. } => "PathInvalidated",
            Event::CandidatesRanked { .. } => "CandidatesRanked",
            Event::PushPlanned(_) => "PushPlanned",
            Event::NoPushPlan { .. } => "NoPushPlan",
            Event::PersonNearPush { .. } => "PersonNearPush",
            Event::UnseenAhead { .. } => "UnseenAhead",
            Event::ViewPlanned(_) => "ViewPlanned",
            Event::NoView { .. } => "NoView",
            Event::PushTestDone(_) => "PushTestDone",
            Event::Cleared { .. } => "Cleared",
            Event::OffLine { .. } => "OffLine",
            Event::Jammed { .. } => "Jammed",
            Event::Stopped => "Stopped",
            Event::Cancel => "Cancel",
            Event::RobotFailed(_) => "RobotFailed",
            Event::PerceptionFailed(_) => "PerceptionFailed",
            Event::TimeUp(_) => "TimeUp",
        }
    }
}
