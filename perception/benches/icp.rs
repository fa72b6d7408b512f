//! Colour ICP of a pushed chair (one-sided view, ~9,000 points per cloud).

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Isometry3, Point3};
use nudge_perception::{IcpConfig, colour_icp};

fn chair_push(c: &mut Criterion) {
    let eye = common::look_at(Point3::new(2.9, 0.3, 1.45), Point3::new(3.9, 0.85, 0.45));
    let start = common::planar(3.8, 0.85, 0.0);
    let end = common::planar(4.0, 0.86, 2f64.to_radians());
    let before = common::object_points(&common::chair("chair", start, [40, 90, 160]), &eye, 1);
    let after = common::object_points(&common::chair("chair", end, [40, 90, 160]), &eye, 2);
    eprintln!(
        "chair: {} points before, {} after",
        before.len(),
        after.len()
    );
    let guess = Isometry3::translation(0.17, 0.0, 0.0);
    let config = IcpConfig::default();
    // `ICP_CALLS=n` runs exactly n colour-ICP calls and exits: a fixed workload for instruction
    // counting (valgrind --tool=callgrind), which does not depend on the machine's load.
    if let Some(n) = std::env::var("ICP_CALLS")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        for _ in 0..n {
            let r = colour_icp(black_box(&before), black_box(&after), &guess, &config);
            black_box(r.ok());
        }
        std::process::exit(0);
    }
    c.bench_function("colour ICP: chair 200 mm push", |b| {
        b.iter(|| colour_icp(black_box(&before), black_box(&after), &guess, &config))
    });
    let geometric = IcpConfig::geometric_only();
    c.bench_function("point-to-plane ICP: chair 200 mm push", |b| {
        b.iter(|| colour_icp(black_box(&before), black_box(&after), &guess, &geometric))
    });
}

criterion_group!(benches, chair_push);
criterion_main!(benches);
