//! One full 176 × 144 colour range frame in the paper's room: floor, four walls (6 × 3.6 m, 2 m
//! high), a table and two chairs built as compounds, seen from the robot's start with the head tilted
//! down. The scene is built with rapier directly so the bench does not depend on the world builder.
#![allow(missing_docs)]

use std::collections::HashMap;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use nudge_sim::scenario::{Scenario, Texture};
use nudge_sim::sensors::colour_range::{ColourRangeConfig, ColourRangeSensor, SensorScene};
use nudge_sim::surface::{Owner, Surface};
use nudge_sim::world::World;
use rapier3d::prelude::*;

struct Room {
    world: PhysicsWorld,
    surfaces: HashMap<ColliderHandle, Surface>,
}

impl Room {
    fn add(&mut self, body: RigidBodyBuilder, collider: ColliderBuilder, surface: Surface) {
        let (_, c) = self.world.insert(body, collider);
        self.surfaces.insert(c, surface);
    }
}

fn cuboid_part(centre: [f32; 3], half: [f32; 3]) -> (Pose, SharedShape) {
    (
        Pose::from_translation(Vector::new(centre[0], centre[1], centre[2])),
        SharedShape::cuboid(half[0], half[1], half[2]),
    )
}

/// Four legs of half width `leg` under a top of half extents `hx × hy` whose underside is at `height`.
fn legs(hx: f32, hy: f32, height: f32, leg: f32) -> Vec<(Pose, SharedShape)> {
    let mut parts = Vec::new();
    for sx in [-1.0, 1.0] {
        for sy in [-1.0, 1.0] {
            parts.push(cuboid_part(
                [sx * (hx - leg), sy * (hy - leg), height / 2.0],
                [leg, leg, height / 2.0],
            ));
        }
    }
    parts
}

fn room() -> Room {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -9.81);
    let mut room = Room {
        world,
        surfaces: HashMap::new(),
    };
    let plain = |colour, owner| Surface::new(colour, Texture::Plain, owner);
    let wall = [225, 222, 210];
    let fixed_at =
        |x: f32, y: f32, z: f32| RigidBodyBuilder::fixed().translation(Vector::new(x, y, z));

    room.add(
        fixed_at(3.0, 1.8, -0.05),
        ColliderBuilder::cuboid(3.0, 1.8, 0.05),
        plain([150, 150, 140], Owner::Floor),
    );
    for (x, y, hx, hy) in [
        (3.0, -0.05, 3.1, 0.05),
        (3.0, 3.65, 3.1, 0.05),
        (-0.05, 1.8, 0.05, 1.8),
        (6.05, 1.8, 0.05, 1.8),
    ] {
        room.add(
            fixed_at(x, y, 1.0),
            ColliderBuilder::cuboid(hx, hy, 1.0),
            plain(wall, Owner::Wall),
        );
    }

    // Table 1.2 × 0.8 × 0.72 turned 90°: 0.8 along x, 1.2 along y.
    let mut table = legs(0.4, 0.6, 0.68, 0.025);
    table.push(cuboid_part([0.0, 0.0, 0.70], [0.4, 0.6, 0.02]));
    room.add(
        RigidBodyBuilder::dynamic().translation(Vector::new(3.0, 1.8, 0.0)),
        ColliderBuilder::compound(table),
        Surface::new([140, 90, 50], Texture::Stripes, Owner::Object(0)),
    );

    // Chairs 0.5 × 0.5, seat at 0.45 m, back up to 0.85 m on the +x side.
    for (i, y) in [(1, 0.85), (2, 2.75)] {
        let mut chair = legs(0.25, 0.25, 0.43, 0.02);
        chair.push(cuboid_part([0.0, 0.0, 0.44], [0.25, 0.25, 0.01]));
        chair.push(cuboid_part([0.23, 0.0, 0.65], [0.02, 0.25, 0.20]));
        room.add(
            RigidBodyBuilder::dynamic().translation(Vector::new(3.8, y, 0.0)),
            ColliderBuilder::compound(chair),
            Surface::new([60, 90, 200], Texture::Checker, Owner::Object(i)),
        );
    }

    room.add(
        fixed_at(1.6, 2.9, 0.005),
        ColliderBuilder::cuboid(0.3, 0.2, 0.005),
        plain([180, 40, 40], Owner::Object(3)),
    );

    room.world.detect_collisions(&(), &());
    room
}

fn bench_frame(c: &mut Criterion) {
    let room = room();
    let sensor = ColourRangeSensor::new(ColourRangeConfig::default());
    let lookup = |h: ColliderHandle| room.surfaces.get(&h).copied();
    let scene = SensorScene {
        bodies: &room.world.bodies,
        colliders: &room.world.colliders,
        broad_phase: &room.world.broad_phase,
        surface: &lookup,
        texture_seed: 1,
        exclude: None,
    };
    // The robot's start, head at 1.4 m looking along +x, tilted 20° down.
    let pose = Isometry3::from_parts(
        Translation3::new(0.6, 1.8, 1.4),
        UnitQuaternion::from_euler_angles(0.0, 20f64.to_radians(), 0.0),
    );
    let valid = sensor.capture(&scene, &pose, 0.0, 0).valid_count();
    eprintln!(
        "range_frame: {valid} of {} pixels return, {} rayon threads",
        sensor.config().camera.width * sensor.config().camera.height,
        rayon::current_num_threads()
    );

    report_cpu("range_frame", |seed| {
        black_box(sensor.capture(&scene, &pose, 0.0, seed));
    });

    let mut seed = 0u64;
    c.bench_function("range_frame_176x144", |b| {
        b.iter(|| {
            seed += 1;
            black_box(sensor.capture(&scene, black_box(&pose), 0.0, seed))
        })
    });

    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    c.bench_function("range_frame_176x144_one_thread", |b| {
        b.iter(|| {
            seed += 1;
            one_thread.install(|| black_box(sensor.capture(&scene, black_box(&pose), 0.0, seed)))
        })
    });
}

/// The same frame in the simulation's own world (`nudge_sim::world::World`) built from the paper's
/// room scenario, seen from the humanoid's head tilted 20° down, its body excluded.
fn bench_world_frame(c: &mut Criterion) {
    let scenario: Scenario =
        toml::from_str(include_str!("../tests/world_common/kakiuchi_room.toml"))
            .expect("bench scenario parses");
    let mut world = World::new(&scenario, 1).expect("bench world");
    world
        .advance(0.01)
        .expect("one step settles the broad phase");
    let sensor = ColourRangeSensor::new(ColourRangeConfig::default());
    let pose = world.humanoid().sensor_pose()
        * UnitQuaternion::from_euler_angles(0.0, 20f64.to_radians(), 0.0);
    world.in_sensor_scene(|scene| {
        let valid = sensor.capture(scene, &pose, 0.0, 0).valid_count();
        eprintln!("range_frame_world: {valid} pixels return");
        report_cpu("range_frame_world", |seed| {
            black_box(sensor.capture(scene, &pose, 0.0, seed));
        });

        let mut seed = 0u64;
        c.bench_function("range_frame_world_176x144", |b| {
            b.iter(|| {
                seed += 1;
                black_box(sensor.capture(scene, black_box(&pose), 0.0, seed))
            })
        });
    });
}

/// Prints the CPU time (user + system, all threads) per call of `frame` over 200 calls: on a shared
/// machine wall-clock medians mostly measure the other processes, CPU time measures the sensor.
fn report_cpu(label: &str, mut frame: impl FnMut(u64)) {
    let frames = 200;
    let Some(before) = process_cpu_seconds() else {
        return;
    };
    for seed in 0..frames {
        frame(seed);
    }
    if let Some(after) = process_cpu_seconds() {
        eprintln!(
            "{label}: {:.2} ms CPU per frame over {frames} frames",
            (after - before) * 1e3 / frames as f64
        );
    }
}

/// User + system CPU time of this process so far (s), from /proc (Linux only).
fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the parenthesised command name; utime and stime are fields 14 and 15 (1-based).
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    // Linux reports these in clock ticks of 1/100 s on every common configuration.
    Some((utime + stime) / 100.0)
}

criterion_group!(benches, bench_frame, bench_world_frame);
criterion_main!(benches);
