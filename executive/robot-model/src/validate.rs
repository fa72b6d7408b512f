//! The range rules a robot description must keep, each naming the field that breaks it.

use crate::model::RobotModel;

/// A broken rule: the field's path (`arm.reach_x[1]`) and what is wrong with it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct Violation {
    /// Path of the field, e.g. `arm.reach_x[1]`.
    pub field: String,
    /// What is wrong with its value.
    pub message: String,
}

/// The most pixels a camera may have (a 4096 × 4096 image): beyond this a typo, not a camera.
const MAX_PIXELS: usize = 1 << 24;

fn positive(field: &str, v: f64) -> Result<(), Violation> {
    check(
        field,
        v.is_finite() && v > 0.0,
        format!("must be positive, got {v}"),
    )
}

fn check(field: &str, ok: bool, message: String) -> Result<(), Violation> {
    if ok {
        Ok(())
    } else {
        Err(Violation {
            field: field.to_owned(),
            message,
        })
    }
}

/// `[low, high]` with both finite and low below high.
fn interval(field: &str, [lo, hi]: [f64; 2]) -> Result<(), Violation> {
    check(
        &format!("{field}[0]"),
        lo.is_finite(),
        format!("must be finite, got {lo}"),
    )?;
    check(
        &format!("{field}[1]"),
        hi.is_finite() && hi > lo,
        format!("must be finite and above {lo}, got {hi}"),
    )
}

impl RobotModel {
    /// Checks every range rule (a model built in code, say, before a run); the first broken one
    /// names its field. [`RobotModel::from_toml_str`] checks them too and places the fault in the text.
    pub fn validate(&self) -> Result<(), Violation> {
        let b = &self.body;
        positive("body.radius", b.radius)?;
        positive("body.walk_speed", b.walk_speed)?;
        positive("body.turn_rate", b.turn_rate)?;
        positive("body.mass", b.mass)?;
        positive("body.linear_accel", b.linear_accel)?;
        positive("body.angular_accel", b.angular_accel)?;
        check(
            "body.step_over",
            b.step_over.is_finite() && b.step_over >= 0.0,
            format!("must be zero or more, got {}", b.step_over),
        )?;
        check(
            "body.safety_margin",
            b.safety_margin.is_finite() && b.safety_margin >= 0.0,
            format!("must be zero or more, got {}", b.safety_margin),
        )?;
        let h = &self.head;
        positive("head.height", h.height)?;
        // The body's cylinder starts at the step-over height, and the head sits on the body.
        check(
            "body.height",
            b.height.is_finite() && b.height > 2.0 * b.step_over && b.height > h.height / 2.0,
            format!(
                "must be above twice body.step_over and half head.height, got {}",
                b.height
            ),
        )?;
        interval("head.pan_limits", h.pan_limits)?;
        interval("head.tilt_limits", h.tilt_limits)?;
        positive("head.rate", h.rate)?;
        let c = &self.camera;
        check(
            "camera.width",
            c.width >= 1 && c.width.saturating_mul(c.height) <= MAX_PIXELS,
            format!(
                "width × height must hold 1 to {MAX_PIXELS} pixels, got {} × {}",
                c.width, c.height
            ),
        )?;
        check(
            "camera.height",
            c.height >= 1,
            format!("must be at least 1, got {}", c.height),
        )?;
        for (field, fov) in [
            ("camera.h_fov_deg", c.h_fov_deg),
            ("camera.v_fov_deg", c.v_fov_deg),
        ] {
            check(
                field,
                fov.is_finite() && fov > 0.0 && fov < 180.0,
                format!("must lie in (0, 180) degrees, got {fov}"),
            )?;
        }
        check(
            "camera.min_range",
            c.min_range.is_finite() && c.min_range >= 0.0,
            format!("must be zero or more, got {}", c.min_range),
        )?;
        check(
            "camera.max_range",
            c.max_range.is_finite() && c.max_range > c.min_range,
            format!(
                "must be finite and above camera.min_range, got {}",
                c.max_range
            ),
        )?;
        check(
            "camera.colour_noise",
            c.colour_noise.is_finite() && c.colour_noise >= 0.0,
            format!("must be zero or more, got {}", c.colour_noise),
        )?;
        let a = &self.arm;
        interval("arm.reach_x", a.reach_x)?;
        interval("arm.reach_y", a.reach_y)?;
        interval("arm.reach_z", a.reach_z)?;
        for (i, v) in a.rest.iter().enumerate() {
            check(
                &format!("arm.rest[{i}]"),
                v.is_finite(),
                format!("must be finite, got {v}"),
            )?;
        }
        for (i, v) in a.hand_half.iter().enumerate() {
            positive(&format!("arm.hand_half[{i}]"), *v)?;
        }
        positive("arm.hand_mass", a.hand_mass)?;
        positive("arm.free_speed", a.free_speed)?;
        positive("arm.accel", a.accel)?;
        positive("arm.max_guarded_speed", a.max_guarded_speed)?;
        check(
            "wrist.rate_hz",
            self.wrist.rate_hz.is_finite() && (1.0..=1.0e6).contains(&self.wrist.rate_hz),
            format!("must lie in [1, 1e6] Hz, got {}", self.wrist.rate_hz),
        )?;
        positive("wrist.stiffness", self.wrist.stiffness)?;
        positive("wrist.damping", self.wrist.damping)?;
        let f = &self.force;
        positive("force.contact_threshold", f.contact_threshold)?;
        for (field, limit) in [
            ("force.test_limit", f.test_limit),
            ("force.clear_limit", f.clear_limit),
        ] {
            check(
                field,
                limit.is_finite() && limit > f.contact_threshold,
                format!("must be finite and above force.contact_threshold, got {limit}"),
            )?;
        }
        Ok(())
    }
}
