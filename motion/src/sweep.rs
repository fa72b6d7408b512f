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

/// What `object` runs into when translated by `offset` among `others` (obstacles other than the
/// object; only those whose height range meets it count) and `validity`'s walls, or `None` when the
/// sweep keeps `clearance` from all of them (see [`sweep_keeps_clear`]).
pub fn sweep_blocked_among(
    object: &Obstacle,
    offset: &Vector2<f64>,
    others: &[&Obstacle],
    validity: &Validity,
    clearance: f64,
) -> Result<Option<SweepBlock>, ObstacleError> {
    let swept = object.swept(offset)?;
    let hit = others
        .iter()
        .filter(|o| o.id() != object.id() && o.heights_overlap(object))
        .find(|o| {
            let start_gap = o.distance_to_obstacle(object);
            if start_gap > 0.0 {
                !sweep_keeps_clear(start_gap, o.distance_to_obstacle(&swept), clearance)
            } else {
                !parts_from(object, offset, o)
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
    clearance: f64,
) -> Result<Option<SweepBlock>, ObstacleError> {
    let others: Vec<&Obstacle> = validity
        .obstacles()
        .iter()
        .filter(|o| o.id() != object.id())
        .collect();
    sweep_blocked_among(object, offset, &others, validity, clearance)
}

/// Whether translating `object` by `offset`, from where it touches or overlaps `other`, never takes
/// it deeper into `other`. Perception's footprints of things a few centimetres apart (a box and a
/// door jamb) may touch; such a push is fine as long as it leads away from, or along, the other.
///
/// The signed distance between two convex footprints is a convex function of the translation (it is
/// the signed distance of a point to their Minkowski difference, a convex set). So if it does not
/// fall over the first centimetre, its slope there is at least −rounding per centimetre, and it
/// can fall at most that fast over the rest. Along a face a few thousandths of a radian off
/// parallel, that is still a millimetre or more over a long push, so the end is checked too;
/// between the two, a push bending round a corner may still dip by that slope times its length.
fn parts_from(object: &Obstacle, offset: &Vector2<f64>, other: &Obstacle) -> bool {
    /// A first step, short against any push, long against parry's f32 rounding.
    const STEP: f64 = 0.01;
    /// How much the signed distance may read lower by rounding alone (m).
    const ROUNDING: f64 = 1e-4;
    let length = offset.norm();
    if length <= 0.0 {
        return true;
    }
    let before = object.signed_distance_to_obstacle(other);
    let no_deeper = |fraction: f64| {
        object
            .translated(&(offset * fraction))
            .is_ok_and(|moved| moved.signed_distance_to_obstacle(other) >= before - ROUNDING)
    };
    no_deeper(STEP.min(length) / length) && no_deeper(1.0)
}

/// Whether a sweep whose footprint lies `swept_gap` (m) from an obstacle, starting `start_gap` from it,
/// keeps clear of it: it never touches it, and keeps `clearance`, or, from an obstacle the object
/// already stands closer to, the gap it starts with (the sweep holds the start footprint, so that is
/// the most it can keep: the object may move away, not closer).
pub fn sweep_keeps_clear(start_gap: f64, swept_gap: f64, clearance: f64) -> bool {
    swept_gap > 0.0 && swept_gap >= clearance.min(start_gap - 1e-6)
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

    #[test]
    fn a_sweep_keeps_the_clearance_or_the_gap_it_starts_with() {
        // Invariant: a push may not graze another obstacle (closer than the clearance) unless the object already starts closer, in which case it may only keep its starting gap (move away or alongside), never come closer or touch.
        assert!(sweep_keeps_clear(0.3, 0.2, 0.05));
        assert!(!sweep_keeps_clear(0.3, 0.01, 0.05));
        assert!(!sweep_keeps_clear(0.3, 0.0, 0.05));
        assert!(sweep_keeps_clear(0.02, 0.02, 0.05));
        assert!(!sweep_keeps_clear(0.02, 0.01, 0.05));
        assert!(!sweep_keeps_clear(0.0, 0.0, 0.05));
    }

    #[test]
    fn a_sweep_names_what_it_runs_into() {
        // Invariant: a box pushed 2 m along +x meets the box 1.5 m ahead of it (named by id), pushed 0.5 m it meets nothing, pushed 5 m it leaves the room; the object itself, also in the world, never blocks its own sweep.
        let object = square(1, 1.0, 1.5, 0.5);
        let ahead = square(2, 2.8, 1.5, 0.5);
        let world = room(vec![object.clone(), ahead]);
        let along = |d: f64| sweep_blocked(&object, &Vector2::new(d, 0.0), &world, 0.05);
        assert_eq!(along(0.5).expect("sweep"), None);
        assert_eq!(
            along(2.0).expect("sweep"),
            Some(SweepBlock::Obstacle(ObjectId(2)))
        );
        let alone = room(vec![object.clone()]);
        assert_eq!(
            sweep_blocked(&object, &Vector2::new(5.0, 0.0), &alone, 0.05).expect("sweep"),
            Some(SweepBlock::Wall)
        );
    }

    #[test]
    fn a_box_whose_outline_touches_a_jamb_may_be_pushed_away_or_along_it_never_into_it() {
        // Invariant: an object whose footprint already overlaps another's (perception joined a box and a door jamb a few centimetres apart) may be pushed where the overlap never deepens (away from the jamb, or along it) and is refused a push into it.
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
        let push = |x: f64, y: f64| sweep_blocked(&object, &Vector2::new(x, y), &world, 0.05);
        assert_eq!(push(1.0, 0.0).expect("east"), None, "along the jamb");
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
