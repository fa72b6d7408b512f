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
