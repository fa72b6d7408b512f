//! Walking: turn in place to face the next waypoint, then walk straight at walking speed, never
//! entering anything: the body's cylinder is shape-cast along every step and stops a safety margin
//! short of the first hit.

use std::collections::VecDeque;
use std::f64::consts::PI;

use nalgebra::{Isometry2, Point2, Vector2};
use nudge_executive::robot::WalkOutcome;
use rapier3d::parry::query::ShapeCastOptions;
use rapier3d::prelude::*;

use crate::world::build::groups;

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
}

/// Limits and body size the walk needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkParams {
    /// Walking speed (m/s).
    pub speed: f64,
    /// Turning rate (rad/s).
    pub turn_rate: f64,
    /// Bounding cylinder radius (m).
    pub radius: f64,
    /// Bounding cylinder height (m).
    pub height: f64,
    /// Height of the cast cylinder's underside: low flat things (mats, cables) are stepped over (m).
    pub step_over: f64,
    /// Distance kept from anything in the way (m).
    pub margin: f64,
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

/// Linear acceleration of the base (m/s²).
pub const LINEAR_ACCEL: f64 = 0.5;
/// Angular acceleration of the base (rad/s²).
pub const ANGULAR_ACCEL: f64 = 1.0;

/// The next speed of a motion that may accelerate at `accel` up to `max` and must stop within `remaining`.
pub fn ramp(current: f64, max: f64, accel: f64, remaining: f64, dt: f64) -> f64 {
    let v = (current + accel * dt)
        .min(max)
        .min((2.0 * accel * remaining).sqrt());
    // Never stall just short of the end.
    v.max((accel * dt).min(max))
}

/// Wraps an angle to (−π, π].
pub fn wrap(a: f64) -> f64 {
    let w = (a + PI).rem_euclid(2.0 * PI) - PI;
    if w <= -PI { w + 2.0 * PI } else { w }
}

/// One step of `dt` seconds: the new base pose, and the walk's new state.
pub fn step(
    walk: &mut Walk,
    rates: &mut Rates,
    base: Isometry2<f64>,
    p: &WalkParams,
    dt: f64,
    world: &PhysicsWorld,
) -> Isometry2<f64> {
    let (mut pos, mut yaw) = (base.translation.vector, base.rotation.angle());
    match walk {
        Walk::Idle(_) => {
            *rates = Rates::default();
            return base;
        }
        Walk::Turn(target) => {
            let err = wrap(*target - yaw);
            rates.angular = ramp(rates.angular, p.turn_rate, ANGULAR_ACCEL, err.abs(), dt);
            let turn = rates.angular * dt;
            yaw += err.clamp(-turn, turn);
            if err.abs() <= turn {
                yaw = *target;
                *rates = Rates::default();
                *walk = Walk::Idle(Some(WalkOutcome::Arrived));
            }
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
                rates.linear = (rates.linear - LINEAR_ACCEL * dt).max(0.0);
                let wanted = Vector2::new(yaw.cos(), yaw.sin()) * (rates.linear * dt);
                let (allowed, blocked) = cast(pos, wanted, p, world);
                pos += allowed;
                if blocked {
                    *rates = Rates::default();
                    *walk = Walk::Idle(Some(WalkOutcome::Blocked {
                        at: Isometry2::new(pos, yaw),
                    }));
                }
            } else if err.abs() > TURN_IN_PLACE {
                rates.angular = ramp(rates.angular, p.turn_rate, ANGULAR_ACCEL, err.abs(), dt);
                yaw += err.clamp(-rates.angular * dt, rates.angular * dt);
            } else {
                // Small heading errors are steered out while walking.
                rates.angular = 0.0;
                yaw += err.clamp(-p.turn_rate * dt, p.turn_rate * dt);
                rates.linear = ramp(rates.linear, p.speed, LINEAR_ACCEL, dist, dt);
                let wanted = to / dist * (rates.linear * dt).min(dist);
                let (allowed, blocked) = cast(pos, wanted, p, world);
                pos += allowed;
                if blocked {
                    *rates = Rates::default();
                    *walk = Walk::Idle(Some(WalkOutcome::Blocked {
                        at: Isometry2::new(pos, yaw),
                    }));
                }
            }
        }
    }
    Isometry2::new(pos, wrap(yaw))
}

/// How far the body may move along `wanted` (and whether it was cut short).
fn cast(
    pos: Vector2<f64>,
    wanted: Vector2<f64>,
    p: &WalkParams,
    world: &PhysicsWorld,
) -> (Vector2<f64>, bool) {
    let half = ((p.height - p.step_over) / 2.0) as f32;
    let shape = Cylinder::new(half, p.radius as f32);
    let shape_pos = Pose::from_parts(
        Vector::new(pos.x as f32, pos.y as f32, p.step_over as f32 + half),
        Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2),
    );
    let filter = QueryFilter::new().groups(InteractionGroups::new(
        groups::ROBOT_BODY,
        groups::WALL | groups::OBJECT | groups::ACTOR,
        InteractionTestMode::And,
    ));
    let query = world.broad_phase.as_query_pipeline(
        world.narrow_phase.query_dispatcher(),
        &world.bodies,
        &world.colliders,
        filter,
    );
    let vel = Vector::new(wanted.x as f32, wanted.y as f32, 0.0);
    let options = ShapeCastOptions {
        max_time_of_impact: 1.0,
        target_distance: p.margin as f32,
        stop_at_penetration: true,
        compute_impact_geometry_on_penetration: true,
    };
    match query.cast_shape(&shape_pos, vel, &shape, options) {
        None => (wanted, false),
        Some((_, hit)) => {
            let away = vel.dot(hit.normal1) > 0.0;
            if hit.time_of_impact <= 1.0e-6 && away {
                (wanted, false)
            } else {
                (wanted * f64::from(hit.time_of_impact), true)
            }
        }
    }
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
