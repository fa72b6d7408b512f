//! The hand's motion: the commanded wrist position in `base_link` and the profile that moves it —
//! to a guarded line's start, along it, back to rest, or at a commanded velocity.

use nalgebra::{Point3, Vector3};
use nudge_robot_model::ArmModel;

use super::ramp;
use crate::robot::{ActionStatus, GuardedMove, HandOutcome, Stamped, Wrench};

/// What the hand is doing.
#[derive(Clone, Debug, PartialEq)]
enum Motion {
    /// Holding the commanded position.
    Hold,
    /// Going (unguarded, slowly) to the start of a guarded line.
    Approach(GuardedMove),
    /// Moving along a guarded line.
    Guarded(GuardedMove),
    /// Going back to the rest pose.
    Retract,
    /// Moving at a commanded velocity in `base_link` (m/s), a Cartesian servo's command, until the
    /// workspace's edge: the ROS 2 bridge's hand.
    Velocity(Vector3<f64>),
}

/// The hand's command state.
#[derive(Clone, Debug, PartialEq)]
pub struct HandMotion {
    /// Commanded wrist position in `base_link` (m).
    pub command: Point3<f64>,
    /// Reachable hand positions in `base_link` (m): [min, max] per axis.
    workspace: [[f64; 2]; 3],
    /// The hand's rest position beside the body (m, `base_link`).
    rest: Point3<f64>,
    /// Speed of unguarded moves (m/s).
    free_speed: f64,
    /// The hand's own acceleration along a line (m/s²).
    accel: f64,
    /// Fastest guarded move accepted (m/s).
    max_guarded_speed: f64,
    speed: f64,
    motion: Motion,
    outcome: Option<HandOutcome>,
}

impl HandMotion {
    /// `model`'s arm, its hand at rest.
    pub fn new(model: &ArmModel) -> Self {
        let [x, y, z] = model.rest;
        let rest = Point3::new(x, y, z);
        Self {
            command: rest,
            workspace: [model.reach_x, model.reach_y, model.reach_z],
            rest,
            free_speed: model.free_speed,
            accel: model.accel,
            max_guarded_speed: model.max_guarded_speed,
            speed: 0.0,
            motion: Motion::Hold,
            outcome: None,
        }
    }

    /// The hand's rest position (m, `base_link`).
    pub fn rest(&self) -> Point3<f64> {
        self.rest
    }

    /// Whether a point is inside the hand workspace.
    pub fn in_workspace(&self, p: &Point3<f64>) -> bool {
        (0..3).all(|i| {
            let [lo, hi] = self.workspace[i];
            p[i].is_finite() && (lo..=hi).contains(&p[i])
        })
    }

    /// Starts a guarded move, or says why not.
    pub fn start_guarded(&mut self, m: GuardedMove) -> Result<(), String> {
        if !self.in_workspace(&m.from) || !self.in_workspace(&m.to) {
            return Err(format!(
                "line {:?} → {:?} leaves the hand workspace {:?}",
                m.from, m.to, self.workspace
            ));
        }
        if !(m.speed.is_finite() && m.speed > 0.0 && m.speed <= self.max_guarded_speed) {
            return Err(format!(
                "speed {} outside (0, {}] m/s",
                m.speed, self.max_guarded_speed
            ));
        }
        if !(m.force_limit.is_finite() && m.force_limit > 0.0) {
            return Err(format!("force limit {} must be positive", m.force_limit));
        }
        if let Some(a) = m.acceleration
            && !(a.is_finite() && a > 0.0)
        {
            return Err(format!("acceleration {a} must be positive"));
        }
        self.motion = Motion::Approach(m);
        self.outcome = None;
        Ok(())
    }

    /// Starts going back to the rest pose.
    pub fn start_retract(&mut self) {
        self.motion = Motion::Retract;
        self.outcome = None;
    }

    /// Moves the hand at `velocity` (m/s, `base_link`) until another command; zero holds it. No
    /// guard: whoever commands the velocity watches the force.
    pub fn set_velocity(&mut self, velocity: Vector3<f64>) {
        if velocity == Vector3::zeros() {
            if self.motion != Motion::Hold {
                self.motion = Motion::Hold;
                self.speed = 0.0;
                self.outcome = Some(HandOutcome::Stopped);
            }
        } else {
            self.motion = Motion::Velocity(velocity);
            self.outcome = None;
        }
    }

    /// Stops the hand where it is.
    pub fn stop(&mut self) {
        if self.motion != Motion::Hold {
            self.motion = Motion::Hold;
            self.speed = 0.0;
            self.outcome = Some(HandOutcome::Stopped);
        }
    }

    /// Whether the hand is being moved.
    pub fn is_moving(&self) -> bool {
        self.motion != Motion::Hold
    }

    /// The force limit of the guarded move under way. The unguarded move to the line's start is
    /// checked against the same limit too: stopping early is never unsafe, and a kinematic wrist
    /// driven into something would otherwise press without bound.
    pub fn guard(&self) -> Option<f64> {
        match &self.motion {
            Motion::Approach(m) | Motion::Guarded(m) => Some(m.force_limit),
            _ => None,
        }
    }

    /// Whether the hand is on a guarded line (not on its way to one): the force rises fastest then,
    /// so the world steps finely.
    pub fn on_guarded_line(&self) -> bool {
        matches!(self.motion, Motion::Guarded(_) | Motion::Velocity(_))
    }

    /// The guarded line under way, once the hand is on it: its force limit and its speed (m/s).
    pub fn guarded_line(&self) -> Option<(f64, f64)> {
        match &self.motion {
            Motion::Guarded(m) => Some((m.force_limit, m.speed)),
            _ => None,
        }
    }

    /// Ends a guarded move at the force limit: the wrist stays where it is now.
    pub fn force_limit_reached(&mut self, wrench: Stamped<Wrench>, at: Point3<f64>) {
        self.motion = Motion::Hold;
        self.speed = 0.0;
        self.outcome = Some(HandOutcome::ForceLimit { wrench, at });
    }

    /// The motion's state.
    pub fn status(&self) -> ActionStatus<HandOutcome> {
        match (&self.motion, &self.outcome) {
            (Motion::Hold, Some(o)) => ActionStatus::Done(o.clone()),
            (Motion::Hold, None) => ActionStatus::Done(HandOutcome::Reached),
            _ => ActionStatus::Running,
        }
    }

    /// Advances the commanded wrist position by `dt` seconds.
    pub fn step(&mut self, dt: f64) {
        match self.motion.clone() {
            Motion::Hold => {}
            Motion::Approach(m) => {
                if self.move_towards(m.from, self.free_speed, self.accel, dt) {
                    self.motion = Motion::Guarded(m);
                }
            }
            Motion::Guarded(m) => {
                let accel = m.acceleration.map_or(self.accel, |a| a.min(self.accel));
                if self.move_towards(m.to, m.speed, accel, dt) {
                    self.motion = Motion::Hold;
                    self.outcome = Some(HandOutcome::Reached);
                }
            }
            Motion::Retract => {
                if self.move_towards(self.rest, self.free_speed, self.accel, dt) {
                    self.motion = Motion::Hold;
                    self.outcome = Some(HandOutcome::Reached);
                }
            }
            Motion::Velocity(v) => {
                let next = self.command + v * dt;
                if self.in_workspace(&next) {
                    self.command = next;
                } else {
                    self.motion = Motion::Hold;
                    self.outcome = Some(HandOutcome::Stopped);
                }
            }
        }
    }

    /// Moves the command towards `target` at up to `max_speed`, ramping the speed up and down at
    /// `accel`; true when it got there (and stopped).
    fn move_towards(&mut self, target: Point3<f64>, max_speed: f64, accel: f64, dt: f64) -> bool {
        let d: Vector3<f64> = target - self.command;
        let n = d.norm();
        self.speed = ramp(self.speed, max_speed, accel, n, dt);
        let step = self.speed * dt;
        if n <= step {
            self.command = target;
            self.speed = 0.0;
            true
        } else {
            self.command += d * (step / n);
            false
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rest() -> Point3<f64> {
        paper_arm().rest()
    }

    fn paper_arm() -> HandMotion {
        HandMotion::new(&ArmModel::default())
    }

    fn line(acceleration: Option<f64>) -> GuardedMove {
        GuardedMove {
            from: rest(),
            to: rest() + Vector3::new(0.1, 0.0, 0.0),
            speed: 0.02,
            force_limit: 20.0,
            acceleration,
        }
    }

    /// Runs the line for `seconds` in 1 ms steps; the commanded travel along it (m).
    fn travel_after(arm: &mut HandMotion, seconds: f64) -> f64 {
        for _ in 0..(seconds * 1000.0).round() as usize {
            arm.step(0.001);
        }
        arm.command.x - rest().x
    }

    #[test]
    fn a_line_with_an_acceleration_ramps_the_hand_up_no_faster() {
        // Invariant: on a guarded line with an acceleration a, the hand has travelled at most a·t²/2 after t seconds, and reaches the line's speed (v²/2a in), not the arm's own ramp.
        let mut gentle = paper_arm();
        gentle.start_guarded(line(Some(0.01))).expect("accepted");
        let early = travel_after(&mut gentle, 1.0);
        assert!(early <= 0.01 * 1.0 / 2.0 + 1e-4, "{early} m after 1 s");
        assert!(early >= 0.004, "{early} m after 1 s: the ramp stalled");
        let at_speed = travel_after(&mut gentle, 1.0);
        let later = travel_after(&mut gentle, 1.0);
        assert!(
            (later - at_speed - 0.02).abs() < 1e-3,
            "the third second covered {} m, not 2 cm at 2 cm/s",
            later - at_speed
        );
        let mut own = paper_arm();
        own.start_guarded(line(None)).expect("accepted");
        let quick = travel_after(&mut own, 1.0);
        assert!(quick > 0.019, "{quick} m after 1 s at the arm's own ramp");
    }

    #[test]
    fn a_line_with_a_bad_acceleration_is_refused() {
        // Invariant: a zero, negative or non-finite acceleration is refused with a reason, and the arm stays still.
        for a in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let mut arm = paper_arm();
            let refused = arm.start_guarded(line(Some(a)));
            assert!(refused.is_err_and(|r| r.contains("acceleration")), "{a}");
            assert!(!arm.is_moving());
        }
    }
}
