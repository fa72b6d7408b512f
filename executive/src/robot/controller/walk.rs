//! Walking: turn in place to face the next waypoint, then walk straight at walking speed, steering
//! out small heading errors, with speeds that ramp up and down. Where the body may go is asked of a
//! `cast`: the simulation shape-casts its cylinder, an adapter assumes the way is free and lets the
//! robot's own safety stop say otherwise.

use std::collections::VecDeque;
use std::f64::consts::PI;

use nalgebra::{Isometry2, Point2, Rotation2, Vector2};

use super::ramp;
use crate::robot::WalkOutcome;

/// Heading error above which the base turns in place instead of walking (rad).
const TURN_IN_PLACE: f64 = 0.05;
/// A waypoint counts as reached within this distance (m).
const REACHED: f64 = 1.0e-3;

/// What the base is doing.
#[derive(Clone, Debug, PartialEq)]
pub enum Walk {
    /// Standing; the last walk ended with this outcome (if any walk was made).
    Idle(Option<WalkOutcome>),
    /// Walking through these waypoints, the first being the current target.
    Path(VecDeque<Point2<f64>>),
    /// Turning on the spot to this yaw.
    Turn(f64),
    /// Moving at a commanded velocity (a `/cmd_vel`): linear in the base frame (m/s), turning rate
    /// (rad/s), until another command.
    Velocity {
        /// Linear velocity in the base frame (m/s).
        linear: Vector2<f64>,
        /// Turning rate, left positive (rad/s).
        angular: f64,
    },
}

/// The walking speed and turning rate a path is walked at, and how fast they are reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkLimits {
    /// Walking speed (m/s).
    pub speed: f64,
    /// Turning rate (rad/s).
    pub turn_rate: f64,
    /// Linear acceleration (m/s²).
    pub linear_accel: f64,
    /// Angular acceleration (rad/s²).
    pub angular_accel: f64,
}

impl WalkLimits {
    /// The limits of a robot's body.
    pub fn of(body: &nudge_robot_model::BodyModel) -> Self {
        Self {
            speed: body.walk_speed,
            turn_rate: body.turn_rate,
            linear_accel: body.linear_accel,
            angular_accel: body.angular_accel,
        }
    }
}

/// The base's current linear and turning speeds, which ramp up and down (the wrist and the hand move
/// with the base; a step change of speed would shake the hand on its compliant wrist).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rates {
    /// Forward speed (m/s).
    pub linear: f64,
    /// Turning speed magnitude (rad/s).
    pub angular: f64,
}

/// Wraps an angle to (−π, π].
pub fn wrap(a: f64) -> f64 {
    let w = (a + PI).rem_euclid(2.0 * PI) - PI;
    if w <= -PI { w + 2.0 * PI } else { w }
}

/// One step of `dt` seconds from `base`: the new base pose, and the walk's new state. `cast(pos,
/// wanted)` says how much of the displacement `wanted` from `pos` the body may make, and whether it
/// was cut short (the walk then ends `Blocked`).
pub fn step_walk(
    walk: &mut Walk,
    rates: &mut Rates,
    base: Isometry2<f64>,
    p: &WalkLimits,
    dt: f64,
    cast: impl FnOnce(Vector2<f64>, Vector2<f64>) -> (Vector2<f64>, bool),
) -> Isometry2<f64> {
    let (mut pos, mut yaw) = (base.translation.vector, base.rotation.angle());
    // The displacement this step asks for, cast after the heading has been updated.
    let wanted = match walk {
        Walk::Idle(_) => {
            *rates = Rates::default();
            return base;
        }
        Walk::Turn(target) => {
            let err = wrap(*target - yaw);
            rates.angular = ramp(rates.angular, p.turn_rate, p.angular_accel, err.abs(), dt);
            let turn = rates.angular * dt;
            yaw += err.clamp(-turn, turn);
            if err.abs() <= turn {
                yaw = *target;
                *rates = Rates::default();
                *walk = Walk::Idle(Some(WalkOutcome::Arrived));
            }
            None
        }
        Walk::Velocity { linear, angular } => {
            let wanted = Rotation2::new(yaw) * (*linear * dt);
            yaw += *angular * dt;
            Some(wanted)
        }
        Walk::Path(points) => {
            while let Some(next) = points.front() {
                if (next.coords - pos).norm() > REACHED {
                    break;
                }
                points.pop_front();
            }
            let Some(next) = points.front().copied() else {
                *rates = Rates::default();
                *walk = Walk::Idle(Some(WalkOutcome::Arrived));
                return base;
            };
            let to = next.coords - pos;
            let dist = to.norm();
            let err = wrap(to.y.atan2(to.x) - yaw);
            if err.abs() > TURN_IN_PLACE && rates.linear > 0.0 {
                // Facing away from the next waypoint while moving: brake first.
                rates.linear = (rates.linear - p.linear_accel * dt).max(0.0);
                Some(Vector2::new(yaw.cos(), yaw.sin()) * (rates.linear * dt))
            } else if err.abs() > TURN_IN_PLACE {
                rates.angular = ramp(rates.angular, p.turn_rate, p.angular_accel, err.abs(), dt);
                yaw += err.clamp(-rates.angular * dt, rates.angular * dt);
                None
            } else {
                // Small heading errors are steered out while walking.
                rates.angular = 0.0;
                yaw += err.clamp(-p.turn_rate * dt, p.turn_rate * dt);
                rates.linear = ramp(rates.linear, p.speed, p.linear_accel, dist, dt);
                Some(to / dist * (rates.linear * dt).min(dist))
            }
        }
    };
    if let Some(wanted) = wanted {
        let (allowed, cut) = cast(pos, wanted);
        pos += allowed;
        if cut {
            *rates = Rates::default();
            *walk = Walk::Idle(Some(WalkOutcome::Blocked {
                at: Isometry2::new(pos, yaw),
            }));
        }
    }
    Isometry2::new(pos, wrap(yaw))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_stays_in_half_open_interval() {
        // wrap maps any angle into (−π, π] without changing its direction.
        for a in [-7.0, -PI, 0.0, PI, 3.5, 12.0] {
            let w = wrap(a);
            assert!(w > -PI && w <= PI);
            assert!(
                ((w - a) / (2.0 * PI)).fract().abs() < 1e-9
                    || ((w - a) / (2.0 * PI)).fract().abs() > 1.0 - 1e-9
            );
        }
    }
}
