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

use crate::problem::GoalRegion;
use crate::validity::{StateValidity, Validity};

/// Side of the flood fill's cells (m): small beside the robot's radius, so a blocked cell's test
/// loses little (half a diagonal, 3.5 cm) and thin walls of grown obstacles still block.
pub const REACH_CELL: f64 = 0.05;

/// Whether the robot's axis certainly cannot move from `start` into `goal` in `validity`'s world.
///
/// `false` means "maybe" (the planner decides). A start outside the planning bounds gives `false`.
pub fn certainly_unreachable(validity: &Validity, start: &Point2<f64>, goal: &GoalRegion) -> bool {
    let bounds = validity.sampling_bounds();
    let (min, size) = (bounds.min(), bounds.size());
    let cols = ((size.x / REACH_CELL).ceil() as usize).max(1);
    let rows = ((size.y / REACH_CELL).ceil() as usize).max(1);
    let cell_of = |p: &Point2<f64>| -> Option<(usize, usize)> {
        let c = ((p.x - min.x) / REACH_CELL).floor();
        let r = ((p.y - min.y) / REACH_CELL).floor();
        let inside = c >= 0.0 && r >= 0.0 && (c as usize) < cols && (r as usize) < rows;
        // A point on the far edge of the bounds belongs to the last cell.
        let clamp = |v: f64, n: usize| (v.max(0.0) as usize).min(n - 1);
        let on_edge = bounds.contains(p);
        (inside || on_edge).then(|| (clamp(c, cols), clamp(r, rows)))
    };
    let Some(first) = cell_of(start) else {
        return false;
    };
    let half_diagonal = REACH_CELL * std::f64::consts::FRAC_1_SQRT_2;
    let centre = |c: usize, r: usize| {
        Point2::new(
            min.x + (c as f64 + 0.5) * REACH_CELL,
            min.y + (r as f64 + 0.5) * REACH_CELL,
        )
    };
    // A cell meets the goal disc when its centre is within the tolerance plus its half-diagonal.
    let meets_goal = |c: usize, r: usize| {
        (centre(c, r) - goal.centre()).norm() <= goal.tolerance() + half_diagonal
    };
    let mut seen = vec![false; cols * rows];
    let mut queue = VecDeque::from([first]);
    seen[first.1 * cols + first.0] = true;
    while let Some((c, r)) = queue.pop_front() {
        if meets_goal(c, r) {
            return false;
        }
        for (dc, dr) in NEIGHBOURS {
            let (nc, nr) = (c as i64 + dc, r as i64 + dr);
            if nc < 0 || nr < 0 || nc as usize >= cols || nr as usize >= rows {
                continue;
            }
            let (nc, nr) = (nc as usize, nr as usize);
            let k = nr * cols + nc;
            if seen[k] {
                continue;
            }
            seen[k] = true;
            if !validity.deeper_than(&centre(nc, nr), half_diagonal) {
                queue.push_back((nc, nr));
            }
        }
    }
    true
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
}
