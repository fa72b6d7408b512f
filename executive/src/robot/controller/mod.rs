//! The motion controllers that run below the adapter boundary: what turns a started walk or hand
//! motion into motion, step by step. The simulation runs them on its bodies; the ROS 2 adapter runs
//! the same ones to turn the executive's actions into the velocity commands a real robot's
//! controllers take (`/cmd_vel`, a Cartesian servo), so both move alike.

mod guard_pace;
mod hand;
mod walk;

pub use guard_pace::{STEADY_MARGIN, STEADY_PRESS_US, STEADY_STEP_US, steady_push};
pub use hand::HandMotion;
pub use walk::{Rates, Walk, WalkLimits, step_walk, wrap};

/// The next speed of a motion that may accelerate at `accel` up to `max` and must stop within `remaining`.
pub fn ramp(current: f64, max: f64, accel: f64, remaining: f64, dt: f64) -> f64 {
    let v = (current + accel * dt)
        .min(max)
        .min((2.0 * accel * remaining).sqrt());
    // Never stall just short of the end.
    v.max((accel * dt).min(max))
}
