//! Colour ICP: how far a pushed object moved, from its points before and after the push.

pub mod colour_icp;
pub mod kdtree;
pub mod result;

pub use colour_icp::{IcpConfig, colour_icp, initial_from_centroids};
pub use kdtree::PointTree;
pub use result::IcpResult;
