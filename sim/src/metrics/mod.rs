//! The standard metrics of a run, scored against the simulation's ground truth, so nudge's runs
//! compare with the interactive-navigation literature:
//!
//! - **success** (the goal reached) and **SPL**, success weighted by path length (Anderson et al.
//!   2018): `S · L* / max(L*, L)`, with `L*` the ideal path in the true world with every movable
//!   object taken away ([`ideal_path`]) and `L` the distance the base walked. This is also iGibson's
//!   path efficiency `P_eff`.
//! - **effort**: the mass displaced (Σ mᵢ·dᵢ over the objects, each by how far it ended from where
//!   it stood), the work and impulse of the hand on what it touched
//!   ([`crate::world::effort::Effort`]).
//! - iGibson's **effort efficiency** `E_eff` (Xia et al. 2020), the mean of its kinematic term
//!   `m₀L₀ / (m₀L₀ + Σ mᵢdᵢ)` and its dynamic term `G·T / (G·T + ∫‖F‖dt)`, `G = m₀ g` the robot's
//!   weight, `T` the run's time, both times success; and the **Interactive Navigation Score**
//!   `INS = α·P_eff + (1 − α)·E_eff` with iGibson's α = 0.5.
//! - the verdicts' mistakes against the truth: **false static** (a movable object called static)
//!   and **false movable** (a static one called movable); **contacts with people**; and **ghosts**,
//!   obstacles kept at the end where the truth has nothing ([`ghosts`]).
//!
//! Where no path exists even without the movable objects, `L*`, SPL and INS are `None`: the right
//! answer there is `no_path`, and a path efficiency has nothing to measure.

pub mod ghosts;
pub mod ideal_path;
pub mod segmentation;

use nalgebra::{Isometry3, Point2};
use nudge_executive::{RunReport, State, Verdict};

use crate::scenario::{GRAVITY, Scenario};
use crate::score::Scored;
use crate::truth::{Movability, Truth};
use crate::world::World;

/// iGibson's weight of path efficiency against effort efficiency in INS.
pub const INS_ALPHA: f64 = 0.5;

/// What is known before the run starts: the ideal path and where every object stands.
#[derive(Clone, Debug, PartialEq)]
pub struct Start {
    /// The ideal path's length (m), `None` if the goal is shut off by static things.
    pub ideal_path: Option<f64>,
    /// Each object's true pose at the start (`None` for one with no body).
    poses: Vec<Option<Isometry3<f64>>>,
}

impl Start {
    /// Reads the start of `scenario`'s run from its freshly built `world`.
    pub fn of(scenario: &Scenario, world: &World) -> Self {
        let truth = Truth::new(world);
        let [x, y, _] = scenario.robot.start;
        let goal = Point2::new(scenario.goal.position[0], scenario.goal.position[1]);
        Self {
            ideal_path: ideal_path::ideal_path_length(
                world,
                Point2::new(x, y),
                goal,
                scenario.goal.tolerance,
                scenario.robot.radius(),
            ),
            poses: (0..world.objects().len())
                .map(|i| truth.object_pose(i))
                .collect(),
        }
    }
}

/// The standard metrics of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunMetrics {
    /// The robot reached the goal.
    pub success: bool,
    /// Distance the base walked (m).
    pub walked: f64,
    /// The ideal path's length (m), `None` if no way exists without moving static things.
    pub ideal_path: Option<f64>,
    /// Success weighted by path length, iGibson's `P_eff`.
    pub spl: Option<f64>,
    /// Σ mᵢ·dᵢ over the objects the robot moved (kg·m); objects people carry are left out.
    pub displaced: f64,
    /// Work the hand exchanged with what it touched (J).
    pub hand_work: f64,
    /// Impulse of the hand's horizontal force on what it touched (N·s).
    pub hand_impulse: f64,
    /// iGibson's effort efficiency `E_eff` (0 when the goal was not reached).
    pub effort_efficiency: f64,
    /// Interactive Navigation Score, `None` where there is no ideal path.
    pub ins: Option<f64>,
    /// Movable objects the push test called static.
    pub false_static: u32,
    /// Static objects the push test called movable.
    pub false_movable: u32,
    /// New contacts of the robot with people, `None` in a scenario without people.
    pub people_contacts: Option<u32>,
    /// New contacts of an object the hand pushed with people, `None` in a scenario without people.
    pub pushed_into_people: Option<u32>,
    /// Obstacles the executive kept at the end where the truth has nothing ([`ghosts::count`]).
    pub ghosts: u32,
}

/// Measures a finished run: `start` read before it, `report` and `scored` its outcome and verdicts,
/// `world` the world at its end.
pub fn measure(start: &Start, report: &RunReport, world: &World, scored: &[Scored]) -> RunMetrics {
    let success = matches!(report.outcome, State::Goal);
    let effort = world.effort();
    let truth = Truth::new(world);
    let displaced: f64 = world
        .objects()
        .iter()
        .enumerate()
        .filter(|(i, _)| !truth.carried_by_an_actor(*i))
        .filter_map(|(i, (spec, _))| {
            let from = start.poses.get(i).copied().flatten()?;
            let to = truth.object_pose(i)?;
            let d = (to.translation.vector - from.translation.vector)
                .xy()
                .norm();
            Some(spec.mass * d)
        })
        .sum();
    let spl = start
        .ideal_path
        .map(|ideal| path_efficiency(success, ideal, effort.walked));
    let robot_mass = world.humanoid().mass();
    let robot_travel = robot_mass * effort.walked;
    let kinematic = ratio(robot_travel, robot_travel + displaced);
    let weight_time = robot_mass * GRAVITY * report.robot_time;
    let dynamic = ratio(weight_time, weight_time + effort.hand_impulse);
    let effort_efficiency = if success {
        0.5 * (kinematic + dynamic)
    } else {
        0.0
    };
    let (false_static, false_movable) = mistakes(world, scored);
    RunMetrics {
        success,
        walked: effort.walked,
        ideal_path: start.ideal_path,
        spl,
        displaced,
        hand_work: effort.hand_work,
        hand_impulse: effort.hand_impulse,
        effort_efficiency,
        ins: spl.map(|p| INS_ALPHA * p + (1.0 - INS_ALPHA) * effort_efficiency),
        false_static,
        false_movable,
        people_contacts: (!world.actors().is_empty()).then_some(effort.people_contacts),
        pushed_into_people: (!world.actors().is_empty()).then_some(effort.pushed_into_people),
        ghosts: ghosts::count(&report.obstacles, &truth),
    }
}

/// SPL's term for one run: `S · L* / max(L*, L)`.
pub fn path_efficiency(success: bool, ideal: f64, walked: f64) -> f64 {
    if !success {
        return 0.0;
    }
    let longest = ideal.max(walked);
    if longest > 0.0 { ideal / longest } else { 1.0 }
}

/// `a / b`, and 1 when both are zero (nothing spent on either side: no inefficiency).
fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 { a / b } else { 1.0 }
}

/// Verdicts that contradict the object's true movability: (called static but movable, called
/// movable but static). A verdict that matched no object is neither.
fn mistakes(world: &World, scored: &[Scored]) -> (u32, u32) {
    let truth = Truth::new(world);
    let movability = |name: &str| {
        let i = world.objects().iter().position(|(s, _)| s.name == name)?;
        truth.movability(i)
    };
    let mut false_static = 0;
    let mut false_movable = 0;
    for s in scored {
        let Some(truly) = s.object.as_deref().and_then(movability) else {
            continue;
        };
        match (&s.verdict, truly) {
            (Verdict::Static { .. }, Movability::Movable) => false_static += 1,
            (Verdict::Movable, Movability::Static) => false_movable += 1,
            _ => {}
        }
    }
    (false_static, false_movable)
}
