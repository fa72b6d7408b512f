//! Moving to see: the questions a look from another place can answer, the viewpoints the view planner
//! chooses, and the regions of floor a run ends without having seen.
//!
//! The robot learns what it has not seen from the obstacle-type grid (cells no ray has crossed and no
//! return has landed in). Where a decision depends on such floor, the machine asks the runner for a
//! viewpoint ([`crate::Command::PlanView`]) that would show the floor that matters to *that* decision,
//! walks there, looks around, and decides again with what it saw.

use nalgebra::Point2;
use nudge_perception::ObjectId;

use crate::state::Purpose;

/// What a look from another place is meant to answer: which unseen floor matters.
#[derive(Clone, Debug, PartialEq)]
pub enum Question {
    /// The path being walked runs over floor the walking camera will not see before the robot steps on
    /// it (around a corner, past a door's jamb): the unseen cells under the path ahead.
    PathAhead,
    /// No path, and nothing left to push: could floor not yet seen open a way? The unseen floor inside
    /// the outlines of the obstacles that close the way (a hull drawn over floor nobody saw, a door
    /// seen only edge-on), along the most plausible way through it.
    Way,
    /// A push of `target` needs floor not yet seen (where the robot would stand, where the object would
    /// go) or the object is seen only in part: the unseen floor around and under it.
    Push {
        /// The object to push.
        target: ObjectId,
        /// Test it, or clear it.
        purpose: Purpose,
    },
}

impl Question {
    /// A short name for logs and timelines.
    pub fn name(&self) -> String {
        match self {
            Question::PathAhead => "the path ahead".into(),
            Question::Way => "a way".into(),
            Question::Push { target, .. } => format!("a push of {target}"),
        }
    }
}

/// A place to look from: where to stand, which way to face for the look-around, and what it should
/// show.
#[derive(Clone, Debug, PartialEq)]
pub struct Viewpoint {
    /// Where the robot stands (map frame, m).
    pub position: Point2<f64>,
    /// Which way the body faces for the look-around (map frame, rad).
    pub yaw: f64,
    /// Unseen floor that matters and that the look is predicted to show (m²).
    pub gain: f64,
    /// Walking distance from where the robot stood when it chose the viewpoint (m).
    pub walk: f64,
    /// The walk there over floor already seen (map frame, from the robot's position then).
    pub path: Vec<Point2<f64>>,
}

/// Why a region of floor that mattered stayed unseen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UnseenWhy {
    /// No place the robot can reach over seen floor has a line of sight to it within the camera's
    /// range: it lies behind obstacles that close the way.
    NoViewpoint,
    /// It was looked at from viewpoints predicted to show it, and stayed unseen: the inside of an
    /// object, or hidden from every reachable place.
    LookedAt(u32),
    /// The view budget was spent before it was looked at.
    ViewLimit,
    /// Obstacles already seen close every way to it: no look could open one.
    BehindObstacles,
}

impl std::fmt::Display for UnseenWhy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UnseenWhy::NoViewpoint => write!(f, "no reachable place sees it"),
            UnseenWhy::LookedAt(n) => {
                write!(
                    f,
                    "looked at from {n} place(s), still unseen (inside an object or hidden)"
                )
            }
            UnseenWhy::ViewLimit => write!(f, "the view budget was spent"),
            UnseenWhy::BehindObstacles => {
                write!(f, "behind obstacles seen that close every way to it")
            }
        }
    }
}

/// A connected region of unseen floor that mattered to the end of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct UnseenRegion {
    /// Its centre (map frame, m).
    pub centre: Point2<f64>,
    /// Corners of the box around it (map frame, m).
    pub bounds: (Point2<f64>, Point2<f64>),
    /// Its area (m²).
    pub area: f64,
    /// Why it stayed unseen.
    pub why: UnseenWhy,
}

impl std::fmt::Display for UnseenRegion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (lo, hi) = self.bounds;
        write!(
            f,
            "{:.2} m² around ({:.2}, {:.2}) in x {:.2}..{:.2}, y {:.2}..{:.2}: {}",
            self.area, self.centre.x, self.centre.y, lo.x, hi.x, lo.y, hi.y, self.why
        )
    }
}

/// One viewpoint the run went to, for reports and pictures.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewRecord {
    /// What it was meant to answer.
    pub question: Question,
    /// The viewpoint.
    pub view: Viewpoint,
}
