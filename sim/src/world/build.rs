//! Building the rapier scene from a scenario: floor, walls, objects (furniture as compound bodies).

use std::collections::HashMap;

use rapier3d::prelude::*;

use super::WorldError;
use crate::scenario::{ObjectKind, ObjectSpec, Room, Texture};
use crate::surface::{Owner, Surface};

/// Collision groups: who touches whom.
pub mod groups {
    use rapier3d::prelude::Group;

    /// The floor slab.
    pub const FLOOR: Group = Group::GROUP_1;
    /// The room's walls.
    pub const WALL: Group = Group::GROUP_2;
    /// Scenario objects.
    pub const OBJECT: Group = Group::GROUP_3;
    /// Actors (people, other robots).
    pub const ACTOR: Group = Group::GROUP_4;
    /// The robot's bounding cylinder.
    pub const ROBOT_BODY: Group = Group::GROUP_5;
    /// The robot's hand.
    pub const HAND: Group = Group::GROUP_6;
}

/// Friction of the floor. Together with [`FLOOR_FRICTION_RULE`] the effective friction between an
/// object (default `Average` rule) and the floor is `object.friction × 1.0`, exactly the scenario's value.
pub const FLOOR_FRICTION: f32 = 1.0;
/// `Multiply` outranks the objects' default `Average` rule, so it decides object–floor pairs.
pub const FLOOR_FRICTION_RULE: CoefficientCombineRule = CoefficientCombineRule::Multiply;
/// Thickness of the floor slab and the walls (m).
const SLAB: f32 = 0.1;
/// Seat top of a chair as a fraction of its height (0.45 m of 0.85 m).
const CHAIR_SEAT_FRACTION: f64 = 0.45 / 0.85;
/// Thickness of table tops, seats and chair backs (m).
const PANEL: f64 = 0.04;
/// Edge of a square leg (m).
const LEG: f64 = 0.04;

/// One part of an object: a cuboid or upright cylinder relative to the object's frame.
struct Part {
    shape: SharedShape,
    /// Pose in the object frame (origin at the footprint centre on the object's underside).
    pose: Pose,
}

/// The scene's static frame: floor and four walls, registered in `surfaces`.
pub fn build_room(
    room: &Room,
    colliders: &mut ColliderSet,
    surfaces: &mut HashMap<ColliderHandle, Surface>,
) {
    let [sx, sy] = [room.size[0] as f32, room.size[1] as f32];
    let h = room.wall_height as f32;
    let floor = ColliderBuilder::cuboid(sx / 2.0 + SLAB, sy / 2.0 + SLAB, SLAB / 2.0)
        .translation(Vector::new(sx / 2.0, sy / 2.0, -SLAB / 2.0))
        .friction(FLOOR_FRICTION)
        .friction_combine_rule(FLOOR_FRICTION_RULE)
        .collision_groups(InteractionGroups::new(
            groups::FLOOR,
            Group::ALL,
            InteractionTestMode::And,
        ))
        .build();
    let fh = colliders.insert(floor);
    surfaces.insert(
        fh,
        Surface::new(room.floor_colour, Texture::Plain, Owner::Floor),
    );
    // Walls stand outside the room so its inside is exactly [0, sx] × [0, sy].
    let walls = [
        (
            Vector::new(sx / 2.0, -SLAB / 2.0, h / 2.0),
            Vector::new(sx / 2.0 + SLAB, SLAB / 2.0, h / 2.0),
        ),
        (
            Vector::new(sx / 2.0, sy + SLAB / 2.0, h / 2.0),
            Vector::new(sx / 2.0 + SLAB, SLAB / 2.0, h / 2.0),
        ),
        (
            Vector::new(-SLAB / 2.0, sy / 2.0, h / 2.0),
            Vector::new(SLAB / 2.0, sy / 2.0, h / 2.0),
        ),
        (
            Vector::new(sx + SLAB / 2.0, sy / 2.0, h / 2.0),
            Vector::new(SLAB / 2.0, sy / 2.0, h / 2.0),
        ),
    ];
    for (centre, half) in walls {
        let wall = ColliderBuilder::cuboid(half.x, half.y, half.z)
            .translation(centre)
            .collision_groups(InteractionGroups::new(
                groups::WALL,
                Group::ALL,
                InteractionTestMode::And,
            ))
            .build();
        let wh = colliders.insert(wall);
        surfaces.insert(
            wh,
            Surface::new(room.wall_colour, Texture::Plain, Owner::Wall),
        );
    }
}

/// Checks an object's numbers; the scene builder never sees a bad one.
pub fn validate_object(spec: &ObjectSpec) -> Result<(), WorldError> {
    let bad = |reason: String| {
        Err(WorldError::InvalidObject {
            name: spec.name.clone(),
            reason,
        })
    };
    let want = if spec.kind == ObjectKind::Cylinder {
        2
    } else {
        3
    };
    if spec.size.len() != want {
        return bad(format!(
            "size needs {want} numbers, got {}",
            spec.size.len()
        ));
    }
    if spec.size.iter().any(|s| !s.is_finite() || *s <= 0.0) {
        return bad("sizes must be positive".into());
    }
    if !(spec.mass.is_finite() && spec.mass > 0.0) {
        return bad("mass must be positive".into());
    }
    if !(spec.friction.is_finite() && (0.0..=2.0).contains(&spec.friction)) {
        return bad("friction must be in [0, 2]".into());
    }
    if !(spec.elevation.is_finite() && spec.elevation >= 0.0) {
        return bad("elevation must be >= 0".into());
    }
    if !(spec.position.iter().all(|p| p.is_finite()) && spec.yaw.is_finite()) {
        return bad("position and yaw must be finite".into());
    }
    if matches!(spec.kind, ObjectKind::Table | ObjectKind::Chair)
        && (spec.size[0] <= 2.0 * LEG || spec.size[1] <= 2.0 * LEG || spec.size[2] <= 2.0 * PANEL)
    {
        return bad("furniture too small for its legs and panels".into());
    }
    Ok(())
}

/// Whether an object is a fixed body: bolted, or lifted off the floor (a shelf, a pipe).
pub fn is_fixed(spec: &ObjectSpec) -> bool {
    spec.fixed || spec.elevation > 0.0
}

/// The pose of an object's frame (footprint centre on its underside) in the map.
pub fn object_pose(spec: &ObjectSpec) -> Pose {
    Pose::from_parts(
        Vector::new(
            spec.position[0] as f32,
            spec.position[1] as f32,
            spec.elevation as f32,
        ),
        Rotation::from_rotation_z(spec.yaw.to_radians() as f32),
    )
}

/// Inserts one object as a body with one collider, and registers its surface.
///
/// Furniture is one compound collider rather than a collider per part: rapier then merges the four
/// legs' floor contacts into one manifold of at most four points (contact clustering), which makes a
/// step with a chair sliding under the hand about 40 % cheaper than four leg–floor pairs of four
/// points each. The parts keep their own look through [`Surface::of_part`].
pub fn build_object(
    index: usize,
    spec: &ObjectSpec,
    bodies: &mut RigidBodySet,
    colliders: &mut ColliderSet,
    surfaces: &mut HashMap<ColliderHandle, Surface>,
) -> Result<RigidBodyHandle, WorldError> {
    validate_object(spec)?;
    let builder = if is_fixed(spec) {
        RigidBodyBuilder::fixed()
    } else {
        RigidBodyBuilder::dynamic()
    };
    let body = bodies.insert(builder.pose(object_pose(spec)).build());
    let parts = parts_of(spec);
    // One density for the whole object: a compound's mass properties weigh its parts by volume.
    let builder = match parts.as_slice() {
        [one] => ColliderBuilder::new(one.shape.clone()).position(one.pose),
        _ => ColliderBuilder::compound(parts.into_iter().map(|p| (p.pose, p.shape)).collect()),
    };
    let collider = builder
        .mass(spec.mass as f32)
        .friction(spec.friction as f32)
        .collision_groups(InteractionGroups::new(
            groups::OBJECT,
            Group::ALL,
            InteractionTestMode::And,
        ))
        .build();
    let ch = colliders.insert_with_parent(collider, body, bodies);
    surfaces.insert(
        ch,
        Surface {
            colour: spec.colour,
            texture: spec.texture,
            owner: Owner::Object(index),
            legs_from: first_leg(spec.kind),
        },
    );
    Ok(body)
}

/// The index of the first leg among an object's parts (listed top/seat, [back], legs), if it has legs.
fn first_leg(kind: ObjectKind) -> Option<usize> {
    match kind {
        ObjectKind::Table => Some(1),
        ObjectKind::Chair => Some(2),
        _ => None,
    }
}

/// The parts of an object, in its own frame (origin at the underside's centre, z up).
fn parts_of(spec: &ObjectSpec) -> Vec<Part> {
    let s = &spec.size;
    match spec.kind {
        ObjectKind::Box | ObjectKind::Mat => {
            vec![cuboid_part([0.0, 0.0, s[2] / 2.0], [s[0], s[1], s[2]])]
        }
        ObjectKind::Cylinder => {
            let (r, h) = (s[0] / 2.0, s[1]);
            vec![Part {
                shape: SharedShape::cylinder(h as f32 / 2.0, r as f32),
                // parry's cylinders stand along y; turn them upright.
                pose: Pose::from_parts(
                    Vector::new(0.0, 0.0, h as f32 / 2.0),
                    Rotation::from_rotation_x(std::f32::consts::FRAC_PI_2),
                ),
            }]
        }
        ObjectKind::Table => {
            let top_z = s[2] - PANEL;
            let mut parts = vec![cuboid_part(
                [0.0, 0.0, top_z + PANEL / 2.0],
                [s[0], s[1], PANEL],
            )];
            parts.extend(legs(s[0], s[1], top_z));
            parts
        }
        ObjectKind::Chair => {
            let seat_top = s[2] * CHAIR_SEAT_FRACTION;
            let seat_z = seat_top - PANEL;
            let mut parts = vec![
                cuboid_part([0.0, 0.0, seat_z + PANEL / 2.0], [s[0], s[1], PANEL]),
                // The back rises from the seat's rear (−x) edge.
                cuboid_part(
                    [-s[0] / 2.0 + PANEL / 2.0, 0.0, (seat_top + s[2]) / 2.0],
                    [PANEL, s[1], s[2] - seat_top],
                ),
            ];
            parts.extend(legs(s[0], s[1], seat_z));
            parts
        }
    }
}

/// Four square legs under a panel whose underside is at `height`, flush with its corners.
fn legs(sx: f64, sy: f64, height: f64) -> Vec<Part> {
    let (ox, oy) = (sx / 2.0 - LEG / 2.0, sy / 2.0 - LEG / 2.0);
    [(ox, oy), (-ox, oy), (ox, -oy), (-ox, -oy)]
        .into_iter()
        .map(|(x, y)| cuboid_part([x, y, height / 2.0], [LEG, LEG, height]))
        .collect()
}

fn cuboid_part(centre: [f64; 3], size: [f64; 3]) -> Part {
    Part {
        shape: SharedShape::cuboid(
            size[0] as f32 / 2.0,
            size[1] as f32 / 2.0,
            size[2] as f32 / 2.0,
        ),
        pose: Pose::from_translation(Vector::new(
            centre[0] as f32,
            centre[1] as f32,
            centre[2] as f32,
        )),
    }
}
