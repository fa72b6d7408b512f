//! nudge-sim: the rapier simulation behind the executive's adapter traits.
//!
//! Scenario files describe a room, the robot, the goal, objects and actors; the world builds a rapier
//! scene from them; the humanoid walks, looks and pushes; the sensors model the paper's colour range
//! sensor and a wrist force/torque sensor; ground truth scores every run. This crate alone knows rapier.
#![warn(missing_docs)]

pub mod actors;
pub mod adapter;
pub mod bridge;
pub mod cli;
pub mod generate;
pub mod humanoid;
pub mod metrics;
pub mod replay;
pub mod run;
pub mod scenario;
pub mod score;
pub mod sensors;
pub mod surface;
pub mod truth;
pub mod world;
