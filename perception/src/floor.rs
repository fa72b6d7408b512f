//! Floor detection (Kakiuchi et al. 2010, §IV-B): the floor is what looks like the floor in front of the
//! robot.
//!
//! The robot stands on the floor, so the points in a square patch in front of it are taken as known floor.
//! From them we fit a Gaussian on height, `P(z) = exp(−(z−μ_z)²/2σ_z²)/(√(2π)σ_z)` (the paper's eq. 1 is
//! misprinted without the square and the 2), and a Gaussian on RGB with a full 3×3 covariance
//! (eq. 2). A point is floor when `P(z)·P(c)` is above a threshold.
//!
//! We work in log-likelihood: `ln P(z)P(c) = −½·d² − ln(√(2π)σ_z) − ln((2π)^{3/2}√|Σ_c|)` with
//! `d² = (z−μ_z)²/σ_z² + (c−μ_c)ᵀΣ_c⁻¹(c−μ_c)`, a Mahalanobis distance in the 4-D (height, colour)
//! space. A threshold on the likelihood is therefore a bound on `d²`; we set it as that bound
//! ([`FloorConfig::max_mahalanobis_sq`], default the χ²(4 dof) 99.9 % quantile) so that it means the same
//! thing whatever σ_z and Σ_c come out, and expose the equivalent log-likelihood threshold.
//!
//! Both spreads are regularised: σ_z is at least [`FloorConfig::min_sigma_z`] (a near patch seen at short
//! range is less noisy than the far floor), and Σ_c gets [`FloorConfig::colour_variance_floor`] added on
//! its diagonal so that a perfectly uniform floor does not give a singular matrix.
//!
//! A mat whose colour differs from the floor is not floor by colour (the paper's Fig. 8 cloth). It stays
//! in the obstacle points with its true height (a few mm), and the later stages keep it that low.

use nalgebra::{Isometry2, Matrix3, Point2, Vector3};
use rayon::prelude::*;

use crate::cloud::{ColourCloud, Rgb};
use crate::error::PerceptionError;

/// Parameters of floor detection.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorConfig {
    /// Distance from the base origin to the centre of the known-floor square, along the robot's heading
    /// (m). Default 1.0: at the paper's steepest tilt (45°) a head-mounted sensor with a 34.6° vertical
    /// field of view first sees the floor about 0.75 m ahead, so the square spans 0.8–1.2 m ahead.
    pub patch_ahead: f64,
    /// Side of the known-floor square (m). Default 0.4 (the paper's 400 mm).
    pub patch_side: f64,
    /// Fewest points in the square to fit the model. Default 30.
    pub min_patch_points: usize,
    /// Where the floor is expected in the map frame (m): the base frame's z = 0, since the robot stands
    /// on it. Default 0.0.
    pub expected_height: f64,
    /// Only square points within this of `expected_height` (m) are taken as known floor. Default 0.05:
    /// when the robot stands at a push pose the object itself may reach into the square, and its points
    /// must not teach the model that the floor is 0.45 m high and blue.
    pub patch_height_tolerance: f64,
    /// Lower bound on the height standard deviation σ_z (m). Default 0.006 (range noise of the far floor).
    pub min_sigma_z: f64,
    /// Variance added to each colour channel's variance (8-bit levels²). Default 25 (σ ≥ 5 levels), so a
    /// uniform floor gives a regular covariance and mild shading stays floor.
    pub colour_variance_floor: f64,
    /// Bound on the 4-D Mahalanobis distance squared `d²` for a floor point. Default 18.47, the 99.9 %
    /// quantile of χ² with 4 degrees of freedom: one true floor point in a thousand is rejected (and then
    /// almost always dropped as a sparse cell by the elevation map).
    pub max_mahalanobis_sq: f64,
}

impl Default for FloorConfig {
    fn default() -> Self {
        Self {
            patch_ahead: 1.0,
            patch_side: 0.4,
            min_patch_points: 30,
            expected_height: 0.0,
            patch_height_tolerance: 0.05,
            min_sigma_z: 0.006,
            colour_variance_floor: 25.0,
            max_mahalanobis_sq: 18.47,
        }
    }
}

impl FloorConfig {
    fn validate(&self) -> Result<(), PerceptionError> {
        let ok = self.patch_ahead.is_finite()
            && self.patch_side.is_finite()
            && self.patch_side > 0.0
            && self.expected_height.is_finite()
            && self.patch_height_tolerance.is_finite()
            && self.patch_height_tolerance > 0.0
            && self.min_sigma_z.is_finite()
            && self.min_sigma_z > 0.0
            && self.colour_variance_floor.is_finite()
            && self.colour_variance_floor > 0.0
            && self.max_mahalanobis_sq.is_finite()
            && self.max_mahalanobis_sq > 0.0;
        if ok {
            Ok(())
        } else {
            Err(PerceptionError::InvalidInput(format!(
                "floor config out of range: {self:?}"
            )))
        }
    }
}

/// The learned floor: a Gaussian on height times a Gaussian on colour.
#[derive(Clone, Debug, PartialEq)]
pub struct FloorModel {
    mu_z: f64,
    sigma_z: f64,
    mu_c: Vector3<f64>,
    cov_c: Matrix3<f64>,
    cov_c_inv: Matrix3<f64>,
    log_norm: f64,
    max_mahalanobis_sq: f64,
    patch_points: usize,
}

impl FloorModel {
    /// Learns the floor from the points of `cloud` (map frame) in the square in front of the robot at
    /// `base_pose` (map frame, planar) that lie near the expected floor height.
    ///
    /// Errors: no valid point in the square, fewer than [`FloorConfig::min_patch_points`], a non-finite
    /// pose or an out-of-range config.
    pub fn learn(
        cloud: &ColourCloud,
        base_pose: &Isometry2<f64>,
        config: &FloorConfig,
    ) -> Result<Self, PerceptionError> {
        config.validate()?;
        if !(base_pose.translation.vector.iter().all(|v| v.is_finite())
            && base_pose.rotation.angle().is_finite())
        {
            return Err(PerceptionError::InvalidInput(
                "base pose is not finite".into(),
            ));
        }
        let map_to_base = base_pose.inverse();
        let half = config.patch_side / 2.0;
        let (near, far) = (config.patch_ahead - half, config.patch_ahead + half);
        let (z_lo, z_hi) = (
            config.expected_height - config.patch_height_tolerance,
            config.expected_height + config.patch_height_tolerance,
        );
        let in_patch = |x: f32, y: f32, z: f32| {
            let z = f64::from(z);
            if z < z_lo || z > z_hi {
                return false;
            }
            let b = map_to_base * Point2::new(f64::from(x), f64::from(y));
            b.x >= near && b.x <= far && b.y.abs() <= half
        };
        let mut n = 0usize;
        let mut sum_z = 0.0;
        let mut sum_c = Vector3::zeros();
        let mut samples: Vec<(f64, Vector3<f64>)> = Vec::new();
        for (_, p, c) in cloud.iter_valid() {
            if in_patch(p.x, p.y, p.z) {
                let cv = colour_vector(c);
                n += 1;
                sum_z += f64::from(p.z);
                sum_c += cv;
                samples.push((f64::from(p.z), cv));
            }
        }
        if n == 0 {
            let centre = base_pose * Point2::new(config.patch_ahead, 0.0);
            return Err(PerceptionError::NoFloorPoints {
                x: centre.x,
                y: centre.y,
            });
        }
        let needed = config.min_patch_points.max(2);
        if n < needed {
            return Err(PerceptionError::TooFewFloorPoints { found: n, needed });
        }
        let mu_z = sum_z / n as f64;
        let mu_c = sum_c / n as f64;
        let mut var_z = 0.0;
        let mut cov_c = Matrix3::zeros();
        for (z, c) in &samples {
            var_z += (z - mu_z).powi(2);
            let d = c - mu_c;
            cov_c += d * d.transpose();
        }
        let sigma_z = (var_z / (n - 1) as f64).sqrt().max(config.min_sigma_z);
        cov_c = cov_c / (n - 1) as f64 + Matrix3::identity() * config.colour_variance_floor;
        // The regularised covariance is symmetric positive definite; Cholesky cannot fail, but an error is
        // still an error rather than a panic.
        let chol = cov_c.cholesky().ok_or_else(|| {
            PerceptionError::InvalidInput("floor colour covariance is not positive definite".into())
        })?;
        let cov_c_inv = chol.inverse();
        let log_det = 2.0 * chol.l().diagonal().iter().map(|d| d.ln()).sum::<f64>();
        let ln_2pi = (2.0 * std::f64::consts::PI).ln();
        let log_norm = -(0.5 * ln_2pi + sigma_z.ln()) - (1.5 * ln_2pi + 0.5 * log_det);
        Ok(Self {
            mu_z,
            sigma_z,
            mu_c,
            cov_c,
            cov_c_inv,
            log_norm,
            max_mahalanobis_sq: config.max_mahalanobis_sq,
            patch_points: n,
        })
    }

    /// Mean floor height μ_z in the map frame (m): the zero of prism heights.
    pub fn height(&self) -> f64 {
        self.mu_z
    }

    /// Height standard deviation σ_z (m), after regularisation.
    pub fn sigma_z(&self) -> f64 {
        self.sigma_z
    }

    /// Mean floor colour μ_c (RGB, 0–255).
    pub fn mean_colour(&self) -> Vector3<f64> {
        self.mu_c
    }

    /// Colour covariance Σ_c (levels², regularised).
    pub fn colour_covariance(&self) -> Matrix3<f64> {
        self.cov_c
    }

    /// Number of known-floor points the model was fitted on.
    pub fn patch_points(&self) -> usize {
        self.patch_points
    }

    /// Squared 4-D Mahalanobis distance `d²` of a point (height `z` in the map frame, colour `c`).
    pub fn mahalanobis_sq(&self, z: f64, c: Rgb) -> f64 {
        let dz = (z - self.mu_z) / self.sigma_z;
        let dc = colour_vector(c) - self.mu_c;
        dz * dz + dc.dot(&(self.cov_c_inv * dc))
    }

    /// `ln P(z)·P(c)` of a point (paper eqs. 1–2).
    pub fn log_likelihood(&self, z: f64, c: Rgb) -> f64 {
        self.log_norm - 0.5 * self.mahalanobis_sq(z, c)
    }

    /// The log-likelihood threshold equivalent to the Mahalanobis bound: floor iff `ln P ≥` this.
    pub fn log_likelihood_threshold(&self) -> f64 {
        self.log_norm - 0.5 * self.max_mahalanobis_sq
    }

    /// True when the point is floor (`d² ≤` the bound; non-finite input is never floor).
    pub fn is_floor(&self, z: f64, c: Rgb) -> bool {
        // The height term alone already exceeds the bound for every point on an obstacle: skip the
        // colour term there.
        let dz = (z - self.mu_z) / self.sigma_z;
        let dz2 = dz * dz;
        if dz2.is_nan() || dz2 > self.max_mahalanobis_sq {
            return false;
        }
        let d2 = self.mahalanobis_sq(z, c);
        d2.is_finite() && d2 <= self.max_mahalanobis_sq
    }

    /// One flag per slot of `cloud`: true for a valid floor point (invalid slots are false).
    pub fn classify(&self, cloud: &ColourCloud) -> Vec<bool> {
        let (zs, cs) = (cloud.zs(), cloud.colours());
        (0..cloud.len())
            .into_par_iter()
            .with_min_len(4096)
            .map(|i| cloud.point(i).is_some() && self.is_floor(f64::from(zs[i]), cs[i]))
            .collect()
    }

    /// Splits `cloud`'s valid points into (floor, everything else), both unorganised in the cloud's
    /// frame, in slot order. Each point is classified once.
    pub fn split(&self, cloud: &ColourCloud) -> (ColourCloud, ColourCloud) {
        let is_floor = self.classify(cloud);
        let floor = slots_where(cloud, |i| is_floor[i]);
        let other = slots_where(cloud, |i| !is_floor[i]);
        (gather(cloud, &floor), gather(cloud, &other))
    }

    /// The valid points of `cloud` that are not floor (in the cloud's frame), in slot order.
    pub fn non_floor(&self, cloud: &ColourCloud) -> ColourCloud {
        let (zs, cs) = (cloud.zs(), cloud.colours());
        gather(
            cloud,
            &slots_where(cloud, |i| !self.is_floor(f64::from(zs[i]), cs[i])),
        )
    }

    /// [`FloorModel::non_floor`] and [`FloorModel::classify`] at once, each point classified once:
    /// the obstacles' points, and one floor flag per slot of `cloud` (for the floor seen free,
    /// without gathering the floor's points).
    pub fn non_floor_and_flags(&self, cloud: &ColourCloud) -> (ColourCloud, Vec<bool>) {
        const CHUNK: usize = 16_384;
        let (xs, ys, zs, cs) = (cloud.xs(), cloud.ys(), cloud.zs(), cloud.colours());
        let n = cloud.len();
        // One pass: each chunk's floor flags and the slots of its other valid points.
        let chunks: Vec<(Vec<bool>, Vec<usize>)> = (0..n.div_ceil(CHUNK))
            .into_par_iter()
            .map(|k| {
                let slots = k * CHUNK..((k + 1) * CHUNK).min(n);
                let mut flags = Vec::with_capacity(slots.len());
                let mut other = Vec::new();
                for i in slots {
                    let valid = xs[i].is_finite() && ys[i].is_finite() && zs[i].is_finite();
                    let floor = valid && self.is_floor(f64::from(zs[i]), cs[i]);
                    flags.push(floor);
                    if valid && !floor {
                        other.push(i);
                    }
                }
                (flags, other)
            })
            .collect();
        let mut is_floor = Vec::with_capacity(n);
        let mut other = Vec::with_capacity(chunks.len());
        for (flags, slots) in chunks {
            is_floor.extend(flags);
            other.push(slots);
        }
        (gather(cloud, &other), is_floor)
    }
}

/// The valid slots of `cloud` that satisfy `keep`, as index lists over fixed chunks filtered in
/// parallel and kept in chunk order (deterministic).
fn slots_where(cloud: &ColourCloud, keep: impl Fn(usize) -> bool + Sync) -> Vec<Vec<usize>> {
    const CHUNK: usize = 16_384;
    let (xs, ys, zs) = (cloud.xs(), cloud.ys(), cloud.zs());
    let n = cloud.len();
    (0..n.div_ceil(CHUNK))
        .into_par_iter()
        .map(|k| {
            (k * CHUNK..((k + 1) * CHUNK).min(n))
                .filter(|&i| xs[i].is_finite() && ys[i].is_finite() && zs[i].is_finite() && keep(i))
                .collect()
        })
        .collect()
}

/// The points of `cloud` at the slots of `parts` (in order), as an unorganised cloud in its frame.
fn gather(cloud: &ColourCloud, parts: &[Vec<usize>]) -> ColourCloud {
    let (xs, ys, zs, cs) = (cloud.xs(), cloud.ys(), cloud.zs(), cloud.colours());
    let total: usize = parts.iter().map(Vec::len).sum();
    let (mut x, mut y, mut z, mut rgb) = (
        Vec::with_capacity(total),
        Vec::with_capacity(total),
        Vec::with_capacity(total),
        Vec::with_capacity(total),
    );
    for &i in parts.iter().flatten() {
        x.push(xs[i]);
        y.push(ys[i]);
        z.push(zs[i]);
        rgb.push(cs[i]);
    }
    let (frame, pose, stamp) = (cloud.frame(), *cloud.sensor_pose(), cloud.stamp());
    ColourCloud::from_arrays(x, y, z, rgb, frame, pose, stamp)
        .unwrap_or_else(|| ColourCloud::empty(frame, pose, stamp))
}

/// The non-floor points of a map-frame cloud (valid points only).
pub fn remove_floor(cloud: &ColourCloud, model: &FloorModel) -> ColourCloud {
    model.non_floor(cloud)
}

fn colour_vector(c: Rgb) -> Vector3<f64> {
    Vector3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::CloudFrame;
    use nalgebra::{Isometry3, Point3};

    fn floor_patch_cloud(colour: impl Fn(usize) -> Rgb) -> ColourCloud {
        let mut cloud = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        for i in 0..400 {
            let x = 0.81 + 0.38 * (i % 20) as f32 / 20.0;
            let y = -0.19 + 0.38 * (i / 20) as f32 / 20.0;
            let z = 0.002 * ((i * 7919 % 13) as f32 / 6.0 - 1.0);
            cloud.push(Point3::new(x, y, z), colour(i));
        }
        cloud
    }

    #[test]
    fn uniform_floor_gives_a_regular_model_and_rejects_a_red_mat() {
        // Invariant: a perfectly uniform floor colour still yields a finite model; a differently coloured
        // point at floor height is not floor, a floor-coloured one is.
        let cloud = floor_patch_cloud(|_| [150, 150, 140]);
        let model = FloorModel::learn(&cloud, &Isometry2::identity(), &FloorConfig::default())
            .expect("patch has points");
        assert!(model.log_likelihood(0.0, [150, 150, 140]).is_finite());
        assert!(model.is_floor(0.003, [152, 149, 141]));
        assert!(!model.is_floor(0.01, [180, 40, 40]));
        assert!(!model.is_floor(0.10, [150, 150, 140]));
        assert!(model.log_likelihood(0.0, [150, 150, 140]) >= model.log_likelihood_threshold());
    }

    #[test]
    fn empty_patch_and_sparse_patch_are_errors() {
        // Invariant: learning needs points in the patch: none → NoFloorPoints, few → TooFewFloorPoints.
        let cloud = floor_patch_cloud(|_| [150, 150, 140]);
        let away = Isometry2::new(nalgebra::Vector2::new(10.0, 10.0), 0.0);
        assert!(matches!(
            FloorModel::learn(&cloud, &away, &FloorConfig::default()),
            Err(PerceptionError::NoFloorPoints { .. })
        ));
        let config = FloorConfig {
            min_patch_points: 1000,
            ..FloorConfig::default()
        };
        assert!(matches!(
            FloorModel::learn(&cloud, &Isometry2::identity(), &config),
            Err(PerceptionError::TooFewFloorPoints { found: 400, .. })
        ));
    }

    #[test]
    fn the_patch_follows_the_robot_heading() {
        // Invariant: the known-floor square lies ahead along the base yaw, not along map x.
        let cloud = floor_patch_cloud(|_| [150, 150, 140]);
        let facing_back = Isometry2::new(nalgebra::Vector2::new(2.0, 0.0), std::f64::consts::PI);
        let model = FloorModel::learn(&cloud, &facing_back, &FloorConfig::default())
            .expect("patch 0.8–1.2 m behind x = 2 holds the points");
        assert_eq!(model.patch_points(), 400);
    }
}
