//! Walking over `/cmd_vel`: the shared walk controller runs here on the base pose from `/tf`, and
//! each stretch of time its step is sent as a velocity. A base that moved far less than it was told
//! was stopped by the robot's own safety layer: the walk ends `Blocked` there.

use nalgebra::{Isometry2, Point2, Rotation2, Vector2};
use nudge_executive::robot::controller::{Rates, Walk, WalkLimits, step_walk, wrap};
use nudge_executive::robot::{ActionStatus, Base, RobotError, Stamped, WalkOutcome};

use super::{Ros2Robot, dds};
use crate::msg::{Twist, Vector3};

/// A step counts as blocked when the base made less than this share of it.
const BLOCKED_SHARE: f64 = 0.5;
/// Steps shorter than this (m, rad) are not judged: noise on a real robot's localisation.
const JUDGED: f64 = 1.0e-4;

fn twist(linear: Vector2<f64>, angular: f64) -> Twist {
    Twist {
        linear: Vector3 {
            x: linear.x,
            y: linear.y,
            z: 0.0,
        },
        angular: Vector3 {
            x: 0.0,
            y: 0.0,
            z: angular,
        },
    }
}

/// Whether a base told to go from `from` to `to` and found at `now` was stopped short by the
/// robot's own safety layer: it made less than [`BLOCKED_SHARE`] of a step long enough to judge.
fn stopped_short(from: &Isometry2<f64>, to: &Isometry2<f64>, now: &Isometry2<f64>) -> bool {
    let wanted = (to.translation.vector - from.translation.vector).norm();
    let made = (now.translation.vector - from.translation.vector).norm();
    wanted > JUDGED && made < BLOCKED_SHARE * wanted
}

impl Ros2Robot {
    fn pose2(&self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        let (pose, stamp) = self.inbox.lookup(
            self.config.frames.map.as_str(),
            self.config.frames.base.as_str(),
        )?;
        let t = pose.translation.vector;
        let (_, _, yaw) = pose.rotation.euler_angles();
        Ok(Stamped {
            stamp,
            value: Isometry2::new(Vector2::new(t.x, t.y), yaw),
        })
    }

    /// Sends the walk's next `dt` seconds as a velocity, after judging the last one.
    pub(super) fn command_base(&mut self, dt: f64) -> Result<(), RobotError> {
        if matches!(self.walk, Walk::Idle(_)) {
            return self.send_base(Vector2::zeros(), 0.0);
        }
        let pose = self.pose2()?.value;
        if let Some((from, to)) = self.expected.take()
            && stopped_short(&from, &to, &pose)
        {
            self.walk = Walk::Idle(Some(WalkOutcome::Blocked { at: pose }));
            self.rates = Rates::default();
            return self.send_base(Vector2::zeros(), 0.0);
        }
        let limits = WalkLimits::of(&self.model.body);
        let next = step_walk(
            &mut self.walk,
            &mut self.rates,
            pose,
            &limits,
            dt,
            |_, w| (w, false),
        );
        let yaw = pose.rotation.angle();
        let linear =
            Rotation2::new(-yaw) * (next.translation.vector - pose.translation.vector) / dt;
        let angular = wrap(next.rotation.angle() - yaw) / dt;
        self.expected = Some((pose, next));
        self.send_base(linear, angular)
    }

    fn send_base(&mut self, linear: Vector2<f64>, angular: f64) -> Result<(), RobotError> {
        let moving = linear != Vector2::zeros() || angular != 0.0;
        if moving || self.walking {
            self.io
                .cmd_vel
                .publish(twist(linear, angular))
                .map_err(dds)?;
        }
        self.walking = moving;
        Ok(())
    }
}

impl Base for Ros2Robot {
    fn base_pose(&mut self) -> Result<Stamped<Isometry2<f64>>, RobotError> {
        self.pump()?;
        self.check()?;
        self.pose2()
    }

    fn start_walk(&mut self, waypoints: &[Point2<f64>]) -> Result<(), RobotError> {
        if waypoints
            .iter()
            .any(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(RobotError::Refused {
                capability: "base",
                reason: "waypoints must be finite".into(),
            });
        }
        self.walk = Walk::Path(waypoints.iter().copied().collect());
        self.expected = None;
        Ok(())
    }

    fn start_turn(&mut self, yaw: f64) -> Result<(), RobotError> {
        if !yaw.is_finite() {
            return Err(RobotError::Refused {
                capability: "base",
                reason: "yaw must be finite".into(),
            });
        }
        self.walk = Walk::Turn(wrap(yaw));
        self.expected = None;
        Ok(())
    }

    fn walk_status(&mut self) -> Result<ActionStatus<WalkOutcome>, RobotError> {
        self.check()?;
        Ok(match &self.walk {
            Walk::Idle(outcome) => {
                ActionStatus::Done(outcome.clone().unwrap_or(WalkOutcome::Arrived))
            }
            _ => ActionStatus::Running,
        })
    }

    fn stop_walk(&mut self) -> Result<(), RobotError> {
        if !matches!(self.walk, Walk::Idle(_)) {
            self.rates = Rates::default();
            self.walk = Walk::Idle(Some(WalkOutcome::Stopped));
        }
        self.expected = None;
        self.send_base(Vector2::zeros(), 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f64, y: f64, yaw: f64) -> Isometry2<f64> {
        Isometry2::new(Vector2::new(x, y), yaw)
    }

    #[test]
    fn a_step_the_base_made_less_than_half_of_was_stopped_short() {
        // Invariant: a base that made under half its commanded step was blocked; one that made half or more (or overshot, a robot running on) was not; turns on the spot and steps below the judged length are never judged blocked.
        let from = at(1.0, 1.0, 0.0);
        let to = at(1.0075, 1.0, 0.0); // 7.5 mm: 50 ms at 0.15 m/s
        assert!(stopped_short(&from, &to, &at(1.003, 1.0, 0.0)));
        assert!(stopped_short(&from, &to, &from));
        assert!(!stopped_short(&from, &to, &at(1.004, 1.0, 0.0)));
        assert!(!stopped_short(&from, &to, &at(1.02, 1.0, 0.0)));
        assert!(!stopped_short(&from, &at(1.0, 1.0, 0.3), &from), "a turn");
        assert!(
            !stopped_short(&from, &at(1.00005, 1.0, 0.0), &from),
            "too short to judge"
        );
    }
}
