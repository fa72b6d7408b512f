//! nudge-perception: from colour range clouds to obstacles.
//!
//! The pipeline runs stage by stage, each callable on its own with its parameters in a config struct:
//! look-around fusion ([`lookaround`]), floor detection ([`floor`]), the elevation map ([`elevation`]),
//! labelling into clusters ([`segment`]), prisms ([`prisms`], [`prism`]) with ids kept across looks, and
//! colour ICP for pushed objects ([`icp`]). [`pipeline::detect_objects`] runs them all.
//!
//! This crate knows nothing of planning, the executive or the physics engine: it works on any adapter's
//! clouds.
#![warn(missing_docs)]

pub mod cloud;
pub mod elevation;
pub mod error;
pub mod floor;
pub mod grid;
pub mod hue;
pub mod icp;
pub mod lookaround;
pub mod moved_part;
pub mod pipeline;
pub mod prism;
pub mod prisms;
pub mod seen_floor;
pub mod seen_through;
pub mod segment;

pub use cloud::{CloudError, CloudFrame, ColourCloud, Rgb};
pub use elevation::{ElevationConfig, ElevationMap};
pub use error::PerceptionError;
pub use floor::{FloorConfig, FloorModel};
pub use icp::{IcpConfig, IcpResult, colour_icp};
pub use lookaround::{HeadView, LookAroundConfig, fuse};
pub use moved_part::{MovedPart, MovedPartConfig, moved_part};
pub use pipeline::{
    Detection, PerceptionConfig, detect, detect_from_views, detect_objects, detect_on_floor,
};
pub use prism::{ObjectId, Prism, track_ids};
pub use prisms::{PrismConfig, build_prisms};
pub use seen_floor::SeenFloor;
pub use seen_through::{Change, LookChanges, SplitLook};
pub use segment::{Cluster, Connectivity, SegmentConfig, label};
