//! A box filling a corridor, its outline leaning a few degrees: the push that opens the way runs
//! along the corridor, a little off the outline's face normal.

mod common;

use nalgebra::{Point2, Rotation2};
use nudge_motion::{Bounds, PushConfig, RobotCylinder, Validity, ValidityConfig, plan_push};
use nudge_perception::{ObjectId, Prism};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// The corridor-niche room: a corridor 1.1 m wide along y = 0 (walls at y 1.1..2.2 over x 0..4
/// and 7..9, a niche between), a box 0.6 m square at x 2.1..2.7 turned by `lean` (rad).
fn corridor(lean: f64) -> (Validity, Prism) {
    corridor_with(lean, &[])
}

/// [`corridor`] with `extra` obstacles in it.
fn corridor_with(lean: f64, extra: &[Prism]) -> (Validity, Prism) {
    let mut prisms = vec![
        common::boxed(1, 0.0, -0.1, 9.0, 0.0, 0.0, 2.0),
        common::boxed(2, 0.0, 1.1, 4.0, 2.2, 0.0, 2.0),
        common::boxed(3, 7.0, 1.1, 9.0, 2.2, 0.0, 2.0),
        common::boxed(4, 0.0, 2.2, 9.0, 2.3, 0.0, 2.0),
    ];
    let centre = Point2::new(2.4, 0.55);
    let turn = Rotation2::new(lean);
    let mut the_box = common::boxed(9, 2.1, 0.25, 2.7, 0.85, 0.0, 0.7);
    for p in &mut the_box.footprint {
        *p = centre + turn * (*p - centre);
    }
    prisms.push(the_box.clone());
    prisms.extend_from_slice(extra);
    let bounds = Bounds::new(Point2::new(0.0, 0.0), Point2::new(9.0, 2.2)).expect("room bounds");
    let robot = RobotCylinder {
        radius: 0.35,
        height: 1.54,
    };
    let v = Validity::new(robot, bounds, &prisms, ValidityConfig::default()).expect("corridor");
    (v, the_box)
}

#[test]
fn a_box_whose_outline_leans_is_pushed_along_the_corridor_not_into_its_wall() {
    // Invariant: with the box's outline leaning 7° (a noisy outline), a push along its face normal would drift 0.3 m sideways over the 2.6 m the way needs and meet the wall; the planner still finds a push that opens the way to the corridor's far end, a few degrees off the normal so that the long sweep stays between the walls. Upright, it pushes along the normal.
    let goal = nudge_motion::GoalRegion::new(Point2::new(8.4, 0.55), 0.2).expect("goal");
    let robot = Point2::new(0.9, 0.55);
    for lean in [0.0, -0.12] {
        let (v, the_box) = corridor(lean);
        let mut rng = ChaCha8Rng::seed_from_u64(9);
        let plan = plan_push(
            &the_box,
            &v,
            &robot,
            &goal,
            &PushConfig::default(),
            &mut rng,
        )
        .expect("the box can be pushed");
        assert_eq!(plan.object, ObjectId(9));
        assert!(plan.opens_path, "lean {lean}: {plan:?}");
        assert!(plan.distance > 2.0, "lean {lean}: {}", plan.distance);
        let heading = plan.direction.y.atan2(plan.direction.x);
        assert!(
            heading.abs() < 0.06,
            "lean {lean}: pushed {heading} rad off the corridor"
        );
        if lean != 0.0 {
            assert!(
                (heading - lean).abs() > 0.05,
                "along the leaning normal: {heading}"
            );
        }
    }
}

#[test]
fn a_box_that_every_push_drives_into_a_block_says_what_it_runs_into() {
    // Invariant: with a fixed block 0.2 m beyond the box across the whole corridor (less than the shortest push, 0.3 m, and its 5 cm clearance), no push of the box is valid, and the planner's error names the block as what the pushes run into.
    let (blocked, the_box) = corridor_with(0.0, &[common::boxed(5, 2.9, 0.0, 3.2, 1.1, 0.0, 2.0)]);
    let goal = nudge_motion::GoalRegion::new(Point2::new(8.4, 0.55), 0.2).expect("goal");
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let out = plan_push(
        &the_box,
        &blocked,
        &Point2::new(0.9, 0.55),
        &goal,
        &PushConfig::default(),
        &mut rng,
    );
    let Err(nudge_motion::PushError::Blocked(id, by)) = &out else {
        panic!("expected every push blocked, got {out:?}");
    };
    assert_eq!(*id, ObjectId(9));
    assert!(by.obstacles.contains(&ObjectId(5)), "{by:?}");
    let message = out.as_ref().expect_err("blocked").to_string();
    assert!(
        message.contains("runs into") && message.contains("obj-5"),
        "{message}"
    );
}
