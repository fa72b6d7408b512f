//! What the robot is, written once.
//!
//! A [`RobotModel`] holds every fact about the robot that more than one part of nudge needs: the
//! body's size and gait, the head's height, limits and speed, the range camera's image and range,
//! the arm's reach and hand, the wrist sensor's rate, and the forces the hand may use. The executive,
//! motion planning, the simulation and every adapter take these facts from here, never from
//! constants of their own. [`RobotModel::default`] is the paper's robot: HRP-2 with an SR-4000 range
//! camera on its head (Kakiuchi et al., IROS 2010). A lab describes its own robot in a TOML file
//! ([`RobotModel::from_toml_str`], [`RobotModel::from_path`]); every field has the paper's value as
//! its default, so a file names only what differs.

#![warn(missing_docs)]

mod error;
mod load;
mod model;
pub mod text_place;
mod validate;

pub use error::{InvalidModel, ModelError};
pub use model::{
    ArmModel, BodyModel, CameraModel, ForceModel, HeadModel, RangeCounts, RobotModel, WristModel,
};
pub use validate::Violation;
