//! One visible shape of a frame and how a ray meets it: boxes and upright cylinders in closed form,
//! anything else through parry.

use rapier3d::geometry::Ray;
use rapier3d::math::{Matrix, Pose, Real, Vector};
use rapier3d::parry::shape::Shape;

use crate::surface::Surface;

/// One piece of a visible collider (a compound's part, or the whole shape) in world coordinates,
/// with its bounding box corners in the sensor frame for culling.
pub(super) struct Leaf<'c> {
    /// The pose of the collider or compound part (the surface pattern's frame).
    pub(super) frame: Pose,
    pub(super) surface: Option<Surface>,
    pub(super) geometry: LeafGeometry<'c>,
    /// World AABB corners, in the sensor frame.
    pub(super) corners: [Vector; 8],
    /// Distance from the sensor to the leaf's AABB: no ray meets the leaf nearer than this.
    pub(super) near: Real,
}

/// How a leaf meets a ray.
pub(super) enum LeafGeometry<'c> {
    /// A box, traced with a slab test in its own frame: most of a room is boxes, and this is several
    /// times cheaper than the generic shape cast.
    Cuboid {
        half: Vector,
        /// World → box rotation.
        to_local: Matrix,
        /// Box → world rotation.
        to_world: Matrix,
        /// The sensor's position in the box frame (every ray of a frame starts there).
        origin: Vector,
    },
    /// An upright cylinder (a person, a bin), traced in closed form in its own frame (axis along
    /// its local y, parry's convention): parry casts rays at cylinders through GJK, which cost
    /// about two thirds of a run's time in a room with a person walking in view.
    Cylinder {
        half_height: Real,
        radius: Real,
        /// World → cylinder rotation.
        to_local: Matrix,
        /// Cylinder → world rotation.
        to_world: Matrix,
        /// The sensor's position in the cylinder frame.
        origin: Vector,
    },
    /// Any other shape, through parry.
    Shape { shape: &'c dyn Shape, pose: Pose },
}

impl LeafGeometry<'_> {
    pub(super) fn new<'s>(
        shape: &'s dyn Shape,
        pose: Pose,
        sensor_origin: Vector,
    ) -> LeafGeometry<'s> {
        let to_local = Matrix::from_quat(pose.rotation.inverse());
        let to_world = Matrix::from_quat(pose.rotation);
        let origin = pose.inverse_transform_point(sensor_origin);
        if let Some(cuboid) = shape.as_cuboid() {
            LeafGeometry::Cuboid {
                half: cuboid.half_extents,
                to_local,
                to_world,
                origin,
            }
        } else if let Some(cylinder) = shape.as_cylinder() {
            LeafGeometry::Cylinder {
                half_height: cylinder.half_height,
                radius: cylinder.radius,
                to_local,
                to_world,
                origin,
            }
        } else {
            LeafGeometry::Shape { shape, pose }
        }
    }

    /// Distance along `ray` (direction `ray.dir`, unit) to the leaf if under `limit`; 0 when the
    /// ray starts inside.
    pub(super) fn toi(&self, ray: &Ray, limit: Real) -> Option<Real> {
        match self {
            LeafGeometry::Cuboid {
                half,
                to_local,
                origin,
                ..
            } => {
                let inv = (*to_local * ray.dir).recip();
                let t1 = (-*half - *origin) * inv;
                let t2 = (*half - *origin) * inv;
                let enter = t1.min(t2).max_element().max(0.0);
                let exit = t1.max(t2).min_element();
                (enter <= exit && enter <= limit).then_some(enter)
            }
            LeafGeometry::Cylinder {
                half_height,
                radius,
                to_local,
                origin,
                ..
            } => cylinder_toi(*origin, *to_local * ray.dir, *half_height, *radius)
                .filter(|&t| t <= limit),
            LeafGeometry::Shape { shape, pose } => shape.cast_ray(pose, ray, limit, true),
        }
    }

    /// The world-frame normal where `ray` meets the leaf at `toi`, or `None` if it does not.
    pub(super) fn normal(&self, ray: &Ray, toi: Real, max_range: Real) -> Option<Vector> {
        match self {
            LeafGeometry::Cuboid {
                half,
                to_local,
                to_world,
                origin,
            } => {
                // The face the local hit point is nearest to, relative to the box's size.
                let p = *origin + (*to_local * ray.dir) * toi;
                let rel = (p / *half).abs();
                let axis = if rel.x >= rel.y && rel.x >= rel.z {
                    Vector::X * p.x.signum()
                } else if rel.y >= rel.z {
                    Vector::Y * p.y.signum()
                } else {
                    Vector::Z * p.z.signum()
                };
                Some(*to_world * axis)
            }
            LeafGeometry::Cylinder {
                half_height,
                radius,
                to_local,
                to_world,
                origin,
            } => {
                if toi == 0.0 {
                    // The sensor is inside: no surface faces it (parry answers the same).
                    return Some(Vector::ZERO);
                }
                // The cap or the side, whichever the local hit point is nearer to relative to
                // the cylinder's size.
                let p = *origin + (*to_local * ray.dir) * toi;
                let radial = Vector::new(p.x, 0.0, p.z);
                let axis = if p.y.abs() / *half_height >= radial.length() / *radius {
                    Vector::Y * p.y.signum()
                } else {
                    radial.normalize_or_zero()
                };
                Some(*to_world * axis)
            }
            LeafGeometry::Shape { shape, pose } => shape
                .cast_ray_and_get_normal(pose, ray, max_range, true)
                .map(|hit| hit.normal),
        }
    }
}

/// Distance along the ray `origin + t·dir` (in the cylinder's frame, axis along y) to the solid
/// cylinder of `half_height` and `radius` centred at the origin; 0 when the ray starts inside.
pub(super) fn cylinder_toi(
    origin: Vector,
    dir: Vector,
    half_height: Real,
    radius: Real,
) -> Option<Real> {
    let (o, d) = (origin, dir);
    let r2 = radius * radius;
    if o.y.abs() <= half_height && o.x * o.x + o.z * o.z <= r2 {
        return Some(0.0);
    }
    let mut best = Real::INFINITY;
    // The side: |(o + t·d)_xz| = r, entered at the smaller root, within the height.
    let a = d.x * d.x + d.z * d.z;
    if a > Real::EPSILON {
        let b = o.x * d.x + o.z * d.z;
        let c = o.x * o.x + o.z * o.z - r2;
        let disc = b * b - a * c;
        if disc >= 0.0 {
            let t = (-b - disc.sqrt()) / a;
            if t >= 0.0 && (o.y + t * d.y).abs() <= half_height {
                best = t;
            }
        }
    }
    // The caps: the plane y = ±h, within the radius.
    if d.y != 0.0 {
        for cap in [-half_height, half_height] {
            let t = (cap - o.y) / d.y;
            if t >= 0.0 && t < best {
                let (x, z) = (o.x + t * d.x, o.z + t * d.z);
                if x * x + z * z <= r2 {
                    best = t;
                }
            }
        }
    }
    best.is_finite().then_some(best)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensors::colour_range::noise::RayRng;
    use rand::TryRng;
    use rapier3d::math::Rotation;

    #[test]
    fn the_closed_form_cylinder_meets_rays_where_parry_does() {
        // Invariant: the culled caster's cylinder returns the exact point where each ray enters a
        // tilted cylinder (from outside or inside), and parry's GJK cast finds the same surface
        // point and normal to within its own tolerance, so the sensor sees the same scene.
        use rapier3d::parry::query::RayCast;
        use rapier3d::parry::shape::Cylinder;
        let (half_height, radius) = (0.85, 0.25);
        let cylinder = Cylinder::new(half_height, radius);
        let pose = Pose::from_parts(
            Vector::new(1.0, -0.5, 0.9),
            Rotation::from_scaled_axis(Vector::new(1.3, 0.2, -0.4)),
        );
        // How far a world point lies outside the solid (negative inside, exact near a face).
        let outside = |world: Vector| {
            let p = pose.inverse_transform_point(world);
            ((p.x * p.x + p.z * p.z).sqrt() - radius).max(p.y.abs() - half_height)
        };
        let mut rng = RayRng::new(7, 0);
        let mut uniform = |lo: Real, hi: Real| {
            lo + (hi - lo) * (rng.try_next_u64().unwrap_or(0) >> 11) as Real / (1u64 << 53) as Real
        };
        let (mut hits, mut inside, mut grazing) = (0, 0, 0);
        for _ in 0..20_000 {
            let origin = Vector::new(uniform(-3.0, 3.0), uniform(-3.0, 3.0), uniform(-1.0, 2.5));
            let target = pose.transform_point(Vector::new(
                uniform(-0.4, 0.4),
                uniform(-1.0, 1.0),
                uniform(-0.4, 0.4),
            ));
            let ray = Ray::new(origin, (target - origin).normalize());
            let at = |t: Real| ray.origin + ray.dir * t;
            let leaf = LeafGeometry::new(&cylinder, pose, origin);
            let ours = leaf.toi(&ray, 10.0);
            let parry = cylinder.cast_ray_and_get_normal(&pose, &ray, 10.0, true);
            match (ours, parry) {
                (Some(0.0), Some(hit)) => {
                    inside += 1;
                    assert!(outside(origin) <= 0.0 && hit.time_of_impact == 0.0);
                }
                (Some(t), Some(hit)) => {
                    hits += 1;
                    // Ours lies on the surface to f32 rounding, and just before it the ray is out.
                    assert!(
                        outside(at(t)).abs() < 1e-5 * (1.0 + t),
                        "{t} is off the surface"
                    );
                    assert!(
                        outside(at(t - 1e-4)) > 0.0,
                        "{t} is not where the ray enters"
                    );
                    // Parry's GJK stops millimetres off the surface where a ray grazes a face or
                    // rim, which along the ray can be centimetres: its point is checked there.
                    assert!(outside(at(hit.time_of_impact)).abs() < 5e-3, "{hit:?}");
                    let normal = leaf.normal(&ray, t, 10.0).unwrap_or(Vector::ZERO);
                    let cos = normal.dot(ray.dir).abs();
                    if cos > 0.2 {
                        assert!((t - hit.time_of_impact).abs() < 1e-2, "{t} vs {hit:?}");
                    }
                    let p = pose.inverse_transform_point(at(t));
                    // Parry blends the two faces' normals near a rim.
                    let on_rim = (p.y.abs() - half_height).abs() < 1e-2
                        && ((p.x * p.x + p.z * p.z).sqrt() - radius).abs() < 1e-2;
                    if !on_rim && cos > 0.2 {
                        assert!(normal.dot(hit.normal) > 0.999, "{normal} vs {}", hit.normal);
                    }
                }
                (None, None) => {}
                // A ray that grazes the surface may be a hit for one and a miss for the other.
                (Some(t), None) => {
                    assert!(outside(at(t)).abs() < 1e-5 * (1.0 + t));
                    grazing += 1;
                }
                (None, Some(hit)) => {
                    assert!(outside(at(hit.time_of_impact)) < 5e-3, "we missed {hit:?}");
                    grazing += 1;
                }
            }
        }
        assert!(
            hits > 10_000,
            "{hits} hits: the rays should mostly meet the cylinder"
        );
        assert!(inside > 0, "no ray started inside");
        assert!(grazing < 20, "{grazing} grazing disagreements");
    }
}
