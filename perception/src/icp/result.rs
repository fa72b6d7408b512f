//! What colour ICP reports.

use nalgebra::{Isometry3, Point3, Vector3};

/// The estimated motion of an object between two clouds, with quality measures.
#[derive(Clone, Debug, PartialEq)]
pub struct IcpResult {
    /// Rigid motion in the map frame taking the before-cloud onto the after-cloud.
    pub transform: Isometry3<f64>,
    /// Displacement of the before-cloud's centroid under `transform` (mm, map frame). This is the
    /// object's displacement independent of where the map origin is (a 2° yaw about the map origin
    /// would otherwise show up as metres of translation).
    pub translation_mm: Vector3<f64>,
    /// Rotation about map z (degrees).
    pub yaw_deg: f64,
    /// Rotation about map y (degrees).
    pub pitch_deg: f64,
    /// Rotation about map x (degrees).
    pub roll_deg: f64,
    /// Fraction of (used) source points with a correspondence within the final distance bound.
    pub fitness: f64,
    /// Root mean square point-to-point distance of those correspondences (m).
    pub rmse: f64,
    /// Gauss–Newton iterations run over all stages.
    pub iterations: usize,
    /// True when the last stage's update fell below the convergence bounds.
    pub converged: bool,
}

impl IcpResult {
    /// A result from a map-frame motion and the before-cloud's centroid.
    pub fn from_motion(
        transform: Isometry3<f64>,
        source_centroid: &Point3<f64>,
        fitness: f64,
        rmse: f64,
        iterations: usize,
        converged: bool,
    ) -> Self {
        let moved = transform * source_centroid;
        let (roll, pitch, yaw) = transform.rotation.euler_angles();
        Self {
            transform,
            translation_mm: (moved - source_centroid) * 1000.0,
            yaw_deg: yaw.to_degrees(),
            pitch_deg: pitch.to_degrees(),
            roll_deg: roll.to_degrees(),
            fitness,
            rmse,
            iterations,
            converged,
        }
    }

    /// Length of the displacement (mm).
    pub fn distance_mm(&self) -> f64 {
        self.translation_mm.norm()
    }
}
