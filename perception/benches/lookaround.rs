//! A whole synthetic look-around (15 frames, ~380,000 points of the default room) to prisms.

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Isometry2, Vector2};
use nudge_perception::{PerceptionConfig, detect_from_views, detect_objects, fuse};

fn look_around_to_prisms(c: &mut Criterion) {
    let scene = common::kakiuchi_room();
    let views = common::look_around(&scene, &common::planar(0.6, 1.8, 0.0), 1);
    let points: usize = views.iter().map(|v| v.len()).sum();
    let base = Isometry2::new(Vector2::new(0.6, 1.8), 0.0);
    let config = PerceptionConfig::default();
    let fused = fuse(&views);
    eprintln!(
        "{} views, {points} slots, {} valid points",
        views.len(),
        fused.len()
    );
    c.bench_function("look-around: fuse 15 views", |b| {
        b.iter(|| fuse(black_box(&views)))
    });
    c.bench_function("look-around: detect on fused cloud", |b| {
        b.iter(|| detect_objects(black_box(&fused), &base, &config, &[]))
    });
    c.bench_function("look-around: 15 views to prisms", |b| {
        b.iter(|| detect_from_views(black_box(&views), &base, &config, &[]))
    });
}

criterion_group!(benches, look_around_to_prisms);
criterion_main!(benches);
