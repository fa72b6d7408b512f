//! What the robot spends and disturbs during a run, read off the physics each step (ground truth,
//! not the sensors): the distance its base walks, the force its hand puts on the things it touches
//! and the work it does on them, and how often it touches a person. These are the inputs of the
//! effort terms of the Interactive Navigation Score (Xia et al. 2020), `crate::metrics`.

use nalgebra::{Point2, Vector2};

/// Effort of a run so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Effort {
    /// Distance the base walked on the floor (m).
    pub walked: f64,
    /// Time integral of the horizontal force the hand put on what it touched (N·s): iGibson's
    /// "force applied by the robot on the environment", summed over time. The wrist's vertical load
    /// (the hand's own weight) is left out: it holds the hand, it pushes nothing.
    pub hand_impulse: f64,
    /// Mechanical work exchanged between the hand and what it touched, Σ |F · Δx| over steps (J):
    /// pushing a sliding chair costs its friction times the distance; pressing a bolted table,
    /// which does not give, costs almost nothing however hard.
    pub hand_work: f64,
    /// Times the robot's body or hand came into contact with a person (each new contact once).
    pub people_contacts: u32,
    /// Times an object the hand was pushing came into contact with a person (each new contact once).
    pub pushed_into_people: u32,
}

/// One step's view of the robot, taken before and after the step.
#[derive(Clone, Copy, Debug)]
pub(super) struct Pose {
    /// The base on the floor.
    pub base: Point2<f64>,
    /// The hand on the floor plan.
    pub hand: Point2<f64>,
}

impl Effort {
    /// Adds one step of `h` seconds: the robot went from `before` to `after`; the hand pressed on
    /// what it touches with `force` (map frame, horizontal part), if it touched anything.
    pub(super) fn add_step(
        &mut self,
        h: f64,
        before: Pose,
        after: Pose,
        touching: Option<Vector2<f64>>,
    ) {
        self.walked += (after.base - before.base).norm();
        if let Some(force) = touching {
            self.hand_impulse += force.norm() * h;
            self.hand_work += force.dot(&(after.hand - before.hand)).abs();
        }
    }

    /// Counts a contact with a person when one begins.
    pub(super) fn person_contact(&mut self, was: bool, is: bool) {
        if is && !was {
            self.people_contacts += 1;
        }
    }

    /// Counts a contact between a pushed object and a person when one begins.
    pub(super) fn pushed_into_person(&mut self, was: bool, is: bool) {
        if is && !was {
            self.pushed_into_people += 1;
        }
    }
}
