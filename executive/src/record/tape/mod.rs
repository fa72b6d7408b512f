//! The replay tape: every adapter call the executive made, with its arguments and what the robot
//! answered, in call order, and the executive's transitions between them. It holds everything the
//! executive consumed, so a run can be driven again from the file alone ([`ReplayRobot`]) and new
//! code shows where its decisions part from the recorded ones (Copper-style bit-exact replay).
//!
//! - [`Taped`] wraps any robot, as the fault decorators do, and writes each call onto a [`Tape`].
//! - The [`crate::record::McapRecorder`] owns the tape's far end: it writes what the tape holds to
//!   its own channel, [`TAPE_TOPIC`], in batches stamped with robot time, beside the Foxglove topics.
//! - [`read_recording`] reads a tape back from an MCAP file; [`Replay`] drives a new run from it
//!   and reports the first [`Divergence`].
//!
//! The encoding ([`encode_entry`], [`decode_batch`]) is a small little-endian binary format: every
//! float as its raw bits (NaN payloads included), lengths as LEB128 varints, a colour cloud as the
//! raw bits of its points with no-return slots left out, or, for a point on its pixel's ray, as a
//! count of the camera's range steps (see `cloud.rs`).

mod call;
mod camera_rays;
mod cloud;
mod codec;
mod file;
mod replay;
mod tape_buffer;
mod taped;
#[cfg(test)]
mod tests;
mod wrench_samples;

pub use call::{Entry, Reply, Request, Transition};
pub use camera_rays::CameraRays;
pub use codec::{DecodeError, decode_batch, encode_entry};
pub use file::{Recording, RecordingError, read_recording};
pub use replay::{Divergence, Replay, ReplayObserver, ReplayRobot};
pub use tape_buffer::Tape;
pub use taped::Taped;

/// The MCAP topic of the tape.
pub const TAPE_TOPIC: &str = "/nudge/tape";

/// The tape channel's message encoding: the format and its version. A reader refuses others.
pub const TAPE_ENCODING: &str = "nudge.tape/2";
