//! One physics step of the paper's room: a coarse 10 ms step while the robot walks, and a fine 1 ms
//! step while the hand pushes a chair (the wrist sensor's rate).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Point2, Point3};
use nudge_executive::robot::{Arm, Base, Clock, GuardedMove};
use nudge_sim::adapter::SimRobot;
use nudge_sim::scenario::Scenario;

const ROOM: &str = include_str!("../tests/world_common/kakiuchi_room.toml");

fn robot() -> SimRobot {
    let scenario: Scenario = toml::from_str(ROOM).expect("bench scenario parses");
    SimRobot::new(&scenario, 1).expect("bench world")
}

fn bench(c: &mut Criterion) {
    let mut walking = robot();
    walking
        .start_walk(&[Point2::new(2.0, 1.8), Point2::new(0.6, 1.8)])
        .expect("walk");
    walking.advance(1.0).expect("start walking");
    c.bench_function("coarse step (10 ms), robot walking", |b| {
        b.iter(|| {
            if walking.now() > 15.0 {
                walking = robot();
                walking.start_walk(&[Point2::new(2.0, 1.8)]).expect("walk");
            }
            walking.advance(black_box(0.010)).expect("step")
        })
    });

    let mut pushing = robot();
    pushing
        .start_walk(&[
            Point2::new(1.5, 0.6),
            Point2::new(3.1, 0.6),
            Point2::new(3.1, 0.8),
        ])
        .expect("walk");
    pushing.advance(25.0).expect("walk");
    pushing.start_turn(0.0).expect("turn");
    pushing.advance(5.0).expect("turn");
    let push = GuardedMove {
        from: Point3::new(0.4, 0.0, 0.43),
        to: Point3::new(0.8, 0.0, 0.43),
        speed: 0.05,
        force_limit: 40.0,
    };
    pushing.start_guarded_move(push.clone()).expect("push");
    pushing.advance(3.0).expect("reach the chair");
    c.bench_function("fine step (1 ms), hand pushing chair-1", |b| {
        b.iter(|| {
            pushing.advance(black_box(0.001)).expect("step");
        })
    });

    c.bench_function("idle second (everything asleep)", |b| {
        let mut idle = robot();
        idle.advance(5.0).expect("settle");
        b.iter(|| idle.advance(black_box(1.0)).expect("idle"))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
