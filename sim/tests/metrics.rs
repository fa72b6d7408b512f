//! The standard metrics against ground truth: the ideal path's length against geometry, the hand's
//! work against friction times distance, and SPL, effort and INS on a whole run.
mod world_common;

use nalgebra::{Point2, Point3};
use nudge_executive::robot::{ActionStatus, Arm, Clock, GuardedMove, WristSensor};
use nudge_sim::adapter::SimRobot;
use nudge_sim::metrics::ideal_path::ideal_path_length;
use nudge_sim::metrics::{Start, measure, path_efficiency};
use nudge_sim::world::World;
use world_common::*;

fn ideal(scenario_text: &str) -> Option<f64> {
    let s = scenario(scenario_text);
    let world = World::new(&s, 1).expect("world");
    let start = Point2::new(s.robot.start[0], s.robot.start[1]);
    let goal = Point2::new(s.goal.position[0], s.goal.position[1]);
    ideal_path_length(&world, start, goal, s.goal.tolerance, s.robot.radius())
}

/// A 6 × 4 m room, the robot at (1, 2), the goal at (5, 2), and `objects` (TOML).
fn room(objects: &str) -> String {
    format!(
        "name = \"m\"\n[room]\nsize = [6.0, 4.0]\n[robot]\nstart = [1.0, 2.0, 0.0]\n[goal]\nposition = [5.0, 2.0]\ntolerance = 0.2\n{objects}"
    )
}

/// A 0.2 m thick wall across the room at x = 3 from y = `from` to y = `to`, bolted (TOML).
fn wall(name: &str, from: f64, to: f64) -> String {
    format!(
        "[[object]]\nname = \"{name}\"\nkind = \"box\"\nposition = [3.0, {}]\nsize = [0.2, {}, 1.0]\nmass = 100.0\nfixed = true\ncolour = [90, 90, 90]\n",
        (from + to) / 2.0,
        to - from
    )
}

#[test]
fn the_ideal_path_in_an_open_room_is_the_straight_line_into_the_goal_disc() {
    // Invariant: with nothing in the way, L* is the distance to the goal disc's edge (4 − 0.2 m), never shorter and at most 2.7 % longer (the 16-neighbour grid's worst heading).
    let l = ideal(&room("")).expect("a way");
    assert!((3.8..=3.8 * 1.027 + 0.05).contains(&l), "{l:.3} m");
}

#[test]
fn the_ideal_path_ignores_movable_objects_and_goes_round_static_ones() {
    // Invariant: a movable box across the straight line leaves L* as in the open room; a bolted wall with a 1.2 m door at one end makes it longer than the detour's lower bound; walls that shut the goal off give no ideal path.
    let open = ideal(&room("")).expect("open");
    let movable = "[[object]]\nname = \"box\"\nkind = \"box\"\nposition = [3.0, 2.0]\nsize = [0.6, 0.6, 0.6]\nmass = 3.0\nfriction = 0.4\ncolour = [200, 60, 60]\n";
    let with_box = ideal(&room(movable)).expect("way with the box");
    assert!((with_box - open).abs() < 1e-9, "{with_box} vs {open}");
    // Door from y = 2.8 to 4.0 (the wall runs 0..2.8).
    let walled = ideal(&room(&wall("w", 0.0, 2.8))).expect("way through the door");
    // Through the door the centre must pass x = 3 at y ≥ 2.8 + radius 0.35.
    let via = Point2::new(3.0, 3.15);
    let lower = (via - Point2::new(1.0, 2.0)).norm() + (Point2::new(5.0, 2.0) - via).norm() - 0.2;
    assert!(walled >= lower - 0.05, "{walled:.3} m below {lower:.3} m");
    assert!(
        walled <= lower * 1.05,
        "{walled:.3} m far above {lower:.3} m"
    );
    let shut = format!("{}{}", wall("a", 0.0, 2.0), wall("b", 2.0, 4.0));
    assert_eq!(ideal(&room(&shut)), None);
}

#[test]
fn spl_is_zero_on_failure_and_never_above_one() {
    // Invariant: path efficiency is S · L* / max(L*, L): 0 without success, 1 at most, L*/L when longer.
    assert_eq!(path_efficiency(false, 4.0, 4.0), 0.0);
    assert_eq!(path_efficiency(true, 4.0, 3.0), 1.0);
    assert!((path_efficiency(true, 4.0, 8.0) - 0.5).abs() < 1e-12);
}

/// Settles the world, tares the wrist and slides [`TEST_CHAIR`] with one guarded stroke of the hand
/// (0.35 m at 2 cm/s, 30 N limit), until the stroke ends.
fn slide_test_chair(robot: &mut SimRobot) {
    robot.advance(0.5).expect("settle");
    robot.tare().expect("tare");
    robot
        .start_guarded_move(GuardedMove {
            from: Point3::new(0.4, 0.0, 0.43),
            to: Point3::new(0.75, 0.0, 0.43),
            speed: 0.02,
            force_limit: 30.0,
            acceleration: None,
        })
        .expect("move accepted");
    for _ in 0..600 {
        robot.advance(0.05).expect("advance");
        if matches!(robot.hand_status().expect("status"), ActionStatus::Done(_)) {
            break;
        }
    }
}

#[test]
fn pushing_a_chair_costs_its_friction_times_the_distance_in_hand_work() {
    // Invariant: the hand's work on a chair it slides is μ m g × the chair's displacement, within 15 %; the impulse is at least μ m g × the sliding time's lower bound; the robot walked nowhere.
    let mut robot = SimRobot::new(&robot_and(TEST_CHAIR), 3).expect("world");
    let before = robot.world().object_pose(0).expect("chair");
    slide_test_chair(&mut robot);
    let after = robot.world().object_pose(0).expect("chair");
    let moved = (after.translation.vector - before.translation.vector)
        .xy()
        .norm();
    assert!(moved > 0.1, "the chair slid {moved:.3} m");
    let effort = robot.world().effort();
    let expected = TEST_CHAIR_MU_M_G * moved;
    assert!(
        (effort.hand_work - expected).abs() < 0.15 * expected,
        "work {:.2} J vs μmg·d {expected:.2} J",
        effort.hand_work
    );
    assert!(
        effort.hand_impulse >= TEST_CHAIR_MU_M_G * moved / 0.02 * 0.85,
        "impulse {:.2} N·s",
        effort.hand_impulse
    );
    assert!(effort.walked < 1e-9, "walked {}", effort.walked);
}

#[test]
fn the_paper_run_scores_a_high_spl_and_ins_with_its_one_chair_moved() {
    // Invariant: the paper's room reaches the goal with SPL in (0.5, 1], INS in (0.5, 1], the displaced mass that of the chair it clears (4–12 kg·m for a ≈4–8 kg chair moved ≈1 m), no verdict mistakes, and no people to touch.
    let s = scenario(KAKIUCHI_ROOM);
    let mut runner = nudge_sim::run::runner(
        &s,
        s.seed,
        nudge_executive::CandidatePolicy::Nearest,
        nudge_executive::record::NullObserver,
    )
    .expect("runner");
    let start = Start::of(&s, runner.robot().world());
    let report = runner.run();
    let (robot, _) = runner.into_parts();
    let scored = nudge_sim::score::score(&report, &robot);
    let m = measure(&start, &report, robot.world(), &scored);
    assert!(m.success);
    let spl = m.spl.expect("a way exists");
    assert!(spl > 0.5 && spl <= 1.0, "SPL {spl}");
    let ins = m.ins.expect("INS");
    assert!(ins > 0.5 && ins <= 1.0, "INS {ins}");
    assert!(
        m.displaced > 1.0 && m.displaced < 12.0,
        "displaced {}",
        m.displaced
    );
    assert_eq!((m.false_static, m.false_movable), (0, 0));
    assert_eq!(m.people_contacts, None);
    assert!(m.walked >= m.ideal_path.expect("ideal") * 0.9, "{m:?}");
}

#[test]
fn a_person_walking_into_the_standing_robot_is_one_contact_and_no_hand_work() {
    // Invariant: a person whose way runs through the standing robot touches it (at least one contact counted, each contact once), and the robot, which did nothing, spent no hand work and walked nowhere.
    let s = scenario(
        r#"
name = "bump"
[room]
size = [6.0, 3.6]
[robot]
start = [3.0, 1.8, 0.0]
[goal]
position = [5.0, 1.8]
[[actor]]
name = "walker"
waypoints = [[1.0, 1.8], [5.0, 1.8]]
speed = 0.5
yields = false
"#,
    );
    let mut world = World::new(&s, 1).expect("world");
    for _ in 0..100 {
        world.advance(0.1).expect("advance");
    }
    let effort = world.effort();
    assert!(effort.people_contacts >= 1, "{effort:?}");
    assert!(
        effort.people_contacts <= 3,
        "one pass, not every step: {effort:?}"
    );
    assert!(
        effort.hand_work < 1e-9 && effort.walked < 1e-9,
        "{effort:?}"
    );
}

#[test]
fn a_person_walking_into_a_chair_the_hand_pushes_is_counted_as_a_pushed_object_contact() {
    // Invariant: while the hand slides a chair, a person whose way runs across the chair's far side touches it, and the run counts that contact of a pushed object with a person (each contact once); the robot's own body and hand touch nobody.
    // A walker crossing just beyond the chair's far side (x 2.05) once the stroke is under way.
    let s = robot_and(&format!(
        "{TEST_CHAIR}\n[[actor]]\nname = \"walker\"\nwaypoints = [[2.25, 0.3], [2.25, 3.3]]\nspeed = 0.4\nstart_time = 2.0"
    ));
    let mut robot = SimRobot::new(&s, 3).expect("world");
    slide_test_chair(&mut robot);
    let effort = robot.world().effort();
    assert!(effort.pushed_into_people >= 1, "{effort:?}");
    assert!(
        effort.pushed_into_people <= 3,
        "one pass, not every step: {effort:?}"
    );
    assert_eq!(effort.people_contacts, 0, "{effort:?}");
}

#[test]
fn an_obstacle_kept_where_nothing_stands_is_a_ghost_and_one_on_an_object_or_a_wall_is_not() {
    // Invariant: ghosts are counted against the truth: an obstacle over the chair (even a hull a few centimetres off its side), over the room's wall or over a person is not a ghost; one over empty floor, or a sliver 0.2 m off the chair, is.
    use nudge_sim::metrics::ghosts;
    use nudge_sim::truth::Truth;
    let s = robot_and(&format!(
        "{TEST_CHAIR}\n[[actor]]\nname = \"bystander\"\nwaypoints = [[3.5, 1.0]]\nspeed = 0.5"
    ));
    let world = World::new(&s, 1).expect("world");
    let truth = Truth::new(&world);
    // The chair stands on x 1.55..2.05, y 1.55..2.05.
    let on_chair = rectangle(1, 1.6, 2.0, 1.6, 2.0);
    let beside_chair = rectangle(2, 2.1, 2.14, 1.6, 2.0);
    let on_floor = rectangle(3, 4.0, 4.5, 2.5, 3.0);
    let off_chair = rectangle(4, 2.3, 2.35, 1.6, 2.0);
    let on_wall = rectangle(5, 0.5, 3.0, -0.02, 0.03);
    let on_person = rectangle(6, 3.4, 3.6, 0.9, 1.1);
    assert!(!ghosts::is_ghost(&on_chair, &truth));
    assert!(
        !ghosts::is_ghost(&beside_chair, &truth),
        "a hull a few cm off"
    );
    assert!(ghosts::is_ghost(&on_floor, &truth));
    assert!(ghosts::is_ghost(&off_chair, &truth), "0.25 m off the chair");
    assert!(!ghosts::is_ghost(&on_wall, &truth));
    assert!(!ghosts::is_ghost(&on_person, &truth));
    let all = [
        on_chair,
        beside_chair,
        on_floor,
        off_chair,
        on_wall,
        on_person,
    ];
    assert_eq!(ghosts::count(&all, &truth), 2);
}
