//! What changed during a look (free-space carving): a whole synthetic look-around of the default
//! room (15 frames, ~380,000 points), its range images and its split into stayed, arrived and
//! departed points.

#[path = "../tests/common/mod.rs"]
mod common;

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nudge_perception::LookChanges;

/// The SR-4000's pixel pitch: 43.6° over 176 pixels.
const PITCH: f64 = 43.6 * std::f64::consts::PI / 180.0 / 176.0;

fn look_changes(c: &mut Criterion) {
    let scene = common::kakiuchi_room();
    let views = common::look_around(&scene, &common::planar(0.6, 1.8, 0.0), 1);
    let changes = LookChanges::new(&views, PITCH);
    let split = changes.split(&views, None);
    let moved = split
        .changes
        .iter()
        .filter(|c| **c != nudge_perception::Change::Stayed)
        .count();
    eprintln!(
        "{} views, {} points, {moved} arrived or departed in a still room",
        views.len(),
        split.fused.len()
    );
    c.bench_function("look changes: range images of 15 views", |b| {
        b.iter(|| LookChanges::new(black_box(&views), PITCH))
    });
    c.bench_function("look changes: split a look of 15 views", |b| {
        b.iter(|| changes.split(black_box(&views), None))
    });
}

criterion_group!(benches, look_changes);
criterion_main!(benches);
