//! End to end in the simulation: the executive against the paper's room and its variants, scored
//! against ground truth.

use nalgebra::{Isometry3, Point2, Point3, Vector2, Vector3};
use nudge_executive::record::{NullObserver, Observer, RobotFrames};
use nudge_executive::runner::GridSetup;
use nudge_executive::{CandidatePolicy, Edge, Purpose, PushIntent, RunReport, State, Verdict};
use nudge_perception::grid::{CellClass, CellIndex, Evidence};
use nudge_perception::{ColourCloud, ObjectId};
use nudge_sim::actors::Plan;
use nudge_sim::adapter::SimRobot;
use nudge_sim::scenario::Scenario;
use nudge_sim::truth::{MOVABLE_MARGIN, Movability, Truth};
use nudge_tests::print_timeline;
use nudge_tests::truth::{Scored, score};

fn run(name: &str, policy: CandidatePolicy) -> (RunReport, Vec<Scored>) {
    let scenario = nudge_tests::scenario(name).expect("scenario loads");
    let (report, robot): (RunReport, SimRobot) =
        nudge_tests::run(&scenario, scenario.seed, policy, NullObserver).expect("world builds");
    let scored = score(&report, &robot);
    println!(
        "{name} ({policy:?}): {} after {:.1} s robot time",
        report.outcome.name(),
        report.robot_time
    );
    print_timeline(&report);
    for s in &scored {
        println!(
            "  {} = {:?}: {:?} ({})",
            s.id,
            s.object,
            s.verdict,
            if s.correct { "right" } else { "WRONG" }
        );
    }
    (report, scored)
}

fn assert_all_correct(scored: &[Scored]) {
    for s in scored {
        assert!(
            s.correct,
            "{} ({:?}) classified {:?} against ground truth",
            s.id, s.object, s.verdict
        );
    }
}

fn assert_force_within_limit(report: &RunReport) {
    for t in &report.knowledge.explanation.tests {
        assert!(
            t.peak_force <= 1.1 * 20.0,
            "push test on {} peaked at {:.1} N",
            t.object,
            t.peak_force
        );
    }
}

/// Every push test of an object the truth calls movable peaked under the midpoint between the
/// object's sliding force (μmg) and the force limit: the test's first contact leaves a movable
/// object margin, it does not read it as static by a transient.
fn assert_movable_peaks_have_margin(scenario: &Scenario, report: &RunReport, scored: &[Scored]) {
    let limit = scenario.robot.model().force.test_limit;
    for t in &report.knowledge.explanation.tests {
        let Some(spec) = scored
            .iter()
            .find(|s| s.id == t.object)
            .and_then(|s| s.object.as_deref())
            .and_then(|n| scenario.objects.iter().find(|o| o.name == n))
        else {
            continue;
        };
        if spec.fixed || spec.elevation > 0.0 || spec.sliding_force() >= MOVABLE_MARGIN * limit {
            continue;
        }
        let midpoint = (spec.sliding_force() + limit) / 2.0;
        assert!(
            t.peak_force < midpoint,
            "push test of movable {} (μmg {:.1} N) peaked at {:.1} N, over the midpoint {midpoint:.1} N",
            spec.name,
            spec.sliding_force(),
            t.peak_force
        );
    }
}

fn named<'a>(scored: &'a [Scored], name: &str) -> Option<&'a Scored> {
    scored.iter().find(|s| s.object.as_deref() == Some(name))
}

#[test]
fn the_papers_room_reaches_the_goal_testing_the_table_first() {
    // Invariant: policy nearest tests the table first (as the paper did), finds it static, finds a chair movable, reaches the goal; every verdict matches truth.
    let (report, scored) = run("kakiuchi-room", CandidatePolicy::Nearest);
    assert_eq!(report.outcome, State::Goal);
    assert_all_correct(&scored);
    assert_force_within_limit(&report);
    let scenario = nudge_tests::scenario("kakiuchi-room").expect("scenario loads");
    assert_movable_peaks_have_margin(&scenario, &report, &scored);
    let tests = &report.knowledge.explanation.tests;
    let first = tests.first().expect("at least one push test");
    assert_eq!(
        named(&scored, "table").map(|s| s.id),
        Some(first.object),
        "the table is tested first"
    );
    assert!(matches!(
        named(&scored, "table").map(|s| &s.verdict),
        Some(Verdict::Static { .. })
    ));
    assert!(
        scored.iter().any(
            |s| s.object.as_deref().is_some_and(|n| n.starts_with("chair"))
                && s.verdict == Verdict::Movable
        ),
        "a chair is found movable"
    );
    assert!(
        report.timeline.iter().any(|t| t.edge == Edge::Cleared),
        "the chair is pushed out of the way"
    );
}

#[test]
fn a_light_tall_box_is_push_tested_below_tipping_and_found_movable_with_margin() {
    // Invariant: with the push test below tipping, the test of a 2 kg box 0.7 m tall on a floor of μ 0.7 (μmg 13.7 N; pushed just below its top it tips at 9 N and locks at the 20 N limit leaning) pushes it low enough to slide before it tips: it is found movable, as the truth has it, with every test's peak under the midpoint between μmg and the limit.
    let scenario = nudge_sim::scenario::push_test_corridor(2.0, 0.7).expect("the corridor loads");
    let mut config = nudge_sim::run::run_config(&scenario, 1, CandidatePolicy::Nearest);
    config.push.test_below_tipping = true;
    let robot = SimRobot::new(&scenario, 1).expect("world builds");
    let mut runner = nudge_executive::Runner::new(robot, NullObserver, config);
    let report = runner.run();
    let (robot, _) = runner.into_parts();
    let scored = score(&report, &robot);
    print_timeline(&report);
    assert_all_correct(&scored);
    assert!(
        !report.knowledge.explanation.tests.is_empty(),
        "the box is push-tested"
    );
    assert_eq!(
        named(&scored, "box").map(|s| &s.verdict),
        Some(&Verdict::Movable)
    );
    assert_movable_peaks_have_margin(&scenario, &report, &scored);
}

#[test]
fn a_box_flush_beside_a_bolted_block_of_its_colour_is_split_off_by_its_push_test() {
    // Invariant: where perception took a light box and the bolted block beside it for one obstacle,
    // the push test that moved the box leaves the box movable and the block an obstacle of its own,
    // untested, where the block truly stands (before, the block went with the box).
    let (report, scored) = run("box-beside-its-twin", CandidatePolicy::Nearest);
    assert_eq!(report.outcome, State::Goal);
    assert_all_correct(&scored);
    assert_eq!(report.knowledge.explanation.tests.len(), 1);
    assert_eq!(
        named(&scored, "box").map(|s| &s.verdict),
        Some(&Verdict::Movable)
    );
    let block_centre = Point2::new(4.5, 1.525);
    let block = report
        .obstacles
        .iter()
        .find(|p| p.contains_xy(&block_centre))
        .expect("an obstacle stands on the block");
    assert!(
        !report
            .knowledge
            .explanation
            .verdicts
            .contains_key(&block.id),
        "the block was never tested"
    );
    let tested = report.knowledge.explanation.tests[0].object;
    assert_ne!(block.id, tested, "the block is not the object tested");
}

#[test]
fn the_blocking_policy_needs_no_more_push_tests_than_nearest() {
    // Invariant: policy blocking reaches the goal in the paper's room with no more push tests than nearest, all verdicts right.
    let (nearest, _) = run("kakiuchi-room", CandidatePolicy::Nearest);
    let (blocking, scored) = run("kakiuchi-room", CandidatePolicy::Blocking);
    assert_eq!(blocking.outcome, State::Goal);
    assert_all_correct(&scored);
    assert_force_within_limit(&blocking);
    let (b, n) = (blocking.knowledge.push_tests, nearest.knowledge.push_tests);
    println!("push tests: blocking {b}, nearest {n}");
    assert!(b <= n, "blocking took {b} push tests, nearest {n}");
}

#[test]
fn the_blocking_policy_skips_the_nearest_obstacle_when_it_blocks_nothing() {
    // Invariant: with a heavy cabinet beside the start and off every way, nearest tests it first and blocking never does, so blocking needs fewer push tests; both reach the goal with every verdict right.
    let (nearest, scored_n) = run("cluttered-room", CandidatePolicy::Nearest);
    let (blocking, scored_b) = run("cluttered-room", CandidatePolicy::Blocking);
    for (report, scored) in [(&nearest, &scored_n), (&blocking, &scored_b)] {
        assert_eq!(report.outcome, State::Goal);
        assert_all_correct(scored);
        assert_force_within_limit(report);
    }
    let first = nearest
        .knowledge
        .explanation
        .tests
        .first()
        .map(|t| t.object);
    assert_eq!(
        first,
        named(&scored_n, "cabinet").map(|s| s.id),
        "nearest tests the cabinet first"
    );
    assert!(
        named(&scored_b, "cabinet").is_none(),
        "blocking never tests the cabinet"
    );
    let (b, n) = (blocking.knowledge.push_tests, nearest.knowledge.push_tests);
    println!("push tests: blocking {b}, nearest {n}");
    assert!(b < n, "blocking took {b} push tests, nearest {n}");
}

#[test]
fn an_all_static_room_ends_in_no_path_with_every_blocking_object_tested() {
    // Invariant: with nothing movable the run ends in NoPathToGoal, every blocking object tested and found static.
    let (report, scored) = run("all-static", CandidatePolicy::Nearest);
    assert!(
        matches!(report.outcome, State::NoPathToGoal(_)),
        "{:?}",
        report.outcome.name()
    );
    assert_all_correct(&scored);
    assert_force_within_limit(&report);
    for name in ["table", "chair-1", "chair-2"] {
        let s = named(&scored, name).unwrap_or_else(|| panic!("{name} was not tested"));
        assert!(
            matches!(s.verdict, Verdict::Static { .. }),
            "{name}: {:?}",
            s.verdict
        );
    }
}

#[test]
fn an_open_room_reaches_the_goal_without_a_push() {
    // Invariant: when a path exists the robot walks to the goal and pushes nothing.
    let (report, scored) = run("open-room", CandidatePolicy::Nearest);
    assert_eq!(report.outcome, State::Goal);
    assert!(scored.is_empty() && report.knowledge.push_tests == 0);
}

#[test]
fn tight_stand_poses_are_reached_with_less_clearance() {
    // Invariant: on the noise seeds where perception's hulls leave no stand pose reachable with full clearance after the table test (7 and 9), the push is planned with less, so all-static still tests every blocking object and cluttered-room still reaches the goal.
    for seed in [7, 9] {
        let all_static = nudge_tests::scenario("all-static").expect("scenario loads");
        let (report, robot) =
            nudge_tests::run(&all_static, seed, CandidatePolicy::Nearest, NullObserver)
                .expect("world builds");
        let scored = score(&report, &robot);
        assert!(
            matches!(report.outcome, State::NoPathToGoal(_)),
            "seed {seed}"
        );
        assert_all_correct(&scored);
        for name in ["table", "chair-1", "chair-2"] {
            assert!(
                named(&scored, name).is_some(),
                "seed {seed}: {name} was not tested"
            );
        }
        let cluttered = nudge_tests::scenario("cluttered-room").expect("scenario loads");
        let (report, robot) =
            nudge_tests::run(&cluttered, seed, CandidatePolicy::Blocking, NullObserver)
                .expect("world builds");
        assert_eq!(report.outcome, State::Goal, "seed {seed}");
        assert_all_correct(&score(&report, &robot));
    }
}

/// Records where the robot's base was at every tick.
#[derive(Default)]
struct Track(Vec<(f64, Point2<f64>)>);

impl Observer for Track {
    fn frames(&mut self, stamp: f64, frames: &RobotFrames) {
        self.0
            .push((stamp, Point2::from(frames.base.translation.vector)));
    }
}

/// Runs a scenario with a person (its first actor), asserting the robot never came closer to them than
/// the two radii; returns the report and its edges.
fn person_run(name: &str) -> (RunReport, Vec<Edge>) {
    let scenario = nudge_tests::scenario(name).expect("scenario loads");
    let (report, _, track) = nudge_sim::run::run(
        &scenario,
        scenario.seed,
        CandidatePolicy::Nearest,
        Track::default(),
    )
    .expect("world builds");
    print_timeline(&report);
    let person = &scenario.actors[0];
    let plan = Plan::new(person).expect("valid actor");
    let closest = track
        .0
        .iter()
        .map(|(t, p)| (plan.state_at(*t).position - p).norm())
        .fold(f64::INFINITY, f64::min);
    println!("closest approach to the person: {closest:.2} m");
    assert!(
        closest >= scenario.robot.radius() + person.radius,
        "{closest:.2} m"
    );
    let edges = report.timeline.iter().map(|t| t.edge).collect();
    (report, edges)
}

#[test]
fn a_person_stepping_onto_the_path_makes_the_robot_replan_around_them() {
    // Invariant: when a person stops on the path being walked, the grid's replanning flag stops the walk, the robot looks again and reaches the goal around them, never closer than the two radii and never blocked.
    let (report, edges) = person_run("person-crossing");
    assert_eq!(report.outcome, State::Goal);
    assert!(
        edges.contains(&Edge::PathInvalidated),
        "the grid flagged the path"
    );
    assert!(
        !edges.contains(&Edge::WalkBlocked),
        "the walk never ran into the person"
    );
}

#[test]
fn a_person_standing_in_the_only_doorway_is_waited_for_not_given_up_on() {
    // Invariant: when the only way is blocked by a person the grid saw walk in, the robot looks again instead of ending in NoPathToGoal, pushes nothing, never comes closer than the two radii, and goes through once the person has walked on.
    let (report, edges) = person_run("person-in-doorway");
    assert_eq!(report.outcome, State::Goal);
    assert_eq!(report.knowledge.push_tests, 0);
    assert!(edges.contains(&Edge::WaitForMover), "the robot waited");
}

/// Records what a run in the cart scenario needs checked: the base track, every state entered after
/// each edge (with its stamp), the stamps of the clouds taken, and the peak force of every clearing
/// push.
#[derive(Default)]
struct Clearing {
    track: Vec<(f64, Point2<f64>)>,
    steps: Vec<(f64, Edge, State)>,
    clouds: Vec<f64>,
    clear_forces: Vec<(ObjectId, f64)>,
}

impl Observer for Clearing {
    fn frames(&mut self, stamp: f64, frames: &RobotFrames) {
        self.track
            .push((stamp, Point2::from(frames.base.translation.vector)));
    }

    fn transition(&mut self, stamp: f64, _from: Option<&State>, edge: Edge, to: &State) {
        self.steps.push((stamp, edge, to.clone()));
    }

    fn cloud(&mut self, cloud: &ColourCloud) {
        self.clouds.push(cloud.stamp());
    }

    fn push(&mut self, _stamp: f64, intent: &PushIntent, force: Option<Vector2<f64>>) {
        // The plan is reported without a force, the push test and the clearing push with their peak.
        if let Some(f) = force {
            self.clear_forces.push((intent.target, f.norm()));
        }
    }
}

#[test]
fn a_cart_seen_left_in_the_doorway_is_cleared_without_a_push_test() {
    // Invariant: an object the grid saw being pulled into the only doorway and left there is movable on passive evidence alone: after its waits the robot pushes it out of the way as KnownMovable with no push test on it, the cart (truly pushable under 20 N) moves, the clearing push stays under its limit, nobody is touched, and the robot ends at the goal.
    let scenario = nudge_tests::scenario("cart-left-in-doorway").expect("scenario loads");
    let (report, robot, seen) = nudge_sim::run::run(
        &scenario,
        scenario.seed,
        CandidatePolicy::Nearest,
        Clearing::default(),
    )
    .expect("world builds");
    for (stamp, edge, to) in &seen.steps {
        println!("  {stamp:7.2} s  {edge:?} -> {}", to.name());
    }
    assert_eq!(report.outcome, State::Goal);
    assert_eq!(report.knowledge.push_tests, 0, "no push test at all");
    assert!(
        !seen
            .steps
            .iter()
            .any(|(_, _, s)| matches!(s, State::PushTest { .. })),
        "no PushTest state"
    );
    // The robot waited for the cart first (it was seen moving), then cleared it without a test.
    let edges: Vec<Edge> = seen.steps.iter().map(|(_, e, _)| *e).collect();
    let flagged = seen
        .steps
        .iter()
        .find(|(_, e, _)| *e == Edge::PathInvalidated)
        .map(|(t, _, _)| *t)
        .expect("the grid stopped the walk");
    // Standing, it watched ahead at the settle rate before looking around (which takes 15 views).
    let setup = GridSetup::default();
    let watched = seen
        .clouds
        .iter()
        .filter(|t| **t > flagged && **t <= flagged + setup.settle_time + 1e-6)
        .count();
    println!(
        "{watched} frames in the {} s after the flag at {flagged:.2} s",
        setup.settle_time
    );
    assert!(watched as f64 >= 0.9 * setup.settle_time / setup.settle_period);
    assert!(
        edges.contains(&Edge::WaitForMover),
        "the robot looked again first"
    );
    let cleared: Vec<ObjectId> = seen
        .steps
        .iter()
        .filter_map(|(_, e, s)| match (e, s) {
            (
                Edge::KnownMovable,
                State::ApproachPushPose {
                    target,
                    purpose: Purpose::Clear,
                    ..
                },
            ) => Some(*target),
            _ => None,
        })
        .collect();
    assert_eq!(cleared.len(), 1, "one KnownMovable clearing: {cleared:?}");
    let cart_id = cleared[0];

    // Ground truth: the object cleared is the cart, it is truly pushable, and the push moved it out of
    // the doorway's approach, from where the person left it (3.0, 1.8) (see the scenario's header).
    let truth = Truth::new(robot.world());
    let cart = robot
        .world()
        .objects()
        .iter()
        .position(|(o, _)| o.name == "cart")
        .expect("the scenario has a cart");
    assert_eq!(truth.movability(cart), Some(Movability::Movable));
    let now = truth.object_pose(cart).expect("cart has a pose");
    let now = Point2::new(now.translation.x, now.translation.y);
    let moved = (now - Point2::new(3.0, 1.8)).norm();
    println!(
        "the cart rests at ({:.2}, {:.2}), {moved:.2} m from where it was left",
        now.x, now.y
    );
    assert!(moved >= 0.3, "the cart moved only {moved:.2} m");
    let prism = report
        .obstacles
        .iter()
        .find(|p| p.id == cart_id)
        .expect("the cleared obstacle is still known");
    assert!(
        prism.contains_xy(&now),
        "the obstacle cleared, {cart_id}, is where the cart truly is"
    );

    // The clearing push is the grid's first active evidence on the cart (push test 0: none): where
    // the cart now stands is Movable by it.
    let grid = report.grid.as_ref().expect("the run keeps a grid");
    let marked = grid
        .object_cells(cart_id)
        .iter()
        .filter(|c| {
            grid.cell(**c).is_some_and(|i| {
                i.class == CellClass::Movable
                    && i.evidence
                        == Evidence::Active {
                            object: cart_id,
                            push_test: 0,
                        }
            })
        })
        .count();
    println!("{marked} cells hold the cart as moved by the clearing push");
    assert!(marked > 0);
    assert!(
        grid.class_at(now) == Some(CellClass::Movable),
        "the cart's true centre lies in a Movable cell"
    );

    // The clearing push stayed under its limit (it never jammed); nothing was pushed but the cart.
    let limit = nudge_executive::RobotModel::default().force.clear_limit;
    assert!(!seen.clear_forces.is_empty());
    for (id, peak) in &seen.clear_forces {
        println!("clearing push on {id}: peak {peak:.1} N");
        assert_eq!(*id, cart_id);
        assert!(*peak <= limit, "{peak:.1} N over the {limit} N limit");
    }
    assert!(!edges.contains(&Edge::Jammed));

    // Nobody was touched, and the robot truly stands at the goal.
    let person = &scenario.actors[0];
    let plan = Plan::new(person).expect("valid actor");
    let closest = seen
        .track
        .iter()
        .map(|(t, p)| (plan.state_at(*t).position - p).norm())
        .fold(f64::INFINITY, f64::min);
    assert!(
        closest >= scenario.robot.radius() + person.radius,
        "{closest:.2} m"
    );
    let base = robot.world().humanoid().base_pose();
    let goal = Point2::new(scenario.goal.position[0], scenario.goal.position[1]);
    let off = (Point2::from(base.translation.vector) - goal).norm();
    assert!(
        off <= scenario.goal.tolerance + 0.05,
        "{off:.2} m from the goal"
    );
}

#[test]
fn the_cart_run_is_the_same_on_repeat() {
    // Invariant: two runs of the cart scenario with its seed are identical: timeline, knowledge, obstacles and grid (the settle frames and the grid's passive verdicts included).
    let scenario = nudge_tests::scenario("cart-left-in-doorway").expect("scenario loads");
    let once = || {
        nudge_tests::run(
            &scenario,
            scenario.seed,
            CandidatePolicy::Nearest,
            NullObserver,
        )
        .expect("world builds")
        .0
    };
    let (a, b) = (once(), once());
    assert!(a.grid.is_some());
    assert_eq!(a, b);
}

#[test]
fn the_same_scenario_and_seed_give_the_same_run() {
    // Invariant: two runs of the paper's room with one seed are identical: timeline, verdicts, obstacles and grid.
    let a = run("kakiuchi-room", CandidatePolicy::Nearest).0;
    let b = run("kakiuchi-room", CandidatePolicy::Nearest).0;
    assert!(a.grid.is_some());
    assert_eq!(a, b);
}

#[test]
fn the_papers_room_leaves_its_verdicts_in_the_shared_grid() {
    // Invariant: after the paper's run the grid holds the push tests' verdicts where the objects truly stand (table Stationary, pushed chair Movable, both by push test) and the floor the chair left is not an obstacle.
    let scenario = nudge_tests::scenario("kakiuchi-room").expect("scenario loads");
    let (report, robot) = nudge_tests::run(
        &scenario,
        scenario.seed,
        CandidatePolicy::Nearest,
        NullObserver,
    )
    .expect("world builds");
    let grid = report.grid.as_ref().expect("the run keeps a grid");
    let scored = score(&report, &robot);
    let truth = Truth::new(robot.world());
    let geometry = grid.geometry();
    let inner = |name: &str, pose: Isometry3<f64>| {
        // Cell centres at least one cell inside the object's true footprint.
        let (i, (spec, _)) = robot
            .world()
            .objects()
            .iter()
            .enumerate()
            .find(|(_, (s, _))| s.name == name)
            .expect("object exists");
        let margin = geometry.resolution();
        let half = (spec.size[0] / 2.0 - margin, spec.size[1] / 2.0 - margin);
        let cells: Vec<CellIndex> = (0..geometry.len())
            .filter_map(|k| geometry.cell_at(k))
            .filter(|&c| {
                let p = geometry.centre(c);
                let local =
                    pose.inverse_transform_point(&Point3::new(p.x, p.y, pose.translation.z));
                local.x.abs() <= half.0 && local.y.abs() <= half.1
            })
            .collect();
        (i, cells)
    };
    let mut checked = 0;
    for s in &scored {
        let name = s.object.clone().expect("every verdict matches an object");
        let (i, _) = inner(&name, Isometry3::identity());
        let now = truth.object_pose(i).expect("object has a pose");
        let (_, cells) = inner(&name, now);
        assert!(!cells.is_empty(), "{name} covers cells");
        let want = if s.verdict.is_movable() {
            CellClass::Movable
        } else {
            CellClass::Stationary
        };
        for c in &cells {
            let info = grid.cell(*c).expect("cell in grid");
            assert_eq!(
                info.class,
                want,
                "{name}'s cell {c:?} at {}",
                geometry.centre(*c)
            );
            assert!(matches!(info.evidence, Evidence::Active { object, .. } if object == s.id));
            checked += 1;
        }
        if s.verdict.is_movable() {
            // Where the chair stood at the start and no longer does, the push freed the floor.
            let spec = &robot.world().objects()[i].0;
            let start = Isometry3::new(
                Vector3::new(spec.position[0], spec.position[1], now.translation.z),
                Vector3::z() * spec.yaw.to_radians(),
            );
            let (_, left) = inner(&name, start);
            let freed: Vec<_> = left.iter().filter(|c| !cells.contains(c)).collect();
            assert!(!freed.is_empty(), "the push moved {name} off its cells");
            for c in freed {
                let class = grid.class(*c).expect("cell in grid");
                assert!(
                    matches!(class, CellClass::Free | CellClass::Unknown),
                    "{name} left cell {c:?} but it is {class:?}"
                );
            }
        }
    }
    println!("{checked} object cells carry their push test's verdict");
    assert!(scored.len() >= 2 && checked > 100);
}
