//! The pan/tilt head: rate-limited angles and the pose of the range sensor it carries.

use nalgebra::{Isometry2, Isometry3, Translation3, UnitQuaternion, Vector3};

/// Pan limits (rad): left positive.
pub const PAN_LIMITS: (f64, f64) = (-1.6, 1.6);
/// Tilt limits (rad): down positive.
pub const TILT_LIMITS: (f64, f64) = (-0.5, 1.3);

/// The head's joint state and its motion target.
#[derive(Clone, Debug, PartialEq)]
pub struct Head {
    /// Current pan (rad, left positive).
    pub pan: f64,
    /// Current tilt (rad, down positive).
    pub tilt: f64,
    target: Option<(f64, f64)>,
    rate: f64,
    height: f64,
}

impl Head {
    /// A head looking straight ahead, at `height` above the floor, turning at `rate` rad/s per axis.
    pub fn new(height: f64, rate: f64) -> Self {
        Self {
            pan: 0.0,
            tilt: 0.0,
            target: None,
            rate,
            height,
        }
    }

    /// Whether (pan, tilt) is inside the joint limits.
    pub fn within_limits(pan: f64, tilt: f64) -> bool {
        pan.is_finite()
            && tilt.is_finite()
            && (PAN_LIMITS.0..=PAN_LIMITS.1).contains(&pan)
            && (TILT_LIMITS.0..=TILT_LIMITS.1).contains(&tilt)
    }

    /// Starts moving to (pan, tilt); the caller checked the limits.
    pub fn point(&mut self, pan: f64, tilt: f64) {
        self.target = Some((pan, tilt));
    }

    /// Whether a head motion is under way.
    pub fn is_moving(&self) -> bool {
        self.target.is_some()
    }

    /// Moves the joints for `dt` seconds.
    pub fn step(&mut self, dt: f64) {
        let Some((pan, tilt)) = self.target else {
            return;
        };
        let max = self.rate * dt;
        self.pan += (pan - self.pan).clamp(-max, max);
        self.tilt += (tilt - self.tilt).clamp(-max, max);
        if self.pan == pan && self.tilt == tilt {
            self.target = None;
        }
    }

    /// The sensor pose in the map for a base at `base`: x along the optical axis, y left, z up.
    pub fn sensor_pose(&self, base: &Isometry2<f64>) -> Isometry3<f64> {
        let base3 = Isometry3::from_parts(
            Translation3::new(base.translation.x, base.translation.y, self.height),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), base.rotation.angle()),
        );
        let pan = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), self.pan);
        // A positive rotation about y turns x towards −z: tilt down is positive.
        let tilt = UnitQuaternion::from_axis_angle(&Vector3::y_axis(), self.tilt);
        base3 * Isometry3::from_parts(Translation3::identity(), pan * tilt)
    }
}
