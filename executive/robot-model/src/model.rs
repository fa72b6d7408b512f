//! The robot description's types and the paper's robot as their defaults.

use serde::{Deserialize, Serialize};

/// Everything nudge knows about the robot's body, sensors and limits. Defaults: HRP-2 with an SR-4000
/// on its head, as in the paper.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RobotModel {
    /// The walking body.
    pub body: BodyModel,
    /// The pan/tilt head carrying the range camera.
    pub head: HeadModel,
    /// The colour range camera on the head.
    pub camera: CameraModel,
    /// The pushing arm and its hand.
    pub arm: ArmModel,
    /// The 6-axis force/torque sensor at the wrist.
    pub wrist: WristModel,
    /// The forces the hand may use and the one that says it touches.
    pub force: ForceModel,
}

/// The walking body: a vertical cylinder for planning, and its gait.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BodyModel {
    /// Radius of the bounding cylinder (m). HRP-2: 0.35 (its arms' span at the shoulders, 0.7 m).
    pub radius: f64,
    /// Height of the bounding cylinder (m). HRP-2: 1.54.
    pub height: f64,
    /// Walking speed (m/s). 0.15: HRP-2's careful indoor gait.
    pub walk_speed: f64,
    /// Turning rate on the spot (rad/s).
    pub turn_rate: f64,
    /// The whole robot's mass (kg): HRP-2's 58 kg with its batteries (Kaneko et al., "Humanoid robot
    /// HRP-2", ICRA 2004). Effort metrics weigh the robot's own travel with it.
    pub mass: f64,
    /// Height of obstacles the feet step over (m): 3 cm, a mat or a cable.
    pub step_over: f64,
    /// Linear acceleration of the base (m/s²): the walking speed is reached in 0.3 s; the wrist and
    /// hand ride on the base, and a speed step would shake the hand on its compliant wrist.
    pub linear_accel: f64,
    /// Angular acceleration of the base (rad/s²): the turning rate is reached in 0.5 s.
    pub angular_accel: f64,
    /// Distance the base's safety layer keeps from anything in the way (m): a walk stops this short
    /// of it and ends blocked.
    pub safety_margin: f64,
}

impl Default for BodyModel {
    fn default() -> Self {
        Self {
            radius: 0.35,
            height: 1.54,
            walk_speed: 0.15,
            turn_rate: 0.5,
            mass: 58.0,
            step_over: 0.03,
            linear_accel: 0.5,
            angular_accel: 1.0,
            safety_margin: 0.015,
        }
    }
}

/// The pan/tilt head. Angles: pan left positive, tilt down positive.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HeadModel {
    /// Height of the pan/tilt centre above the floor (m), where the camera sits. HRP-2: 1.4.
    pub height: f64,
    /// Pan joint limits (rad, as a URDF writes them), right then left.
    pub pan_limits: [f64; 2],
    /// Tilt joint limits (rad), up then down.
    pub tilt_limits: [f64; 2],
    /// Joint speed per axis (rad/s).
    pub rate: f64,
}

impl Default for HeadModel {
    fn default() -> Self {
        Self {
            height: 1.4,
            pan_limits: [-1.6, 1.6],
            tilt_limits: [-0.5, 1.3],
            rate: 1.0,
        }
    }
}

/// The colour range camera: a pinhole image of ranges and colours, at the head's pan/tilt centre
/// looking along the head's forward axis.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CameraModel {
    /// Pixel columns. SR-4000: 176.
    pub width: usize,
    /// Pixel rows. SR-4000: 144.
    pub height: usize,
    /// Horizontal field of view, edge to edge (deg). SR-4000: 43.6.
    pub h_fov_deg: f64,
    /// Vertical field of view, edge to edge (deg). SR-4000: 34.6.
    pub v_fov_deg: f64,
    /// Returns nearer than this are lost (m).
    pub min_range: f64,
    /// Returns farther than this are lost (m). SR-4000: 5, its non-ambiguity range.
    pub max_range: f64,
    /// Noise σ of each channel of the colour registered to a return (8-bit counts): 3 for the
    /// colour cameras beside the paper's SR-4000. The simulation adds this much; perception tells
    /// touching things apart by colour only beyond what it explains (`nudge_perception::hue`).
    pub colour_noise: f64,
}

impl Default for CameraModel {
    fn default() -> Self {
        Self {
            width: 176,
            height: 144,
            h_fov_deg: 43.6,
            v_fov_deg: 34.6,
            min_range: 0.1,
            max_range: 5.0,
            colour_noise: 3.0,
        }
    }
}

impl CameraModel {
    /// Horizontal field of view, edge to edge (rad).
    pub fn h_fov(&self) -> f64 {
        self.h_fov_deg.to_radians()
    }

    /// Vertical field of view, edge to edge (rad).
    pub fn v_fov(&self) -> f64 {
        self.v_fov_deg.to_radians()
    }

    /// The step of the ranges the camera reports (m): its range limit over 2¹⁴. The SR-4000 reports
    /// distance as a 14-bit count over its 5 m non-ambiguity range (0.31 mm), thirteen times finer
    /// than its 4 mm noise at 1.3 m, so the step costs nothing the noise had not already taken.
    #[inline]
    pub fn range_step(&self) -> f64 {
        self.max_range / f64::from(1u32 << RANGE_BITS)
    }

    /// A range as the camera reports it: `range` on its [`Self::range_step`] grid.
    pub fn reported_range(&self, range: f64) -> f64 {
        self.range_counts().reported(range)
    }

    /// What turns ranges into reported ones, worked out once for a frame's many rays.
    pub fn range_counts(&self) -> RangeCounts {
        let step = self.range_step();
        RangeCounts {
            step,
            per_step: 1.0 / step,
        }
    }

    /// Unit ray directions through the pixel centres in the camera frame (x forward, y left, z up),
    /// row-major like the image, row 0 at the top, column 0 at the left: a pinhole on a tangent-plane
    /// grid. The sensor model casts these rays and a recording's tape rebuilds the points from them,
    /// so both must take them from here, to the bit.
    pub fn pixel_rays(&self) -> Vec<[f32; 3]> {
        let half_w = (self.h_fov() / 2.0).tan();
        let half_h = (self.v_fov() / 2.0).tan();
        let (w, h) = (self.width as f64, self.height as f64);
        let mut rays = Vec::with_capacity(self.width.saturating_mul(self.height));
        for row in 0..self.height {
            let up = half_h * (1.0 - (2.0 * row as f64 + 1.0) / h);
            for col in 0..self.width {
                let left = half_w * (1.0 - (2.0 * col as f64 + 1.0) / w);
                let norm = (1.0 + left * left + up * up).sqrt();
                rays.push([
                    (1.0 / norm) as f32,
                    (left / norm) as f32,
                    (up / norm) as f32,
                ]);
            }
        }
        rays
    }
}

/// Bits of the camera's range count ([`CameraModel::range_step`]): the SR-4000's 14.
const RANGE_BITS: u32 = 14;

/// The camera's range step and its reciprocal ([`CameraModel::range_counts`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RangeCounts {
    step: f64,
    per_step: f64,
}

impl RangeCounts {
    /// `range` as the camera reports it: the nearest whole count of steps (half a step away from
    /// zero), times the step. It runs for every ray of every frame, so it multiplies by the step's
    /// reciprocal and rounds with a truncating cast: a division and `f64::round` (a library call on
    /// the baseline x86-64 target) cost a crowded run 4 % of its time.
    #[inline]
    pub fn reported(&self, range: f64) -> f64 {
        let steps = self.steps(range);
        let count = if steps >= 0.0 {
            (steps + 0.5) as i64
        } else {
            -((0.5 - steps) as i64)
        };
        self.range_of(count)
    }

    /// `range` in steps, not rounded.
    #[inline]
    pub fn steps(&self, range: f64) -> f64 {
        range * self.per_step
    }

    /// The range `count` steps make, to the bit as [`Self::reported`] gives it.
    #[inline]
    pub fn range_of(&self, count: i64) -> f64 {
        count as f64 * self.step
    }
}

/// The pushing arm: where its hand can be, in `base_link` (x forward, y left, z up from the floor).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ArmModel {
    /// Nearest and farthest the hand reaches ahead of the body axis (m).
    pub reach_x: [f64; 2],
    /// Farthest the hand reaches to the right and to the left (m).
    pub reach_y: [f64; 2],
    /// Lowest and highest the hand reaches (m).
    pub reach_z: [f64; 2],
    /// The hand's rest position beside the body, inside the bounding cylinder (m).
    pub rest: [f64; 3],
    /// Half extents of the hand's box (m): thickness along x (the palm faces forward), width, height.
    pub hand_half: [f64; 3],
    /// Mass of the hand (kg).
    pub hand_mass: f64,
    /// Speed of the hand's unguarded moves, to a guarded line's start and back to rest (m/s).
    pub free_speed: f64,
    /// Acceleration of the hand along its line (m/s²): a speed step would shake the hand on its
    /// compliant wrist (0.5 m/s² on the 0.5 kg hand is 0.25 N).
    pub accel: f64,
    /// Fastest guarded move the arm accepts (m/s).
    pub max_guarded_speed: f64,
}

impl Default for ArmModel {
    fn default() -> Self {
        Self {
            reach_x: [0.2, 0.8],
            reach_y: [-0.4, 0.4],
            reach_z: [0.2, 1.2],
            rest: [0.22, -0.18, 0.8],
            hand_half: [0.02, 0.05, 0.05],
            hand_mass: 0.5,
            free_speed: 0.2,
            accel: 0.5,
            max_guarded_speed: 0.5,
        }
    }
}

/// The wrist's 6-axis force/torque sensor.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WristModel {
    /// Sample rate (Hz): the paper's 1 kHz control loop.
    pub rate_hz: f64,
    /// Linear stiffness between the arm and the hand, sensor included (N/m): arm and sensor are not
    /// infinitely stiff. 20 kN/m makes a 0.1 m/s push into something fixed rise by at most 2 N per
    /// 1 ms sample; it bounds how fast the force can rise, which says how often a guard must look.
    pub stiffness: f64,
    /// Damping of that compliance (N·s/m), near critical for the hand's 0.5 kg.
    pub damping: f64,
}

impl Default for WristModel {
    fn default() -> Self {
        Self {
            rate_hz: 1000.0,
            stiffness: 20_000.0,
            damping: 200.0,
        }
    }
}

/// Forces at the hand (N), read as the wrist's force norm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ForceModel {
    /// Above this the hand counts as touching: ten times the simulated wrist's noise (0.2 N per
    /// axis), so noise alone never reads as a touch.
    pub contact_threshold: f64,
    /// Limit of a push test's guarded move: reaching it means static. The paper: 20 N.
    pub test_limit: f64,
    /// Limit of a clearing stroke. The object is known to move, so this only has to catch a jam; it
    /// sits above the test's limit because every stroke starts with an impact, and on a 4 kg chair
    /// sliding at 15.7 N a 2 cm/s impact alone reaches 18–20 N.
    pub clear_limit: f64,
}

impl Default for ForceModel {
    fn default() -> Self {
        Self {
            contact_threshold: 2.0,
            test_limit: 20.0,
            clear_limit: 30.0,
        }
    }
}

#[cfg(test)]
mod camera_tests {
    use super::*;

    #[test]
    fn pixel_rays_are_unit_and_span_the_field_of_view_and_ranges_fall_on_the_step() {
        // Invariant: the SR-4000's rays are unit vectors, the image centre looks along +x, the corner rays lie half a pixel inside the field of view on the tangent plane, and a reported range is on the 5 m / 2^14 grid within half a step of the range.
        let c = CameraModel::default();
        let rays = c.pixel_rays();
        assert_eq!(rays.len(), c.width * c.height);
        for r in &rays {
            let n = r.iter().map(|&v| f64::from(v).powi(2)).sum::<f64>().sqrt();
            assert!((n - 1.0).abs() < 1e-6, "{r:?}");
        }
        let first = rays[0];
        // Pixel centres are evenly spaced on the tangent plane: the first half a pixel in.
        let left = f64::from(first[1]) / f64::from(first[0]);
        let expected = (c.h_fov() / 2.0).tan() * (1.0 - 1.0 / c.width as f64);
        assert!((left - expected).abs() < 1e-6, "{left} vs {expected}");
        assert!(f64::from(first[2]) > 0.0, "row 0 looks up");
        assert_eq!(c.range_step(), 5.0 / 16384.0);
        for range in [0.1, 1.234_567, 4.999] {
            let r = c.reported_range(range);
            assert!((r - range).abs() <= c.range_step() / 2.0, "{r}");
            assert_eq!((r / c.range_step()).fract(), 0.0);
        }
    }
}
