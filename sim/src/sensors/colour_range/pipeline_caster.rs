//! The reference caster: every ray through rapier's query pipeline.

use rapier3d::geometry::{Collider, ColliderHandle, Ray};
use rapier3d::math::{Pose, Real};
use rapier3d::parry::shape::Compound;
use rapier3d::pipeline::QueryPipeline;

use super::scene::SensorScene;
use super::trace::{Hit, RowCaster};
use crate::surface::Surface;

/// Rays through rapier's query pipeline (the broad phase's BVH), the reference caster.
pub(super) struct PipelineCaster<'c> {
    pub(super) scene: &'c SensorScene<'c>,
    pub(super) pipeline: QueryPipeline<'c>,
    /// The last collider hit and its surface: neighbouring pixels mostly share a collider.
    pub(super) last: Option<(ColliderHandle, &'c Collider, Option<Surface>)>,
}

impl<'c> PipelineCaster<'c> {
    pub(super) fn new(scene: &'c SensorScene<'c>) -> Self {
        Self {
            scene,
            pipeline: scene.query_pipeline(),
            last: None,
        }
    }
}

impl<'c> RowCaster<'c> for PipelineCaster<'c> {
    fn begin_row(&mut self, _row: usize) {}

    fn first_hit(&mut self, _col: usize, ray: &Ray, max_range: Real) -> Option<Hit> {
        // The BVH's ray cast without normals takes parry's SIMD path; the normal then comes from
        // the one collider hit.
        let (handle, _) = self.pipeline.cast_ray(ray, max_range, true)?;
        let (collider, surface) = match self.last {
            Some((h, co, surface)) if h == handle => (co, surface),
            _ => {
                let co = self.scene.colliders.get(handle)?;
                let surface = (self.scene.surface)(handle);
                self.last = Some((handle, co, surface));
                (co, surface)
            }
        };
        let intersection =
            collider
                .shape()
                .cast_ray_and_get_normal(collider.position(), ray, max_range, true)?;
        let (frame, surface) = match collider.shape().as_compound() {
            Some(compound) => {
                let (k, pose) = part_hit(compound, collider, ray, max_range);
                (pose, surface.map(|s| s.of_part(k)))
            }
            None => (*collider.position(), surface),
        };
        Some(Hit {
            frame,
            surface,
            toi: intersection.time_of_impact,
            normal: intersection.normal,
        })
    }
}

/// The part of a compound collider that `ray` meets first, and its pose (part 0 if none does).
pub(super) fn part_hit(
    compound: &Compound,
    collider: &Collider,
    ray: &Ray,
    max_range: Real,
) -> (usize, Pose) {
    let pose_of = |part_pose: &Pose| *collider.position() * *part_pose;
    let mut best = (0, Real::INFINITY);
    for (k, (part_pose, part)) in compound.shapes().iter().enumerate() {
        if let Some(t) = part.cast_ray(&pose_of(part_pose), ray, max_range, true)
            && t < best.1
        {
            best = (k, t);
        }
    }
    let part_pose = compound
        .shapes()
        .get(best.0)
        .map_or(Pose::IDENTITY, |(p, _)| *p);
    (best.0, pose_of(&part_pose))
}
