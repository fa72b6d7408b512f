//! Whether the robot can make the pushes a generated room needs, checked on the true world.
//!
//! A family that stands things against walls and each other promises more than "a way exists once
//! the movable things are gone": that the robot can *make* that way. Each push it names
//! ([`NeededPush`]) is checked against the objects' true footprints, with the robot's own body, arm
//! and push planning parameters:
//!
//! - **a stand pose**: the robot's cylinder, facing the push, clear of every true footprint and of
//!   the room's walls, with the hand's contact point (where the line through the object's centre
//!   leaves its back) ahead of the body axis by the planner's stand-off and within the arm's reach
//!   ahead and to the side; reachable from the start in the true world as it stands then (every
//!   object bolted where it is, earlier pushes made), to within the reachability search's cell;
//! - **a sweep that fits** (clearing pushes): the object's footprint translated along the push from
//!   where it stands to where it ends never goes into another object or a wall. Touching is allowed:
//!   a crate flush against a wall slides along it;
//! - **the way it opens**: each clearing push's distance is the shortest, in the planner's
//!   short-push steps up to the longest push it plans, after which a way joins start and goal with
//!   that object moved and the other objects to be cleared taken away; with every clearing push made, every object bolted where it
//!   ends, a way must exist (where it does not, every clearing push goes one step farther while
//!   its sweep fits).
//!
//! A push test needs only its stand pose: the object it tests stays where it is.

use nalgebra::{Point2, Vector2};
use nudge_motion::Obstacle;
use nudge_perception::ObjectId;

use crate::metrics::ideal_path::{CELL, Reachable, ideal_path_length};
use crate::scenario::{ObjectKind, ObjectSpec, Scenario};
use crate::world::{World, WorldError};

/// What a room needs done to one of its objects.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PushKind {
    /// Pushed out of the way: it must move far enough along the push for the way to open.
    Clear,
    /// Push-tested where it stands (a static object whose verdict the room expects).
    Test,
}

/// A push a generated room needs: its object, which way, and what for.
#[derive(Clone, Debug, PartialEq)]
pub struct NeededPush {
    /// The object's name.
    pub object: String,
    /// Unit direction of the push in the map frame.
    pub direction: [f64; 2],
    /// Clearing or testing.
    pub kind: PushKind,
}

/// A needed push as the check found it can be made.
#[derive(Clone, Debug, PartialEq)]
pub struct PushMade {
    /// The push.
    pub push: NeededPush,
    /// Where the robot's centre stands for it (map frame, m).
    pub stand: [f64; 2],
    /// How far the object moves (m): the shortest that opens the way (0 for a test).
    pub distance: f64,
}

/// Touching allowed between a sweep and what it passes (m): numerical slack only.
const TOUCH: f64 = 1.0e-3;

/// Checks every push of `needs` on `scenario`'s true world, in order. `Ok(None)` when one cannot be
/// made (no stand pose, a sweep that runs into something, or a way that does not open).
pub fn check_pushes(
    scenario: &Scenario,
    needs: &[NeededPush],
) -> Result<Option<Vec<PushMade>>, WorldError> {
    if needs.is_empty() {
        return Ok(Some(Vec::new()));
    }
    let model = scenario.robot.model();
    let planning = nudge_motion::PushConfig::for_robot(&model);
    let radius = model.body.radius;
    let mut bolted = scenario.clone();
    for o in &mut bolted.objects {
        o.fixed = true;
    }
    let clears: Vec<&NeededPush> = needs.iter().filter(|n| n.kind == PushKind::Clear).collect();
    // The planner's short-push step, up to the longest push it plans (as far as the camera sees).
    let step = nudge_motion::push::SHORT_PUSH_STEP;
    let longest = planning.distances.last().copied().unwrap_or(0.0);
    // Each clearing push on its own: its shortest distance that opens the way, the others taken
    // away.
    let mut distances = Vec::with_capacity(clears.len());
    for push in &clears {
        let others: Vec<&str> = clears
            .iter()
            .filter(|p| p.object != push.object)
            .map(|p| p.object.as_str())
            .collect();
        let mut found = None;
        let mut d = step;
        while d <= longest + 1e-9 {
            if !sweep_fits(&bolted, push, d)? {
                break;
            }
            let mut after = moved(&bolted, &push.object, push.direction, d);
            after.objects.retain(|o| !others.contains(&o.name.as_str()));
            if way(&after)? {
                found = Some(d);
                break;
            }
            d += step;
        }
        let Some(d) = found else {
            return Ok(None);
        };
        distances.push(d);
    }
    // All of them made, the way must stay open with every object where it ends. Two boxes pushed
    // out of a doorway side by side can shut its far side together: they go on, a step at a time
    // each, while their sweeps fit.
    if clears.len() > 1 {
        let mut open = false;
        while !open {
            let mut end = bolted.clone();
            for (push, d) in clears.iter().zip(&distances) {
                end = moved(&end, &push.object, push.direction, *d);
            }
            open = way(&end)?;
            if !open {
                for (push, d) in clears.iter().zip(distances.iter_mut()) {
                    *d += step;
                    if *d > longest + 1e-9 || !sweep_fits(&bolted, push, *d)? {
                        return Ok(None);
                    }
                }
            }
        }
    }
    // Stand poses, each in the room as the earlier pushes left it.
    let mut state = bolted;
    let mut made = Vec::with_capacity(needs.len());
    let mut clear_index = 0;
    for push in needs {
        let Some(stand) = stand_pose(&state, push, &planning, radius)? else {
            return Ok(None);
        };
        let distance = match push.kind {
            PushKind::Clear => {
                let d = distances[clear_index];
                clear_index += 1;
                state = moved(&state, &push.object, push.direction, d);
                d
            }
            PushKind::Test => 0.0,
        };
        made.push(PushMade {
            push: push.clone(),
            stand: [stand.x, stand.y],
            distance,
        });
    }
    Ok(Some(made))
}

/// Whether a way joins the start to the goal disc in `scenario`'s true world, movable objects
/// counted as free floor (the caller bolts what must stay).
fn way(scenario: &Scenario) -> Result<bool, WorldError> {
    let world = World::new(scenario, scenario.seed)?;
    let [x, y, _] = scenario.robot.start;
    let goal = Point2::new(scenario.goal.position[0], scenario.goal.position[1]);
    Ok(ideal_path_length(
        &world,
        Point2::new(x, y),
        goal,
        scenario.goal.tolerance,
        scenario.robot.radius(),
    )
    .is_some())
}

/// `scenario` with object `name` moved `distance` along `direction`.
fn moved(scenario: &Scenario, name: &str, direction: [f64; 2], distance: f64) -> Scenario {
    let mut s = scenario.clone();
    for o in s.objects.iter_mut().filter(|o| o.name == name) {
        o.position[0] += direction[0] * distance;
        o.position[1] += direction[1] * distance;
    }
    s
}

/// Whether `push`'s object, translated `distance` along it, sweeps clear of every other object and
/// of the room's walls (touching allowed).
fn sweep_fits(scenario: &Scenario, push: &NeededPush, distance: f64) -> Result<bool, WorldError> {
    let Some(object) = footprint_of(scenario, &push.object) else {
        return Ok(false);
    };
    let offset = Vector2::new(push.direction[0], push.direction[1]) * distance;
    let Ok(swept) = object.swept(&offset) else {
        return Ok(false);
    };
    let fits = obstacles_but(scenario, &push.object)
        .iter()
        .all(|o| swept.signed_distance_to_obstacle(o) >= -TOUCH);
    Ok(fits)
}

/// A stand pose for `push` in `scenario` as it stands, or `None`.
fn stand_pose(
    scenario: &Scenario,
    push: &NeededPush,
    planning: &nudge_motion::PushConfig,
    radius: f64,
) -> Result<Option<Point2<f64>>, WorldError> {
    let Some(object) = footprint_of(scenario, &push.object) else {
        return Ok(None);
    };
    let d = Vector2::new(push.direction[0], push.direction[1]);
    let across = Vector2::new(-d.y, d.x);
    let contact = back_of(&object, &d);
    let mut everything = obstacles_but(scenario, &push.object);
    everything.push(object);
    let world = World::new(scenario, scenario.seed)?;
    let [x, y, _] = scenario.robot.start;
    let Some(reachable) = Reachable::from(&world, Point2::new(x, y), radius) else {
        return Ok(None);
    };
    // Ahead: from the planner's stand-off (the body clear of the face by its margin) to the arm's
    // farthest reach; to the side: the planner's lateral offsets, which the arm's side reach bounds.
    let nearest = (radius + planning.standoff_margin).max(planning.reach_x.0);
    let mut ahead = nearest;
    while ahead <= planning.reach_x.1 + 1e-9 {
        for &side in &planning.lateral_offsets {
            let stand = contact - d * ahead + across * side;
            let clear = everything.iter().all(|o| !o.disc_hits(&stand, radius));
            // Within one search cell's diagonal: the search's centres stand on a 5 cm lattice.
            if clear && reachable.near(stand, CELL * std::f64::consts::SQRT_2) {
                return Ok(Some(stand));
            }
        }
        ahead += planning.standoff_step;
    }
    Ok(None)
}

/// Where the line through `object`'s centre along `-d` leaves its footprint: the hand's contact for
/// a push along `d` through the centre.
fn back_of(object: &Obstacle, d: &Vector2<f64>) -> Point2<f64> {
    let aabb = object.aabb();
    let centre = nalgebra::center(&aabb.min, &aabb.max);
    let (mut inside, mut outside) = (0.0, (aabb.max - aabb.min).norm());
    for _ in 0..40 {
        let t = 0.5 * (inside + outside);
        if object.contains(&(centre - d * t)) {
            inside = t;
        } else {
            outside = t;
        }
    }
    centre - d * outside
}

/// The true footprint of every object but `name`, and the room's four walls.
fn obstacles_but(scenario: &Scenario, name: &str) -> Vec<Obstacle> {
    let mut out: Vec<Obstacle> = scenario
        .objects
        .iter()
        .filter(|o| o.name != name)
        .filter_map(footprint)
        .collect();
    let [w, h] = scenario.room.size;
    let t = 1.0;
    for (lo, hi) in [
        ([-t, -t], [w + t, 0.0]),
        ([-t, h], [w + t, h + t]),
        ([-t, -t], [0.0, h + t]),
        ([w, -t], [w + t, h + t]),
    ] {
        let corners = [
            Point2::new(lo[0], lo[1]),
            Point2::new(hi[0], lo[1]),
            Point2::new(hi[0], hi[1]),
            Point2::new(lo[0], hi[1]),
        ];
        if let Ok(o) = Obstacle::new(ObjectId(u32::MAX), &corners, 0.0, 2.0) {
            out.push(o);
        }
    }
    out
}

/// The true footprint of object `name`.
fn footprint_of(scenario: &Scenario, name: &str) -> Option<Obstacle> {
    scenario
        .objects
        .iter()
        .find(|o| o.name == name)
        .and_then(footprint)
}

/// An object's true footprint: its box, turned by its yaw (a chair's or a table's the box around
/// its legs), or a 24-gon for a cylinder. Mats are stepped over and have none.
fn footprint(spec: &ObjectSpec) -> Option<Obstacle> {
    let c = Point2::new(spec.position[0], spec.position[1]);
    let corners: Vec<Point2<f64>> = match spec.kind {
        ObjectKind::Mat => return None,
        ObjectKind::Cylinder => {
            let r = spec.size.first().copied()? / 2.0;
            (0..24)
                .map(|k| {
                    let a = f64::from(k) * std::f64::consts::TAU / 24.0;
                    c + Vector2::new(a.cos(), a.sin()) * r
                })
                .collect()
        }
        _ => {
            let (hx, hy) = (spec.size.first()? / 2.0, spec.size.get(1)? / 2.0);
            let rot = nalgebra::Rotation2::new(spec.yaw.to_radians());
            [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)]
                .into_iter()
                .map(|(x, y)| c + rot * Vector2::new(x, y))
                .collect()
        }
    };
    Obstacle::new(ObjectId(0), &corners, 0.0, 1.0).ok()
}
