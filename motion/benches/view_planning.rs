//! One next-best-view decision on the office: an 800 × 600 grid (40 × 30 m, 5 cm cells) of rooms
//! joined by doors along a corridor, with furniture, filled by 360° laser scans (four frames each)
//! from 25 poses along the corridor, through the open plan and in some rooms. The targets are the
//! never-observed cells of one room (x 20..25, y 14..20), which the corridor saw only through its
//! door; the robot stands in the corridor 5 m away. Before criterion runs, the decision is taken
//! once and printed with the sizes of its inputs and the time of each stage (best of 20, which
//! the shared machine's load disturbs least). Timing is printed, never asserted.

#[path = "../tests/common/mod.rs"]
mod common;
#[path = "../tests/view_world/mod.rs"]
mod view_world;

use std::hint::black_box;

use common::best_of;
use criterion::{Criterion, criterion_group};
use nalgebra::Point2;
use nudge_motion::view::{Lattice, SightMap, Targets, ViewConfig, ViewScene, plan_view};
use view_world::{OFFICE_TARGET_ROOM, ROBOT, office, office_scan_poses, unobserved_in};

/// Where the robot stands: in the corridor, 5 m from the target room's door.
const ROBOT_AT: (f64, f64) = (17.5, 13.0);

fn bench(c: &mut Criterion) {
    let world = office();
    let mut grid = world.grid();
    world.scan_all(&mut grid, &office_scan_poses());
    // Perception keeps every point of a cluster; here 5 cm across the faces, 25 cm up them.
    let prisms = world.prisms_sampled(0.05, 0.25);
    let validity = world.validity(&prisms);
    let (lo, hi) = OFFICE_TARGET_ROOM;
    let targets = Targets::uniform(unobserved_in(&grid, lo, hi));
    let robot = Point2::new(ROBOT_AT.0, ROBOT_AT.1);
    let config = ViewConfig::default();
    let scene = ViewScene {
        grid: &grid,
        prisms: &prisms,
        validity: &validity,
        robot,
        targets: &targets,
        seen_floor: None,
    };
    let vp = plan_view(&scene, &config).expect("a viewpoint");
    let points: usize = prisms.iter().map(|p| p.points.len()).sum();
    let observed: u32 = grid.observed_words().iter().map(|w| w.count_ones()).sum();
    println!(
        "office: {} × {} cells, {} observed; {} prisms with {} points; {} target cells",
        grid.geometry().width(),
        grid.geometry().height(),
        observed,
        prisms.len(),
        points,
        targets.len()
    );
    println!(
        "view: stand at ({:.2}, {:.2}) facing {:.1}°, walk {:.2} m, gain {:.2} m², {:.4} m²/s, {} cells seen",
        vp.position.x,
        vp.position.y,
        vp.yaw.to_degrees(),
        vp.walk,
        vp.gain,
        vp.score,
        vp.seen.len()
    );
    let sight = best_of(20, || {
        black_box(SightMap::new(
            &grid,
            &prisms,
            &targets,
            &config.coverage,
            ROBOT.radius,
        ));
    });
    let lattice = best_of(20, || {
        black_box(Lattice::observed_floor(&grid, &validity, 2, config.clearance, robot).ok());
    });
    let l = Lattice::observed_floor(&grid, &validity, 2, config.clearance, robot).expect("lattice");
    let search = best_of(20, || {
        black_box(l.distances(robot).ok());
    });
    let whole = best_of(20, || {
        black_box(plan_view(&scene, &config).ok());
    });
    println!(
        "best of 20: sight map {sight:.2?}, lattice {lattice:.2?}, distances {search:.2?}, plan_view {whole:.2?}"
    );

    c.bench_function("view/plan_view_office_800x600", |b| {
        b.iter(|| black_box(plan_view(black_box(&scene), &config)))
    });
}

criterion_group!(benches, bench);

fn main() {
    benches();
    Criterion::default().configure_from_args().final_summary();
}
