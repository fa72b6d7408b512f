//! RRT-Connect (Kuffner & LaValle 2000): two trees, one from the start and one from the goal; each
//! iteration one tree takes a step toward a random sample and the other greedily connects to it.

use rand_chacha::ChaCha8Rng;

use super::{Budget, Metered, NoPath, Planner, Tree, free_goal, steer};
use crate::path::Path;
use crate::problem::Problem;
use crate::validity::StateValidity;

/// Bidirectional RRT with the greedy CONNECT heuristic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RrtConnect {
    /// Longest edge added in one step (m).
    pub range: f64,
}

impl Default for RrtConnect {
    fn default() -> Self {
        Self { range: 1.0 }
    }
}

enum Grow {
    Reached(usize),
    Advanced(usize),
    Trapped,
    OutOfChecks,
}

fn extend(
    tree: &mut Tree,
    from_index: usize,
    target: &nalgebra::Point2<f64>,
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

impl Planner for RrtConnect {
    fn solve(
        &mut self,
        problem: &Problem,
        validity: &dyn StateValidity,
        budget: Budget,
        rng: &mut ChaCha8Rng,
    ) -> Result<Path, NoPath> {
        let goal = free_goal(problem, validity, rng)?;
        let start = problem.start();
        if problem.goal().contains(&start) {
            return Path::new(vec![start]).map_err(|_| NoPath::StartInCollision);
        }
        let range = if self.range.is_finite() && self.range > 0.0 {
            self.range
        } else {
            1.0
        };
        let metered = Metered::new(validity, &budget);
        let mut trees = [
            Tree::new(start, metered.bounds()),
            Tree::new(goal, metered.bounds()),
        ];
        // trees[a] grows toward the sample; trees[1 - a] connects.
        let mut a = 0;
        for iteration in 0..budget.max_iterations {
            let out = NoPath::NotFound {
                iterations: iteration,
            };
            let sample = metered.bounds().sample(rng);
            let near = trees[a].nearest(&sample);
            let new = match extend(&mut trees[a], near, &sample, range, &metered) {
                Grow::OutOfChecks => return Err(out),
                Grow::Trapped => {
                    a = 1 - a;
                    continue;
                }
                Grow::Reached(i) | Grow::Advanced(i) => i,
            };
            let target = trees[a].point(new);
            let b = 1 - a;
            let mut last = trees[b].nearest(&target);
            loop {
                match extend(&mut trees[b], last, &target, range, &metered) {
                    Grow::OutOfChecks => return Err(out),
                    Grow::Trapped => break,
                    Grow::Advanced(i) => last = i,
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
            }
            a = b;
        }
        Err(NoPath::NotFound {
            iterations: budget.max_iterations,
        })
    }
}
