//! Ground truth on the paper's room.
mod world_common;

use nalgebra::Point2;
use nudge_sim::truth::{Movability, TrueClass, Truth};
use world_common::*;

#[test]
fn paper_room_movability_follows_the_rule() {
    // The 25 kg table (μmg ≈ 147 N) is static; the 4 kg chairs (μmg ≈ 15.7 N < 16 N) are movable.
    let w = world(&scenario(KAKIUCHI_ROOM));
    let t = Truth::new(&w);
    assert_eq!(t.movability(0), Some(Movability::Static));
    assert_eq!(t.movability(1), Some(Movability::Movable));
    assert_eq!(t.movability(2), Some(Movability::Movable));
    assert_eq!(t.movability(9), None);
}

#[test]
fn paper_room_classes_at_known_points() {
    // Points in the table's, chairs' and mat's footprints, in the open and outside the room get
    // their true class; the robot's own position is free.
    let w = world(&scenario(KAKIUCHI_ROOM));
    let t = Truth::new(&w);
    let cases = [
        ((3.0, 1.8), TrueClass::Stationary),
        ((3.35, 2.35), TrueClass::Stationary),
        ((3.8, 0.85), TrueClass::Movable),
        ((4.0, 2.55), TrueClass::Movable),
        ((1.6, 2.9), TrueClass::Free),
        ((0.6, 1.8), TrueClass::Free),
        ((3.0, 0.5), TrueClass::Free),
        ((-0.1, 1.0), TrueClass::Stationary),
        ((6.2, 1.0), TrueClass::Stationary),
    ];
    for ((x, y), class) in cases {
        assert_eq!(t.true_class_at(Point2::new(x, y)), class, "at ({x}, {y})");
    }
}

#[test]
fn actors_are_moving() {
    // An actor's footprint is Moving.
    let s = scenario(
        r#"
name = "a"
[room]
size = [6.0, 3.6]
[robot]
start = [0.6, 0.6, 0.0]
[goal]
position = [5.0, 1.8]
[[actor]]
name = "p"
waypoints = [[2.0, 2.0], [4.0, 2.0]]
speed = 0.5
"#,
    );
    let mut w = world(&s);
    w.advance(2.0).expect("advance");
    let t = Truth::new(&w);
    assert_eq!(t.true_class_at(Point2::new(3.0, 2.0)), TrueClass::Moving);
    assert_eq!(t.true_class_at(Point2::new(2.0, 2.0)), TrueClass::Free);
}

#[test]
fn a_sliding_object_is_moving_then_movable_at_rest() {
    // A light box launched at 1 m/s is Moving while it slides and Movable once at rest.
    use rapier3d::prelude::Vector;
    let s = robot_and(
        "name = \"box\"\nkind = \"box\"\nposition = [3.0, 1.8]\nsize = [0.4, 0.4, 0.3]\nmass = 2.0\nfriction = 0.4\ncolour = [1, 2, 3]",
    );
    let mut w = world(&s);
    w.advance(0.3).expect("settle");
    assert_eq!(
        Truth::new(&w).true_class_at(Point2::new(3.0, 1.8)),
        TrueClass::Movable
    );
    let body = w.objects()[0].1;
    w.physics_mut()
        .bodies
        .get_mut(body)
        .expect("box")
        .set_linvel(Vector::new(1.0, 0.0, 0.0), true);
    w.advance(0.05).expect("slide");
    let x = w.object_pose(0).expect("box").translation.x;
    assert_eq!(
        Truth::new(&w).true_class_at(Point2::new(x, 1.8)),
        TrueClass::Moving
    );
    w.advance(2.0).expect("stop");
    let x = w.object_pose(0).expect("box").translation.x;
    assert_eq!(
        Truth::new(&w).true_class_at(Point2::new(x, 1.8)),
        TrueClass::Movable
    );
    assert_eq!(
        Truth::new(&w).true_class_at(Point2::new(2.85, 1.8)),
        TrueClass::Free,
        "the old footprint is free"
    );
}
