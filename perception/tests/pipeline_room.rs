//! The whole pipeline on a synthetic look-around of the default room (kakiuchi-room).

mod common;

use common::{kakiuchi_room, look_around, planar};
use nalgebra::{Isometry2, Point2, Vector2};
use nudge_perception::prism::convex_iou;
use nudge_perception::{PerceptionConfig, Prism, detect_objects, fuse};

fn rect(x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<Point2<f64>> {
    vec![
        Point2::new(x0, y0),
        Point2::new(x1, y0),
        Point2::new(x1, y1),
        Point2::new(x0, y1),
    ]
}

fn start_pose() -> Isometry2<f64> {
    Isometry2::new(Vector2::new(0.6, 1.8), 0.0)
}

fn detect_room(seed: u64, previous: &[Prism]) -> Vec<Prism> {
    let scene = kakiuchi_room();
    let clouds = look_around(&scene, &planar(0.6, 1.8, 0.0), seed);
    let fused = fuse(&clouds);
    detect_objects(
        &fused,
        &start_pose(),
        &PerceptionConfig::default(),
        previous,
    )
    .expect("the room has floor in front of the robot")
}

fn best_match<'a>(prisms: &'a [Prism], truth: &[Point2<f64>]) -> (&'a Prism, f64) {
    prisms
        .iter()
        .map(|p| (p, convex_iou(&p.footprint, truth)))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("some prism")
}

#[test]
fn room_objects_become_prisms_with_true_footprints_and_heights() {
    // Invariant: the table and the chairs each give one prism whose footprint overlaps the truth
    // (IoU ≥ 0.8) and whose top is within 40 mm of the true height.
    let prisms = detect_room(1, &[]);
    for p in &prisms {
        eprintln!(
            "{} area {:.3} z {:.3}..{:.3} pts {} verts {:?}",
            p.id,
            p.area(),
            p.z_min,
            p.z_max,
            p.points.len(),
            p.footprint
                .iter()
                .map(|v| (format!("{:.2}", v.x), format!("{:.2}", v.y)))
                .collect::<Vec<_>>()
        );
    }
    let cases = [
        ("table", rect(2.6, 3.4, 1.2, 2.4), 0.72),
        ("chair-1", rect(3.55, 4.05, 0.6, 1.1), 0.85),
        ("chair-2", rect(3.55, 4.05, 2.5, 3.0), 0.85),
    ];
    for (name, truth, top) in cases {
        let (p, iou) = best_match(&prisms, &truth);
        eprintln!("{name}: IoU {iou:.3} top {:.3}", p.z_max);
        assert!(iou >= 0.8, "{name}: IoU {iou}");
        assert!((p.z_max - top).abs() <= 0.04, "{name}: top {}", p.z_max);
    }
}

#[test]
fn the_mat_is_a_flat_prism_that_motion_can_cross() {
    // Invariant: a 1 cm mat of another colour than the floor is not floor, and its prism is at most
    // 3 cm tall (nothing in the pipeline inflates it).
    let prisms = detect_room(2, &[]);
    let (mat, iou) = best_match(&prisms, &rect(1.3, 1.9, 2.7, 3.1));
    assert!(iou >= 0.5, "mat IoU {iou}");
    assert!(mat.z_max <= 0.03, "mat top {}", mat.z_max);
}

#[test]
fn walls_are_obstacles_but_never_one_hull_over_the_room() {
    // Invariant: the walls' inner faces are inside prisms, while the free floor (start, goal, the
    // corridors) is inside none and no prism is larger than a wall run could be.
    let prisms = detect_room(3, &[]);
    let covered = |p: Point2<f64>| prisms.iter().any(|q| q.contains_xy(&p));
    for wall_point in [
        Point2::new(6.0, 1.8),
        Point2::new(4.0, 0.0),
        Point2::new(4.0, 3.6),
        Point2::new(6.0, 0.5),
    ] {
        assert!(covered(wall_point), "wall point {wall_point:?} not covered");
    }
    for free in [
        Point2::new(0.6, 1.8),
        Point2::new(5.4, 1.8),
        Point2::new(2.0, 1.0),
        Point2::new(4.8, 1.8),
        Point2::new(4.8, 0.5),
        Point2::new(3.0, 0.55),
        Point2::new(5.0, 3.0),
    ] {
        assert!(!covered(free), "free point {free:?} is inside a prism");
    }
    for p in &prisms {
        assert!(p.area() < 1.5, "prism {} has area {}", p.id, p.area());
    }
}

#[test]
fn ids_survive_a_second_look_with_fresh_noise() {
    // Invariant: re-detecting the same room keeps every object's id.
    let first = detect_room(4, &[]);
    let second = detect_room(5, &first);
    for (name, truth) in [
        ("table", rect(2.6, 3.4, 1.2, 2.4)),
        ("chair-1", rect(3.55, 4.05, 0.6, 1.1)),
        ("chair-2", rect(3.55, 4.05, 2.5, 3.0)),
    ] {
        let (a, _) = best_match(&first, &truth);
        let (b, _) = best_match(&second, &truth);
        assert_eq!(a.id, b.id, "{name} changed id");
    }
}

#[test]
fn detection_is_deterministic() {
    // Invariant: the same clouds give the same prisms, bit for bit.
    let a = detect_room(6, &[]);
    let b = detect_room(6, &[]);
    assert_eq!(a, b);
}

#[test]
fn each_piece_of_furniture_is_exactly_one_prism() {
    // Invariant: no second prism sits inside the table or a chair (a leg seen apart from its seat is
    // merged into the chair).
    let prisms = detect_room(7, &[]);
    for (name, truth) in [
        ("table", rect(2.6, 3.4, 1.2, 2.4)),
        ("chair-1", rect(3.55, 4.05, 0.6, 1.1)),
        ("chair-2", rect(3.55, 4.05, 2.5, 3.0)),
    ] {
        let inside = prisms
            .iter()
            .filter(|p| {
                nudge_perception::prism::convex_intersection_area(&p.footprint, &truth)
                    > 0.5 * p.area()
            })
            .count();
        assert_eq!(inside, 1, "{name}: {inside} prisms inside");
    }
}

#[test]
fn detection_does_not_depend_on_the_thread_count() {
    // Invariant: one thread and four threads give the same prisms, bit for bit.
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool")
        .install(|| detect_room(8, &[]));
    let many = rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build()
        .expect("a four-thread pool")
        .install(|| detect_room(8, &[]));
    assert_eq!(one, many);
}
