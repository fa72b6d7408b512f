//! RRT as in Kakiuchi et al.: one tree from the start, grown toward random samples, biased toward
//! the goal, a fixed step at a time.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::{Budget, Metered, NoPath, Planner, Tree, free_goal, steer};
use crate::path::Path;
use crate::problem::Problem;
use crate::validity::StateValidity;

/// Rapidly-exploring random tree with goal bias.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rrt {
    /// Longest edge added in one step (m).
    pub range: f64,
    /// Probability of steering toward the goal region instead of a uniform sample.
    pub goal_bias: f64,
}

impl Default for Rrt {
    fn default() -> Self {
        Self {
            range: 0.5,
            goal_bias: 0.05,
        }
    }
}

impl Planner for Rrt {
    fn solve(
        &mut self,
        problem: &Problem,
        validity: &dyn StateValidity,
        budget: Budget,
        rng: &mut ChaCha8Rng,
    ) -> Result<Path, NoPath> {
        let goal = free_goal(problem, validity, rng)?;
        let start = problem.start();
        let region = problem.goal();
        if region.contains(&start) {
            return Path::new(vec![start]).map_err(|_| NoPath::StartInCollision);
        }
        let range = if self.range.is_finite() && self.range > 0.0 {
            self.range
        } else {
            0.5
        };
        let metered = Metered::new(validity, &budget);
        let mut tree = Tree::new(start, metered.bounds());
        for iteration in 0..budget.max_iterations {
            let target = if rng.random::<f64>() < self.goal_bias {
                goal
            } else {
                metered.bounds().sample(rng)
            };
            let near = tree.nearest(&target);
            let from = tree.point(near);
            let to = steer(&from, &target, range);
            match metered.motion_free(&from, &to) {
                None => {
                    return Err(NoPath::NotFound {
                        iterations: iteration,
                    });
                }
                Some(false) => continue,
                Some(true) => {}
            }
            let new = tree.add(to, near);
            if region.contains(&to) {
                return Path::new(tree.branch(new)).map_err(|_| NoPath::NotFound {
                    iterations: iteration,
                });
            }
            // Close the last gap straight to the goal when it is within one step.
            if nalgebra::distance(&to, &goal) <= range {
                match metered.motion_free(&to, &goal) {
                    None => {
                        return Err(NoPath::NotFound {
                            iterations: iteration,
                        });
                    }
                    Some(true) => {
                        let end = tree.add(goal, new);
                        return Path::new(tree.branch(end)).map_err(|_| NoPath::NotFound {
                            iterations: iteration,
                        });
                    }
                    Some(false) => {}
                }
            }
        }
        Err(NoPath::NotFound {
            iterations: budget.max_iterations,
        })
    }
}
