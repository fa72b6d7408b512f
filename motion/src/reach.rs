//! A proof that no path exists, cheaper than a planner running out of budget.
//!
//! A sampling planner cannot tell "no path" from "not found yet": a query with no answer spends its
//! whole budget (thousands of iterations). Push planning asks many such questions — every push that
//! does not open the way to the goal is one. Here the free space is over-approximated on a grid: a
//! cell is *blocked* only when every robot position inside it overlaps an obstacle, shown by its
//! centre lying deeper than the cell's half-diagonal inside an obstacle grown by the robot's radius.
//! Any collision-free path of the robot's axis passes only through cells that are not blocked, each
//! touching the next at an edge or a corner; so when a flood fill over such cells (8-neighbours) from
//! the start's cell reaches no cell meeting the goal region, no path exists at all. The converse does
//! not hold: a fill that reaches the goal proves nothing, and the planner must run.

use std::collections::VecDeque;

use nalgebra::Point2;
use nudge_perception::ObjectId;

use crate::problem::GoalRegion;
use crate::validity::{StateValidity, Validity};

/// Side of the flood fill's cells (m): small beside the robot's radius, so a blocked cell's test
/// loses little (half a diagonal, 3.5 cm) and thin walls of grown obstacles still block.
pub const REACH_CELL: f64 = 0.05;

/// Whether the robot's axis certainly cannot move from `start` into `goal` in `validity`'s world.
///
/// `false` means "maybe" (the planner decides). A start outside the planning bounds gives `false`.
pub fn certainly_unreachable(validity: &Validity, start: &Point2<f64>, goal: &GoalRegion) -> bool {
    let cells = Cells::of(validity);
    cells.flood(start, goal, |_, p| {
        validity.deeper_than(p, cells.half_diagonal)
    })
}

/// What a flood fill's cells found in one world, kept for the flood fills of its variants (some of
/// its obstacles taken away, one of them moved): a push sequence's search asks the same room again
/// and again with one or two things changed. A variant tests again only the cells whose answer the
/// change can alter, so its answer is exactly [`certainly_unreachable`]'s.
pub struct ReachMemo<'v> {
    base: &'v Validity,
    cells: Cells,
    found: Vec<Memo>,
}

/// How a variant of the memo's world differs from it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Change<'a> {
    /// Obstacles taken away.
    pub removed: &'a [ObjectId],
    /// An obstacle moved (it is in the variant at its new place).
    pub moved: Option<ObjectId>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Memo {
    Unknown,
    Free,
    Blocked(ObjectId),
}

impl<'v> ReachMemo<'v> {
    /// An empty memo of `base`.
    pub fn new(base: &'v Validity) -> Self {
        let cells = Cells::of(base);
        Self {
            base,
            found: vec![Memo::Unknown; cells.cols * cells.rows],
            cells,
        }
    }

    /// [`certainly_unreachable`] in `variant`, which is the memo's world changed by `change`. A
    /// variant with other planning bounds is flood-filled afresh.
    pub fn certainly_unreachable(
        &mut self,
        variant: &Validity,
        change: Change<'_>,
        start: &Point2<f64>,
        goal: &GoalRegion,
    ) -> bool {
        if variant.sampling_bounds() != self.base.sampling_bounds() {
            return certainly_unreachable(variant, start, goal);
        }
        let half = self.cells.half_diagonal;
        let (base, found) = (self.base, &mut self.found);
        self.cells.flood(start, goal, |k, p| {
            if found[k] == Memo::Unknown {
                found[k] = base
                    .deeper_than_which(p, half)
                    .map_or(Memo::Free, Memo::Blocked);
            }
            match found[k] {
                // Nothing overlaps here in the world itself: only the moved obstacle can.
                Memo::Free | Memo::Unknown => change
                    .moved
                    .is_some_and(|id| variant.obstacle_deeper_than(id, p, half)),
                Memo::Blocked(id) if !change.removed.contains(&id) && change.moved != Some(id) => {
                    true
                }
                Memo::Blocked(_) => variant.deeper_than(p, half),
            }
        })
    }
}

/// The flood fill's grid over a world's planning bounds.
struct Cells {
    min: Point2<f64>,
    cols: usize,
    rows: usize,
    half_diagonal: f64,
    bounds: crate::space::Bounds,
}

impl Cells {
    fn of(validity: &Validity) -> Self {
        let bounds = validity.sampling_bounds();
        let (min, size) = (bounds.min(), bounds.size());
        Self {
            min,
            cols: ((size.x / REACH_CELL).ceil() as usize).max(1),
            rows: ((size.y / REACH_CELL).ceil() as usize).max(1),
            half_diagonal: REACH_CELL * std::f64::consts::FRAC_1_SQRT_2,
            bounds: *bounds,
        }
    }

    fn cell_of(&self, p: &Point2<f64>) -> Option<(usize, usize)> {
        let c = ((p.x - self.min.x) / REACH_CELL).floor();
        let r = ((p.y - self.min.y) / REACH_CELL).floor();
        let inside = c >= 0.0 && r >= 0.0 && (c as usize) < self.cols && (r as usize) < self.rows;
        // A point on the far edge of the bounds belongs to the last cell.
        let clamp = |v: f64, n: usize| (v.max(0.0) as usize).min(n - 1);
        let on_edge = self.bounds.contains(p);
        (inside || on_edge).then(|| (clamp(c, self.cols), clamp(r, self.rows)))
    }

    fn centre(&self, c: usize, r: usize) -> Point2<f64> {
        Point2::new(
            self.min.x + (c as f64 + 0.5) * REACH_CELL,
            self.min.y + (r as f64 + 0.5) * REACH_CELL,
        )
    }

    /// Breadth-first from `start`'s cell through cells `blocked(index, centre)` refuses; true when
    /// no cell meeting the goal disc is reached.
    fn flood(
        &self,
        start: &Point2<f64>,
        goal: &GoalRegion,
        mut blocked: impl FnMut(usize, &Point2<f64>) -> bool,
    ) -> bool {
        let Some(first) = self.cell_of(start) else {
            return false;
        };
        // A cell meets the goal disc when its centre is within the tolerance plus its half-diagonal.
        let meets_goal = |c: usize, r: usize| {
            (self.centre(c, r) - goal.centre()).norm() <= goal.tolerance() + self.half_diagonal
        };
        let cols = self.cols;
        let mut seen = vec![false; cols * self.rows];
        let mut queue = VecDeque::from([first]);
        seen[first.1 * cols + first.0] = true;
        while let Some((c, r)) = queue.pop_front() {
            if meets_goal(c, r) {
                return false;
            }
            for (dc, dr) in NEIGHBOURS {
                let (nc, nr) = (c as i64 + dc, r as i64 + dr);
                if nc < 0 || nr < 0 || nc as usize >= cols || nr as usize >= self.rows {
                    continue;
                }
                let (nc, nr) = (nc as usize, nr as usize);
                let k = nr * cols + nc;
                if seen[k] {
                    continue;
                }
                seen[k] = true;
                if !blocked(k, &self.centre(nc, nr)) {
                    queue.push_back((nc, nr));
                }
            }
        }
        true
    }
}

/// The 8-neighbourhood of a grid cell, as (column, row) steps.
pub(crate) const NEIGHBOURS: [(i64, i64); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (1, -1),
    (-1, 1),
    (-1, -1),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::obstacle::Obstacle;
    use crate::space::Bounds;
    use crate::validity::{RobotCylinder, ValidityConfig};
    use nudge_perception::ObjectId;

    fn wall_with_gap(gap: f64) -> Validity {
        // A wall across y = 4..5 of a 10 × 10 room, with a gap of `gap` metres around x = 5.
        let rect = |id, x0: f64, x1: f64| {
            let pts = [
                Point2::new(x0, 4.0),
                Point2::new(x1, 4.0),
                Point2::new(x1, 5.0),
                Point2::new(x0, 5.0),
            ];
            Obstacle::new(ObjectId(id), &pts, 0.0, 1.0).expect("rectangle")
        };
        let robot = RobotCylinder {
            radius: 0.3,
            height: 1.5,
        };
        let walls = Bounds::new(Point2::new(0.0, 0.0), Point2::new(10.0, 10.0)).expect("bounds");
        let obstacles = vec![
            rect(1, 0.0, 5.0 - gap / 2.0),
            rect(2, 5.0 + gap / 2.0, 10.0),
        ];
        Validity::from_obstacles(robot, walls, obstacles, ValidityConfig::default())
            .expect("valid world")
    }

    #[test]
    fn a_wall_narrower_than_the_robot_is_proven_closed_and_a_wide_gap_is_not() {
        // Invariant: a gap narrower than the robot's diameter is proven unpassable (by a margin of
        // the cell's half-diagonal), while a gap the robot fits through is never declared closed.
        let goal = GoalRegion::new(Point2::new(5.0, 8.0), 0.2).expect("goal");
        let start = Point2::new(5.0, 1.0);
        assert!(certainly_unreachable(&wall_with_gap(0.4), &start, &goal));
        assert!(certainly_unreachable(&wall_with_gap(0.0), &start, &goal));
        for gap in [0.61, 0.7, 1.0] {
            let v = wall_with_gap(gap);
            assert!(
                v.is_free(&Point2::new(5.0, 4.5)),
                "gap {gap} fits the robot"
            );
            assert!(!certainly_unreachable(&v, &start, &goal), "gap {gap}");
        }
        // The same side of the wall: reachable.
        let near = GoalRegion::new(Point2::new(8.0, 1.0), 0.2).expect("goal");
        assert!(!certainly_unreachable(&wall_with_gap(0.0), &start, &near));
    }

    #[test]
    fn the_memo_answers_every_variant_as_a_fresh_flood_fill() {
        // Invariant: for a world's variants (obstacles removed, one moved by many offsets, both), a memo shared across all of them gives exactly the fresh flood fill's answer, both answers occurring.
        let square = |id, x: f64, y: f64| {
            let pts = [
                Point2::new(x, y),
                Point2::new(x + 0.8, y),
                Point2::new(x + 0.8, y + 0.8),
                Point2::new(x, y + 0.8),
            ];
            Obstacle::new(ObjectId(id), &pts, 0.0, 1.0).expect("square")
        };
        let robot = RobotCylinder {
            radius: 0.3,
            height: 1.5,
        };
        let walls = Bounds::new(Point2::new(0.0, 0.0), Point2::new(6.0, 4.0)).expect("bounds");
        // A wall of squares across x = 3 with one more beside it, and a stray square.
        let obstacles: Vec<Obstacle> = (0..5)
            .map(|k| square(k + 1, 2.6, f64::from(k) * 0.8))
            .chain([square(6, 1.5, 1.6), square(7, 4.5, 0.5)])
            .collect();
        let base = Validity::from_obstacles(robot, walls, obstacles, ValidityConfig::default())
            .expect("world");
        let start = Point2::new(0.8, 2.0);
        let goal = GoalRegion::new(Point2::new(5.3, 2.0), 0.2).expect("goal");
        let mut memo = ReachMemo::new(&base);
        let mut answers = [0, 0];
        for removed in [vec![], vec![ObjectId(3)], vec![ObjectId(2), ObjectId(3)]] {
            for moved in [None, Some(ObjectId(6)), Some(ObjectId(4))] {
                for k in 0..6 {
                    let offset =
                        nalgebra::Vector2::new(f64::from(k) * 0.35, f64::from(k % 3) * 0.4);
                    let mut variant = base.without(&removed);
                    if let Some(id) = moved.filter(|id| !removed.contains(id)) {
                        variant = variant.with_moved(id, &offset).expect("moved");
                    }
                    let fresh = certainly_unreachable(&variant, &start, &goal);
                    let change = Change {
                        removed: &removed,
                        moved: moved.filter(|id| !removed.contains(id)),
                    };
                    let shared = memo.certainly_unreachable(&variant, change, &start, &goal);
                    assert_eq!(
                        shared, fresh,
                        "removed {removed:?}, moved {moved:?} by {offset:?}"
                    );
                    answers[usize::from(fresh)] += 1;
                }
            }
        }
        assert!(answers[0] > 0 && answers[1] > 0, "{answers:?}");
    }
}
