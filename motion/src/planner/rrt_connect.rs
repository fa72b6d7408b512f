//! RRT-Connect (Kuffner & LaValle 2000): two trees, one from the start and one from the goal; each
//! iteration the smaller tree takes a step toward a sample and the other greedily connects to it.
//! Samples are uniform, except that a blocked step may be followed by a bridge-test sample near where
//! it was blocked ([`Sampling`]): that is what finds narrow passages.

use nalgebra::Point2;
use rand_chacha::ChaCha8Rng;

use super::sampler::Sampling;
use super::{Budget, Effort, Metered, NoPath, Planner, SearchTree, Tree, free_goal, steer};
use crate::path::Path;
use crate::problem::Problem;
use crate::validity::StateValidity;

/// Bidirectional RRT with the greedy CONNECT heuristic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RrtConnect {
    /// Longest edge added in one step (m).
    pub range: f64,
    /// How samples are drawn (uniform mixed with bridge-test samples).
    pub sampling: Sampling,
}

impl Default for RrtConnect {
    fn default() -> Self {
        Self {
            range: 0.5,
            sampling: Sampling::default(),
        }
    }
}

enum Grow {
    Reached(usize),
    Advanced(usize),
    Trapped,
    OutOfChecks,
}

/// One step of at most `range` from node `from_index` toward `target`.
fn extend(
    tree: &mut Tree,
    from_index: usize,
    target: &Point2<f64>,
    range: f64,
    v: &Metered,
) -> Grow {
    let from = tree.point(from_index);
    let to = steer(&from, target, range);
    match v.motion_free(&from, &to) {
        None => Grow::OutOfChecks,
        Some(false) => Grow::Trapped,
        Some(true) => {
            let i = tree.add(to, from_index);
            if to == *target {
                Grow::Reached(i)
            } else {
                Grow::Advanced(i)
            }
        }
    }
}

/// CONNECT: steps of `range` from node `from_index` straight toward `target` until one is blocked.
///
/// The nodes added are exactly those of stepping one check at a time, found with fewer checks: the
/// whole segment first (the usual case in open space), else a binary search for the last free step
/// (a prefix of a free motion is free, so "free up to step k" is monotone in k).
fn connect(
    tree: &mut Tree,
    from_index: usize,
    target: &Point2<f64>,
    range: f64,
    v: &Metered,
) -> Grow {
    let from = tree.point(from_index);
    let len = nalgebra::distance(&from, target);
    let steps = ((len / range).ceil() as usize).max(1);
    let at = |k: usize| {
        if k >= steps {
            *target
        } else {
            from + (target - from) * (k as f64 * range / len)
        }
    };
    let free_steps = match v.motion_free(&from, target) {
        None => return Grow::OutOfChecks,
        Some(true) => steps,
        Some(false) => {
            // Invariant: step `lo` is reachable, step `hi` is not.
            let (mut lo, mut hi) = (0, steps);
            while hi - lo > 1 {
                let mid = (lo + hi) / 2;
                match v.motion_free(&from, &at(mid)) {
                    None => return Grow::OutOfChecks,
                    Some(true) => lo = mid,
                    Some(false) => hi = mid,
                }
            }
            lo
        }
    };
    let mut last = from_index;
    for k in 1..=free_steps {
        last = tree.add(at(k), last);
    }
    match free_steps {
        0 => Grow::Trapped,
        k if k == steps => Grow::Reached(last),
        _ => Grow::Advanced(last),
    }
}

/// The tree to grow next: the smaller one (ties: the start tree), Kuffner and LaValle's balanced
/// variant; it keeps one tree from stalling in a dead end while the other grows (−12 % work on Z).
fn smaller(trees: &[Tree]) -> usize {
    usize::from(trees[1].len() < trees[0].len())
}

impl Planner for RrtConnect {
    fn solve(
        &mut self,
        problem: &Problem,
        validity: &dyn StateValidity,
        budget: Budget,
        rng: &mut ChaCha8Rng,
    ) -> Result<Path, NoPath> {
        self.solve_with_effort(problem, validity, budget, rng).0
    }
}

impl RrtConnect {
    /// [`Planner::solve`], also returning the work it took (iterations and checks).
    pub fn solve_with_effort(
        &self,
        problem: &Problem,
        validity: &dyn StateValidity,
        budget: Budget,
        rng: &mut ChaCha8Rng,
    ) -> (Result<Path, NoPath>, Effort) {
        let (out, effort, _) = self.solve_recorded(problem, validity, budget, rng);
        (out, effort)
    }

    /// [`Self::solve_with_effort`], also returning the trees it grew (empty when start or goal were in
    /// collision): what a recording shows of the search.
    pub fn solve_recorded(
        &self,
        problem: &Problem,
        validity: &dyn StateValidity,
        budget: Budget,
        rng: &mut ChaCha8Rng,
    ) -> (Result<Path, NoPath>, Effort, SearchTree) {
        let metered = Metered::new(validity, &budget);
        let mut iterations = 0;
        let mut trees = Vec::with_capacity(2);
        let out = self.grow(problem, &metered, budget, rng, &mut iterations, &mut trees);
        (out, metered.effort(iterations), SearchTree::of(&trees))
    }

    fn grow(
        &self,
        problem: &Problem,
        metered: &Metered,
        budget: Budget,
        rng: &mut ChaCha8Rng,
        iterations: &mut usize,
        trees: &mut Vec<Tree>,
    ) -> Result<Path, NoPath> {
        let goal = free_goal(problem, metered.inner(), rng)?;
        let start = problem.start();
        if problem.goal().contains(&start) {
            return Path::new(vec![start]).map_err(|_| NoPath::StartInCollision);
        }
        let range = if self.range.is_finite() && self.range > 0.0 {
            self.range
        } else {
            0.5
        };
        // The caller's vector, so the trees outlive every way out of the search.
        trees.clear();
        trees.push(Tree::new(start, metered.bounds()));
        trees.push(Tree::new(goal, metered.bounds()));
        // trees[a] grows toward the sample; trees[1 - a] connects.
        let mut a = 0;
        let mut pending = None;
        for iteration in 0..budget.max_iterations {
            *iterations = iteration + 1;
            let out = NoPath::NotFound {
                iterations: iteration,
            };
            let sample = match pending.take() {
                Some(p) => p,
                None => self.sampling.uniform(metered, rng),
            };
            let near = trees[a].nearest(&sample);
            let new = match extend(&mut trees[a], near, &sample, range, metered) {
                Grow::OutOfChecks => return Err(out),
                Grow::Trapped => {
                    // No tree changed, so trees[a] stays the smaller one and the bridge found
                    // near where it was blocked (if any) is its next sample.
                    let blocked = steer(&trees[a].point(near), &sample, range);
                    pending = self.sampling.bridge_near(&blocked, metered, rng);
                    continue;
                }
                Grow::Reached(i) | Grow::Advanced(i) => i,
            };
            let target = trees[a].point(new);
            let b = 1 - a;
            let near_b = trees[b].nearest(&target);
            match connect(&mut trees[b], near_b, &target, range, metered) {
                Grow::OutOfChecks => return Err(out),
                Grow::Trapped | Grow::Advanced(_) => {}
                Grow::Reached(i) => {
                    let (s, g) = if a == 0 { (new, i) } else { (i, new) };
                    let mut points = trees[0].branch(s);
                    let mut back = trees[1].branch(g);
                    back.reverse();
                    // The meeting point is in both branches.
                    points.extend(back.into_iter().skip(1));
                    return Path::new(points).map_err(|_| out);
                }
            }
            a = smaller(trees);
        }
        Err(NoPath::NotFound {
            iterations: budget.max_iterations,
        })
    }
}
