//! The simulated body's walk: the shared walk controller, never entering anything: the body's
//! cylinder is shape-cast along every step and stops a safety margin short of the first hit.

use nalgebra::{Isometry2, Vector2};
use nudge_executive::robot::controller::{Rates, Walk, WalkLimits, step_walk};
use rapier3d::parry::query::ShapeCastOptions;
use rapier3d::prelude::*;

use crate::world::build::groups;

/// Limits and body size the walk needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WalkParams {
    /// Speeds and accelerations.
    pub limits: WalkLimits,
    /// Bounding cylinder radius (m).
    pub radius: f64,
    /// Bounding cylinder height (m).
    pub height: f64,
    /// Height of the cast cylinder's underside: low flat things (mats, cables) are stepped over (m).
    pub step_over: f64,
    /// Distance kept from anything in the way (m).
    pub margin: f64,
}

/// One step of `dt` seconds: the new base pose, and the walk's new state; the body's cylinder is
/// cast along the step.
pub fn step(
    walk: &mut Walk,
    rates: &mut Rates,
    base: Isometry2<f64>,
    p: &WalkParams,
    dt: f64,
    world: &PhysicsWorld,
) -> Isometry2<f64> {
    step_walk(walk, rates, base, &p.limits, dt, |pos, wanted| {
        cast(pos, wanted, p, world)
    })
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
