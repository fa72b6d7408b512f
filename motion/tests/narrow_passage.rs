//! Narrow passages A and Z: 10 cm of clearance in a 10 m world.

mod common;

use nudge_motion::planner::sampler::Sampling;
use nudge_motion::{Budget, Planner, Problem, Rrt, RrtConnect, StateValidity, Validity};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

const SEEDS: u64 = 200;

fn successes(
    planner: &mut dyn Planner,
    world: &(nudge_motion::Validity, nudge_motion::Problem),
    budget: Budget,
) -> u64 {
    let (v, p) = world;
    let mut ok = 0;
    for seed in 0..SEEDS {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        if let Ok(path) = planner.solve(p, v, budget, &mut rng) {
            assert!(path.is_free(v), "seed {seed}: path collides (exact check)");
            assert_eq!(
                path.first_collision(v, 0.01),
                None,
                "seed {seed}: sample collides"
            );
            assert_eq!(path.start(), p.start());
            assert!(p.goal().contains(&path.end()));
            assert!(v.is_free(&path.end()));
            ok += 1;
        }
    }
    ok
}

#[test]
fn rrt_connect_solves_a_and_z_on_every_seed() {
    // Invariant: RRT-Connect solves both narrow passages on 200 of 200 seeds with free paths.
    let budget = Budget::iterations(200_000);
    let a = successes(&mut RrtConnect::default(), &common::narrow_a(), budget);
    let z = successes(&mut RrtConnect::default(), &common::narrow_z(), budget);
    println!("RRT-Connect: A {a}/{SEEDS}, Z {z}/{SEEDS}");
    assert_eq!((a, z), (SEEDS, SEEDS));
}

/// Median iterations of RRT-Connect with `sampling` over the seeds, and how many it solved.
fn median_iterations(sampling: Sampling, world: &(Validity, Problem)) -> (usize, u64) {
    let (v, p) = world;
    let planner = RrtConnect {
        sampling,
        ..RrtConnect::default()
    };
    let mut iterations = Vec::new();
    let mut solved = 0;
    for seed in 0..SEEDS {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let (out, effort) = planner.solve_with_effort(p, v, Budget::iterations(200_000), &mut rng);
        solved += u64::from(out.is_ok());
        iterations.push(effort.iterations);
    }
    iterations.sort_unstable();
    (iterations[iterations.len() / 2], solved)
}

#[test]
fn bridges_at_blocked_steps_find_the_passages_sooner() {
    // Invariant: on Z, bridge samples where a tree is blocked need fewer iterations than uniform
    // sampling alone (median over 200 seeds), and both solve every seed.
    let uniform = Sampling {
        bridge_attempts: 0,
        ..Sampling::default()
    };
    let world = common::narrow_z();
    let (with, with_solved) = median_iterations(Sampling::default(), &world);
    let (without, without_solved) = median_iterations(uniform, &world);
    println!("Z median iterations: bridges {with}, uniform {without}");
    assert_eq!((with_solved, without_solved), (SEEDS, SEEDS));
    assert!(with < without, "bridges {with} vs uniform {without}");
}

#[test]
fn rrt_paths_are_free_and_it_mostly_succeeds() {
    // Invariant: goal-biased RRT returns only free paths; its success rate is reported.
    let budget = Budget::iterations(50_000);
    let a = successes(&mut Rrt::default(), &common::narrow_a(), budget);
    let z = successes(&mut Rrt::default(), &common::narrow_z(), budget);
    println!("RRT: A {a}/{SEEDS}, Z {z}/{SEEDS}");
    assert!(a > 0 && z > 0, "RRT never solved a narrow passage");
}

#[test]
fn the_passages_are_really_narrow() {
    // Invariant: the gaps leave 5 cm each side: 4 cm off centre is free, 6 cm is not.
    let (v, _) = common::narrow_a();
    let centre = nalgebra::Point2::new(6.8 + common::GAP / 2.0, 5.0);
    assert!(v.is_free(&centre));
    assert!(v.is_free(&(centre + nalgebra::Vector2::new(0.04, 0.0))));
    assert!(!v.is_free(&(centre + nalgebra::Vector2::new(0.06, 0.0))));
    assert!((v.clearance(&centre) - 0.05).abs() < 1e-4);
}

#[test]
fn the_recorded_tree_is_the_search_that_found_the_path() {
    // Invariant: every recorded tree edge is a free motion, every path waypoint is a tree node, and the
    // recorded solve returns the same path as the plain solve with the same seed.
    let (v, p) = common::narrow_z();
    let planner = RrtConnect::default();
    let budget = Budget::iterations(200_000);
    let plain = planner
        .solve_with_effort(&p, &v, budget, &mut ChaCha8Rng::seed_from_u64(7))
        .0
        .expect("Z is solved on seed 7");
    let (path, _, tree) = planner.solve_recorded(&p, &v, budget, &mut ChaCha8Rng::seed_from_u64(7));
    let path = path.expect("the recorded solve finds the same path");
    assert_eq!(path.waypoints(), plain.waypoints());
    assert!(tree.edges.len() >= path.waypoints().len() - 1);
    for [a, b] in &tree.edges {
        assert!(v.motion_free(a, b), "edge {a} -> {b} collides");
    }
    for w in path.waypoints() {
        assert!(
            tree.edges.iter().any(|[a, b]| a == w || b == w),
            "waypoint {w} is not in the tree"
        );
    }
}
