//! The next-best-view planner on small worlds whose grids were filled by laser scans from chosen
//! poses (so "observed" is the grid's own), unless a test says its cells are placed by hand.

mod view_world;

use nalgebra::Point2;
use nudge_motion::view::{
    LookCoverage, NoView, SightMap, Targets, ViewConfig, ViewScene, plan_view,
};
use nudge_motion::{StateValidity, Validity};
use nudge_perception::Prism;
use nudge_perception::grid::{CellClass, CellIndex, ObstacleGrid};
use view_world::{Block, World, cells_of_class, segment_crosses, unobserved_in};

fn scene<'a>(
    grid: &'a ObstacleGrid,
    prisms: &'a [Prism],
    validity: &'a Validity,
    robot: Point2<f64>,
    targets: &'a Targets,
) -> ViewScene<'a> {
    ViewScene {
        grid,
        prisms,
        validity,
        robot,
        targets,
        seen_floor: None,
    }
}

fn wrap(a: f64) -> f64 {
    a.sin().atan2(a.cos())
}

/// A 10 × 8 m floor with a wall from the bottom edge to y = 5, the robot left of it at (3.5, 1.5),
/// scanned from there: the floor behind the wall is never observed.
fn wall_world() -> (World, Block, Point2<f64>) {
    let wall = Block::new(5.0, 0.0, 5.2, 5.0, 0.0, 2.0);
    let world = World {
        size: [10.0, 8.0],
        blocks: vec![wall],
    };
    (world, wall, Point2::new(3.5, 1.5))
}

#[test]
fn a_wall_hides_the_targets_and_the_planner_walks_round_its_end() {
    // Invariant: targets behind a wall are predicted unseen from the robot; the chosen position
    // lies past the wall's end with every cell it expects to see in line of sight, and its walking
    // distance is the collision-free geodesic path's length, longer than the straight line through
    // the wall.
    let (world, wall, robot) = wall_world();
    let mut grid = world.grid();
    world.scan_all(&mut grid, &[robot]);
    let prisms = world.prisms();
    let validity = world.validity(&prisms);
    let cells = unobserved_in(&grid, [6.0, 0.5], [8.5, 3.0]);
    assert!(cells.len() > 1500, "{} unobserved cells", cells.len());
    let targets = Targets::uniform(cells);
    let config = ViewConfig::default();
    let sight = SightMap::new(&grid, &prisms, &targets, &config.coverage, 0.3).expect("targets");
    assert_eq!(sight.gain_at(robot).1, 0.0, "the wall hides every target");

    let vp = plan_view(&scene(&grid, &prisms, &validity, robot, &targets), &config)
        .expect("a view round the wall");
    assert!(
        vp.position.y > 5.0 + 0.3,
        "past the wall's end: {:?}",
        vp.position
    );
    assert!(vp.gain > 1.0, "gain {}", vp.gain);
    assert!(!vp.seen.is_empty());
    let g = grid.geometry();
    for &c in &vp.seen {
        assert!(
            !segment_crosses(&wall, vp.position, g.centre(c)),
            "{c:?} behind the wall"
        );
        assert!(sight.floor_visible(vp.position, c));
    }
    // The walk is the geodesic path: it starts at the robot, ends at the position, is free, and
    // its length is the walking distance (which starts at the centre of the robot's lattice cell,
    // at most half its diagonal from the robot).
    assert_eq!(vp.path.first(), Some(&robot));
    assert_eq!(vp.path.last(), Some(&vp.position));
    let length: f64 = vp.path.windows(2).map(|s| (s[1] - s[0]).norm()).sum();
    assert!((length - vp.walk).abs() < 0.075, "{} vs {length}", vp.walk);
    for s in vp.path.windows(2) {
        assert!(validity.motion_free(&s[0], &s[1]), "{s:?}");
    }
    assert!(
        !validity.motion_free(&robot, &vp.position),
        "the straight line meets the wall"
    );
    assert!(
        vp.walk > (vp.position - robot).norm() + 0.3,
        "walk {}",
        vp.walk
    );
    let seconds = vp.walk / config.walk_speed + config.look_time;
    assert!((vp.score - vp.gain / seconds).abs() < 1e-12);
}

#[test]
fn a_low_box_hides_only_the_floor_in_its_shadow() {
    // Invariant: a box of height h whose far edge is at distance d hides the floor from d to
    // d·H/(H − h) along the ray from an eye at H; the floor beyond is predicted visible, and a look
    // from the robot counts it. (The target cells are chosen by hand: a strip behind the box.)
    let boxed = Block::new(3.02, 3.52, 3.32, 4.52, 0.0, 0.4);
    let world = World {
        size: [8.0, 8.0],
        blocks: vec![boxed],
    };
    let robot = Point2::new(1.025, 4.025);
    let mut grid = world.grid();
    world.scan_all(&mut grid, &[robot]);
    let prisms = world.prisms();
    let face = cells_of_class(&grid, CellClass::Stationary, [3.0, 3.5], [3.1, 4.5]);
    assert!(
        face.len() >= 15,
        "the box's face is Stationary: {}",
        face.len()
    );
    let row = 80; // y = 4.025: straight along +x from the robot
    let strip: Vec<CellIndex> = (68..110).map(|x| CellIndex::new(x, row)).collect();
    let targets = Targets::uniform(strip.iter().copied());
    let coverage = LookCoverage::default();
    let sight = SightMap::new(&grid, &prisms, &targets, &coverage, 0.3).expect("targets");
    let h = coverage.eye_height;
    let occluder = sight
        .occluder_height(CellIndex::new(63, row))
        .expect("box points");
    assert!((occluder - 0.4).abs() < 1e-6, "{occluder}");
    // The farthest occluder cell ends at x = 3.35, 2.325 m from the eye.
    let shadow_end = robot.x + (3.35 - robot.x) * h / (h - 0.4);
    let look = sight.predict(robot);
    let g = grid.geometry();
    for &c in &strip {
        let x = g.centre(c).x;
        let visible = sight.floor_visible(robot, c);
        if x < 3.32 {
            continue; // under the box
        } else if x < shadow_end - 0.05 {
            assert!(!visible, "x = {x} is in the shadow (ends {shadow_end})");
            assert!(!look.seen.contains(&c));
        } else if x > shadow_end + 0.05 {
            assert!(visible, "x = {x} is beyond the shadow (ends {shadow_end})");
            if x - robot.x < coverage.far - 0.05 {
                assert!(look.seen.contains(&c), "x = {x}");
            }
        }
    }
    assert!(
        wrap(look.heading).abs() < 0.2,
        "faces the strip: {}",
        look.heading
    );
}

#[test]
fn a_prism_hides_behind_its_points_not_inside_its_hull() {
    // Invariant: the unseen interior of a prism's hull is no occluder (floor inside it is predicted
    // visible), while the cells holding its points occlude up to their height. (Hand-placed: the
    // grid is never updated, so no cell is an obstacle and the prism alone occludes; its points lie
    // on its far face only, as when the near face was never seen.)
    let world = World {
        size: [8.0, 8.0],
        blocks: vec![],
    };
    let grid = world.grid();
    let robot = Point2::new(1.025, 4.025);
    let mut prism = Block::new(3.02, 3.02, 4.52, 5.02, 0.0, 1.0).prism(1, 0.025);
    let (xs, ys, zs) = (
        prism.points.xs().to_vec(),
        prism.points.ys().to_vec(),
        prism.points.zs().to_vec(),
    );
    let mut far_face = nudge_perception::ColourCloud::empty(
        nudge_perception::CloudFrame::Map,
        nalgebra::Isometry3::identity(),
        0.0,
    );
    for ((&x, &y), &z) in xs.iter().zip(&ys).zip(&zs) {
        if x > 4.5 {
            far_face.push(nalgebra::Point3::new(x, y, z), [90, 90, 90]);
        }
    }
    prism.points = far_face;
    let prisms = vec![prism];
    let row = 80;
    let inside: Vec<CellIndex> = (62..88).map(|x| CellIndex::new(x, row)).collect();
    let behind: Vec<CellIndex> = (92..100).map(|x| CellIndex::new(x, row)).collect();
    let targets = Targets::uniform(inside.iter().chain(&behind).copied());
    let sight =
        SightMap::new(&grid, &prisms, &targets, &LookCoverage::default(), 0.3).expect("targets");
    for &c in &inside {
        assert_eq!(sight.occluder_height(c), None, "{c:?}");
        assert!(sight.floor_visible(robot, c), "{c:?} inside the hull");
    }
    assert!(sight.occluder_height(CellIndex::new(90, row)).is_some());
    for &c in &behind {
        // The face at x ≈ 4.5, 1 m high, shades to 1 + 3.5 · 1.4 / 0.4 m: beyond the range.
        assert!(!sight.floor_visible(robot, c), "{c:?} behind the face");
    }
    let look = sight.predict(robot);
    assert!(look.seen.iter().all(|c| inside.contains(c)));
    assert!(look.seen.len() >= inside.len() - 2, "{}", look.seen.len());
}

#[test]
fn targets_behind_the_robot_turn_it_round() {
    // Invariant: a robot that scanned only ahead (+x) and is asked for the floor behind it stays
    // where it is (no walk beats looking from here) and faces about π.
    let world = World {
        size: [10.0, 8.0],
        blocks: vec![],
    };
    let robot = Point2::new(5.0, 4.0);
    let mut grid = world.grid();
    world.scan(&mut grid, robot, 0.0, 170f64.to_radians(), 4);
    let prisms = world.prisms();
    let validity = world.validity(&prisms);
    let cells = unobserved_in(&grid, [2.5, 3.0], [4.0, 5.0]);
    assert!(cells.len() > 800, "{}", cells.len());
    let targets = Targets::uniform(cells);
    let vp = plan_view(
        &scene(&grid, &prisms, &validity, robot, &targets),
        &ViewConfig::default(),
    )
    .expect("a view");
    assert_eq!(vp.position, robot);
    assert_eq!(vp.walk, 0.0);
    assert_eq!(vp.path, vec![robot]);
    assert!(
        wrap(vp.yaw - std::f64::consts::PI).abs() < 5f64.to_radians(),
        "yaw {}",
        vp.yaw
    );
    // Nearly all of the 1.5 × 2 m region: what the rays sample of it.
    assert!(
        vp.gain > 0.9 * 3.0 && vp.gain < 1.1 * 3.0,
        "gain {}",
        vp.gain
    );
}

#[test]
fn targets_reached_only_through_unobserved_floor_are_unreachable() {
    // Invariant: when every position that could see the targets lies beyond floor the grid never
    // observed, the planner answers Unreachable; once that floor is scanned, it walks there.
    let wall = |y0: f64, y1: f64| Block::new(8.0, y0, 8.2, y1, 0.0, 2.0);
    let world = World {
        size: [14.0, 8.0],
        blocks: vec![wall(0.0, 3.5), wall(4.5, 8.0)],
    };
    let robot = Point2::new(3.0, 4.0);
    let mut grid = world.grid();
    // Only the floor towards −x is scanned: the door at x = 8 lies behind the robot.
    world.scan(
        &mut grid,
        robot,
        std::f64::consts::PI,
        170f64.to_radians(),
        4,
    );
    let prisms = world.prisms();
    let validity = world.validity(&prisms);
    let cells = unobserved_in(&grid, [9.5, 2.0], [11.5, 6.0]);
    let targets = Targets::uniform(cells.iter().copied());
    let config = ViewConfig::default();
    let got = plan_view(&scene(&grid, &prisms, &validity, robot, &targets), &config);
    assert_eq!(
        got,
        Err(NoView::Unreachable {
            targets: cells.len()
        })
    );
    // A scan from the door's side of the room makes the floor there walkable.
    world.scan(
        &mut grid,
        Point2::new(6.5, 4.0),
        0.0,
        std::f64::consts::TAU,
        4,
    );
    let vp = plan_view(&scene(&grid, &prisms, &validity, robot, &targets), &config)
        .expect("reachable now");
    assert!(vp.walk > 2.0 && vp.gain > 0.5, "{vp:?}");
    assert!(vp.position.x > 5.0, "{:?}", vp.position);
}

#[test]
fn the_same_inputs_give_the_same_answer_bit_for_bit() {
    // Invariant: plan_view is a function of its inputs: two calls, and a call on a copy of the
    // grid, give equal viewpoints (f64s compared exactly, cells in the same order).
    let (world, _, robot) = wall_world();
    let mut grid = world.grid();
    world.scan_all(&mut grid, &[robot]);
    let prisms = world.prisms();
    let validity = world.validity(&prisms);
    let targets = Targets::uniform(unobserved_in(&grid, [6.0, 0.5], [8.5, 3.0]));
    let config = ViewConfig::default();
    let a = plan_view(&scene(&grid, &prisms, &validity, robot, &targets), &config);
    let b = plan_view(&scene(&grid, &prisms, &validity, robot, &targets), &config);
    let copy = grid.clone();
    let c = plan_view(&scene(&copy, &prisms, &validity, robot, &targets), &config);
    assert!(a.is_ok());
    assert_eq!(a, b);
    assert_eq!(a, c);
    let (a, b) = (a.expect("ok"), b.expect("ok"));
    assert_eq!(a.yaw.to_bits(), b.yaw.to_bits());
    assert_eq!(a.score.to_bits(), b.score.to_bits());
}

#[test]
fn too_little_to_see_and_nothing_to_see_are_refused() {
    // Invariant: a look showing less than min_gain is refused with the best gain found; no target
    // (or none in the grid) is NoTargets; bad settings are errors, not panics.
    let world = World {
        size: [10.0, 8.0],
        blocks: vec![],
    };
    let robot = Point2::new(5.0, 4.0);
    let mut grid = world.grid();
    world.scan(&mut grid, robot, 0.0, 170f64.to_radians(), 4);
    let prisms = world.prisms();
    let validity = world.validity(&prisms);
    let targets = Targets::uniform(unobserved_in(&grid, [3.0, 3.8], [3.3, 4.2]));
    let s = scene(&grid, &prisms, &validity, robot, &targets);
    let config = ViewConfig {
        min_gain: 1.0,
        ..ViewConfig::default()
    };
    match plan_view(&s, &config) {
        Err(NoView::TooLittle {
            best_gain,
            min_gain,
        }) => {
            assert_eq!(min_gain, 1.0);
            assert!(best_gain > 0.05 && best_gain < 0.2, "{best_gain}");
        }
        other => panic!("{other:?}"),
    }
    let empty = Targets::default();
    assert_eq!(
        plan_view(&scene(&grid, &prisms, &validity, robot, &empty), &config),
        Err(NoView::NoTargets)
    );
    let outside = Targets::uniform([CellIndex::new(10_000, 3)]);
    assert_eq!(
        plan_view(&scene(&grid, &prisms, &validity, robot, &outside), &config),
        Err(NoView::NoTargets)
    );
    let bad = ViewConfig {
        walk_speed: 0.0,
        ..ViewConfig::default()
    };
    assert_eq!(plan_view(&s, &bad), Err(NoView::BadConfig("walk_speed")));
    let off_grid = scene(&grid, &prisms, &validity, Point2::new(-3.0, 1.0), &targets);
    assert!(matches!(
        plan_view(&off_grid, &ViewConfig::default()),
        Err(NoView::Lattice(_))
    ));
}

#[test]
fn the_search_finds_a_view_as_good_as_predicting_every_candidate() {
    // Invariant: on the office, from robots in the corridor, a room and the open plan, the view
    // plan_view chooses (best first, coarse to fine) scores within 5 % of the best of every
    // candidate — each reachable lattice cell every `spacing` in range of a target, and the
    // robot's own position — predicted on the grid's own cells.
    let world = view_world::office();
    let mut grid = world.grid();
    world.scan_all(&mut grid, &view_world::office_scan_poses());
    let prisms = world.prisms_sampled(0.05, 0.25);
    let validity = world.validity(&prisms);
    let (lo, hi) = view_world::OFFICE_TARGET_ROOM;
    let targets = Targets::uniform(unobserved_in(&grid, lo, hi));
    let config = ViewConfig::default();
    let sight = SightMap::new(&grid, &prisms, &targets, &config.coverage, 0.3).expect("targets");
    for robot in [(17.5, 13.0), (12.5, 9.0), (30.0, 25.5), (27.5, 9.0)] {
        let robot = Point2::new(robot.0, robot.1);
        let vp =
            plan_view(&scene(&grid, &prisms, &validity, robot, &targets), &config).expect("a view");
        let lattice = nudge_motion::view::Lattice::observed_floor(&grid, &validity, 2, 0.05, robot)
            .expect("lattice");
        let field = lattice.distances(robot).expect("inside");
        let time = |walk: f64| walk / config.walk_speed + config.look_time;
        let mut best = sight.gain_at(robot).1 / time(0.0);
        for y in (0..lattice.rows() as u32).step_by(3) {
            for x in (0..lattice.cols() as u32).step_by(3) {
                let c = nudge_motion::view::LatticeCell::new(x, y);
                let p = lattice.centre(c);
                if let Some(walk) = field.distance(c)
                    && lattice.is_passable(c)
                    && sight.within_reach(p)
                {
                    let gain = sight.gain_at(p).1;
                    if gain >= config.min_gain {
                        best = best.max(gain / time(walk));
                    }
                }
            }
        }
        assert!(
            vp.score >= 0.95 * best,
            "from {robot:?}: {} at {:?} against {best}",
            vp.score,
            vp.position
        );
    }
}
