//! The next-best-view planner: where to walk, and which way to face for a look-around, to see as
//! much as possible of the grid cells a decision needs, per second of robot time.
//!
//! - [`coverage`]: the floor one look-around shows, an annulus sector about the body's heading,
//!   derived from the camera and the head's views.
//! - [`targets`]: the cells to see, with weights.
//! - [`lattice`]: a coarse planning lattice over the grid (where the robot may stand: free of
//!   obstacles by its radius and a clearance, on floor the grid has seen free), with [`geodesic`]
//!   walking distances and paths over it (Dijkstra in a bucket queue).
//! - [`sight`] and [`visibility`]: the occluder heights and target weights over the grid (and a
//!   coarse copy, `raster.rs`), and the prediction of what a look-around from a position shows
//!   (rays marched through the grid with a running shadow end) and the heading that shows the
//!   most.
//! - [`planner`]: [`plan_view`] scores candidate positions by predicted area per second of walking
//!   and looking, and returns the best with its heading, path and the cells it expects to see
//!   (the search itself, best first and coarse to fine, is `search.rs`).

pub mod coverage;
mod dilate;
pub mod geodesic;
pub mod lattice;
pub mod planner;
mod raster;
mod search;
pub mod sight;
pub mod targets;
pub mod visibility;

pub use coverage::{CoverageError, LookCoverage};
pub use geodesic::{DIAGONAL, DistanceField, STRAIGHT};
pub use lattice::{Lattice, LatticeCell, LatticeError};
pub use planner::{NoView, ViewConfig, ViewScene, Viewpoint, plan_view};
pub use sight::SightMap;
pub use targets::Targets;
pub use visibility::{LookPrediction, Scratch};
