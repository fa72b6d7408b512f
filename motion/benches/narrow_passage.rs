//! Narrow passages A and Z: nudge's RRT-Connect (with and without shortcutting) against the `rrt`
//! crate's dual RRT-Connect on the same worlds, the same disc checks and seeded sampling.
//!
//! Before criterion runs, every planner solves 200 seeds once and the median / p90 / success are
//! printed (criterion reports means per iteration, not percentiles), and for nudge's RRT-Connect
//! (with and without bridge samples) the median / p90 iterations and checks, which do not depend on
//! the machine's load. Timing is printed, never asserted.

#[path = "../tests/common/mod.rs"]
mod common;

use std::cell::RefCell;
use std::hint::black_box;
use std::time::Instant;

use criterion::{Criterion, criterion_group};
use nalgebra::Point2;
use nudge_motion::planner::Effort;
use nudge_motion::planner::sampler::Sampling;
use nudge_motion::{Budget, Planner, Problem, Rrt, RrtConnect, Shortcut, StateValidity, Validity};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

const SEEDS: u64 = 200;
/// The `rrt` crate checks points only: a step finer than the 5 cm clearance each side keeps its
/// paths from cutting corners by more than a few millimetres.
const RRT_CRATE_STEP: f64 = 0.05;

type World = (Validity, Problem);

fn ours(world: &World, seed: u64, shortcut: bool) -> Option<f64> {
    let (v, p) = world;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let path = RrtConnect::default()
        .solve(p, v, Budget::iterations(200_000), &mut rng)
        .ok()?;
    let path = if shortcut {
        Shortcut::default().shorten(&path, v, &mut rng)
    } else {
        path
    };
    Some(path.length())
}

/// RRT-Connect with uniform samples only (the sampler before bridge tests), for comparison.
fn uniform_only() -> RrtConnect {
    RrtConnect {
        sampling: Sampling {
            bridge_attempts: 0,
            ..Sampling::default()
        },
        ..RrtConnect::default()
    }
}

fn ours_uniform(world: &World, seed: u64) -> Option<f64> {
    let (v, p) = world;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let path = uniform_only()
        .solve(p, v, Budget::iterations(200_000), &mut rng)
        .ok()?;
    Some(path.length())
}

/// Work per solve, independent of the machine's load: median / p90 iterations and checks.
fn effort(name: &str, planner: &RrtConnect, world: &World) {
    let (v, p) = world;
    let mut runs: Vec<Effort> = (0..SEEDS)
        .map(|seed| {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            planner
                .solve_with_effort(p, v, Budget::iterations(200_000), &mut rng)
                .1
        })
        .collect();
    let mut quantiles = |key: fn(&Effort) -> usize| {
        runs.sort_by_key(key);
        let at = |q: f64| key(&runs[((runs.len() as f64 - 1.0) * q).round() as usize]);
        format!("{:6} / {:6}", at(0.5), at(0.9))
    };
    println!(
        "{name:<32} median / p90: iterations {}  motion checks {}  point checks {}",
        quantiles(|e| e.iterations),
        quantiles(|e| e.motion_checks),
        quantiles(|e| e.point_checks),
    );
}

fn ours_rrt(world: &World, seed: u64) -> Option<f64> {
    let (v, p) = world;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let path = Rrt::default()
        .solve(p, v, Budget::iterations(200_000), &mut rng)
        .ok()?;
    Some(path.length())
}

/// The `rrt` crate's dual RRT-Connect on the same world: point checks with our disc test every
/// `step`, seeded uniform sampling. Returns the path length, and whether the path is free under
/// nudge's exact swept-disc check (point-checked steps can cut corners).
fn rrt_crate_checked(world: &World, seed: u64, step: f64) -> Option<(f64, bool)> {
    let (v, p) = world;
    let rng = RefCell::new(ChaCha8Rng::seed_from_u64(seed));
    let bounds = *v.sampling_bounds();
    let start = p.start();
    let goal = p.goal().centre();
    let path = rrt::dual_rrt_connect(
        &[start.x, start.y],
        &[goal.x, goal.y],
        |q: &[f64]| v.is_free(&Point2::new(q[0], q[1])),
        || {
            let mut r = rng.borrow_mut();
            let (min, max) = (bounds.min(), bounds.max());
            vec![r.random_range(min.x..max.x), r.random_range(min.y..max.y)]
        },
        step,
        200_000,
    )
    .ok()?;
    let points: Vec<Point2<f64>> = path.iter().map(|q| Point2::new(q[0], q[1])).collect();
    let free = points.windows(2).all(|w| v.motion_free(&w[0], &w[1]));
    let length = points
        .windows(2)
        .map(|w| nalgebra::distance(&w[0], &w[1]))
        .sum();
    Some((length, free))
}

fn rrt_crate(world: &World, seed: u64, step: f64) -> Option<f64> {
    rrt_crate_checked(world, seed, step).map(|(length, _)| length)
}

/// How many of the `rrt` crate's paths collide under the exact swept-disc check.
fn corner_cuts(world: &World, step: f64) -> usize {
    (0..SEEDS)
        .filter_map(|s| rrt_crate_checked(world, s, step))
        .filter(|(_, free)| !free)
        .count()
}

fn percentiles(name: &str, mut solve: impl FnMut(u64) -> Option<f64>) {
    let mut times = Vec::new();
    let mut lengths = Vec::new();
    for seed in 0..SEEDS {
        let t = Instant::now();
        let out = solve(seed);
        times.push(t.elapsed().as_secs_f64() * 1e3);
        if let Some(l) = out {
            lengths.push(l);
        }
    }
    times.sort_by(f64::total_cmp);
    lengths.sort_by(f64::total_cmp);
    let at = |v: &[f64], q: f64| {
        v.get(((v.len() as f64 - 1.0) * q).round() as usize)
            .copied()
    };
    println!(
        "{name:<32} median {:7.3} ms  p90 {:7.3} ms  max {:7.3} ms  success {}/{SEEDS}  median length {:.2} m",
        at(&times, 0.5).unwrap_or(f64::NAN),
        at(&times, 0.9).unwrap_or(f64::NAN),
        at(&times, 1.0).unwrap_or(f64::NAN),
        lengths.len(),
        at(&lengths, 0.5).unwrap_or(f64::NAN),
    );
}

fn worlds() -> [(&'static str, World); 2] {
    [("A", common::narrow_a()), ("Z", common::narrow_z())]
}

fn print_percentiles() {
    for (name, world) in worlds() {
        percentiles(&format!("{name} nudge rrt-connect"), |s| {
            ours(&world, s, false)
        });
        percentiles(&format!("{name} nudge rrt-connect (uniform)"), |s| {
            ours_uniform(&world, s)
        });
        effort(
            &format!("{name} nudge rrt-connect"),
            &RrtConnect::default(),
            &world,
        );
        effort(
            &format!("{name} nudge rrt-connect (uniform)"),
            &uniform_only(),
            &world,
        );
        percentiles(&format!("{name} nudge rrt-connect+shortcut"), |s| {
            ours(&world, s, true)
        });
        percentiles(&format!("{name} nudge rrt (goal bias)"), |s| {
            ours_rrt(&world, s)
        });
        percentiles(&format!("{name} rrt crate (step {RRT_CRATE_STEP})"), |s| {
            rrt_crate(&world, s, RRT_CRATE_STEP)
        });
        percentiles(&format!("{name} rrt crate (step 0.5, unsafe)"), |s| {
            rrt_crate(&world, s, 0.5)
        });
        for step in [RRT_CRATE_STEP, 0.5] {
            println!(
                "{name} rrt crate (step {step}): {} of {SEEDS} paths collide under the exact check",
                corner_cuts(&world, step)
            );
        }
    }
}

fn bench(c: &mut Criterion) {
    for (name, world) in worlds() {
        let mut group = c.benchmark_group(format!("narrow_{name}"));
        let mut seed = 0u64;
        group.bench_function("nudge_rrt_connect", |b| {
            b.iter(|| {
                seed = (seed + 1) % SEEDS;
                black_box(ours(&world, seed, false))
            })
        });
        group.bench_function("nudge_rrt_connect_shortcut", |b| {
            b.iter(|| {
                seed = (seed + 1) % SEEDS;
                black_box(ours(&world, seed, true))
            })
        });
        group.bench_function("rrt_crate", |b| {
            b.iter(|| {
                seed = (seed + 1) % SEEDS;
                black_box(rrt_crate(&world, seed, RRT_CRATE_STEP))
            })
        });
        group.finish();
    }
}

criterion_group!(benches, bench);

fn main() {
    print_percentiles();
    benches();
    Criterion::default().configure_from_args().final_summary();
}
