//! Ghosts: obstacles the executive still keeps at the end of a run where the truth has nothing — no
//! wall, no object (of any height), no person. A person's smear that became an obstacle and stayed
//! is the usual one.

use nalgebra::{Point2, Vector2};
use nudge_perception::Prism;

use crate::truth::Truth;

/// How far an obstacle's footprint may reach past what it was made from (m): footprints are hulls
/// of 4 cm elevation cells with about a centimetre of range noise, so a true object's obstacle can
/// stand up to about two cells off it.
const REACH: f64 = 0.1;

/// Spacing of the points at which a footprint is asked about (m): the grid's 5 cm cell.
const STEP: f64 = 0.05;

/// How many of `obstacles` are ghosts: no point of its footprint (sampled every 5 cm) has anything
/// true within reach of it (`REACH`).
pub fn count(obstacles: &[Prism], truth: &Truth<'_>) -> u32 {
    obstacles.iter().filter(|p| is_ghost(p, truth)).count() as u32
}

/// Whether `prism` stands where the truth has nothing.
pub fn is_ghost(prism: &Prism, truth: &Truth<'_>) -> bool {
    let Some((lo, hi)) = bounds(&prism.footprint) else {
        return false;
    };
    let offsets = [-REACH, 0.0, REACH];
    let near_something = |q: Point2<f64>| {
        offsets.iter().any(|&dx| {
            offsets
                .iter()
                .any(|&dy| truth.anything_at(q + Vector2::new(dx, dy)))
        })
    };
    let (nx, ny) = (
        ((hi.x - lo.x) / STEP).ceil() as usize,
        ((hi.y - lo.y) / STEP).ceil() as usize,
    );
    let mut inside = prism
        .footprint
        .iter()
        .copied()
        .chain((0..=nx).flat_map(|i| {
            (0..=ny).map(move |j| Point2::new(lo.x + i as f64 * STEP, lo.y + j as f64 * STEP))
        }));
    !inside.any(|q| (prism.contains_xy(&q) || prism.footprint.contains(&q)) && near_something(q))
}

/// Corners of the box around `footprint`; `None` for an empty one.
fn bounds(footprint: &[Point2<f64>]) -> Option<(Point2<f64>, Point2<f64>)> {
    let first = *footprint.first()?;
    Some(
        footprint
            .iter()
            .fold((first, first), |(lo, hi), p| (lo.inf(p), hi.sup(p))),
    )
}
