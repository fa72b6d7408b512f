//! Friction against the floor is exactly each object's scenario friction.
mod world_common;

use nudge_sim::surface::Owner;
use rapier3d::prelude::*;
use world_common::*;

#[test]
fn floor_contact_friction_equals_object_friction() {
    // For every collider of every object, the combined friction with the floor is the object's μ.
    let w = world(&scenario(KAKIUCHI_ROOM));
    let floor = w
        .colliders()
        .iter()
        .find(|(h, _)| w.surface(*h).map(|s| s.owner) == Some(Owner::Floor))
        .map(|(_, c)| c)
        .expect("a floor");
    let mut checked = 0;
    for (h, c) in w.colliders().iter() {
        let Some(Owner::Object(i)) = w.surface(h).map(|s| s.owner) else {
            continue;
        };
        let mu = CoefficientCombineRule::combine(
            floor.friction(),
            c.friction(),
            floor.friction_combine_rule(),
            c.friction_combine_rule(),
        );
        assert_eq!(
            mu,
            w.objects()[i].0.friction as f32,
            "collider of object {i}"
        );
        checked += 1;
    }
    // One collider per object (furniture is one compound of its top/seat, back and legs).
    assert_eq!(checked, 4);
}

#[test]
fn sliding_box_stops_after_v2_over_2_mu_g() {
    // A box launched at 1 m/s on the floor with μ = 0.4 slides v²/(2 μ g) ≈ 0.127 m, within 5 % plus
    // one coarse 10 ms physics step of travel (1 cm): nothing touches the hand, so the world steps coarsely.
    let s = robot_and(
        "name = \"box\"\nkind = \"box\"\nposition = [3.0, 1.8]\nsize = [0.4, 0.4, 0.3]\nmass = 4.0\nfriction = 0.4\ncolour = [1, 2, 3]",
    );
    let mut w = world(&s);
    w.advance(0.3).expect("settle");
    let x0 = w.object_pose(0).expect("box").translation.x;
    let body = w.objects()[0].1;
    w.physics_mut()
        .bodies
        .get_mut(body)
        .expect("box body")
        .set_linvel(Vector::new(1.0, 0.0, 0.0), true);
    w.advance(1.0).expect("slide");
    let slid = w.object_pose(0).expect("box").translation.x - x0;
    let expected = 1.0 / (2.0 * 0.4 * 9.81);
    assert!(
        (slid - expected).abs() < 0.05 * expected + 0.01,
        "slid {slid} m, expected {expected} m"
    );
}

#[test]
fn invalid_objects_are_errors_not_panics() {
    // An object with the wrong number of sizes, a non-positive mass or friction out of [0, 2] is
    // refused with an error naming it.
    use nudge_sim::world::{World, WorldError};
    for object in [
        "name = \"bad\"\nkind = \"box\"\nposition = [3.0, 1.8]\nsize = [0.4, 0.4]\nmass = 4.0\ncolour = [1, 2, 3]",
        "name = \"bad\"\nkind = \"chair\"\nposition = [3.0, 1.8]\nsize = [0.5, 0.5, 0.85]\nmass = 0.0\ncolour = [1, 2, 3]",
        "name = \"bad\"\nkind = \"cylinder\"\nposition = [3.0, 1.8]\nsize = [0.4, 0.8]\nmass = 1.0\nfriction = 2.5\ncolour = [1, 2, 3]",
    ] {
        match World::new(&robot_and(object), 1) {
            Err(WorldError::InvalidObject { name, .. }) => assert_eq!(name, "bad"),
            Err(e) => panic!("wrong error {e}"),
            Ok(_) => panic!("accepted {object}"),
        }
    }
}
