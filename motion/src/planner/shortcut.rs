//! Path shortcutting: replace stretches of a path by straight motions that are free.
//!
//! Random pairs of points along the path (by arc length, not only waypoints) are joined when the
//! straight motion between them is free; a final greedy pass drops waypoints that can be skipped.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use crate::path::Path;
use crate::validity::StateValidity;

/// Seeded random shortcutting.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shortcut {
    /// Random shortcut attempts.
    pub attempts: usize,
}

impl Default for Shortcut {
    fn default() -> Self {
        Self { attempts: 64 }
    }
}

impl Shortcut {
    /// A path no longer than `path`, free wherever `path` is free, with the same ends.
    pub fn shorten(&self, path: &Path, validity: &dyn StateValidity, rng: &mut ChaCha8Rng) -> Path {
        let mut current = path.clone();
        for _ in 0..self.attempts {
            let len = current.length();
            if current.waypoints().len() < 3 || len <= 0.0 {
                break;
            }
            let mut s0 = rng.random::<f64>() * len;
            let mut s1 = rng.random::<f64>() * len;
            if s0 > s1 {
                std::mem::swap(&mut s0, &mut s1);
            }
            let cum = current.cumulative();
            let i0 = cum.partition_point(|&c| c <= s0);
            let i1 = cum.partition_point(|&c| c < s1);
            // Only worth it when at least one waypoint lies strictly between the two points.
            if i1 <= i0 {
                continue;
            }
            let (p0, p1) = (current.point_at(s0), current.point_at(s1));
            if !validity.motion_free(&p0, &p1) {
                continue;
            }
            let w = current.waypoints();
            let mut points = w[..i0].to_vec();
            points.push(p0);
            points.push(p1);
            points.extend_from_slice(&w[i1..]);
            points.dedup();
            if let Ok(shorter) = Path::new(points)
                && shorter.length() < current.length()
            {
                current = shorter;
            }
        }
        greedy(&current, validity)
    }
}

/// From each kept waypoint, jump to the farthest later waypoint reachable in a straight free motion.
fn greedy(path: &Path, validity: &dyn StateValidity) -> Path {
    let w = path.waypoints();
    let mut kept = vec![w[0]];
    let mut i = 0;
    while i + 1 < w.len() {
        let mut j = w.len() - 1;
        while j > i + 1 && !validity.motion_free(&w[i], &w[j]) {
            j -= 1;
        }
        kept.push(w[j]);
        i = j;
    }
    Path::new(kept).unwrap_or_else(|_| path.clone())
}
