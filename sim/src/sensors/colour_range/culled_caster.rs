//! The default caster: a frame's visible shapes gathered once and culled per image row.

use rapier3d::geometry::{Aabb, ColliderHandle, Ray};
use rapier3d::math::{Pose, Real, Vector};
use rapier3d::parry::bounding_volume::BoundingVolume;
use rapier3d::parry::shape::Shape;

use super::leaf::{Leaf, LeafGeometry};
use super::trace::{Frame, Hit, RowCaster};
use crate::surface::Surface;

/// Every leaf a frame's rays can reach.
pub(super) struct Leaves<'c> {
    pub(super) leaves: Vec<Leaf<'c>>,
    /// Tangent of half the horizontal field of view.
    pub(super) half_w: Real,
    /// Tangent of half the vertical field of view.
    pub(super) half_h: Real,
    pub(super) width: usize,
    pub(super) height: usize,
}

impl<'c> Leaves<'c> {
    /// The leaves of the colliders the broad phase finds inside the view frustum's bounding box, with
    /// the scene's filter (robot body excluded, trigger volumes skipped).
    pub(super) fn gather(frame: &Frame<'c>) -> Self {
        let config = &frame.sensor.config;
        let half_w = (config.camera.h_fov_deg.to_radians() / 2.0).tan() as Real;
        let half_h = (config.camera.v_fov_deg.to_radians() / 2.0).tan() as Real;
        let max_range = config.camera.max_range as Real;
        // Every point within max_range along a ray of the frustum lies in the pyramid from the
        // sensor to the far rectangle at x = max_range.
        let mut frustum_points = vec![frame.pose.translation];
        for (sy, sz) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
            let far = Vector::new(max_range, sy * half_w * max_range, sz * half_h * max_range);
            frustum_points.push(frame.pose.transform_point(far));
        }
        let frustum = Aabb::from_points(frustum_points);

        let scene = frame.scene;
        let pipeline = scene.query_pipeline();
        let mut leaves = Vec::new();
        let handles: Vec<ColliderHandle> = pipeline
            .intersect_aabb_conservative(frustum)
            .map(|(handle, _)| handle)
            .collect();
        for handle in handles {
            let Some(collider) = scene.colliders.get(handle) else {
                continue;
            };
            let surface = (scene.surface)(handle);
            let mut push = |shape: &'c dyn Shape, pose: Pose, surface: Option<Surface>| {
                let aabb = shape.compute_aabb(&pose);
                if !aabb.intersects(&frustum) {
                    return;
                }
                // Corner i takes maxs on the axes whose bit is set in i (x = 1, y = 2, z = 4), so
                // box edges join corners whose indices differ in one bit.
                let corners: [Vector; 8] = std::array::from_fn(|i| {
                    let pick = |bit: usize, lo: Real, hi: Real| if i & bit == 0 { lo } else { hi };
                    let v = Vector::new(
                        pick(1, aabb.mins.x, aabb.maxs.x),
                        pick(2, aabb.mins.y, aabb.maxs.y),
                        pick(4, aabb.mins.z, aabb.maxs.z),
                    );
                    frame.pose.inverse_transform_point(v)
                });
                leaves.push(Leaf {
                    frame: pose,
                    surface,
                    geometry: LeafGeometry::new(shape, pose, frame.pose.translation),
                    corners,
                    near: (frame.pose.translation
                        - frame.pose.translation.clamp(aabb.mins, aabb.maxs))
                    .length(),
                });
            };
            match collider.shape().as_compound() {
                Some(compound) => {
                    for (k, (part_pose, part)) in compound.shapes().iter().enumerate() {
                        let look = surface.map(|s| s.of_part(k));
                        push(part.as_ref(), *collider.position() * *part_pose, look);
                    }
                }
                None => push(collider.shape(), *collider.position(), surface),
            }
        }
        // Nearest first (ties keep the broad phase's order, so the order is deterministic).
        leaves.sort_by(|a, b| a.near.total_cmp(&b.near));
        Self {
            leaves,
            half_w,
            half_h,
            width: config.camera.width,
            height: config.camera.height,
        }
    }

    /// The columns `[lo, hi]` of `row` whose rays may meet `leaf`, or `None` if none may.
    ///
    /// A row's rays all lie in one plane through the sensor; the leaf's box meets that plane in a
    /// convex polygon, and the rays that can hit it are those within the polygon's angular span.
    pub(super) fn columns(&self, leaf: &Leaf<'_>, row: usize) -> Option<(usize, usize)> {
        let up = self.half_h * (1.0 - (2.0 * row as Real + 1.0) / self.height as Real);
        // Rays (1, y, up) satisfy z - up·x = 0.
        let side = leaf.corners.map(|c| c.z - up * c.x);
        let (mut y_min, mut y_max) = (Real::INFINITY, Real::NEG_INFINITY);
        let mut behind = false;
        let mut any = false;
        let mut visit = |p: Vector| {
            any = true;
            if p.x <= 1e-6 {
                behind = true;
            } else {
                let y = p.y / p.x;
                y_min = y_min.min(y);
                y_max = y_max.max(y);
            }
        };
        for (i, &si) in side.iter().enumerate() {
            if si == 0.0 {
                visit(leaf.corners[i]);
            }
            // Box edges join corners whose indices differ in one bit.
            for bit in [1, 2, 4] {
                let j = i ^ bit;
                if j > i && si * side[j] < 0.0 {
                    let t = si / (si - side[j]);
                    visit(leaf.corners[i] + (leaf.corners[j] - leaf.corners[i]) * t);
                }
            }
        }
        if !any {
            return None;
        }
        if behind {
            // The section reaches beside or behind the sensor: do not cull within the row.
            return Some((0, self.width - 1));
        }
        // Column c looks along y = half_w · (1 − (2c + 1) / width); y falls as c grows.
        let col_of = |y: Real| ((1.0 - y / self.half_w) * self.width as Real - 1.0) / 2.0;
        let lo = (col_of(y_max).floor() - 1.0).max(0.0);
        let hi = (col_of(y_min).ceil() + 1.0).min(self.width as Real - 1.0);
        (lo <= hi).then_some((lo as usize, hi as usize))
    }
}

/// Rays against a frame's leaves, culled per row: each ray only tests the few leaves whose column
/// span in its row contains it.
pub(super) struct CulledCaster<'l, 'c> {
    pub(super) leaves: &'l Leaves<'c>,
    /// (first column, last column, leaf index) of the leaves the current row may see.
    pub(super) candidates: Vec<(usize, usize, usize)>,
}

impl<'l, 'c> CulledCaster<'l, 'c> {
    pub(super) fn new(leaves: &'l Leaves<'c>) -> Self {
        Self {
            leaves,
            candidates: Vec::with_capacity(leaves.leaves.len()),
        }
    }
}

impl<'c> RowCaster<'c> for CulledCaster<'_, 'c> {
    fn begin_row(&mut self, row: usize) {
        self.candidates.clear();
        for (i, leaf) in self.leaves.leaves.iter().enumerate() {
            if let Some((lo, hi)) = self.leaves.columns(leaf, row) {
                self.candidates.push((lo, hi, i));
            }
        }
    }

    fn first_hit(&mut self, col: usize, ray: &Ray, max_range: Real) -> Option<Hit> {
        let mut best: Option<(usize, Real)> = None;
        for &(lo, hi, i) in &self.candidates {
            if col < lo || col > hi {
                continue;
            }
            // Leaves come nearest first (see `Leaves::gather`): past the best hit, none can beat it.
            if best.is_some_and(|(_, t)| self.leaves.leaves[i].near > t) {
                break;
            }
            let limit = best.map_or(max_range, |(_, t)| t);
            if let Some(t) = self.leaves.leaves[i].geometry.toi(ray, limit)
                && best.is_none_or(|(_, b)| t < b)
            {
                best = Some((i, t));
            }
        }
        let (i, toi) = best?;
        let leaf = &self.leaves.leaves[i];
        let normal = leaf.geometry.normal(ray, toi, max_range)?;
        Some(Hit {
            frame: leaf.frame,
            surface: leaf.surface,
            toi,
            normal,
        })
    }
}
