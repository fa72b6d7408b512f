//! nudge-motion: planning for a bounding cylinder among prisms, and planning pushes.
//!
//! Kept apart the way OMPL keeps them: the configuration space, the validity checker, the problem and
//! the planners, so that a new planner is one file and a benchmark can run every planner on one problem.
#![warn(missing_docs)]
