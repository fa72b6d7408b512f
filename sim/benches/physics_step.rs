//! One physics step of the paper's room: a coarse 10 ms step while the robot walks, a fine 1 ms step
//! while the hand pushes chair-1 (the wrist sensor's rate), a 10 ms step of a steady clearing push
//! (ten 1 ms solver substeps), and one idle second.
//!
//! Each scene is rebuilt (untimed) before its action would end, so every timed step does real work.
//! The last benchmark is a scripted version of the paper's whole run without range frames: look
//! around (15 head poses), walk to the table and push it (static), walk behind chair-1, push it,
//! push it 0.8 m further by walking with the hand on it, and walk on towards the goal.

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Point2, Point3};
use nudge_executive::robot::{
    ActionStatus, Arm, Base, Clock, GuardedMove, Head, RangeCamera, WristSensor,
};
use nudge_sim::adapter::SimRobot;
use nudge_sim::scenario::Scenario;

const ROOM: &str = include_str!("../tests/world_common/kakiuchi_room.toml");

fn robot() -> SimRobot {
    let scenario: Scenario = toml::from_str(ROOM).expect("bench scenario parses");
    SimRobot::new(&scenario, 1).expect("bench world")
}

/// The robot walking along the room, 1 s into its walk (which lasts about 9 s more).
fn walking() -> SimRobot {
    let mut r = robot();
    r.start_walk(&[Point2::new(2.0, 1.8)]).expect("walk");
    r.advance(1.0).expect("start walking");
    r
}

/// The robot walked to stand behind chair-1, facing it, its hand not yet out.
fn behind_chair() -> SimRobot {
    let mut r = robot();
    r.start_walk(&[
        Point2::new(1.5, 0.6),
        Point2::new(3.1, 0.6),
        Point2::new(3.1, 0.8),
    ])
    .expect("walk");
    r.advance(25.0).expect("walk");
    r.start_turn(0.0).expect("turn");
    r.advance(5.0).expect("turn");
    r
}

/// The robot behind chair-1 with its hand pushing it (about 4 s of push left).
fn pushing() -> SimRobot {
    let mut r = behind_chair();
    let push = GuardedMove {
        from: Point3::new(0.4, 0.0, 0.43),
        to: Point3::new(0.8, 0.0, 0.43),
        speed: 0.05,
        force_limit: 40.0,
        acceleration: None,
    };
    r.start_guarded_move(push).expect("push");
    r.advance(3.0).expect("reach the chair");
    r
}

/// The robot behind chair-1 pushing it steadily as a clearing push does (2 cm/s, 30 N guard), past
/// the first contact's 0.2 s: the world steps it in 10 ms steps (about 14 s of push left).
fn clearing() -> SimRobot {
    let mut r = behind_chair();
    r.tare().expect("tare");
    let push = GuardedMove {
        from: Point3::new(0.4, 0.0, 0.43),
        to: Point3::new(0.8, 0.0, 0.43),
        speed: 0.02,
        force_limit: 30.0,
        acceleration: None,
    };
    r.start_guarded_move(push).expect("push");
    r.advance(4.0).expect("reach the chair and press");
    let (steps, fine) = (r.world().steps(), r.world().fine_steps());
    r.advance(0.01).expect("one step");
    assert_eq!(
        (r.world().steps() - steps, r.world().fine_steps() - fine),
        (1, 0),
        "a steady push takes one 10 ms step"
    );
    assert_eq!(r.hand_status().expect("hand"), ActionStatus::Running);
    r
}

/// Times `iters` calls of `advance(dt)`, rebuilding the scene with `make` every `per_scene` calls.
fn timed_steps(iters: u64, dt: f64, per_scene: u64, make: fn() -> SimRobot) -> Duration {
    let mut total = Duration::ZERO;
    let mut r = make();
    for i in 0..iters {
        if i > 0 && i % per_scene == 0 {
            r = make();
        }
        let start = Instant::now();
        r.advance(black_box(dt)).expect("step");
        total += start.elapsed();
    }
    total
}

fn wait_walk(r: &mut SimRobot) {
    while r.walk_status().expect("walk") == ActionStatus::Running {
        r.advance(0.05).expect("advance");
    }
}

fn wait_hand(r: &mut SimRobot) {
    while r.hand_status().expect("hand") == ActionStatus::Running {
        r.advance(0.001).expect("advance");
        black_box(r.drain_wrenches().expect("drain"));
    }
}

/// The scripted paper run, capturing a range frame at each of the 15 views when `frames`; returns
/// the simulated time it took.
fn paper_run(frames: bool) -> f64 {
    let mut r = robot();
    for tilt in [0.78, 0.52, 0.35] {
        for pan in [0.87, 0.44, 0.0, -0.44, -0.87] {
            r.start_point_head(pan, tilt).expect("head");
            while r.head_status().expect("head") == ActionStatus::Running {
                r.advance(0.05).expect("advance");
            }
            if frames {
                black_box(r.capture().expect("range frame"));
            }
            // The paper's 53 s for 15 views: about 2 s per capture.
            r.advance(2.0).expect("advance");
        }
    }
    r.start_walk(&[Point2::new(2.0, 1.8)]).expect("walk");
    wait_walk(&mut r);
    r.tare().expect("tare");
    let table = GuardedMove {
        from: Point3::new(0.4, 0.0, 0.7),
        to: Point3::new(0.8, 0.0, 0.7),
        speed: 0.05,
        force_limit: 20.0,
        acceleration: None,
    };
    r.start_guarded_move(table).expect("push table");
    wait_hand(&mut r);
    r.start_retract().expect("retract");
    wait_hand(&mut r);
    r.start_walk(&[
        Point2::new(1.5, 0.6),
        Point2::new(3.1, 0.6),
        Point2::new(3.1, 0.8),
    ])
    .expect("walk");
    wait_walk(&mut r);
    r.start_turn(0.0).expect("turn");
    wait_walk(&mut r);
    r.tare().expect("tare");
    let chair = GuardedMove {
        from: Point3::new(0.4, 0.0, 0.43),
        to: Point3::new(0.7, 0.0, 0.43),
        speed: 0.05,
        force_limit: 20.0,
        acceleration: None,
    };
    r.start_guarded_move(chair).expect("push chair");
    wait_hand(&mut r);
    r.start_walk(&[Point2::new(3.9, 0.8)]).expect("clear path");
    wait_walk(&mut r);
    r.start_retract().expect("retract");
    wait_hand(&mut r);
    r.start_walk(&[
        Point2::new(3.7, 0.6),
        Point2::new(4.6, 1.6),
        Point2::new(5.4, 1.8),
    ])
    .expect("walk");
    wait_walk(&mut r);
    r.now()
}

fn bench(c: &mut Criterion) {
    c.bench_function("coarse step (10 ms), robot walking", |b| {
        b.iter_custom(|n| timed_steps(n, 0.010, 800, walking))
    });
    c.bench_function("fine step (1 ms), hand pushing chair-1", |b| {
        b.iter_custom(|n| timed_steps(n, 0.001, 3500, pushing))
    });
    c.bench_function(
        "steady push step (10 ms, ten 1 ms substeps), hand clearing chair-1",
        |b| b.iter_custom(|n| timed_steps(n, 0.010, 1000, clearing)),
    );
    c.bench_function("idle second (everything asleep)", |b| {
        let mut idle = robot();
        idle.advance(5.0).expect("settle");
        b.iter(|| idle.advance(black_box(1.0)).expect("idle"))
    });
    let mut group = c.benchmark_group("paper run");
    group.sample_size(10);
    let simulated = paper_run(false);
    group.bench_function(
        format!("scripted run, {simulated:.0} s simulated, no range frames"),
        |b| b.iter(|| paper_run(false)),
    );
    group.bench_function(
        format!("scripted run, {simulated:.0} s simulated, 15 range frames"),
        |b| b.iter(|| paper_run(true)),
    );
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
