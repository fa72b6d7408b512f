//! The shipped scenario files: they load, and their geometry shows what each one is meant to show.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use nalgebra::{Point2, Vector2};
use nudge_sim::scenario::{ExpectedOutcome, Footprint, ObjectSpec, Scenario};

/// The push test's force limit (N) from the brief: an object that needs more is static.
const PUSH_LIMIT: f64 = 20.0;
/// Occupancy-grid cell for the flood fill (m).
const CELL: f64 = 0.02;

fn scenarios_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenarios")
}

fn load(name: &str) -> Scenario {
    let path = scenarios_dir().join(format!("{name}.toml"));
    Scenario::from_path(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn object<'a>(scenario: &'a Scenario, name: &str) -> &'a ObjectSpec {
    scenario
        .object(name)
        .unwrap_or_else(|| panic!("no object {name}"))
}

fn footprint(object: &ObjectSpec) -> Footprint {
    object
        .footprint()
        .expect("a loaded scenario has valid sizes")
}

/// Footprints of objects the robot can neither walk over nor under.
fn obstacles(scenario: &Scenario) -> Vec<(String, Footprint)> {
    scenario
        .objects
        .iter()
        .filter(|o| o.blocks_height(scenario.robot.height()))
        .map(|o| (o.name.clone(), footprint(o)))
        .collect()
}

/// Breadth-first flood fill over a grid of `CELL` cells where a cell is free when the robot's disc centred
/// there touches neither a wall nor an obstacle; true when the goal's cell is reached from the start's.
fn start_reaches_goal(scenario: &Scenario) -> bool {
    let r = scenario.robot.radius();
    let (nx, ny) = (
        (scenario.room.size[0] / CELL).floor() as usize,
        (scenario.room.size[1] / CELL).floor() as usize,
    );
    let centre = |i: usize, j: usize| Point2::new((i as f64 + 0.5) * CELL, (j as f64 + 0.5) * CELL);
    let blocked = obstacles(scenario);
    let free = |i: usize, j: usize| {
        let disc = Footprint::Disc {
            centre: centre(i, j),
            radius: r,
        };
        scenario.room.clearance(&disc) >= 0.0
            && blocked
                .iter()
                .all(|(_, f)| f.distance_to_point(&centre(i, j)) > r)
    };
    let cell_of = |p: Point2<f64>| ((p.x / CELL) as usize, (p.y / CELL) as usize);
    let (start, goal) = (
        cell_of(scenario.robot.start_position()),
        cell_of(scenario.goal.centre()),
    );
    assert!(free(start.0, start.1), "the start cell itself must be free");
    let mut seen = vec![false; nx * ny];
    let mut queue = VecDeque::from([start]);
    seen[start.1 * nx + start.0] = true;
    while let Some((i, j)) = queue.pop_front() {
        if (i, j) == goal {
            return true;
        }
        let neighbours = [
            (i.wrapping_sub(1), j),
            (i + 1, j),
            (i, j.wrapping_sub(1)),
            (i, j + 1),
        ];
        for (a, b) in neighbours {
            if a < nx && b < ny && !seen[b * nx + a] && free(a, b) {
                seen[b * nx + a] = true;
                queue.push_back((a, b));
            }
        }
    }
    false
}

fn all_files() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenarios_dir())
        .expect("scenarios/ exists")
        .map(|entry| entry.expect("a readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

#[test]
fn every_shipped_file_loads_validates_and_is_named_after_itself() {
    // Invariant: every file in scenarios/ loads without error and its `name` is its file stem.
    let files = all_files();
    assert!(
        files.len() >= 5,
        "expected the five shipped scenarios, found {files:?}"
    );
    for path in files {
        let scenario = Scenario::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
        scenario
            .validate()
            .unwrap_or_else(|v| panic!("{}: {v}", path.display()));
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .expect("a UTF-8 stem");
        assert_eq!(scenario.name, stem, "{}", path.display());
        assert!(
            scenario.expect.is_some(),
            "{} has an [expect] block",
            path.display()
        );
    }
}

#[test]
fn the_embedded_default_room_is_the_shipped_file() {
    // Invariant: `default_room` never fails and is exactly scenarios/kakiuchi-room.toml.
    let embedded = Scenario::default_room().expect("the embedded room is valid");
    assert_eq!(embedded, load("kakiuchi-room"));
}

#[test]
fn the_kakiuchi_room_has_the_geometry_of_the_brief() {
    // Invariant: footprints, masses and start/goal are the numbers every helper relies on.
    let room = load("kakiuchi-room");
    assert_eq!(room.room.size, [6.0, 3.6]);
    assert_eq!(room.robot.start, [0.6, 1.8, 0.0]);
    assert_eq!(room.goal.position, [5.4, 1.8]);
    assert_eq!(room.seed, 1);
    let expected = [
        ("table", (2.6, 1.2), (3.4, 2.4)),
        ("chair-1", (3.55, 0.6), (4.05, 1.1)),
        ("chair-2", (3.55, 2.5), (4.05, 3.0)),
        ("mat", (1.3, 2.7), (1.9, 3.1)),
    ];
    for (name, lo, hi) in expected {
        let (got_lo, got_hi) = footprint(object(&room, name)).aabb();
        let close = |a: Point2<f64>, b: (f64, f64)| (a - Point2::new(b.0, b.1)).norm() < 1e-9;
        assert!(
            close(got_lo, lo) && close(got_hi, hi),
            "{name}: {got_lo} .. {got_hi}"
        );
    }
    let table = object(&room, "table");
    assert!(!table.fixed && table.sliding_force() > PUSH_LIMIT);
    assert!(
        (table.sliding_force() - 147.15).abs() < 1e-9,
        "μmg ≈ 147 N as the brief says"
    );
    let chair = object(&room, "chair-1");
    assert!(!chair.fixed && chair.sliding_force() < PUSH_LIMIT);
    let expect = room.expect.as_ref().expect("an [expect] block");
    assert_eq!(expect.outcome, ExpectedOutcome::Goal);
    assert_eq!(
        (expect.movable.as_slice(), expect.static_.as_slice()),
        (&[][..], &["table".to_owned()][..]),
        "either chair may be the one found movable; the table must be static"
    );
}

#[test]
fn every_gap_in_the_kakiuchi_barrier_is_narrower_than_the_robot() {
    // Invariant: wall–chair and chair–table gaps in the barrier are all below the robot's diameter.
    let room = load("kakiuchi-room");
    let diameter = 2.0 * room.robot.radius();
    let barrier: Vec<Footprint> = ["chair-1", "table", "chair-2"]
        .iter()
        .map(|n| footprint(object(&room, n)))
        .collect();
    let wall_gaps = [
        footprint(object(&room, "chair-1")).aabb().0.y,
        room.room.size[1] - footprint(object(&room, "chair-2")).aabb().1.y,
    ];
    let object_gaps = [
        barrier[0].distance_to(&barrier[1]),
        barrier[1].distance_to(&barrier[2]),
    ];
    for gap in wall_gaps.iter().chain(&object_gaps) {
        assert!(
            *gap < diameter,
            "gap {gap} lets a {diameter} m robot through"
        );
    }
    assert!(
        (wall_gaps[0] - 0.6).abs() < 1e-9 && (wall_gaps[1] - 0.6).abs() < 1e-9,
        "{wall_gaps:?}"
    );
    let corner = (0.15f64.powi(2) + 0.1f64.powi(2)).sqrt();
    assert!(
        object_gaps.iter().all(|g| (g - corner).abs() < 1e-9),
        "{object_gaps:?}"
    );
}

#[test]
fn the_table_is_the_obstacle_nearest_the_start() {
    // Invariant: of the objects the robot cannot walk over, the table is closest to its start (the
    // executive's first push candidate).
    let room = load("kakiuchi-room");
    let start = room.robot.start_position();
    let nearest = obstacles(&room)
        .into_iter()
        .min_by(|a, b| {
            a.1.distance_to_point(&start)
                .total_cmp(&b.1.distance_to_point(&start))
        })
        .expect("obstacles");
    assert_eq!(nearest.0, "table");
}

#[test]
fn pushing_chair_1_by_0_8_m_opens_the_kakiuchi_room() {
    // Invariant: no free path at the start; after moving chair-1 0.8 m along +x one exists.
    let mut room = load("kakiuchi-room");
    assert!(
        !start_reaches_goal(&room),
        "the barrier must be closed at the start"
    );
    let chair = room
        .objects
        .iter_mut()
        .find(|o| o.name == "chair-1")
        .expect("chair-1");
    chair.position[0] += 0.8;
    room.validate()
        .expect("the pushed chair is still inside the room");
    assert!(start_reaches_goal(&room), "moving chair-1 must open a path");
    // The room is mirror-symmetric about y = 1.8, so chair-2 pushed the same way opens it too; which chair
    // the executive tries is its choice, not the geometry's.
    let mut other = load("kakiuchi-room");
    let chair = other
        .objects
        .iter_mut()
        .find(|o| o.name == "chair-2")
        .expect("chair-2");
    chair.position[0] += 0.8;
    assert!(
        start_reaches_goal(&other),
        "chair-2 is the mirror image of chair-1, so it opens the room too"
    );
}

#[test]
fn free_paths_match_the_expected_outcomes() {
    // Invariant: rooms expecting `goal` without pushes are open from the start; the barrier rooms are not.
    assert!(start_reaches_goal(&load("open-room")));
    assert!(
        start_reaches_goal(&load("pipe-overhang")),
        "the pipe is above the robot"
    );
    assert!(
        start_reaches_goal(&load("tamura-hallway")),
        "objects alone leave the hallway open"
    );
    assert!(!start_reaches_goal(&load("all-static")));
    assert!(!start_reaches_goal(&load("kakiuchi-room")));
}

#[test]
fn expected_classes_agree_with_physics() {
    // Invariant: every object expected static is bolted or too heavy to push at the limit, every object
    // expected movable is loose and light enough; in all-static the whole barrier is static.
    for path in all_files() {
        let scenario = Scenario::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
        let Some(expect) = &scenario.expect else {
            continue;
        };
        for name in &expect.static_ {
            let o = object(&scenario, name);
            assert!(
                o.sliding_force() > PUSH_LIMIT,
                "{}: {name} should be static",
                path.display()
            );
        }
        for name in &expect.movable {
            let o = object(&scenario, name);
            assert!(
                o.sliding_force() < PUSH_LIMIT,
                "{}: {name} should be movable",
                path.display()
            );
        }
    }
    let all_static = load("all-static");
    let expect = all_static.expect.as_ref().expect("[expect]");
    assert_eq!(expect.outcome, ExpectedOutcome::NoPath);
    assert!(expect.movable.is_empty());
    for name in ["table", "chair-1", "chair-2"] {
        assert!(
            expect.static_.iter().any(|s| s == name),
            "{name} must be expected static"
        );
    }
}

#[test]
fn the_pipe_is_above_the_robot_and_spans_the_room() {
    // Invariant: the overhang is higher than the robot and reaches wall to wall, so only its height lets
    // the robot pass.
    let scenario = load("pipe-overhang");
    let pipe = object(&scenario, "pipe");
    assert!(pipe.elevation > scenario.robot.height());
    assert!(!pipe.blocks_height(scenario.robot.height()));
    let (lo, hi) = footprint(pipe).aabb();
    assert!(lo.y <= 1e-9 && hi.y >= scenario.room.size[1] - 1e-9);
    let mut lowered = scenario.clone();
    lowered
        .objects
        .iter_mut()
        .filter(|o| o.name == "pipe")
        .for_each(|o| o.elevation = 0.0);
    assert!(
        !start_reaches_goal(&lowered),
        "on the floor the pipe would close the room"
    );
}

/// When an actor arrives at and leaves each waypoint (s), walking straight at its speed.
fn timetable(scenario: &Scenario, actor: &str) -> Vec<(f64, f64)> {
    let actor = scenario
        .actors
        .iter()
        .find(|a| a.name == actor)
        .expect("the actor");
    let points = actor.waypoint_points();
    let mut t = actor.start_time;
    let mut out = Vec::new();
    for (i, p) in points.iter().enumerate() {
        if i > 0 {
            t += (p - points[i - 1]).norm() / actor.speed;
        }
        let arrive = t;
        t += actor.pause.get(i).copied().unwrap_or(0.0);
        out.push((arrive, t));
    }
    out
}

#[test]
fn the_tamura_timeline_plays_while_the_robot_walks() {
    // Invariant: the suitcase is dropped ahead of the robot, the person then walks more than 5 m away, and
    // the pick-up happens before the robot reaches the suitcase or the goal.
    let scenario = load("tamura-hallway");
    let person = &scenario.actors[0];
    assert_eq!(person.carries.as_deref(), Some("suitcase"));
    let (drop, pick) = (
        person.drop_at.expect("drop_at"),
        person.pick_at.expect("pick_at"),
    );
    let times = timetable(&scenario, "person");
    let points = person.waypoint_points();
    let robot = &scenario.robot;
    let robot_at = |t: f64| robot.start_position() + Vector2::new(robot.walk_speed() * t, 0.0);
    let walk_time = (scenario.goal.centre() - robot.start_position()).norm() / robot.walk_speed();
    assert!(
        (robot.walk_speed() - 0.2).abs() < 1e-12 && walk_time > 50.0,
        "{walk_time}"
    );

    let dropped_at = times[drop].0;
    assert!(
        points[drop].x > robot_at(dropped_at).x + 2.0,
        "dropped well ahead of the robot"
    );

    let far = (drop + 1..pick)
        .max_by(|&a, &b| points[a].x.total_cmp(&points[b].x))
        .expect("a waypoint between drop and pick");
    let (arrive_far, leave_far) = times[far];
    for t in [arrive_far, leave_far] {
        assert!(
            (points[far] - robot_at(t)).norm() > 5.0,
            "out of view at t = {t}"
        );
    }
    let picked_at = times[pick].1;
    let suitcase = object(&scenario, "suitcase");
    // The suitcase trails the person: its rear is at most a body radius, its length and a 0.1 m handle behind.
    let (lo, hi) = footprint(suitcase).aabb();
    let suitcase_rear = points[drop].x - person.radius - (hi.x - lo.x) - 0.1;
    assert!(
        picked_at < walk_time,
        "picked at {picked_at} s, robot done at {walk_time} s"
    );
    assert!(
        robot_at(picked_at).x + robot.radius() < suitcase_rear,
        "picked up before the robot passes it"
    );
    assert!(
        points.last().expect("waypoints").x < robot_at(times.last().expect("times").0).x,
        "leaves past the robot"
    );
}

#[test]
fn the_example_in_the_format_docs_loads() {
    // Invariant: the full example in the module docs of `scenario.rs` is a valid scenario, so the
    // documentation of the format cannot drift from the format.
    let source =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/scenario.rs"))
            .expect("the module source");
    let example: String = source
        .lines()
        .skip_while(|l| *l != "//! ```toml")
        .skip(1)
        .take_while(|l| *l != "//! ```")
        .map(|l| {
            format!(
                "{}\n",
                l.trim_start_matches("//!").strip_prefix(' ').unwrap_or("")
            )
        })
        .collect();
    assert!(
        example.lines().count() > 40,
        "the example was not found:\n{example}"
    );
    let scenario =
        Scenario::from_toml_str(&example, "scenario.rs docs").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((scenario.objects.len(), scenario.actors.len()), (1, 1));
}
