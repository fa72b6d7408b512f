//! The range rules a scenario must satisfy beyond its TOML types.
//!
//! Rules run section by section (room, robot, goal, objects, actors, expect) and the first broken one
//! is reported, so the same file always gives the same message.

use std::collections::HashMap;

use nalgebra::Point2;

use super::error::{FieldPath, ScenarioFault};
use super::geometry::Footprint;
use super::{ActorSpec, Expect, Goal, ObjectSpec, RobotSpec, Room, Scenario};

/// The most objects a scenario may hold.
pub const MAX_OBJECTS: usize = 500;
/// The longest room side (m).
pub const MAX_ROOM_SIDE: f64 = 100.0;
/// Friction coefficients allowed, inclusive.
pub const FRICTION_RANGE: (f64, f64) = (0.0, 2.0);
/// Slack for "on the wall counts as inside" comparisons (m), so a footprint typed flush with a wall
/// is not refused for a rounding error.
const EPSILON: f64 = 1e-9;

/// A broken rule: which field, and what is wrong with it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field}: {fault}")]
pub struct Violation {
    /// The offending field, e.g. `object[2].mass`.
    pub field: FieldPath,
    /// What is wrong.
    pub fault: ScenarioFault,
}

type Checked = Result<(), Violation>;

fn violation(field: FieldPath, fault: ScenarioFault) -> Violation {
    Violation { field, fault }
}

impl Scenario {
    /// Checks every range rule of the format and returns the first broken one.
    ///
    /// Loading runs this already; call it again after changing a scenario in code. Mats do not count as
    /// obstacles for the start and goal rules (the robot walks over them), nor do objects whose underside
    /// is above the robot's height (it walks under them).
    pub fn validate(&self) -> Result<(), Violation> {
        let root = FieldPath::root();
        check_room(&self.room, &root.key("room"))?;
        check_robot(&self.robot, &self.room, &root.key("robot"))?;
        check_goal(&self.goal, &self.room, &root.key("goal"))?;
        check_objects(&self.objects, &self.room, &root.key("object"))?;
        check_clear_start_and_goal(self)?;
        check_actors(&self.actors, &self.objects, &self.room, &root.key("actor"))?;
        if let Some(expect) = &self.expect {
            check_expect(expect, &self.objects, &root.key("expect"))?;
        }
        Ok(())
    }
}

fn finite(field: &FieldPath, value: f64) -> Checked {
    if value.is_finite() {
        Ok(())
    } else {
        Err(violation(field.clone(), ScenarioFault::NotFinite { value }))
    }
}

fn positive(field: &FieldPath, value: f64) -> Checked {
    finite(field, value)?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(violation(
            field.clone(),
            ScenarioFault::NotPositive { value },
        ))
    }
}

fn non_negative(field: &FieldPath, value: f64) -> Checked {
    finite(field, value)?;
    if value >= 0.0 {
        Ok(())
    } else {
        Err(violation(field.clone(), ScenarioFault::Negative { value }))
    }
}

fn all_finite(field: &FieldPath, values: &[f64]) -> Checked {
    values
        .iter()
        .enumerate()
        .try_for_each(|(i, &v)| finite(&field.index(i), v))
}

fn outside(field: &FieldPath, room: &Room, what: String) -> Violation {
    violation(
        field.clone(),
        ScenarioFault::OutsideRoom {
            what,
            width: room.size[0],
            depth: room.size[1],
        },
    )
}

fn check_room(room: &Room, field: &FieldPath) -> Checked {
    let size = field.key("size");
    for (i, &side) in room.size.iter().enumerate() {
        positive(&size.index(i), side)?;
        if side > MAX_ROOM_SIDE {
            return Err(violation(
                size.index(i),
                ScenarioFault::RoomTooLarge {
                    value: side,
                    max: MAX_ROOM_SIDE,
                },
            ));
        }
    }
    positive(&field.key("wall_height"), room.wall_height)
}

fn check_robot(robot: &RobotSpec, room: &Room, field: &FieldPath) -> Checked {
    all_finite(&field.key("start"), &robot.start)?;
    for (key, value) in [
        ("radius", robot.radius),
        ("height", robot.height),
        ("walk_speed", robot.walk_speed),
    ] {
        if let Some(v) = value {
            positive(&field.key(key), v)?;
        }
    }
    // A shorthand and the body field it stands for, both set to different values: one would be
    // ignored without a word.
    let body = &robot.model.body;
    let paper = nudge_robot_model::BodyModel::default();
    for (key, shorthand, in_model, default) in [
        ("radius", robot.radius, body.radius, paper.radius),
        ("height", robot.height, body.height, paper.height),
        (
            "walk_speed",
            robot.walk_speed,
            body.walk_speed,
            paper.walk_speed,
        ),
    ] {
        if shorthand.is_some_and(|v| v != in_model) && in_model != default {
            return Err(violation(
                field.key(key),
                ScenarioFault::RobotModel {
                    message: format!(
                        "set here and as robot.model.body.{key} ({in_model}): keep one"
                    ),
                },
            ));
        }
    }
    // The description's own rules, on the model the shorthands make: a fault in a shorthand was
    // caught above, so what breaks here lies in `[robot.model]`.
    robot.model().validate().map_err(|v| {
        let at = v.field.split('.').fold(field.key("model"), |path, part| {
            match part.split_once('[') {
                Some((key, index)) => {
                    let path = path.key(key);
                    match index.trim_end_matches(']').parse() {
                        Ok(i) => path.index(i),
                        Err(_) => path,
                    }
                }
                None => path.key(part),
            }
        });
        violation(at, ScenarioFault::RobotModel { message: v.message })
    })?;
    if room.clearance(&robot.start_footprint()) < -EPSILON {
        return Err(outside(
            &field.key("start"),
            room,
            "the robot's disc at the start".into(),
        ));
    }
    Ok(())
}

fn check_goal(goal: &Goal, room: &Room, field: &FieldPath) -> Checked {
    all_finite(&field.key("position"), &goal.position)?;
    positive(&field.key("tolerance"), goal.tolerance)?;
    let centre = goal.centre();
    if !room.contains_point(&centre) {
        return Err(outside(
            &field.key("position"),
            room,
            format!("the goal ({}, {})", centre.x, centre.y),
        ));
    }
    Ok(())
}

fn check_objects(objects: &[ObjectSpec], room: &Room, field: &FieldPath) -> Checked {
    if objects.len() > MAX_OBJECTS {
        return Err(violation(
            field.index(MAX_OBJECTS),
            ScenarioFault::TooManyObjects {
                count: objects.len(),
                max: MAX_OBJECTS,
            },
        ));
    }
    let mut names = HashMap::new();
    for (i, object) in objects.iter().enumerate() {
        let here = field.index(i);
        unique_name(&mut names, &object.name, &here)?;
        check_object(object, room, &here)?;
    }
    Ok(())
}

fn unique_name<'a>(
    names: &mut HashMap<&'a str, FieldPath>,
    name: &'a str,
    here: &FieldPath,
) -> Checked {
    match names.get(name) {
        Some(first) => Err(violation(
            here.key("name"),
            ScenarioFault::DuplicateName {
                name: name.to_owned(),
                first: first.to_string(),
            },
        )),
        None => {
            names.insert(name, here.clone());
            Ok(())
        }
    }
}

fn check_object(object: &ObjectSpec, room: &Room, field: &FieldPath) -> Checked {
    all_finite(&field.key("position"), &object.position)?;
    finite(&field.key("yaw"), object.yaw)?;
    let (expected, meaning) = object.kind.size_entries();
    if object.size.len() != expected {
        return Err(violation(
            field.key("size"),
            ScenarioFault::SizeEntries {
                kind: object.kind,
                expected,
                meaning,
                got: object.size.len(),
            },
        ));
    }
    let size = field.key("size");
    for (i, &entry) in object.size.iter().enumerate() {
        positive(&size.index(i), entry)?;
    }
    non_negative(&field.key("elevation"), object.elevation)?;
    positive(&field.key("mass"), object.mass)?;
    finite(&field.key("friction"), object.friction)?;
    let (min, max) = FRICTION_RANGE;
    if !(min..=max).contains(&object.friction) {
        return Err(violation(
            field.key("friction"),
            ScenarioFault::OutOfRange {
                value: object.friction,
                min,
                max,
            },
        ));
    }
    check_footprint_in_room(object, room, field)
}

fn check_footprint_in_room(object: &ObjectSpec, room: &Room, field: &FieldPath) -> Checked {
    let Some(footprint) = object.footprint() else {
        return Ok(()); // unreachable after the size rule; nothing to place
    };
    if room.clearance(&footprint) >= -EPSILON {
        return Ok(());
    }
    let what = match footprint {
        Footprint::Disc { .. } => "the footprint disc".to_owned(),
        Footprint::Rectangle { .. } => {
            let corner = footprint
                .polygon()
                .into_iter()
                .find(|p| !room_contains_with_slack(room, p))
                .unwrap_or(footprint.centre());
            format!("footprint corner ({:.3}, {:.3})", corner.x, corner.y)
        }
    };
    Err(outside(&field.key("position"), room, what))
}

fn room_contains_with_slack(room: &Room, p: &Point2<f64>) -> bool {
    p.x >= -EPSILON
        && p.y >= -EPSILON
        && p.x <= room.size[0] + EPSILON
        && p.y <= room.size[1] + EPSILON
}

/// Objects the robot can neither walk over (mats) nor under (overhead pipes, shelves).
fn robot_obstacles(scenario: &Scenario) -> impl Iterator<Item = (&ObjectSpec, Footprint)> {
    scenario
        .objects
        .iter()
        .filter(|o| o.blocks_height(scenario.robot.height()))
        .filter_map(|o| Some((o, o.footprint()?)))
}

fn check_clear_start_and_goal(scenario: &Scenario) -> Checked {
    let start = scenario.robot.start_footprint();
    if let Some((object, _)) = robot_obstacles(scenario).find(|(_, f)| f.distance_to(&start) <= 0.0)
    {
        return Err(violation(
            FieldPath::root().key("robot").key("start"),
            ScenarioFault::StartInsideObject {
                object: object.name.clone(),
            },
        ));
    }
    let goal = scenario.goal.centre();
    if let Some((object, _)) = robot_obstacles(scenario).find(|(_, f)| f.contains(&goal)) {
        return Err(violation(
            FieldPath::root().key("goal").key("position"),
            ScenarioFault::GoalInsideObject {
                object: object.name.clone(),
            },
        ));
    }
    Ok(())
}

fn check_actors(
    actors: &[ActorSpec],
    objects: &[ObjectSpec],
    room: &Room,
    field: &FieldPath,
) -> Checked {
    let mut names = HashMap::new();
    let mut carried: HashMap<&str, &str> = HashMap::new();
    for (i, actor) in actors.iter().enumerate() {
        let here = field.index(i);
        unique_name(&mut names, &actor.name, &here)?;
        check_actor_body(actor, room, &here)?;
        check_carrying(actor, objects, &mut carried, &here)?;
    }
    Ok(())
}

fn check_actor_body(actor: &ActorSpec, room: &Room, field: &FieldPath) -> Checked {
    positive(&field.key("radius"), actor.radius)?;
    positive(&field.key("height"), actor.height)?;
    positive(&field.key("speed"), actor.speed)?;
    non_negative(&field.key("start_time"), actor.start_time)?;
    let waypoints = field.key("waypoints");
    if actor.waypoints.is_empty() {
        return Err(violation(waypoints, ScenarioFault::NoWaypoints));
    }
    for (i, w) in actor.waypoints.iter().enumerate() {
        all_finite(&waypoints.index(i), w)?;
        let disc = Footprint::Disc {
            centre: Point2::new(w[0], w[1]),
            radius: actor.radius,
        };
        if room.clearance(&disc) < -EPSILON {
            return Err(outside(
                &waypoints.index(i),
                room,
                format!("the actor's disc at waypoint ({}, {})", w[0], w[1]),
            ));
        }
    }
    let pause = field.key("pause");
    if !actor.pause.is_empty() && actor.pause.len() != actor.waypoints.len() {
        return Err(violation(
            pause,
            ScenarioFault::PauseLength {
                got: actor.pause.len(),
                waypoints: actor.waypoints.len(),
            },
        ));
    }
    for (i, &seconds) in actor.pause.iter().enumerate() {
        non_negative(&pause.index(i), seconds)?;
    }
    Ok(())
}

fn check_carrying<'a>(
    actor: &'a ActorSpec,
    objects: &[ObjectSpec],
    carried: &mut HashMap<&'a str, &'a str>,
    field: &FieldPath,
) -> Checked {
    let Some(name) = actor.carries.as_deref() else {
        return match (actor.drop_at, actor.pick_at) {
            (None, None) => Ok(()),
            (Some(_), _) => Err(violation(
                field.key("drop_at"),
                ScenarioFault::NothingCarried,
            )),
            (None, Some(_)) => Err(violation(
                field.key("pick_at"),
                ScenarioFault::NothingCarried,
            )),
        };
    };
    let carries = field.key("carries");
    let Some(object) = objects.iter().find(|o| o.name == name) else {
        return Err(violation(
            carries,
            ScenarioFault::UnknownObject { name: name.into() },
        ));
    };
    if object.fixed {
        return Err(violation(
            carries,
            ScenarioFault::CarriedFixed { name: name.into() },
        ));
    }
    if let Some(by) = carried.insert(name, &actor.name) {
        return Err(violation(
            carries,
            ScenarioFault::AlreadyCarried {
                name: name.into(),
                by: by.into(),
            },
        ));
    }
    let count = actor.waypoints.len();
    for (key, index) in [("drop_at", actor.drop_at), ("pick_at", actor.pick_at)] {
        if let Some(index) = index.filter(|&i| i >= count) {
            return Err(violation(
                field.key(key),
                ScenarioFault::IndexPastWaypoints { index, count },
            ));
        }
    }
    match (actor.drop_at, actor.pick_at) {
        (None, Some(_)) => Err(violation(
            field.key("pick_at"),
            ScenarioFault::PickWithoutDrop,
        )),
        (Some(drop_at), Some(pick_at))
            if pick_at == drop_at || (pick_at < drop_at && !actor.repeat) =>
        {
            Err(violation(
                field.key("pick_at"),
                ScenarioFault::PickBeforeDrop { drop_at, pick_at },
            ))
        }
        _ => Ok(()),
    }
}

fn check_expect(expect: &Expect, objects: &[ObjectSpec], field: &FieldPath) -> Checked {
    for (key, names) in [("movable", &expect.movable), ("static", &expect.static_)] {
        for (i, name) in names.iter().enumerate() {
            if !objects.iter().any(|o| &o.name == name) {
                return Err(violation(
                    field.key(key).index(i),
                    ScenarioFault::UnknownObject { name: name.clone() },
                ));
            }
        }
    }
    if let Some((i, name)) = expect
        .static_
        .iter()
        .enumerate()
        .find(|(_, name)| expect.movable.contains(name))
    {
        return Err(violation(
            field.key("static").index(i),
            ScenarioFault::ContradictoryExpect { name: name.clone() },
        ));
    }
    Ok(())
}
