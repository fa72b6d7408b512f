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
            !sweep_keeps_clear(
                o.distance_to_obstacle(object),
                o.distance_to_obstacle(&swept),
                clearance,
            )
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
}
