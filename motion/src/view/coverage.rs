//! The floor one look-around shows from a stand pose: an annulus sector about the body's heading.
//!
//! A look-around pans and tilts the head through a fixed set of views relative to the body. The
//! floor they show together is bounded below by the lowest ray of the most tilted view, above by the
//! range limit (or by the highest ray of the least tilted view when that still points down), and
//! sideways by the widest pan plus half the horizontal field of view. Between those bounds the views
//! overlap (the paper's pans are 25° apart, less than the 43.6° field of view; its tilts 10°–15°
//! apart, less than the 34.6° one), so the sector is covered without gaps.

use nalgebra::{Point2, Vector2};
use nudge_perception::LookAroundConfig;
use nudge_robot_model::RobotModel;

/// Why a coverage could not be derived.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum CoverageError {
    /// A height, angle or range is not finite, or not positive where it must be.
    #[error("camera parameters must be finite and positive (eye height, fields of view, range)")]
    BadCamera,
    /// No tilt or no pan was given.
    #[error("a look-around needs at least one tilt and one pan")]
    NoViews,
    /// The range limit does not reach the floor, or no view looks below the horizon.
    #[error("no view of this look-around sees the floor")]
    NoFloor,
}

/// The floor a look-around shows from a stand pose: every point at a horizontal distance in
/// `near..=far` from the eye, within `half_angle` of the body's heading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LookCoverage {
    /// Height of the eye (the camera's optical centre) above the floor (m).
    pub eye_height: f64,
    /// Nearest floor seen (m, horizontal from the eye).
    pub near: f64,
    /// Farthest floor seen (m, horizontal from the eye).
    pub far: f64,
    /// Half the angle the views span about the heading (rad), at most π.
    pub half_angle: f64,
}

impl LookCoverage {
    /// The coverage of views at `tilts` × `pans` (rad; tilt positive down, pan either way) of a
    /// camera with fields of view `h_fov` × `v_fov` (rad) and range limit `max_range` (m, along the
    /// ray) at `eye_height` (m):
    ///
    /// - `near = eye_height / tan(max tilt + v_fov/2)` (0 when that ray points straight down or
    ///   behind),
    /// - `far = min(√(max_range² − eye_height²), eye_height / tan(min tilt − v_fov/2))`, the second
    ///   only when that angle points below the horizon,
    /// - `half_angle = max |pan| + h_fov/2`, at most π.
    pub fn from_camera(
        eye_height: f64,
        h_fov: f64,
        v_fov: f64,
        max_range: f64,
        tilts: &[f64],
        pans: &[f64],
    ) -> Result<Self, CoverageError> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let finite = tilts.iter().chain(pans).all(|v| v.is_finite());
        let camera = positive(eye_height) && positive(h_fov) && positive(v_fov);
        if !(camera && positive(max_range) && finite) {
            return Err(CoverageError::BadCamera);
        }
        if tilts.is_empty() || pans.is_empty() {
            return Err(CoverageError::NoViews);
        }
        let max_tilt = tilts.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min_tilt = tilts.iter().copied().fold(f64::INFINITY, f64::min);
        let lowest = max_tilt + v_fov / 2.0;
        let highest = min_tilt - v_fov / 2.0;
        if lowest <= 0.0 || max_range <= eye_height {
            return Err(CoverageError::NoFloor);
        }
        let near = if lowest >= std::f64::consts::FRAC_PI_2 {
            0.0
        } else {
            eye_height / lowest.tan()
        };
        let mut far = (max_range * max_range - eye_height * eye_height).sqrt();
        if highest > 0.0 {
            // A top ray straight down or behind leaves nothing beyond the near edge (tan ≤ 0).
            let reach = eye_height / highest.tan();
            far = if reach > 0.0 { far.min(reach) } else { 0.0 };
        }
        if far <= near {
            return Err(CoverageError::NoFloor);
        }
        let widest = pans.iter().map(|p| p.abs()).fold(0.0, f64::max);
        Ok(Self {
            eye_height,
            near,
            far,
            half_angle: (widest + h_fov / 2.0).min(std::f64::consts::PI),
        })
    }

    /// Whether a look-around from `position` facing `heading` (rad, map frame) shows the floor at
    /// `point`, occlusion aside.
    pub fn covers(&self, position: Point2<f64>, heading: f64, point: Point2<f64>) -> bool {
        let v: Vector2<f64> = point - position;
        let r = v.norm();
        if !(r >= self.near && r <= self.far) {
            return false;
        }
        let bearing = v.y.atan2(v.x) - heading;
        let off = bearing.sin().atan2(bearing.cos()).abs();
        off <= self.half_angle
    }
}

impl Default for LookCoverage {
    /// The paper's look-around ([`LookAroundConfig::default`]) with the paper's robot's camera
    /// ([`RobotModel::default`]): an SR-4000 (43.6° × 34.6°, 5 m range) at 1.4 m, tilts 45°, 30°,
    /// 20° down × pans ±50°, ±25°, 0°. The most tilted view's lowest ray is 45° + 17.3° = 62.3° down,
    /// so `near = 1.4 / tan 62.3° ≈ 0.73 m`; the least tilted view's highest ray is 20° − 17.3° =
    /// 2.7° down, reaching the floor at 29.7 m, beyond the range, so `far = √(5² − 1.4²) ≈ 4.80 m`;
    /// `half_angle = 50° + 21.8° = 71.8°`.
    fn default() -> Self {
        Self::from_robot(&RobotModel::default(), &LookAroundConfig::default())
    }
}

impl LookCoverage {
    /// What `look` shows with `robot`'s camera on its head ([`Self::from_camera`]); when they make no
    /// sense (a checked model always does), nothing but the ring the camera's range allows.
    pub fn from_robot(robot: &RobotModel, look: &LookAroundConfig) -> Self {
        let (camera, eye_height) = (&robot.camera, robot.head.height);
        let radians = |degrees: &[f64]| degrees.iter().map(|d| d.to_radians()).collect::<Vec<_>>();
        Self::from_camera(
            eye_height,
            camera.h_fov(),
            camera.v_fov(),
            camera.max_range,
            &radians(&look.tilts_deg),
            &radians(&look.pans_deg),
        )
        .unwrap_or(Self {
            eye_height,
            near: camera.max_range,
            far: camera.max_range,
            half_angle: 0.0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_look_around_covers_0_73_to_4_8_m_over_143_6_degrees() {
        // Invariant: the default coverage is the SR-4000 derivation: near = 1.4 / tan 62.3°,
        // far = √(5² − 1.4²) (the range, not the 2.7° ray), half angle 50° + 21.8°.
        let c = LookCoverage::default();
        assert!((c.near - 1.4 / 62.3_f64.to_radians().tan()).abs() < 1e-12);
        assert!((c.near - 0.735).abs() < 0.005, "{}", c.near);
        assert!((c.far - (25.0_f64 - 1.96).sqrt()).abs() < 1e-12);
        assert!((c.far - 4.80).abs() < 0.005, "{}", c.far);
        assert!((c.half_angle.to_degrees() - 71.8).abs() < 1e-9);
        assert_eq!(c.eye_height, 1.4);
    }

    #[test]
    fn a_shallow_top_view_or_a_straight_down_view_bounds_the_annulus() {
        // Invariant: when the least tilted view's top ray meets the floor inside the range, far is
        // that distance; when the most tilted view sees straight down, near is 0; pans beyond
        // ±(π − h_fov/2) cover the whole circle (π).
        let d = f64::to_radians;
        let c = LookCoverage::from_camera(1.0, d(40.0), d(20.0), 10.0, &[d(30.0)], &[0.0])
            .expect("sees the floor");
        assert!((c.far - 1.0 / d(20.0).tan()).abs() < 1e-12);
        assert!((c.near - 1.0 / d(40.0).tan()).abs() < 1e-12);
        assert!((c.half_angle - d(20.0)).abs() < 1e-12);
        let down = LookCoverage::from_camera(1.0, d(60.0), d(40.0), 3.0, &[d(80.0)], &[d(170.0)])
            .expect("sees the floor");
        assert_eq!(down.near, 0.0);
        assert!(
            (down.far - 1.0 / d(60.0).tan()).abs() < 1e-12,
            "top ray 60° down"
        );
        let ranged = LookCoverage::from_camera(1.0, d(60.0), d(40.0), 3.0, &[d(10.0)], &[0.0])
            .expect("sees the floor");
        assert!(
            (ranged.far - 8.0_f64.sqrt()).abs() < 1e-12,
            "top ray above the horizon"
        );
        assert_eq!(down.half_angle, std::f64::consts::PI);
    }

    #[test]
    fn cameras_that_cannot_see_the_floor_are_refused() {
        // Invariant: bad parameters, no views, views above the horizon or a range shorter than the
        // eye height give an error, never a panic or a NaN coverage.
        let d = f64::to_radians;
        let ok = |t: &[f64], p: &[f64], r: f64| LookCoverage::from_camera(1.4, 0.7, 0.6, r, t, p);
        assert_eq!(ok(&[], &[0.0], 5.0), Err(CoverageError::NoViews));
        assert_eq!(ok(&[d(30.0)], &[], 5.0), Err(CoverageError::NoViews));
        assert_eq!(ok(&[d(-40.0)], &[0.0], 5.0), Err(CoverageError::NoFloor));
        assert_eq!(ok(&[d(30.0)], &[0.0], 1.0), Err(CoverageError::NoFloor));
        assert_eq!(ok(&[f64::NAN], &[0.0], 5.0), Err(CoverageError::BadCamera));
        assert_eq!(
            LookCoverage::from_camera(-1.0, 0.7, 0.6, 5.0, &[0.5], &[0.0]),
            Err(CoverageError::BadCamera)
        );
    }

    #[test]
    fn covers_is_the_annulus_sector_about_the_heading() {
        // Invariant: a point is covered iff its distance is within near..far and its bearing within
        // the half angle of the heading (wrapping through ±π).
        let c = LookCoverage::default();
        let o = Point2::new(1.0, 2.0);
        let at = |r: f64, a: f64| o + Vector2::new(a.cos(), a.sin()) * r;
        let pi = std::f64::consts::PI;
        assert!(c.covers(o, 0.0, at(2.0, 0.0)));
        assert!(!c.covers(o, 0.0, at(0.5, 0.0)), "under the lowest ray");
        assert!(!c.covers(o, 0.0, at(5.0, 0.0)), "beyond the range");
        assert!(c.covers(o, 0.0, at(2.0, 1.25)));
        assert!(!c.covers(o, 0.0, at(2.0, 1.26)));
        assert!(c.covers(o, pi, at(2.0, -pi + 0.3)), "wraps through ±π");
        assert!(!c.covers(o, 0.0, at(2.0, pi)));
    }
}
