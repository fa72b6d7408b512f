//! nudge-motion: planning for a bounding cylinder among prisms, and planning pushes.
//!
//! Kept apart the way OMPL keeps them: the configuration space ([`space`]), the validity checker
//! ([`validity`], with the obstacles of [`obstacle`] in a [`broad_phase`] grid), the problem
//! ([`problem`]) and the planners ([`planner`]), so that a new planner is one file and a benchmark can
//! run every planner on one problem. On top of them: which obstacles block the way ([`blocking`]) and
//! where and how to push one ([`push`]), two pushes that together open the way ([`sequence`]), whether a
//! push's sweep keeps clear ([`sweep`]), a cheap proof that no path exists ([`reach`]), where to walk
//! and look to see what a decision needs ([`view`]), and whether floor not yet seen could open a way
//! ([`way`]).
//!
//! The robot is a vertical cylinder, so its configuration for collision is its position in the plane;
//! SE(2) poses appear where heading matters (standing in front of a face to push it).
#![warn(missing_docs)]

pub mod blocking;
pub mod broad_phase;
pub mod hand_height;
pub mod obstacle;
pub mod path;
pub mod planner;
pub mod problem;
pub mod push;
pub mod reach;
pub mod seen_floor;
pub mod sequence;
pub mod space;
pub mod sweep;
pub mod validity;
pub mod view;
pub mod way;

pub use blocking::{
    BlockingConfig, BlockingReport, Crossing, CrossingConfig, blocking_obstacles, cheapest_crossing,
};
pub use obstacle::{Obstacle, ObstacleError};
pub use path::{Path, PathError};
pub use planner::{Budget, NoPath, Planner, rrt::Rrt, rrt_connect::RrtConnect, shortcut::Shortcut};
pub use problem::{GoalRegion, Problem, ProblemError};
pub use push::{
    PushConfig, PushError, PushPlan, RunsInto, SweptPush, plan_of_swept, plan_push,
    plan_push_among, plan_push_over, swept_pushes,
};
pub use reach::certainly_unreachable;
pub use seen_floor::{AllSeen, FloorCheck, SeenFloor, shadow_length};
pub use sequence::{
    PairMiss, PairRecord, Sequence, SequenceConfig, plan_sequence, single_removal_opens,
};
pub use space::{Bounds, SpaceError};
pub use sweep::{SweepBlock, SweepMargins, sweep_blocked, sweep_blocked_among};
pub use validity::{RobotCylinder, StateValidity, Validity, ValidityConfig, ValidityError};
pub use view::{
    Lattice, LatticeCell, LookCoverage, LookPrediction, NoView, SightMap, Targets, ViewConfig,
    ViewScene, Viewpoint, plan_view,
};
pub use way::{WayHypothesis, unseen_way};
