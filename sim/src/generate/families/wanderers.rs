//! `wanderers`: an open room with people walking about among a few light pieces.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::{bare, cm};
use crate::generate::Guarantee;
use crate::generate::furniture::{FloorPlan, light};
use crate::scenario::{ActorSpec, Scenario};

/// How far a person's way keeps from the robot's start and the goal (m): the robot's radius, the
/// person's and a step, so nobody walks through where the robot stands at either end.
const KEEP_OFF: f64 = 1.2;

/// A 7–10 × 6–8 m room, 2–4 light pieces and 0–10 people walking 0.3–1.0 m/s round 2–4 free places
/// over and over; no person's way passes through a piece, the start or the goal.
pub(super) fn wanderers(rng: &mut ChaCha8Rng) -> (Scenario, Guarantee) {
    let [w, h] = [
        cm(rng.random_range(7.0..10.0)),
        cm(rng.random_range(6.0..8.0)),
    ];
    let start = [1.0, cm(rng.random_range(1.0..h - 1.0)), 0.0];
    let goal = [cm(w - 1.0), cm(rng.random_range(1.0..h - 1.0))];
    let mut s = bare([w, h], start, goal);
    let mut plan = FloorPlan::default();
    plan.keep_clear([start[0], start[1]], 0.9);
    plan.keep_clear(goal, 0.9);
    let mut discs: Vec<([f64; 2], f64)> = vec![([start[0], start[1]], KEEP_OFF), (goal, KEEP_OFF)];
    for k in 0..rng.random_range(2..=4) {
        let mut spec = light(rng, format!("piece-{k}"));
        if plan.place(rng, &mut spec, [1.8, w - 1.8], [0.05, h - 0.05]) {
            spec.position = [cm(spec.position[0]), cm(spec.position[1])];
            discs.push((
                spec.position,
                crate::generate::furniture::reach(&spec) + 0.35,
            ));
            s.objects.push(spec);
        }
    }
    let people = rng.random_range(0..=10);
    for k in 0..people {
        if let Some(waypoints) = way(rng, [w, h], &discs) {
            s.actors.push(ActorSpec {
                name: format!("person-{k}"),
                radius: 0.25,
                height: 1.7,
                waypoints,
                speed: cm(rng.random_range(0.3..1.0)),
                start_time: cm(rng.random_range(0.0..20.0)),
                pause: Vec::new(),
                repeat: true,
                carries: None,
                drop_at: None,
                pick_at: None,
                yields: true,
            });
        }
    }
    (s, Guarantee::WayExists)
}

/// 2–4 places 0.5 m or more from the walls whose closed loop keeps off every disc; `None` after 50
/// tries.
fn way(rng: &mut ChaCha8Rng, [w, h]: [f64; 2], discs: &[([f64; 2], f64)]) -> Option<Vec<[f64; 2]>> {
    'draw: for _ in 0..50 {
        let n = rng.random_range(2..=4);
        let points: Vec<[f64; 2]> = (0..n)
            .map(|_| {
                [
                    cm(rng.random_range(0.5..w - 0.5)),
                    cm(rng.random_range(0.5..h - 0.5)),
                ]
            })
            .collect();
        for i in 0..n {
            let (a, b) = (points[i], points[(i + 1) % n]);
            if discs.iter().any(|(c, r)| segment_distance(a, b, *c) < *r) {
                continue 'draw;
            }
        }
        return Some(points);
    }
    None
}

/// Distance from `p` to the segment `a`–`b`.
fn segment_distance(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}
