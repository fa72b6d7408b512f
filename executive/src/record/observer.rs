//! What a run reports as it goes. Every method has an empty default, so an observer implements only
//! what it needs; all stamps are robot-clock seconds.

use nalgebra::{Isometry2, Isometry3, Point2, Point3, Vector2};
use nudge_perception::{ColourCloud, ObjectId, Prism};

use crate::machine::Edge;
use crate::push_test::{PushEvidence, PushIntent, Verdict};
use crate::robot::Wrench;
use crate::state::State;

/// Severity of a free-text note.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LogLevel {
    /// Progress worth a line in the timeline.
    Info,
    /// Something odd that did not stop the run.
    Warning,
    /// Something that ended or damaged the run.
    Error,
}

/// The obstacle-type grid as a plain raster, for recorders that should not depend on the grid type.
#[derive(Clone, Copy, Debug)]
pub struct GridView<'a> {
    /// Map-frame position of the corner of cell (0, 0) (m).
    pub origin: Point2<f64>,
    /// Cell side (m).
    pub resolution: f64,
    /// Cells along x.
    pub width: usize,
    /// Cells along y.
    pub height: usize,
    /// One class code per cell, row-major from (0, 0), rows along x.
    pub classes: &'a [u8],
}

/// Where the robot's frames are.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RobotFrames {
    /// `base_link` in `map`.
    pub base: Isometry2<f64>,
    /// Head (pan, tilt), rad.
    pub head: (f64, f64),
    /// `camera` in `map`.
    pub camera: Isometry3<f64>,
    /// Hand position in `base_link` (m).
    pub hand: Point3<f64>,
}

/// Receives what happens during a run.
#[allow(unused_variables)]
pub trait Observer {
    /// The machine took `edge` from `from` to `to`; `from` is `None` for the run's first step
    /// ([`Edge::Start`]), which leaves no state.
    fn transition(&mut self, stamp: f64, from: Option<&State>, edge: Edge, to: &State) {}
    /// A push test ended in a verdict, with its evidence.
    fn verdict(
        &mut self,
        stamp: f64,
        object: ObjectId,
        verdict: &Verdict,
        evidence: &PushEvidence,
    ) {
    }
    /// A colour cloud was captured.
    fn cloud(&mut self, cloud: &ColourCloud) {}
    /// Perception produced these obstacles.
    fn prisms(&mut self, stamp: f64, prisms: &[Prism]) {}
    /// The obstacle-type grid changed.
    fn grid(&mut self, stamp: f64, grid: &GridView<'_>) {}
    /// The planner's search tree, as edges.
    fn tree(&mut self, stamp: f64, edges: &[[Point2<f64>; 2]]) {}
    /// The path the robot is about to walk.
    fn path(&mut self, stamp: f64, waypoints: &[Point2<f64>]) {}
    /// A push is about to run (`force` is `None`) or ran with this peak force vector (map frame, N).
    fn push(&mut self, stamp: f64, intent: &PushIntent, force: Option<Vector2<f64>>) {}
    /// The robot's frames.
    fn frames(&mut self, stamp: f64, frames: &RobotFrames) {}
    /// One wrist force/torque reading (wrist frame).
    fn wrench(&mut self, stamp: f64, wrench: &Wrench) {}
    /// A free-text note for the timeline.
    fn note(&mut self, stamp: f64, level: LogLevel, text: &str) {}
}

/// An observer that ignores everything.
#[derive(Clone, Copy, Debug, Default)]
pub struct NullObserver;

impl Observer for NullObserver {}

/// Two observers side by side: both see everything, the first first.
impl<A: Observer, B: Observer> Observer for (A, B) {
    fn transition(&mut self, stamp: f64, from: Option<&State>, edge: Edge, to: &State) {
        self.0.transition(stamp, from, edge, to);
        self.1.transition(stamp, from, edge, to);
    }
    fn verdict(
        &mut self,
        stamp: f64,
        object: ObjectId,
        verdict: &Verdict,
        evidence: &PushEvidence,
    ) {
        self.0.verdict(stamp, object, verdict, evidence);
        self.1.verdict(stamp, object, verdict, evidence);
    }
    fn cloud(&mut self, cloud: &ColourCloud) {
        self.0.cloud(cloud);
        self.1.cloud(cloud);
    }
    fn prisms(&mut self, stamp: f64, prisms: &[Prism]) {
        self.0.prisms(stamp, prisms);
        self.1.prisms(stamp, prisms);
    }
    fn grid(&mut self, stamp: f64, grid: &GridView<'_>) {
        self.0.grid(stamp, grid);
        self.1.grid(stamp, grid);
    }
    fn tree(&mut self, stamp: f64, edges: &[[Point2<f64>; 2]]) {
        self.0.tree(stamp, edges);
        self.1.tree(stamp, edges);
    }
    fn path(&mut self, stamp: f64, waypoints: &[Point2<f64>]) {
        self.0.path(stamp, waypoints);
        self.1.path(stamp, waypoints);
    }
    fn push(&mut self, stamp: f64, intent: &PushIntent, force: Option<Vector2<f64>>) {
        self.0.push(stamp, intent, force);
        self.1.push(stamp, intent, force);
    }
    fn frames(&mut self, stamp: f64, frames: &RobotFrames) {
        self.0.frames(stamp, frames);
        self.1.frames(stamp, frames);
    }
    fn wrench(&mut self, stamp: f64, wrench: &Wrench) {
        self.0.wrench(stamp, wrench);
        self.1.wrench(stamp, wrench);
    }
    fn note(&mut self, stamp: f64, level: LogLevel, text: &str) {
        self.0.note(stamp, level, text);
        self.1.note(stamp, level, text);
    }
}

/// An observer that may be absent (`--record` not given): forwards to the inner one when present.
impl<O: Observer> Observer for Option<O> {
    fn transition(&mut self, stamp: f64, from: Option<&State>, edge: Edge, to: &State) {
        if let Some(o) = self {
            o.transition(stamp, from, edge, to);
        }
    }
    fn verdict(
        &mut self,
        stamp: f64,
        object: ObjectId,
        verdict: &Verdict,
        evidence: &PushEvidence,
    ) {
        if let Some(o) = self {
            o.verdict(stamp, object, verdict, evidence);
        }
    }
    fn cloud(&mut self, cloud: &ColourCloud) {
        if let Some(o) = self {
            o.cloud(cloud);
        }
    }
    fn prisms(&mut self, stamp: f64, prisms: &[Prism]) {
        if let Some(o) = self {
            o.prisms(stamp, prisms);
        }
    }
    fn grid(&mut self, stamp: f64, grid: &GridView<'_>) {
        if let Some(o) = self {
            o.grid(stamp, grid);
        }
    }
    fn tree(&mut self, stamp: f64, edges: &[[Point2<f64>; 2]]) {
        if let Some(o) = self {
            o.tree(stamp, edges);
        }
    }
    fn path(&mut self, stamp: f64, waypoints: &[Point2<f64>]) {
        if let Some(o) = self {
            o.path(stamp, waypoints);
        }
    }
    fn push(&mut self, stamp: f64, intent: &PushIntent, force: Option<Vector2<f64>>) {
        if let Some(o) = self {
            o.push(stamp, intent, force);
        }
    }
    fn frames(&mut self, stamp: f64, frames: &RobotFrames) {
        if let Some(o) = self {
            o.frames(stamp, frames);
        }
    }
    fn wrench(&mut self, stamp: f64, wrench: &Wrench) {
        if let Some(o) = self {
            o.wrench(stamp, wrench);
        }
    }
    fn note(&mut self, stamp: f64, level: LogLevel, text: &str) {
        if let Some(o) = self {
            o.note(stamp, level, text);
        }
    }
}
