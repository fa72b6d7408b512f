//! Actors against their scenario: they keep their timetable and leave what they carry where told.
mod world_common;

use nudge_sim::world::World;
use world_common::*;

const ACTOR_ROOM: &str = r#"
name = "actors"
[room]
size = [6.0, 3.6]
[robot]
start = [0.6, 0.6, 0.0]
[goal]
position = [5.0, 1.8]
[[object]]
name = "crate"
kind = "box"
position = [1.0, 3.0]
size = [0.4, 0.4, 0.4]
mass = 5.0
colour = [200, 150, 20]
[[actor]]
name = "walker"
waypoints = [[1.5, 1.5], [4.5, 1.5], [4.5, 3.0]]
speed = 0.5
start_time = 1.0
pause = [0.0, 2.0, 0.0]
carries = "crate"
drop_at = 1
"#;

#[test]
fn actor_keeps_its_timetable() {
    // The actor waits until start_time, walks at its speed, pauses, and stops at the last waypoint.
    let mut w: World = world(&scenario(ACTOR_ROOM));
    // (time, expected x, expected y): 3 m leg takes 6 s from t = 1, a 2 s pause (to t = 9), then 1.5 m in 3 s.
    let expected = [
        (0.5, 1.5, 1.5),
        (4.0, 3.0, 1.5),
        (7.0, 4.5, 1.5),
        (8.5, 4.5, 1.5),
        (10.0, 4.5, 2.0),
        (12.0, 4.5, 3.0),
        (20.0, 4.5, 3.0),
    ];
    for (t, x, y) in expected {
        w.advance(t - w.time()).expect("advance");
        let p = w.actors()[0].state().position;
        assert!(
            (p.x - x).abs() < 1e-6 && (p.y - y).abs() < 1e-6,
            "t {t}: at {p:?}, expected ({x}, {y})"
        );
    }
}

#[test]
fn actor_drops_what_it_carries_where_told() {
    // The crate follows behind the actor until waypoint 1, then rests there as a dynamic body.
    let mut w = world(&scenario(ACTOR_ROOM));
    w.advance(4.0).expect("advance");
    let p = w.object_pose(0).expect("crate").translation.vector;
    // Behind the actor at (3.0, 1.5) heading +x: actor radius 0.25 + gap 0.05 + half crate 0.2.
    assert!(
        (p.x - 2.5).abs() < 1e-3 && (p.y - 1.5).abs() < 1e-3,
        "crate at {p:?}"
    );
    assert_eq!(w.actors()[0].carrying(), Some(0));
    w.advance(16.0).expect("advance");
    assert_eq!(w.actors()[0].carrying(), None);
    let p = w.object_pose(0).expect("crate").translation.vector;
    assert!(
        (p.x - 4.0).abs() < 0.01 && (p.y - 1.5).abs() < 0.01 && p.z.abs() < 0.01,
        "crate left at {p:?}"
    );
    assert!(w.object_speed(0).expect("crate") < 1e-3);
    let body = w.objects()[0].1;
    assert!(w.bodies().get(body).expect("crate body").is_dynamic());
}

#[test]
fn repeating_actor_drops_and_picks_up_again() {
    // A repeating actor goes round its waypoints, leaves its crate at waypoint 1 and takes it back at
    // waypoint 0 on the next round; its position at a time in the second round matches the first.
    let text = r#"
name = "loop"
[room]
size = [6.0, 3.6]
[robot]
start = [0.6, 0.6, 0.0]
[goal]
position = [5.0, 1.8]
[[object]]
name = "crate"
kind = "box"
position = [1.0, 3.0]
size = [0.4, 0.4, 0.4]
mass = 5.0
colour = [200, 150, 20]
[[actor]]
name = "walker"
waypoints = [[1.5, 1.5], [4.5, 1.5]]
speed = 0.5
pause = [1.0, 1.0]
repeat = true
carries = "crate"
drop_at = 1
pick_at = 0
"#;
    let mut w = world(&scenario(text));
    // Cycle: 1 s pause, 6 s to waypoint 1, 1 s pause, 6 s back = 14 s.
    w.advance(4.0).expect("advance");
    let first = w.actors()[0].state().position;
    assert_eq!(w.actors()[0].carrying(), Some(0));
    w.advance(3.5).expect("advance");
    assert_eq!(
        w.actors()[0].carrying(),
        None,
        "dropped at waypoint 1 (t = 7)"
    );
    let dropped = w.object_pose(0).expect("crate").translation.vector;
    assert!(
        (dropped.x - 4.0).abs() < 0.01 && (dropped.y - 1.5).abs() < 0.01,
        "dropped at {dropped:?}"
    );
    // Walking back, the actor shoves its crate (it is a dynamic body in its way) until it takes it again.
    w.advance(7.5).expect("advance");
    assert_eq!(
        w.actors()[0].carrying(),
        Some(0),
        "picked up again at waypoint 0 (t = 14)"
    );
    w.advance(3.0).expect("advance");
    let second = w.actors()[0].state().position;
    assert!(
        (first - second).norm() < 1e-9,
        "t = 4: {first:?}, t = 18: {second:?}"
    );
}
