//! The part of a rapier world the sensor looks at during one capture.

use rapier3d::dynamics::{RigidBodyHandle, RigidBodySet};
use rapier3d::geometry::{BroadPhaseBvh, ColliderHandle, ColliderSet};
use rapier3d::parry::query::DefaultQueryDispatcher;
use rapier3d::pipeline::{QueryFilter, QueryFilterFlags, QueryPipeline};

use crate::surface::Surface;

/// Looks up what a collider looks like; `None` for colliders without a known surface.
pub type SurfaceLookup<'a> = dyn Fn(ColliderHandle) -> Option<Surface> + Sync + 'a;

/// The part of a rapier world the sensor looks at, borrowed for one capture.
///
/// The broad phase must be up to date with the colliders' poses (step the pipeline, or update the
/// broad phase after moving bodies by hand) — the sensor sees what the broad phase indexes.
pub struct SensorScene<'a> {
    /// The world's rigid bodies.
    pub bodies: &'a RigidBodySet,
    /// The world's colliders.
    pub colliders: &'a ColliderSet,
    /// The world's broad phase, whose BVH the rays traverse.
    pub broad_phase: &'a BroadPhaseBvh,
    /// What each collider looks like.
    pub surface: &'a SurfaceLookup<'a>,
    /// Seed of the surface textures (the scenario seed): fixed for a run, so textures stay put from
    /// frame to frame.
    pub texture_seed: u64,
    /// A body the sensor never sees: the robot carrying it.
    pub exclude: Option<RigidBodyHandle>,
}

impl SensorScene<'_> {
    /// A query pipeline over this scene that skips the excluded body and trigger volumes.
    ///
    /// Cheap (a bundle of references); not `Sync`, so each rayon worker builds its own.
    pub(super) fn query_pipeline(&self) -> QueryPipeline<'_> {
        let filter = QueryFilter {
            flags: QueryFilterFlags::EXCLUDE_SENSORS,
            exclude_rigid_body: self.exclude,
            ..QueryFilter::default()
        };
        self.broad_phase.as_query_pipeline(
            &DefaultQueryDispatcher,
            self.bodies,
            self.colliders,
            filter,
        )
    }
}
