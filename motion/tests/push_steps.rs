//! A push that opens nothing is a step: it must not leave the object where moving the others
//! cannot get past it.

mod common;

use nalgebra::Point2;
use nudge_motion::{
    Bounds, GoalRegion, PushConfig, PushPlan, RobotCylinder, Validity, ValidityConfig,
    certainly_unreachable, plan_push_among, plan_push_over,
};
use nudge_perception::{ObjectId, Prism};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const PUSHED_THROUGH: ObjectId = ObjectId(1);
const IN_DOORWAY: ObjectId = ObjectId(2);

/// A box from the floor to `top`.
fn block(id: u32, x0: f64, y0: f64, x1: f64, y1: f64, top: f64) -> Prism {
    common::boxed(id, x0, y0, x1, y1, 0.0, top)
}

/// `two-boxes-in-doorway` half way: a 9 × 4 m room split at x 4.4..4.6 with a 1.4 m doorway
/// (y 1.3..2.7); the south box (id 1, known to move) already pushed just through it, the north box
/// (id 2, 0.5 m square) still in the doorway's north half, sticking out 0.35 m on the robot's side;
/// a wardrobe (bolted) 1.05 m past the doorway, from the north wall down to y 1.95, so that while
/// the south box stands where it does no push of the north box opens the way. The goal at
/// (7.6, 0.9).
fn half_way() -> (Vec<Prism>, Validity, GoalRegion) {
    let prisms = vec![
        block(1, 4.85, 1.35, 5.35, 1.85, 0.7),
        block(2, 4.05, 2.1, 4.55, 2.6, 0.7),
        block(10, 4.4, 0.0, 4.6, 1.3, 2.0),
        block(11, 4.4, 2.7, 4.6, 4.0, 2.0),
        block(12, 5.65, 1.95, 6.25, 4.0, 1.5),
    ];
    let robot = RobotCylinder {
        radius: 0.35,
        height: 1.5,
    };
    let walls = Bounds::new(Point2::new(0.0, 0.0), Point2::new(9.0, 4.0)).expect("room");
    let validity =
        Validity::new(robot, walls, &prisms, ValidityConfig::default()).expect("validity");
    let goal = GoalRegion::new(Point2::new(7.6, 0.9), 0.2).expect("goal");
    (prisms, validity, goal)
}

/// The push test's configuration: the short pushes only.
fn test_config() -> PushConfig {
    let config = PushConfig::default();
    PushConfig {
        distances: config
            .distances
            .iter()
            .copied()
            .filter(|d| *d <= nudge_motion::push::SHORT_PUSHES + 1e-9)
            .collect(),
        ..config
    }
}

/// Whether, after `plan`, the goal is certainly unreachable even with the known mover gone.
fn shuts_the_way(plan: &PushPlan, validity: &Validity, goal: &GoalRegion) -> bool {
    let after = validity
        .with_moved(plan.object, &(plan.direction.into_inner() * plan.distance))
        .expect("moved")
        .without(&[PUSHED_THROUGH]);
    certainly_unreachable(&after, &plan.end, goal)
}

#[test]
fn a_step_that_opens_nothing_leaves_the_way_to_the_known_mover() {
    // Invariant: when no short push of the box left in a doorway opens the way, the push chosen does not leave it where the way stays shut even with the other box (known to move) gone — while the shortest push in face order, asked without movers, does.
    let (prisms, validity, goal) = half_way();
    let robot = Point2::new(3.9, 3.1);
    let config = test_config();
    let in_doorway = &prisms[1];
    let plain = plan_push_over(
        in_doorway,
        &validity,
        &robot,
        &goal,
        &config,
        None,
        &mut ChaCha8Rng::seed_from_u64(3),
    )
    .expect("a push");
    assert!(!plain.opens_path, "no short push opens the way: {plain:?}");
    assert!(
        shuts_the_way(&plain, &validity, &goal),
        "the fixture's shortest push in face order shuts the doorway: {:?} {:.1} m",
        plain.direction,
        plain.distance
    );
    let known = [PUSHED_THROUGH];
    let chosen = plan_push_among(
        in_doorway,
        &validity,
        &robot,
        &goal,
        &config,
        None,
        &known,
        &mut ChaCha8Rng::seed_from_u64(3),
    )
    .expect("a push");
    assert_eq!(chosen.object, IN_DOORWAY);
    assert!(
        !shuts_the_way(&chosen, &validity, &goal),
        "the step chosen leaves the way to the known mover: {:?} {:.1} m",
        chosen.direction,
        chosen.distance
    );
}
