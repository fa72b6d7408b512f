//! The paper's room (BRIEF geometry): no path at the start, pushing a chair opens one.

mod common;

use common::{CHAIR_1, CHAIR_2, MAT, TABLE};
use nudge_motion::{
    BlockingConfig, Budget, Planner, PushConfig, PushPlan, RrtConnect, StateValidity, Validity,
    blocking_obstacles, plan_push,
};
use nudge_perception::{ObjectId, Prism};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn prism(id: ObjectId) -> Prism {
    common::room_prisms()
        .into_iter()
        .find(|p| p.id == id)
        .expect("the room holds this object")
}

/// Checks what every push plan must satisfy, returns the world after the push.
fn check_push(plan: &PushPlan, v: &Validity) -> Validity {
    let stand = plan.stand_pose.translation.vector.into();
    assert!(v.is_free(&stand), "robot stands inside something");
    assert!(plan.approach.is_free(v), "approach collides");
    let offset = plan.direction.into_inner() * plan.distance;
    let object = v
        .obstacle(plan.object)
        .expect("pushed object is an obstacle");
    let swept = object.swept(&offset).expect("swept footprint");
    for other in v.obstacles().iter().filter(|o| o.id() != plan.object) {
        if other.heights_overlap(object) {
            assert!(
                other.distance_to_obstacle(&swept) > 0.0,
                "{} pushed into {}",
                plan.object,
                other.id()
            );
        }
    }
    assert!(swept.footprint().iter().all(|p| v.walls().contains(p)));
    // Hand within reach in base_link.
    let contact = nalgebra::Point2::new(plan.contact_point.x, plan.contact_point.y);
    let hand = plan.stand_pose.inverse_transform_point(&contact);
    assert!(
        (0.2..=0.8).contains(&hand.x) && (-0.4..=0.4).contains(&hand.y),
        "{hand:?}"
    );
    assert!((0.2..=1.2).contains(&plan.hand_height));
    let after = v.with_moved(plan.object, &offset).expect("object moves");
    if let Some(path) = &plan.path_after {
        assert!(path.is_free(&after));
        assert_eq!(path.first_collision(&after, 0.01), None);
    }
    after
}

#[test]
fn no_path_at_the_start() {
    // Invariant: every gap in the room is narrower than the robot, so no planner finds a path.
    let (v, p) = common::room();
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let out = RrtConnect::default().solve(&p, &v, Budget::iterations(20_000), &mut rng);
    assert_eq!(
        out,
        Err(nudge_motion::NoPath::NotFound { iterations: 20_000 })
    );
    // The mat lies on the floor: it does not block.
    assert_eq!(v.passable(), &[MAT]);
}

#[test]
fn removing_a_chair_opens_a_path() {
    // Invariant: the blocking query says removing either chair (or the table) opens a path.
    let (v, p) = common::room();
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    let reports = blocking_obstacles(
        &p,
        &v,
        &[TABLE, CHAIR_1, CHAIR_2, ObjectId(99)],
        &BlockingConfig::default(),
        &mut rng,
    );
    for r in &reports {
        println!("without {}: {:?} m", r.object, r.path_length());
    }
    assert_eq!(reports.len(), 3, "unknown ids are skipped");
    assert!(reports.iter().all(|r| r.opens_path()));
    let lengths: Vec<f64> = reports.iter().filter_map(|r| r.path_length()).collect();
    assert!(lengths.windows(2).all(|w| w[0] <= w[1]), "sorted by length");
}

#[test]
fn pushing_chair_1_opens_a_path() {
    // Invariant: the push planner finds a valid push of chair 1 that opens a path to the goal.
    let (v, p) = common::room();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let plan = plan_push(
        &prism(CHAIR_1),
        &v,
        &p.start(),
        p.goal(),
        &PushConfig::default(),
        &mut rng,
    )
    .expect("chair 1 can be pushed");
    println!(
        "chair-1: stand {:?} dir {:?} distance {:.1} hand {:.2} opens {} after {:?} m",
        plan.stand_pose.translation.vector,
        plan.direction.into_inner(),
        plan.distance,
        plan.hand_height,
        plan.opens_path,
        plan.path_after.as_ref().map(|p| p.length())
    );
    assert!(plan.opens_path);
    let after = check_push(&plan, &v);
    // After the push a path exists from the original start too.
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    let path = RrtConnect::default()
        .solve(&p, &after, Budget::iterations(20_000), &mut rng)
        .expect("a path after pushing chair 1");
    assert!(path.is_free(&after));
}

#[test]
fn pushes_of_chair_2_and_table_are_planned_valid_and_open_a_path() {
    // Invariant: the planner finds a push of chair 2 and of the table (the planner knows nothing of verdicts), each valid (free stand pose and approach, a sweep that hits nothing, the hand within reach) and each opening a path to the goal that is free once the object is moved.
    let (v, p) = common::room();
    for id in [CHAIR_2, TABLE] {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let plan = plan_push(
            &prism(id),
            &v,
            &p.start(),
            p.goal(),
            &PushConfig::default(),
            &mut rng,
        )
        .unwrap_or_else(|e| panic!("{id} can be pushed: {e}"));
        assert_eq!(plan.object, id);
        assert!(plan.opens_path, "{id}: the push opens a way");
        assert!(plan.path_after.is_some(), "{id}: with the path it opens");
        check_push(&plan, &v);
    }
}

#[test]
fn the_mat_cannot_be_pushed() {
    // Invariant: a prism that does not block (the mat) is not a push target.
    let (v, p) = common::room();
    let mut rng = ChaCha8Rng::seed_from_u64(6);
    let out = plan_push(
        &prism(MAT),
        &v,
        &p.start(),
        p.goal(),
        &PushConfig::default(),
        &mut rng,
    );
    assert_eq!(out, Err(nudge_motion::PushError::UnknownObject(MAT)));
}

#[test]
fn the_cheapest_crossing_goes_through_movable_candidates_only() {
    // Invariant: with the chairs passable and the table not, the cheapest path crosses only chairs.
    let (v, p) = common::room();
    let crossing = nudge_motion::cheapest_crossing(
        &p,
        &v,
        &[CHAIR_1, CHAIR_2],
        &nudge_motion::CrossingConfig::default(),
    )
    .expect("the chairs can be crossed");
    println!(
        "crossing {:?} cost {:.2} length {:.2}",
        crossing.crossed,
        crossing.cost,
        crossing.path.length()
    );
    assert!(!crossing.crossed.is_empty());
    assert!(
        crossing
            .crossed
            .iter()
            .all(|id| [CHAIR_1, CHAIR_2].contains(id))
    );
    assert!(crossing.cost >= crossing.path.length());
    // Everything passable: the straight line through the table is cheapest.
    let all = nudge_motion::cheapest_crossing(
        &p,
        &v,
        &[TABLE, CHAIR_1, CHAIR_2],
        &nudge_motion::CrossingConfig::default(),
    )
    .expect("all passable");
    println!("all passable: {:?} cost {:.2}", all.crossed, all.cost);
    assert!(all.cost <= crossing.cost);
    // Nothing passable: no way through.
    let none =
        nudge_motion::cheapest_crossing(&p, &v, &[], &nudge_motion::CrossingConfig::default());
    assert!(matches!(none, Err(nudge_motion::NoPath::NotFound { .. })));
}

#[test]
fn the_push_that_opens_the_way_is_longer_by_the_margin_and_its_sweep_keeps_clear() {
    // Invariant: the planned push is the shortest that opens the way plus the distance margin (an object that turns as it slides ends short), and its sweep keeps at least the sweep clearance from every other obstacle.
    let (v, p) = common::room();
    let exact = PushConfig {
        distance_margin: 0.0,
        ..PushConfig::default()
    };
    let config = PushConfig::default();
    let plan_with = |config: &PushConfig| {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        plan_push(&prism(CHAIR_1), &v, &p.start(), p.goal(), config, &mut rng)
            .expect("chair 1 can be pushed")
    };
    let (shortest, planned) = (plan_with(&exact), plan_with(&config));
    assert!(shortest.opens_path && planned.opens_path);
    assert!(
        shortest.direction.angle(&planned.direction) < 1e-9,
        "{:?} vs {:?}",
        shortest.direction,
        planned.direction
    );
    assert!(
        (planned.distance - shortest.distance - config.distance_margin).abs() < 1e-9,
        "{} vs {}",
        planned.distance,
        shortest.distance
    );
    let object = v.obstacle(CHAIR_1).expect("chair 1 is an obstacle");
    let swept = object
        .swept(&(planned.direction.into_inner() * planned.distance))
        .expect("swept footprint");
    for other in v.obstacles().iter().filter(|o| o.id() != CHAIR_1) {
        if other.heights_overlap(object) {
            assert!(other.distance_to_obstacle(&swept) > config.sweep_clearance);
        }
    }
    check_push(&planned, &v);
}

/// Floor seen everywhere but in a box (x0..x1, y0..y1).
struct SeenBut(f64, f64, f64, f64);

impl nudge_motion::SeenFloor for SeenBut {
    fn seen(&self, p: &nalgebra::Point2<f64>) -> bool {
        !(p.x >= self.0 && p.x <= self.2 && p.y >= self.1 && p.y <= self.3)
    }
}

#[test]
fn a_push_keeps_to_seen_floor_or_the_objects_own_shadow() {
    // Invariant: with the floor behind chair 1 unseen, its push is planned when that floor lies within the chair's own shadow (behind it from the eye), refused with UnseenFloor when the shadow is shorter than the sweep, and refused the same way when the robot would stand on unseen floor; with floor unseen only farther on, a short push that does not open the way is planned and says a longer one was refused for unseen floor; with everything seen it is the plan made without a floor check.
    let (v, p) = common::room();
    let config = PushConfig::default();
    let chair = prism(CHAIR_1);
    let plan_seen_from = |seen: &dyn nudge_motion::SeenFloor, own_shadow: f64, eye| {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        nudge_motion::plan_push_over(
            &chair,
            &v,
            &p.start(),
            p.goal(),
            &config,
            Some(nudge_motion::FloorCheck {
                seen,
                own_shadow,
                eye,
            }),
            &mut rng,
        )
    };
    // Looked at from straight in front, where the sweep behind it is all in its shadow.
    let in_front = nalgebra::Point2::new(1.0, 0.85);
    let plan_with = |seen: &dyn nudge_motion::SeenFloor, own_shadow: f64| {
        plan_seen_from(seen, own_shadow, in_front)
    };
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let unchecked = plan_push(&chair, &v, &p.start(), p.goal(), &config, &mut rng).expect("a push");
    let everything = nudge_motion::AllSeen;
    assert_eq!(plan_with(&everything, 0.0).as_ref(), Ok(&unchecked));
    // The floor behind the chair (beyond its far face, x > 4.05) is unseen.
    let behind = SeenBut(4.06, 0.0, 6.0, 3.6);
    let shadowed = plan_with(&behind, 2.0).expect("pushed into its own shadow");
    assert!(shadowed.opens_path);
    assert_eq!(
        plan_with(&behind, 0.05),
        Err(nudge_motion::PushError::UnseenFloor(CHAIR_1))
    );
    // Seen from beyond the chair, that floor lies before it, not behind it: not its own shadow.
    assert_eq!(
        plan_seen_from(&behind, 2.0, nalgebra::Point2::new(4.6, 0.85)),
        Err(nudge_motion::PushError::UnseenFloor(CHAIR_1))
    );
    // The floor unseen only from 0.45 m beyond the chair's far face: the short pushes are planned,
    // none opens the way, and the plan says a longer one was refused for unseen floor.
    let farther = SeenBut(4.5, 0.0, 6.0, 3.6);
    let short = plan_with(&farther, 0.05).expect("a short push");
    assert!(!short.opens_path && short.unseen_refused, "{short:?}");
    assert!(!unchecked.unseen_refused);
    // The floor in front of the chair, where the robot stands, is unseen.
    let front = SeenBut(2.5, 0.0, 3.5, 1.6);
    assert_eq!(
        plan_with(&front, 10.0),
        Err(nudge_motion::PushError::UnseenFloor(CHAIR_1))
    );
}
