//! Prisms: the obstacles nudge plans around and pushes.
//!
//! A prism is the convex hull of a cluster's points projected on the floor plane, extruded from its
//! lowest to its highest point. It keeps the cluster's coloured points so that colour ICP can follow
//! the object when it is pushed.

use nalgebra::Point2;

use crate::cloud::ColourCloud;

/// An object's identity, stable across look-arounds (matched by footprint overlap).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct ObjectId(pub u32);

impl std::fmt::Display for ObjectId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "obj-{}", self.0)
    }
}

/// An obstacle: a convex footprint in the map frame extruded between two heights.
#[derive(Clone, Debug, PartialEq)]
pub struct Prism {
    /// Identity, stable across looks.
    pub id: ObjectId,
    /// Convex footprint in the map frame (m), counter-clockwise, first vertex not repeated.
    pub footprint: Vec<Point2<f64>>,
    /// Height of the lowest point above the floor (m); above zero for overhangs such as a shelf.
    pub z_min: f64,
    /// Height of the highest point above the floor (m).
    pub z_max: f64,
    /// The cluster's coloured points in the map frame, kept for colour ICP.
    pub points: ColourCloud,
}
