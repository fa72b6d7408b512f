//! Commands: what the machine asks the runner to do.

use nudge_perception::ObjectId;

use crate::config::CandidatePolicy;
use crate::push_test::{PushIntent, Verdict};
use crate::state::Purpose;
use crate::view::{Question, Viewpoint};

/// One thing for the runner to do; each ends in an [`crate::Event`].
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Sweep the head through the look-around views and capture a cloud at each.
    LookAround,
    /// Turn the latest look-around into obstacles and update the grid.
    DetectObjects,
    /// Plan a path from the robot to the goal among the known obstacles.
    PlanPath,
    /// Walk the planned path, watching the grid and the sensor for obstacles on it.
    FollowPath {
        /// Stop before floor under the path that the walking camera cannot see in time
        /// ([`crate::Event::UnseenAhead`]); false once no viewpoint could show it.
        stop_at_unseen: bool,
    },
    /// Stop the walk under way.
    StopWalk,
    /// Stand and keep watching ahead for a moment, frames into the grid: what flagged the path is
    /// seen walking on, coming to rest, or standing, before the look-around.
    WatchAhead,
    /// Rank push candidates among the obstacles by `policy`, leaving out `exclude`.
    RankCandidates {
        /// The ranking policy.
        policy: CandidatePolicy,
        /// Objects already decided or impossible to push.
        exclude: Vec<ObjectId>,
    },
    /// Plan a push of `target` from the robot's position.
    PlanPush {
        /// The object.
        target: ObjectId,
        /// Test it, or clear it.
        purpose: Purpose,
        /// The robot may stand on, and push the object over, floor nobody has seen (no viewpoint could
        /// show it; the guarded stroke's force limit still stops at anything there).
        allow_unseen: bool,
    },
    /// Choose where to look from to answer the question.
    PlanView(Question),
    /// Walk to a viewpoint over seen floor, watching, and face its heading.
    WalkToView(Viewpoint),
    /// Walk to the stand pose of `intent`.
    WalkToPushPose(PushIntent),
    /// Run one push test (tare, clouds before, guarded move, clouds after, retract, ICP).
    PushTest {
        /// The plan.
        intent: PushIntent,
        /// 1 or 2.
        attempt: u8,
    },
    /// Write a verdict into the obstacle-type grid as active evidence.
    MarkVerdict {
        /// The object.
        target: ObjectId,
        /// Its verdict.
        verdict: Verdict,
        /// Index of the push test behind it (1-based, over the run).
        push_test: u32,
    },
    /// Push a movable object along the plan, watching force.
    ClearPath(PushIntent),
    /// Retract the arm and stop the base.
    SafeStop,
}
