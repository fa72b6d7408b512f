//! Footprints and shapes computed from scenario objects: what the world builder and ground truth rely on.

use std::f64::consts::FRAC_PI_2;

use nalgebra::{Point2, Vector2};
use nudge_sim::scenario::{
    DISC_POLYGON_CORNERS, Footprint, ObjectKind, ObjectSpec, Room, Shape, Texture,
};

fn object(kind: ObjectKind, position: [f64; 2], yaw: f64, size: &[f64]) -> ObjectSpec {
    ObjectSpec {
        name: "thing".into(),
        kind,
        position,
        yaw,
        size: size.to_vec(),
        elevation: 0.0,
        mass: 1.0,
        friction: 0.5,
        fixed: false,
        colour: [1, 2, 3],
        texture: Texture::Plain,
    }
}

fn rect(centre: (f64, f64), half: (f64, f64), yaw: f64) -> Footprint {
    Footprint::Rectangle {
        centre: Point2::new(centre.0, centre.1),
        half_extents: Vector2::new(half.0, half.1),
        yaw,
    }
}

fn signed_area(polygon: &[Point2<f64>]) -> f64 {
    polygon
        .iter()
        .zip(polygon.iter().cycle().skip(1))
        .map(|(p, q)| p.x * q.y - q.x * p.y)
        .sum::<f64>()
        / 2.0
}

#[test]
fn a_turned_table_swaps_its_footprint_extents() {
    // Invariant: yaw is in degrees and turns the footprint about its centre (the brief's table at 90°).
    let table = object(ObjectKind::Table, [3.0, 1.8], 90.0, &[1.2, 0.8, 0.72]);
    let (lo, hi) = table.footprint().expect("three size entries").aabb();
    assert!(
        (lo - Point2::new(2.6, 1.2)).norm() < 1e-12 && (hi - Point2::new(3.4, 2.4)).norm() < 1e-12,
        "{lo} {hi}"
    );
    assert_eq!(table.height(), Some(0.72));
    assert!((table.pose().rotation.angle() - FRAC_PI_2).abs() < 1e-12);
}

#[test]
fn polygons_are_counter_clockwise_with_the_right_area() {
    // Invariant: footprint polygons wind counter-clockwise; a rectangle's area is x × y whatever its yaw,
    // and the disc's polygon contains the disc.
    let turned = rect((1.0, 1.0), (0.3, 0.2), 0.7).polygon();
    assert_eq!(turned.len(), 4);
    assert!((signed_area(&turned) - 0.24).abs() < 1e-12);
    let disc = Footprint::Disc {
        centre: Point2::new(2.0, 2.0),
        radius: 0.5,
    };
    let polygon = disc.polygon();
    assert_eq!(polygon.len(), DISC_POLYGON_CORNERS);
    let area = signed_area(&polygon);
    assert!(
        area > std::f64::consts::PI * 0.25 && area < std::f64::consts::PI * 0.25 * 1.02,
        "{area}"
    );
    // The midpoint of every edge lies on or outside the circle.
    for (p, q) in polygon.iter().zip(polygon.iter().cycle().skip(1)) {
        assert!((nalgebra::center(p, q) - Point2::new(2.0, 2.0)).norm() >= 0.5 - 1e-12);
    }
}

#[test]
fn point_distances_are_zero_inside_and_euclidean_outside() {
    // Invariant: distance_to_point is 0 on and inside, and the true distance outside a rotated rectangle.
    let square = rect((0.0, 0.0), (1.0, 1.0), std::f64::consts::FRAC_PI_4);
    assert_eq!(square.distance_to_point(&Point2::new(0.0, 1.4)), 0.0);
    assert!(square.contains(&Point2::new(0.0, 2f64.sqrt())));
    let d = square.distance_to_point(&Point2::new(0.0, 2.0));
    assert!((d - (2.0 - 2f64.sqrt())).abs() < 1e-12, "{d}");
    let disc = Footprint::Disc {
        centre: Point2::new(1.0, 0.0),
        radius: 0.5,
    };
    assert!((disc.distance_to_point(&Point2::new(3.0, 0.0)) - 1.5).abs() < 1e-12);
}

#[test]
fn footprint_gaps_are_corner_distances_or_zero_when_crossing() {
    // Invariant: the gap between rectangles is their nearest corner–edge distance, and 0 when they overlap
    // even with no corner inside the other (a cross).
    let table = rect((3.0, 1.8), (0.4, 0.6), 0.0);
    let chair = rect((3.8, 0.85), (0.25, 0.25), 0.0);
    let corner = (0.15f64.powi(2) + 0.1f64.powi(2)).sqrt();
    assert!((table.distance_to(&chair) - corner).abs() < 1e-12);
    assert!((chair.distance_to(&table) - corner).abs() < 1e-12);
    let long = rect((0.0, 0.0), (2.0, 0.1), 0.0);
    let tall = rect((0.0, 0.0), (0.1, 2.0), 0.0);
    assert_eq!(long.distance_to(&tall), 0.0);
    let disc = Footprint::Disc {
        centre: Point2::new(3.0, 0.0),
        radius: 0.5,
    };
    assert!((long.distance_to(&disc) - 0.5).abs() < 1e-12);
    assert!((disc.distance_to(&long) - 0.5).abs() < 1e-12);
}

#[test]
fn shapes_follow_kind_and_refuse_wrong_sizes_without_panicking() {
    // Invariant: a cylinder reads [diameter, height]; a size of the wrong length gives None, not a panic.
    let bin = object(ObjectKind::Cylinder, [1.0, 1.0], 0.0, &[0.4, 0.6]);
    assert_eq!(
        bin.shape(),
        Some(Shape::Cylinder {
            radius: 0.2,
            height: 0.6
        })
    );
    assert_eq!(bin.top(), Some(0.6));
    assert!(matches!(bin.footprint(), Some(Footprint::Disc { radius, .. }) if radius == 0.2));
    let broken = object(ObjectKind::Chair, [1.0, 1.0], 0.0, &[0.5, 0.5]);
    assert_eq!(
        (broken.shape(), broken.footprint(), broken.height()),
        (None, None, None)
    );
    let mut pipe = object(ObjectKind::Box, [1.0, 1.0], 0.0, &[0.1, 3.0, 0.1]);
    pipe.elevation = 1.7;
    assert!(!pipe.blocks_height(1.54) && pipe.blocks_height(1.8));
    assert!(!object(ObjectKind::Mat, [1.0, 1.0], 0.0, &[1.0, 1.0, 0.01]).blocks_height(1.54));
}

#[test]
fn wall_clearance_is_the_distance_to_the_nearest_wall() {
    // Invariant: Room::clearance is the smallest footprint–wall distance, negative when poking through.
    let room = Room {
        size: [6.0, 3.6],
        wall_height: 2.0,
        floor_colour: [0, 0, 0],
        wall_colour: [0, 0, 0],
    };
    assert!((room.clearance(&rect((3.8, 0.85), (0.25, 0.25), 0.0)) - 0.6).abs() < 1e-12);
    assert!((room.clearance(&rect((5.9, 1.0), (0.25, 0.25), 0.0)) + 0.15).abs() < 1e-12);
}
