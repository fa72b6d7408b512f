//! The planning lattice built by the planner's rule, against its definition cell by cell, on a grid
//! filled by laser scans.

mod view_world;

use nalgebra::Point2;
use nudge_motion::view::{Lattice, LatticeCell};
use nudge_perception::grid::{CellClass, CellIndex};
use view_world::{Block, World};

#[test]
fn a_lattice_cell_is_open_iff_the_disc_fits_on_observed_floor() {
    // Invariant: with the planner's rule, a lattice cell (2 × 2 grid cells) is open iff its centre
    // is farther than the robot's radius plus the clearance from every blocking obstacle and
    // wall, and at least 2 of its 4 grid cells are Free — or its centre lies within the robot's
    // radius of the robot; a mat (stepped over) and a shelf above the head block nothing.
    let world = World {
        size: [8.0, 6.0],
        blocks: vec![
            Block::new(3.0, 2.0, 4.2, 2.6, 0.0, 0.8),
            Block::new(5.5, 4.0, 6.0, 5.5, 0.0, 2.0),
            Block::new(1.0, 4.0, 2.0, 5.0, 0.0, 0.01),
            Block::new(6.0, 1.0, 7.0, 2.0, 1.6, 1.9),
        ],
    };
    let robot = Point2::new(1.5, 1.5);
    let mut grid = world.grid();
    // Half a turn, facing +x: the floor behind the robot stays unobserved.
    world.scan(&mut grid, robot, 0.0, std::f64::consts::PI, 4);
    let prisms = world.prisms();
    let validity = world.validity(&prisms);
    let clearance = 0.05;
    let lattice = Lattice::observed_floor(&grid, &validity, 2, clearance, robot).expect("lattice");
    assert_eq!((lattice.cols(), lattice.rows()), (80, 60));
    let radius = validity.robot().radius;
    let (mut open, mut unobserved, mut under_robot) = (0, 0, 0);
    for y in 0..60u32 {
        for x in 0..80u32 {
            let c = LatticeCell::new(x, y);
            let p = lattice.centre(c);
            // Distance from the disc's surface to the nearest obstacle or wall, less the clearance.
            let margin = validity.clearance(&p) - clearance;
            if margin.abs() < 1e-4 {
                continue; // on the boundary, to f32 precision
            }
            let free = (0..2)
                .flat_map(|dy| (0..2).map(move |dx| CellIndex::new(2 * x + dx, 2 * y + dy)))
                .filter(|&g| grid.class(g) == Some(CellClass::Free))
                .count();
            let by_robot = (p - robot).norm() <= radius;
            let want = margin > 0.0 && (free >= 2 || by_robot);
            assert_eq!(lattice.is_passable(c), want, "cell ({x}, {y}) at {p:?}");
            open += usize::from(want);
            unobserved += usize::from(margin > 0.0 && free < 2 && !by_robot);
            under_robot += usize::from(margin > 0.0 && free < 2 && by_robot);
        }
    }
    assert!(
        open > 1000 && unobserved > 500,
        "{open} open, {unobserved} unobserved"
    );
    assert!(under_robot > 0, "the robot's own cells count as floor");
    // The mat and the shelf block nothing: the cells over them are open where the floor was seen.
    for p in [Point2::new(1.55, 4.45), Point2::new(6.55, 1.55)] {
        let c = lattice.cell_of(p).expect("inside");
        let seen = grid.class_at(p) == Some(CellClass::Free);
        assert_eq!(lattice.is_passable(c), seen, "{p:?}");
    }
}
