//! Conversions between rapier's glam types (f32) and the project's nalgebra types (f64).

use nalgebra::{Isometry3, Point3, Quaternion, Translation3, UnitQuaternion, Vector3};
use rapier3d::prelude::{Pose, Rotation, Vector};

/// A rapier pose as an nalgebra isometry.
pub fn iso_from_pose(p: &Pose) -> Isometry3<f64> {
    let t = p.translation;
    let q = p.rotation;
    Isometry3::from_parts(
        Translation3::new(f64::from(t.x), f64::from(t.y), f64::from(t.z)),
        UnitQuaternion::new_normalize(Quaternion::new(
            f64::from(q.w),
            f64::from(q.x),
            f64::from(q.y),
            f64::from(q.z),
        )),
    )
}

/// An nalgebra isometry as a rapier pose.
pub fn pose_from_iso(i: &Isometry3<f64>) -> Pose {
    let t = i.translation.vector;
    let q = i.rotation.quaternion();
    Pose::from_parts(
        Vector::new(t.x as f32, t.y as f32, t.z as f32),
        Rotation::from_xyzw(q.i as f32, q.j as f32, q.k as f32, q.w as f32).normalize(),
    )
}

/// A rapier vector as an nalgebra vector.
pub fn vec_from_glam(v: Vector) -> Vector3<f64> {
    Vector3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
}

/// An nalgebra point as a rapier vector.
pub fn glam_from_point(p: &Point3<f64>) -> Vector {
    Vector::new(p.x as f32, p.y as f32, p.z as f32)
}

/// An nalgebra vector as a rapier vector.
pub fn glam_from_vec(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x as f32, v.y as f32, v.z as f32)
}
