//! Fault injection as adapter decorators, in the manner of OpenRR's `arci` decorators: each fault is
//! a struct generic over the robot it wraps, implements every capability trait by forwarding, and
//! changes only what its fault changes. Faults stack (`CameraDropout::new(ClockJump::new(robot, …),
//! …)`), need no flag in any adapter, and work on any [`Robot`]: the fake, the simulation, a real
//! robot on a test stand.
//!
//! *When* a fault acts is a [`FaultWindow`]: a [`Trigger`] (from a robot time, from the n-th chance
//! the fault gets, or while the executive is in a given state, seen through a [`StateProbe`]) and how
//! many times it may act. Every decorator records when it first acted ([`FaultWindow::first`]), so a
//! test tells a fault that changed the run from one that never got its chance.
//!
//! Sensor faults are faults of what the executive *reads*. An adapter's own force guard reads its
//! sensor directly (the simulation every physics step, a real arm at controller rate), so a wrench
//! the decorators spoil is spoilt for the executive, not for the guard: that is the adapter contract
//! ([`crate::robot`]), and the fault table checks the executive keeps the rest of it safe.
//!
//! | Decorator | What the executive sees |
//! |---|---|
//! | [`CameraDropout`] | `capture` fails: no frame |
//! | [`EmptyCloud`] | a frame with no points |
//! | [`NanCloud`] | a frame with NaN in some coordinates of some points |
//! | [`ScrambledCloud`] | after a push, a frame of noise that ICP cannot register |
//! | [`WrenchSpike`] | one huge wrist reading |
//! | [`NanWrench`] | wrist readings of NaN |
//! | [`StuckWrench`] | the wrist repeating its last reading forever |
//! | [`ShortWalk`] | a walk or turn reported done before it got there |
//! | [`ArmStall`] | the hand stopping where it is while its status says running |
//! | [`ActionHang`] | an action whose status never says done |
//! | [`CallError`] | one adapter call failing (a fault, or the adapter's own timeout) |
//! | [`ClockJump`] | the clock leaping forwards or backwards |
//!
//! [`Bounded`] is the harness's side: outermost, it ends a run that passes a bound of robot time or
//! of calls, so that a test meets a hang as a failure.

mod action_hang;
mod arm_stall;
mod bounded;
mod call_error;
mod camera_dropout;
mod clock_jump;
mod empty_cloud;
mod forward;
mod nan_cloud;
mod nan_wrench;
mod probe;
mod scrambled_cloud;
mod short_walk;
mod stuck_wrench;
mod window;
mod wrench_spike;

pub use action_hang::ActionHang;
pub use arm_stall::ArmStall;
pub use bounded::Bounded;
pub use call_error::{CallError, ErrorKind};
pub use camera_dropout::CameraDropout;
pub use clock_jump::ClockJump;
pub use empty_cloud::EmptyCloud;
pub use nan_cloud::NanCloud;
pub use nan_wrench::NanWrench;
pub use probe::StateProbe;
pub use scrambled_cloud::ScrambledCloud;
pub use short_walk::ShortWalk;
pub use stuck_wrench::StuckWrench;
pub use window::{FaultWindow, Firing, Trigger};
pub use wrench_spike::WrenchSpike;

use super::Robot;

/// What every fault decorator offers besides the capability traits: its window, and the robot it
/// wraps (to read ground truth from a fake or a simulation after a run).
pub trait Fault: Robot {
    /// The wrapped robot.
    type Inner: Robot;

    /// When the fault acts, and whether it has.
    fn window(&self) -> &FaultWindow;

    /// The wrapped robot.
    fn inner(&self) -> &Self::Inner;

    /// Unwraps the decorator.
    fn into_inner(self) -> Self::Inner;
}

#[cfg(test)]
mod tests;
