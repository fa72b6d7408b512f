//! Whether an object's sweep keeps clear of everything else: push planning checks every push with it,
//! and a clearing push re-checks the rest of its sweep from where the object was last measured.

use nalgebra::Vector2;
use nudge_perception::ObjectId;

use crate::obstacle::{Obstacle, ObstacleError};
use crate::validity::Validity;

/// What a sweep runs into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepBlock {
    /// Another obstacle whose height range meets the object's.
    Obstacle(ObjectId),
    /// The room's walls.
    Wall,
}

/// How close a sweep may come to what it passes.
///
/// Footprints are convex hulls of noisy points, so two things that touch (a box flush against a
/// wall, two boxes abreast in a doorway) have hulls that touch, overlap by a centimetre, or part by
/// one, and their faces lean a degree or two off each other. A push along such a neighbour comes a
/// little closer to it, or a little deeper into it, over its length without the true objects
/// meeting any more than they do. `contact` is how much: about what a hull's faces are known to.
/// A hull's extreme points lie up to three range-noise σ outside the true surface, and the
/// camera's σ grows with distance to 4 mm × (5 m / 1.3 m) = 15 mm at its 5 m range: 4.6 cm, one
/// elevation cell (4 cm) to within the cell's own rounding. The planner sets it to that cell
/// ([`crate::PushConfig::sweep_margins`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweepMargins {
    /// Least gap (m) kept from every obstacle the object starts more than `contact` from.
    pub clearance: f64,
    /// How much closer, or deeper into it, a push may take the object over its whole length (m)
    /// than it starts to an obstacle it starts within `contact` of; from one farther away, how
    /// much of its start gap a push may close when that gap is below `clearance`.
    pub contact: f64,
    /// Most a push may head into what it starts within `contact` of (rad, off parallel to their
    /// contact): beyond it the push lies within their contact's friction cone and may jam rather
    /// than slide along ([`crate::push::MAX_CONTACT_FRICTION`]). Where two hulls meet at a corner,
    /// their contact normal turns through the corner's angle as the gap closes, so the lean alone
    /// says little of a push's path; the depth over its length (`contact`) bounds that.
    pub lean: f64,
}

impl SweepMargins {
    /// Whether a sweep whose footprint lies `swept_gap` (m) from an obstacle it starts `start_gap`
    /// (m) from, both more than `contact`, keeps clear of it: it keeps `clearance`, or from an
    /// obstacle it starts nearer to, closes at most `contact` of its gap. The sweep holds the start
    /// footprint, so `swept_gap <= start_gap` always.
    pub fn keep_clear(&self, start_gap: f64, swept_gap: f64) -> bool {
        swept_gap > 0.0 && swept_gap >= self.clearance.min(start_gap - self.contact)
    }

    /// Whether a push along `direction` (unit) of an object within `contact` of an obstacle, at
    /// `start` (m, signed) from it with `normal` the unit normal of their contact (from the object
    /// towards the obstacle), whose sweep lies `swept` (m, signed) from it, slides along or away
    /// from it: it heads into it by no more than `lean` off parallel and, over its length, goes at
    /// most `contact` deeper. The depth alone would not do: against a hull only a few centimetres thick
    /// (a cabinet seen only by its face) the deepest a sweep straight into it can read is that
    /// thickness.
    pub fn slides_along(
        &self,
        direction: &Vector2<f64>,
        normal: &Vector2<f64>,
        start: f64,
        swept: f64,
    ) -> bool {
        direction.dot(normal) <= self.lean.sin() && swept >= start - self.contact
    }
}

/// What `object` runs into when translated by `offset` among `others` (obstacles other than the
/// object; only those whose height range meets it count) and `validity`'s walls, or `None` when the
/// push keeps `margins` from all of them: from what it starts within `margins.contact` of, it
/// slides along or away ([`SweepMargins::slides_along`]); from the rest its sweep keeps clear
/// ([`SweepMargins::keep_clear`]). The sweep's footprint is the hull of the start and end
/// footprints, which for a convex footprint translated along a line is the union of every
/// footprint on the way: its gap is the least gap the push comes to.
pub fn sweep_blocked_among(
    object: &Obstacle,
    offset: &Vector2<f64>,
    others: &[&Obstacle],
    validity: &Validity,
    margins: SweepMargins,
) -> Result<Option<SweepBlock>, ObstacleError> {
    let length = offset.norm();
    if length <= 0.0 {
        return Ok(None);
    }
    let direction = offset / length;
    let swept = object.swept(offset)?;
    let hit = others
        .iter()
        .filter(|o| o.id() != object.id() && o.heights_overlap(object))
        .find(|o| {
            let start_gap = object.distance_to_obstacle(o);
            // Only what the object starts against needs their contact's normal and depth.
            let contact = (start_gap <= margins.contact)
                .then(|| object.contact_with(o, margins.contact))
                .flatten();
            match contact {
                Some((normal, start)) => {
                    let swept_gap = swept.signed_distance_to_obstacle(o);
                    !margins.slides_along(&direction, &normal, start, swept_gap)
                }
                None => !margins.keep_clear(start_gap, swept.distance_to_obstacle(o)),
            }
        });
    if let Some(o) = hit {
        return Ok(Some(SweepBlock::Obstacle(o.id())));
    }
    let walls = validity.walls();
    Ok((!swept.footprint().iter().all(|p| walls.contains(p))).then_some(SweepBlock::Wall))
}

/// [`sweep_blocked_among`] against every obstacle of `validity` but `object` itself (matched by id):
/// for a caller that holds the object where it was measured, not where the world model has it.
pub fn sweep_blocked(
    object: &Obstacle,
    offset: &Vector2<f64>,
    validity: &Validity,
    margins: SweepMargins,
) -> Result<Option<SweepBlock>, ObstacleError> {
    let others: Vec<&Obstacle> = validity
        .obstacles()
        .iter()
        .filter(|o| o.id() != object.id())
        .collect();
    sweep_blocked_among(object, offset, &others, validity, margins)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::validity::{RobotCylinder, ValidityConfig};
    use nalgebra::Point2;

    fn square(id: u32, x: f64, y: f64, side: f64) -> Obstacle {
        let h = side / 2.0;
        let f = [
            Point2::new(x - h, y - h),
            Point2::new(x + h, y - h),
            Point2::new(x + h, y + h),
            Point2::new(x - h, y + h),
        ];
        Obstacle::new(ObjectId(id), &f, 0.0, 1.0).expect("square")
    }

    fn room(obstacles: Vec<Obstacle>) -> Validity {
        let bounds = crate::space::Bounds::new(Point2::new(0.0, 0.0), Point2::new(6.0, 3.0))
            .expect("bounds");
        Validity::from_obstacles(
            RobotCylinder {
                radius: 0.35,
                height: 1.5,
            },
            bounds,
            obstacles,
            ValidityConfig::default(),
        )
        .expect("validity")
    }

    const MARGINS: SweepMargins = SweepMargins {
        clearance: 0.05,
        contact: 0.04,
        lean: std::f64::consts::FRAC_PI_4,
    };

    #[test]
    fn a_sweep_keeps_the_clearance_or_comes_at_most_the_contact_margin_closer() {
        // Invariant: a sweep keeps the clearance from what it starts well clear of and never touches it; from what it starts within the clearance of, it closes at most `contact` of the gap; from what it starts within `contact` of, a push heads into it by less than `lean` and closes in by at most `contact` over its whole length.
        assert!(MARGINS.keep_clear(0.3, 0.2));
        assert!(!MARGINS.keep_clear(0.3, 0.01));
        assert!(!MARGINS.keep_clear(0.3, 0.0));
        assert!(MARGINS.keep_clear(0.07, 0.035));
        assert!(!MARGINS.keep_clear(0.07, 0.02), "closes more than contact");
        assert!(!MARGINS.keep_clear(0.045, 0.0), "never touches");
        let east = Vector2::new(1.0, 0.0);
        let north = Vector2::new(0.0, 1.0);
        let leaning = Vector2::new(1.0, 0.1).normalize();
        assert!(
            MARGINS.slides_along(&east, &north, -0.01, -0.02),
            "along it"
        );
        assert!(
            MARGINS.slides_along(&leaning, &north, -0.01, -0.04),
            "6° into it, 3 cm deeper"
        );
        assert!(
            !MARGINS.slides_along(&leaning, &north, -0.01, -0.06),
            "6° into it, 5 cm deeper"
        );
        assert!(
            !MARGINS.slides_along(&north, &north, -0.01, -0.03),
            "straight into it, however thin its hull"
        );
        assert!(
            MARGINS.slides_along(&-north, &north, -0.01, -0.01),
            "away from it"
        );
    }

    #[test]
    fn a_sweep_names_what_it_runs_into() {
        // Invariant: a box pushed 2 m along +x meets the box 1.5 m ahead of it (named by id), pushed 0.5 m it meets nothing, pushed 5 m it leaves the room; the object itself, also in the world, never blocks its own sweep.
        let object = square(1, 1.0, 1.5, 0.5);
        let ahead = square(2, 2.8, 1.5, 0.5);
        let world = room(vec![object.clone(), ahead]);
        let along = |d: f64| sweep_blocked(&object, &Vector2::new(d, 0.0), &world, MARGINS);
        assert_eq!(along(0.5).expect("sweep"), None);
        assert_eq!(
            along(2.0).expect("sweep"),
            Some(SweepBlock::Obstacle(ObjectId(2)))
        );
        let alone = room(vec![object.clone()]);
        assert_eq!(
            sweep_blocked(&object, &Vector2::new(5.0, 0.0), &alone, MARGINS).expect("sweep"),
            Some(SweepBlock::Wall)
        );
    }

    #[test]
    fn a_box_whose_outline_touches_a_jamb_may_be_pushed_away_or_along_it_never_into_it() {
        // Invariant: an object whose footprint already overlaps another's (a box and a door jamb a few centimetres apart) may be pushed where the overlap deepens by no more than the contact margin (away from the jamb, or along it as its lean is measured) and is refused a push into it.
        let object = square(1, 2.0, 1.5, 0.6);
        // The jamb overlaps the box's north face by 2 cm.
        let jamb = Obstacle::new(
            ObjectId(2),
            &[
                Point2::new(1.9, 1.78),
                Point2::new(2.1, 1.78),
                Point2::new(2.1, 2.5),
                Point2::new(1.9, 2.5),
            ],
            0.0,
            2.0,
        )
        .expect("jamb");
        assert!(object.signed_distance_to_obstacle(&jamb) < -0.015);
        let world = room(vec![object.clone(), jamb]);
        let push = |x: f64, y: f64| sweep_blocked(&object, &Vector2::new(x, y), &world, MARGINS);
        assert_eq!(push(1.0, 0.0).expect("east"), None, "along the jamb");
        assert_eq!(
            push(1.0, 0.05).expect("east, 3° into it"),
            None,
            "along it as a hull's lean is measured: 2 cm deeper at the jamb, less than contact"
        );
        assert_eq!(
            push(1.0, 0.2).expect("east, 11° into it"),
            Some(SweepBlock::Obstacle(ObjectId(2))),
            "8 cm deeper at the jamb, more than contact"
        );
        assert_eq!(push(0.0, -0.8).expect("south"), None, "away from it");
        assert_eq!(
            push(0.0, 0.5).expect("north"),
            Some(SweepBlock::Obstacle(ObjectId(2))),
            "into it"
        );
        assert_eq!(
            push(0.5, 0.3).expect("north-east"),
            Some(SweepBlock::Obstacle(ObjectId(2))),
            "deeper first, clear later"
        );
    }
}
