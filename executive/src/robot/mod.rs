//! The adapter boundary: one small trait per robot capability, bundled by [`Robot`].
//!
//! Rules every adapter keeps:
//! - Sensor values are stamped with the robot's clock ([`Clock::now`]) and carry their frame.
//! - Actions (walk, point the head, move the hand) are *started*, then *polled* each tick, so the
//!   executive stays synchronous and deterministic, can watch sensors while an action runs, and can
//!   cancel.
//! - Guarded hand moves carry their force limit into the adapter, which checks it at its own rate (the
//!   simulation every physics step, a real arm at controller rate). The executive only sees "stopped
//!   at the limit, with this wrench".
//! - Time comes from the adapter: [`Clock::advance`] is the only way time passes.

mod arm;
mod base;
mod clock;
pub mod controller;
mod error;
mod fake;
pub mod faults;
mod head;
mod range_camera;
mod types;
mod wrist;

pub use arm::{Arm, GuardedMove, HandOutcome};
pub use base::{Base, WalkOutcome};
pub use clock::Clock;
pub use error::RobotError;
pub use fake::{
    FakeCamera, FakeRobot, FakeScene, ForcePeak, ObjectResponse, SceneBox, ScriptedObject,
};
pub use head::Head;
pub use range_camera::RangeCamera;
pub use types::{ActionStatus, Stamped, Wrench};
pub use wrist::WristSensor;

/// Everything the executive needs from a robot.
///
/// Implemented automatically for any type that implements every capability trait.
pub trait Robot: Clock + Base + Head + RangeCamera + WristSensor + Arm {}

impl<T: Clock + Base + Head + RangeCamera + WristSensor + Arm> Robot for T {}
