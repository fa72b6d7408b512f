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
    // Invariant: a 1 cm mat of another colour than the floor is not floor, and its prism is no taller
    // than the mat (0.5 mm rounding): its top is the median of its top cells, not its noisiest point.
    let prisms = detect_room(2, &[]);
    let (mat, iou) = best_match(&prisms, &rect(1.3, 1.9, 2.7, 3.1));
    assert!(iou >= 0.5, "mat IoU {iou}");
    println!("mat top {:.5} m", mat.z_max);
    assert!(mat.z_max <= 0.0105, "mat top {}", mat.z_max);
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

#[test]
fn an_overhang_keeps_its_lowest_point_above_the_floor() {
    // Invariant: a shelf floating 0.8 m up gives a prism with z_min ≈ 0.8 (the space below is free
    // for anything lower), and z_max at its top.
    let mut scene = kakiuchi_room();
    scene.objects.push(common::SynthObject {
        name: "shelf",
        pose: planar(2.0, 0.8, 0.0),
        boxes: vec![common::SynthBox {
            pose: nalgebra::Isometry3::translation(0.0, 0.0, 0.82),
            half: nalgebra::Vector3::new(0.2, 0.3, 0.02),
            texture: common::Texture::Uniform([90, 60, 160]),
        }],
    });
    let clouds = look_around(&scene, &planar(0.6, 1.8, 0.0), 9);
    let prisms = detect_objects(
        &fuse(&clouds),
        &start_pose(),
        &PerceptionConfig::default(),
        &[],
    )
    .expect("floor in front");
    let (shelf, iou) = best_match(&prisms, &rect(1.8, 2.2, 0.5, 1.1));
    assert!(iou >= 0.7, "shelf IoU {iou}");
    assert!(
        (shelf.z_min - 0.80).abs() < 0.03,
        "shelf bottom {}",
        shelf.z_min
    );
    assert!(
        (shelf.z_max - 0.84).abs() < 0.03,
        "shelf top {}",
        shelf.z_max
    );
}

#[test]
fn a_pushed_chair_keeps_its_id_when_its_icp_motion_is_applied_before_tracking() {
    // Invariant: after chair-1 is pushed 0.8 m, colour ICP between its prism points before and after
    // gives the push, and tracking the moved previous prisms keeps the chair's id.
    let first = detect_room(10, &[]);
    let (chair_before, _) = best_match(&first, &rect(3.55, 4.05, 0.6, 1.1));
    let mut scene = kakiuchi_room();
    scene.objects[2].pose = planar(4.6, 0.85, 0.0);
    let clouds = look_around(&scene, &planar(0.6, 1.8, 0.0), 11);
    let mut second = detect_objects(
        &fuse(&clouds),
        &start_pose(),
        &PerceptionConfig::default(),
        &first,
    )
    .expect("floor in front");
    let chair_after_index = second
        .iter()
        .enumerate()
        .map(|(i, p)| (i, convex_iou(&p.footprint, &rect(4.35, 4.85, 0.6, 1.1))))
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(i, _)| i)
        .expect("prisms");
    assert_ne!(
        second[chair_after_index].id, chair_before.id,
        "moved 0.8 m: no overlap"
    );
    let guess = nalgebra::Isometry3::translation(0.7, 0.0, 0.0);
    let push = nudge_perception::colour_icp(
        &chair_before.points,
        &second[chair_after_index].points,
        &guess,
        &nudge_perception::IcpConfig::default(),
    )
    .expect("both clouds hold the chair");
    eprintln!(
        "chair push read {:?} mm, yaw {:.2}°",
        push.translation_mm, push.yaw_deg
    );
    assert!(
        (push.translation_mm.x - 800.0).abs() < 10.0,
        "{:?}",
        push.translation_mm
    );
    let moved: Vec<Prism> = first
        .iter()
        .map(|p| {
            if p.id == chair_before.id {
                p.transformed(&push.transform)
            } else {
                p.clone()
            }
        })
        .collect();
    nudge_perception::track_ids(&moved, &mut second);
    assert_eq!(second[chair_after_index].id, chair_before.id);
}

#[test]
fn at_the_push_pose_the_chair_in_the_floor_square_does_not_poison_the_floor() {
    // Invariant: standing at (3.0, 0.55) facing +x, where chair-1 reaches into the known-floor square,
    // the floor is still learned from floor points only and the chair is still an obstacle.
    let scene = kakiuchi_room();
    let clouds = look_around(&scene, &planar(3.0, 0.55, 0.0), 12);
    let pose = Isometry2::new(Vector2::new(3.0, 0.55), 0.0);
    let prisms = detect_objects(&fuse(&clouds), &pose, &PerceptionConfig::default(), &[])
        .expect("floor in front");
    let (chair, iou) = best_match(&prisms, &rect(3.55, 4.05, 0.6, 1.1));
    eprintln!(
        "chair-1 from the push pose: IoU {iou:.3}, top {:.3}",
        chair.z_max
    );
    assert!(iou >= 0.6, "chair-1 IoU {iou}");
    assert!((chair.z_max - 0.85).abs() < 0.04);
}
