//! One image row: a ray per pixel, its nearest surface, and the noisy range and colour it returns.

use nalgebra::Point3;
use rapier3d::geometry::Ray;
use rapier3d::math::{Matrix, Pose, Real, Vector};

use super::ColourRangeSensor;
use super::noise::{RayRng, gaussian};
use super::scene::SensorScene;
use crate::surface::{Owner, Surface};

/// One row's slices of the output arrays.
pub(super) struct RowOut<'r> {
    pub(super) x: &'r mut [f32],
    pub(super) y: &'r mut [f32],
    pub(super) z: &'r mut [f32],
    pub(super) rgb: &'r mut [[u8; 3]],
}

/// Everything one capture shares between rows.
pub(super) struct Frame<'f> {
    pub(super) sensor: &'f ColourRangeSensor,
    pub(super) scene: &'f SensorScene<'f>,
    pub(super) pose: Pose,
    pub(super) frame_seed: u64,
}

/// The nearest surface a ray meets.
pub(super) struct Hit {
    /// The frame the surface's pattern is fixed to: the pose of the collider, or of the compound's
    /// part, that was hit.
    pub(super) frame: Pose,
    pub(super) surface: Option<Surface>,
    /// Distance along the ray (m).
    pub(super) toi: Real,
    /// World-frame surface normal at the hit.
    pub(super) normal: Vector,
}

/// Finds the nearest surface along each ray of a row; one per rayon worker.
pub(super) trait RowCaster<'c> {
    /// Prepares for the rays of `row`.
    fn begin_row(&mut self, row: usize);
    /// The nearest surface within `max_range` along `ray`, the ray of column `col`.
    fn first_hit(&mut self, col: usize, ray: &Ray, max_range: Real) -> Option<Hit>;
}

/// One image row's rays: their directions in the sensor frame, the frame's rotation into the map,
/// and the range limits a return must lie within.
struct RowRays<'d> {
    /// Index of the row's first pixel in the image.
    first: usize,
    dirs: &'d [Vector],
    rotation: Matrix,
    min_range: Real,
    max_range: Real,
}

impl Frame<'_> {
    /// Begins `row` on `caster` and gives its rays.
    fn row_rays<'c>(&self, caster: &mut impl RowCaster<'c>, row: usize) -> RowRays<'_> {
        let camera = &self.sensor.config.camera;
        let first = row * camera.width;
        caster.begin_row(row);
        RowRays {
            first,
            dirs: &self.sensor.directions[first..first + camera.width],
            rotation: Matrix::from_quat(self.pose.rotation),
            min_range: camera.min_range as Real,
            max_range: camera.max_range as Real,
        }
    }

    /// Traces every pixel of `row` and writes its return (or NaN) into `out`.
    pub(super) fn trace_row<'c>(
        &self,
        caster: &mut impl RowCaster<'c>,
        row: usize,
        out: RowOut<'_>,
    ) {
        let config = &self.sensor.config;
        let rays = self.row_rays(caster, row);
        let counts = config.camera.range_counts();

        for (col, dir) in rays.dirs.iter().enumerate() {
            let world_dir = rays.rotation * *dir;
            let ray = Ray::new(self.pose.translation, world_dir);
            let Some((hit, cos_incidence)) = self.kept_hit(caster, col, &ray, &rays) else {
                continue;
            };
            let toi = hit.toi;

            let mut noise = RayRng::new(self.frame_seed, rays.first + col);
            let true_range = f64::from(toi);
            let sigma = config.range_sigma(true_range, f64::from(cos_incidence));
            let range = counts.reported(true_range + sigma * gaussian(&mut noise));
            let p = *dir * range as Real;
            out.x[col] = p.x;
            out.y[col] = p.y;
            out.z[col] = p.z;

            let base = match &hit.surface {
                Some(surface) => {
                    let world_hit = ray.origin + world_dir * toi;
                    let local = hit.frame.inverse_transform_point(world_hit);
                    let local =
                        Point3::new(f64::from(local.x), f64::from(local.y), f64::from(local.z));
                    surface.colour_at(local, self.scene.texture_seed)
                }
                None => config.unknown_colour,
            };
            out.rgb[col] = base.map(|c| {
                let v = f64::from(c) + config.colour_noise_sigma * gaussian(&mut noise);
                // Rounds half up; the float-to-int cast saturates, which clamps to 0–255.
                (v + 0.5) as u8
            });
        }
    }

    /// The surface `ray` (column `col` of the row begun) returns, with the cosine of its incidence,
    /// if the sensor keeps it: within the row's range limits, not at grazing incidence, not the
    /// robot's own part when self-filtered. Noise is added after: it never changes which surface
    /// returns.
    fn kept_hit<'c>(
        &self,
        caster: &mut impl RowCaster<'c>,
        col: usize,
        ray: &Ray,
        rays: &RowRays<'_>,
    ) -> Option<(Hit, Real)> {
        let config = &self.sensor.config;
        let hit = caster.first_hit(col, ray, rays.max_range)?;
        let cos_incidence = hit.normal.dot(ray.dir).abs();
        let own_part =
            config.self_filter && hit.surface.is_some_and(|s| matches!(s.owner, Owner::Robot));
        let kept = hit.toi >= rays.min_range
            && cos_incidence >= self.sensor.min_cos_incidence
            && !own_part;
        kept.then_some((hit, cos_incidence))
    }

    /// Who owns the surface each pixel of `row` returns (`None`: no return, or a surface without
    /// an owner): the ground truth a segmentation is scored against.
    pub(super) fn owners_row<'c>(
        &self,
        caster: &mut impl RowCaster<'c>,
        row: usize,
        out: &mut [Option<Owner>],
    ) {
        let rays = self.row_rays(caster, row);
        for (col, dir) in rays.dirs.iter().enumerate() {
            let ray = Ray::new(self.pose.translation, rays.rotation * *dir);
            out[col] = self
                .kept_hit(caster, col, &ray, &rays)
                .and_then(|(hit, _)| hit.surface.map(|s| s.owner));
        }
    }
}
