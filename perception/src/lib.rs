//! nudge-perception: from colour range clouds to obstacles.
//!
//! The pipeline runs stage by stage, each callable on its own with its parameters in a config struct:
//! look-around fusion ([`cloud`]), floor detection, the elevation map, labelling into clusters, prisms
//! ([`prism`]), colour ICP for pushed objects, and the obstacle-type grid that every part of nudge reads.
//!
//! This crate knows nothing of planning, the executive or the physics engine: it works on any adapter's
//! clouds.
#![warn(missing_docs)]

pub mod cloud;
pub mod grid;
pub mod prism;

pub use cloud::{CloudError, CloudFrame, ColourCloud, Rgb};
pub use prism::{ObjectId, Prism};
