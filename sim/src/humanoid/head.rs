//! The pan/tilt head: rate-limited angles and the pose of the range sensor it carries.

use nalgebra::{Isometry2, Isometry3, Translation3, UnitQuaternion, Vector3};
use nudge_robot_model::HeadModel;

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
    pan_limits: [f64; 2],
    tilt_limits: [f64; 2],
}

impl Head {
    /// `model`'s head looking straight ahead.
    pub fn new(model: &HeadModel) -> Self {
        Self {
            pan: 0.0,
            tilt: 0.0,
            target: None,
            rate: model.rate,
            height: model.height,
            pan_limits: model.pan_limits,
            tilt_limits: model.tilt_limits,
        }
    }

    /// Pan joint limits (rad), right then left.
    pub fn pan_limits(&self) -> [f64; 2] {
        self.pan_limits
    }

    /// Tilt joint limits (rad), up then down.
    pub fn tilt_limits(&self) -> [f64; 2] {
        self.tilt_limits
    }

    /// Whether (pan, tilt) is inside the joint limits.
    pub fn within_limits(&self, pan: f64, tilt: f64) -> bool {
        let [pan_lo, pan_hi] = self.pan_limits;
        let [tilt_lo, tilt_hi] = self.tilt_limits;
        pan.is_finite()
            && tilt.is_finite()
            && (pan_lo..=pan_hi).contains(&pan)
            && (tilt_lo..=tilt_hi).contains(&tilt)
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
