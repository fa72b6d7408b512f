//! What the colour range sensor is: image size, field of view, range limits and noise.

use nudge_robot_model::{CameraModel, RobotModel};

/// Parameters of the colour range sensor; [`Default`] is the paper's SR-4000 with colour cameras.
/// The image and range are the robot's ([`ColourRangeConfig::for_camera`]); the noise is the sensor
/// model's own.
#[derive(Clone, Debug, PartialEq)]
pub struct ColourRangeConfig {
    /// The camera: image size, fields of view and range limits, the robot description's.
    pub camera: CameraModel,
    /// Range noise σ at `range_sigma_ref_distance`, normal incidence (m).
    pub range_sigma_ref: f64,
    /// The distance at which `range_sigma_ref` holds (m).
    pub range_sigma_ref_distance: f64,
    /// Exponent `a` of the distance term: σ ∝ (r / r_ref)^a. 2 = background-limited ToF noise
    /// (σ ∝ 1 / amplitude ∝ r²); 1 = shot-noise-limited.
    pub range_sigma_distance_exponent: f64,
    /// Exponent `b` of the obliquity term: σ ∝ 1 / cos(θ)^b (θ = angle of incidence).
    pub range_sigma_incidence_exponent: f64,
    /// Returns from surfaces seen more obliquely than this are lost (deg from the surface normal).
    pub max_incidence_deg: f64,
    /// Colour noise σ per channel (0–255 units).
    pub colour_noise_sigma: f64,
    /// Colour of returns from colliders the surface lookup does not know.
    pub unknown_colour: [u8; 3],
    /// Drop returns from the robot's own parts (surface owner [`crate::surface::Owner::Robot`]), like ROS's
    /// robot_self_filter: the pixel is lost, not seen through. The body carrying the sensor is
    /// excluded altogether through [`super::SensorScene::exclude`].
    pub self_filter: bool,
    /// How rays find their nearest surface.
    pub caster: RayCaster,
}

/// How the sensor finds the nearest surface along each ray. Both give the same returns up to float
/// rounding at silhouette edges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RayCaster {
    /// Per frame, gather the leaf shapes inside the view frustum (through the broad phase) and cull
    /// them per image row: a row's rays lie in one plane, so each leaf covers a column span of it and
    /// a ray tests only the leaves whose span holds it. Fast for room-sized scenes.
    #[default]
    RowCulled,
    /// Cast every ray through rapier's query pipeline (the broad phase's BVH): the reference.
    QueryPipeline,
}

impl Default for ColourRangeConfig {
    /// The paper's robot's camera ([`RobotModel::default`]).
    fn default() -> Self {
        Self::for_camera(&RobotModel::default().camera)
    }
}

impl ColourRangeConfig {
    /// A sensor with `camera`'s image, range and colour noise, and the SR-4000's range noise: 4 mm
    /// σ at 1.3 m growing linearly with range (shot-noise limited) and as 1/√cos of the incidence,
    /// lost beyond 80° incidence.
    pub fn for_camera(camera: &CameraModel) -> Self {
        Self {
            camera: camera.clone(),
            range_sigma_ref: 0.004,
            range_sigma_ref_distance: 1.3,
            range_sigma_distance_exponent: 1.0,
            range_sigma_incidence_exponent: 0.5,
            max_incidence_deg: 80.0,
            colour_noise_sigma: camera.colour_noise,
            unknown_colour: [128, 128, 128],
            self_filter: true,
            caster: RayCaster::RowCulled,
        }
    }
}

/// The most pixels a sensor may have (a 4096 × 4096 image): beyond this a typo, not a camera.
pub const MAX_PIXELS: usize = 1 << 24;

/// Why a [`ColourRangeConfig`] cannot describe a sensor.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ColourRangeConfigError {
    /// The image has no pixels, or more than [`MAX_PIXELS`].
    #[error("image size {width} × {height} must have between 1 and {MAX_PIXELS} pixels")]
    ImageSize {
        /// Columns asked for.
        width: usize,
        /// Rows asked for.
        height: usize,
    },
    /// A field of view outside (0°, 180°).
    #[error("field of view {h_fov_deg}° × {v_fov_deg}° must lie in (0°, 180°) on both axes")]
    FieldOfView {
        /// Horizontal field of view asked for (deg).
        h_fov_deg: f64,
        /// Vertical field of view asked for (deg).
        v_fov_deg: f64,
    },
    /// Range limits that are not `0 ≤ min < max < ∞`.
    #[error("range limits [{min_range}, {max_range}] m must satisfy 0 ≤ min < max < ∞")]
    RangeLimits {
        /// Minimum range asked for (m).
        min_range: f64,
        /// Maximum range asked for (m).
        max_range: f64,
    },
    /// A noise parameter that is negative or not finite.
    #[error("noise parameter {name} = {value} must be finite and non-negative")]
    Noise {
        /// Name of the field.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A maximum incidence angle outside (0°, 90°].
    #[error("maximum incidence {0}° must lie in (0°, 90°]")]
    Incidence(f64),
}

impl ColourRangeConfig {
    /// Checks that the configuration describes a sensor that can see something.
    pub fn validate(&self) -> Result<(), ColourRangeConfigError> {
        if self.camera.width == 0
            || self.camera.height == 0
            || self
                .camera
                .width
                .checked_mul(self.camera.height)
                .is_none_or(|n| n > MAX_PIXELS)
        {
            return Err(ColourRangeConfigError::ImageSize {
                width: self.camera.width,
                height: self.camera.height,
            });
        }
        let fov_ok = |deg: f64| deg > 0.0 && deg < 180.0;
        if !(fov_ok(self.camera.h_fov_deg) && fov_ok(self.camera.v_fov_deg)) {
            return Err(ColourRangeConfigError::FieldOfView {
                h_fov_deg: self.camera.h_fov_deg,
                v_fov_deg: self.camera.v_fov_deg,
            });
        }
        if !(self.camera.min_range >= 0.0
            && self.camera.min_range < self.camera.max_range
            && self.camera.max_range.is_finite())
        {
            return Err(ColourRangeConfigError::RangeLimits {
                min_range: self.camera.min_range,
                max_range: self.camera.max_range,
            });
        }
        for (name, value) in [
            ("range_sigma_ref", self.range_sigma_ref),
            (
                "range_sigma_distance_exponent",
                self.range_sigma_distance_exponent,
            ),
            (
                "range_sigma_incidence_exponent",
                self.range_sigma_incidence_exponent,
            ),
            ("colour_noise_sigma", self.colour_noise_sigma),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(ColourRangeConfigError::Noise { name, value });
            }
        }
        if !(self.range_sigma_ref_distance.is_finite() && self.range_sigma_ref_distance > 0.0) {
            return Err(ColourRangeConfigError::Noise {
                name: "range_sigma_ref_distance",
                value: self.range_sigma_ref_distance,
            });
        }
        if !(self.max_incidence_deg > 0.0 && self.max_incidence_deg <= 90.0) {
            return Err(ColourRangeConfigError::Incidence(self.max_incidence_deg));
        }
        Ok(())
    }

    /// The range noise σ (m) of a return at distance `range` (m) whose surface normal makes
    /// `cos_incidence` with the ray.
    pub fn range_sigma(&self, range: f64, cos_incidence: f64) -> f64 {
        let distance_term = power(
            range / self.range_sigma_ref_distance,
            self.range_sigma_distance_exponent,
        );
        let incidence_term = power(cos_incidence, self.range_sigma_incidence_exponent);
        self.range_sigma_ref * distance_term / incidence_term
    }
}

/// `x^e`, with the exponents the noise model uses most spelled out: `powf` per ray is costly.
fn power(x: f64, e: f64) -> f64 {
    if e == 2.0 {
        x * x
    } else if e == 1.0 {
        x
    } else if e == 0.5 {
        x.sqrt()
    } else if e == 0.0 {
        1.0
    } else {
        x.powf(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_config_is_the_sr4000_and_valid() {
        // The default configuration is the paper's SR-4000 (176 × 144, 43.6° × 34.6°) and validates.
        let c = ColourRangeConfig::default();
        assert_eq!((c.camera.width, c.camera.height), (176, 144));
        assert_eq!((c.camera.h_fov_deg, c.camera.v_fov_deg), (43.6, 34.6));
        assert!(c.validate().is_ok());
        assert!((c.range_sigma(1.3, 1.0) - 0.004).abs() < 1e-12);
    }
}
