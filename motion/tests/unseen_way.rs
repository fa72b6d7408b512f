//! The hypothesis behind "no path means no path": could floor nobody has seen open a way?

use nalgebra::{Isometry3, Point2, Point3};
use nudge_motion::{RobotCylinder, WayHypothesis, unseen_way};
use nudge_perception::grid::{GridConfig, GridGeometry, ObstacleGrid};
use nudge_perception::{CloudFrame, ColourCloud, ObjectId, Prism};

const ROBOT: RobotCylinder = RobotCylinder {
    radius: 0.35,
    height: 1.54,
};

/// A 6 × 4 m grid never updated: every cell unknown to the grid (what was seen is the test's say).
fn grid() -> ObstacleGrid {
    let geometry =
        GridGeometry::new(Point2::origin(), [6.0, 4.0], 0.05).expect("a 6 × 4 m grid of 5 cm");
    ObstacleGrid::new(geometry, GridConfig::default())
}

/// A partition at x 2.95..3.05 across the room, as one hull from wall to wall (perception joined the
/// two runs either side of the door at y 1.5..2.5), with returns every 2 cm on the runs at 0.3 to
/// 1.9 m: and on the door too when `door_seen_shut`.
fn partition(door_seen_shut: bool) -> Prism {
    let mut points = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
    for k in 0..=200 {
        let y = 0.02 * f64::from(k);
        if !door_seen_shut && (1.5..=2.5).contains(&y) {
            continue;
        }
        for z in [0.3, 1.0, 1.9] {
            points.push(Point3::new(3.0, y as f32, z), [200, 196, 186]);
        }
    }
    Prism {
        id: ObjectId(1),
        footprint: vec![
            Point2::new(2.95, 0.0),
            Point2::new(3.05, 0.0),
            Point2::new(3.05, 4.0),
            Point2::new(2.95, 4.0),
        ],
        z_min: 0.0,
        z_max: 2.0,
        points,
    }
}

fn ask(prism: &Prism, seen: &dyn Fn(usize) -> bool, open: &dyn Fn(usize) -> bool) -> WayHypothesis {
    unseen_way(
        &grid(),
        std::slice::from_ref(prism),
        ROBOT,
        0.03,
        (Point2::new(1.0, 2.0), Point2::new(5.0, 2.0), 0.2),
        seen,
        open,
    )
}

/// The centre of grid cell `i` of [`grid`].
fn centre(i: usize) -> Point2<f64> {
    let g = grid();
    let geometry = g.geometry();
    geometry.centre(geometry.cell_at(i).expect("a cell of the grid"))
}

#[test]
fn a_hull_over_an_unseen_door_is_a_way_through_the_door() {
    // Invariant: a hull drawn across a door whose floor nobody saw (returns only on the runs either side) leaves a way through the door, and the cells to look at are the hull's unseen cells in the doorway, none on the runs.
    let wall = partition(false);
    let WayHypothesis::Through(cells) = ask(&wall, &|_| false, &|_| true) else {
        panic!("an unseen door is a way");
    };
    assert!(!cells.is_empty());
    for &i in &cells {
        let p = centre(i);
        assert!(
            (2.95..=3.05).contains(&p.x),
            "{p} is not in the partition's hull"
        );
        assert!((1.5..=2.5).contains(&p.y), "{p} is not in the doorway");
    }
}

#[test]
fn a_hull_whose_floor_was_seen_or_held_returns_closes_the_way() {
    // Invariant: no unseen floor opens a way when the hull's floor in the doorway was seen (the hull is the object there), when returns stand all along the partition, or when the doorway's cells were given up on after looks that failed to show them.
    let wall = partition(false);
    assert_eq!(ask(&wall, &|_| true, &|_| true), WayHypothesis::Closed);
    assert_eq!(
        ask(&partition(true), &|_| false, &|_| true),
        WayHypothesis::Closed
    );
    assert_eq!(ask(&wall, &|_| false, &|_| false), WayHypothesis::Closed);
}

#[test]
fn floor_outside_every_hull_is_no_guess() {
    // Invariant: with no obstacle between the robot and the goal the hypothesis needs no guess: a way through no unseen hull cell.
    let far = Prism {
        footprint: vec![
            Point2::new(5.6, 3.6),
            Point2::new(5.9, 3.6),
            Point2::new(5.9, 3.9),
            Point2::new(5.6, 3.9),
        ],
        ..partition(false)
    };
    assert_eq!(
        ask(&far, &|_| false, &|_| true),
        WayHypothesis::Through(Vec::new())
    );
}
