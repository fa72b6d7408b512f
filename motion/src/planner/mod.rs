//! Planners: the [`Planner`] trait, its budget and its typed failure, and the trees they grow.
//!
//! Every planner is deterministic: randomness comes only from the `ChaCha8Rng` passed in, and the
//! budget counts iterations and motion checks, never the wall clock.

use std::cell::Cell;

use nalgebra::Point2;
use rand_chacha::ChaCha8Rng;

use crate::path::Path;
use crate::problem::Problem;
use crate::space::Bounds;
use crate::validity::StateValidity;

pub mod nearest;
pub mod rrt;
pub mod rrt_connect;
pub mod sampler;
pub mod search_tree;
pub mod shortcut;

pub use search_tree::SearchTree;

/// How much work a planner may do: a deterministic stand-in for planning time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Budget {
    /// Most tree-growing iterations (samples drawn).
    pub max_iterations: usize,
    /// Most motion (swept-disc) checks, if limited; the finer measure of time spent.
    pub max_motion_checks: Option<usize>,
}

impl Budget {
    /// At most `n` iterations, any number of checks.
    pub fn iterations(n: usize) -> Self {
        Self {
            max_iterations: n,
            max_motion_checks: None,
        }
    }

    /// The same budget with at most `n` motion checks as well.
    pub fn with_motion_checks(self, n: usize) -> Self {
        Self {
            max_motion_checks: Some(n),
            ..self
        }
    }
}

/// Why a planner returned no path.
#[derive(Debug, thiserror::Error, Clone, Copy, PartialEq, Eq)]
pub enum NoPath {
    /// The robot already overlaps an obstacle or a wall where it stands.
    #[error("the start is in collision")]
    StartInCollision,
    /// No position of the goal region is free.
    #[error("the whole goal region is in collision")]
    GoalInCollision,
    /// The budget ran out before start and goal were connected.
    #[error("no path found in {iterations} iterations")]
    NotFound {
        /// Iterations spent.
        iterations: usize,
    },
}

/// A motion planner: OMPL's `Planner`, one file per algorithm.
pub trait Planner {
    /// A collision-free path from the problem's start into its goal region, within `budget`.
    fn solve(
        &mut self,
        problem: &Problem,
        validity: &dyn StateValidity,
        budget: Budget,
        rng: &mut ChaCha8Rng,
    ) -> Result<Path, NoPath>;
}

/// How many goal-region samples are tried before the goal is declared in collision.
const GOAL_PROBES: usize = 256;

/// Checks start and goal, returning a free goal position (the centre when it is free).
pub(crate) fn free_goal(
    problem: &Problem,
    validity: &dyn StateValidity,
    rng: &mut ChaCha8Rng,
) -> Result<Point2<f64>, NoPath> {
    if !validity.is_free(&problem.start()) {
        return Err(NoPath::StartInCollision);
    }
    let goal = problem.goal();
    if validity.is_free(&goal.centre()) {
        return Ok(goal.centre());
    }
    (0..GOAL_PROBES)
        .map(|_| goal.sample(rng))
        .find(|p| validity.is_free(p))
        .ok_or(NoPath::GoalInCollision)
}

/// The work one solve took, counted rather than timed so that it does not depend on the machine's load.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Effort {
    /// Tree-growing iterations (samples drawn).
    pub iterations: usize,
    /// Motion (swept-disc) checks.
    pub motion_checks: usize,
    /// Point (disc) checks made while sampling.
    pub point_checks: usize,
}

/// A validity checker that counts motion checks against a budget.
pub(crate) struct Metered<'a> {
    inner: &'a dyn StateValidity,
    checks: Cell<usize>,
    point_checks: Cell<usize>,
    limit: usize,
}

impl<'a> Metered<'a> {
    pub(crate) fn new(inner: &'a dyn StateValidity, budget: &Budget) -> Self {
        Self {
            inner,
            checks: Cell::new(0),
            point_checks: Cell::new(0),
            limit: budget.max_motion_checks.unwrap_or(usize::MAX),
        }
    }

    /// Whether the motion is free; `None` once the check budget is spent.
    pub(crate) fn motion_free(&self, a: &Point2<f64>, b: &Point2<f64>) -> Option<bool> {
        let n = self.checks.get();
        if n >= self.limit {
            return None;
        }
        self.checks.set(n + 1);
        Some(self.inner.motion_free(a, b))
    }

    /// Whether the robot at `p` is free; point checks are counted, never limited (they are cheap).
    pub(crate) fn is_free(&self, p: &Point2<f64>) -> bool {
        self.point_checks.set(self.point_checks.get() + 1);
        self.inner.is_free(p)
    }

    /// The work done so far, after `iterations` iterations.
    pub(crate) fn effort(&self, iterations: usize) -> Effort {
        Effort {
            iterations,
            motion_checks: self.checks.get(),
            point_checks: self.point_checks.get(),
        }
    }

    /// The checker being metered.
    pub(crate) fn inner(&self) -> &'a dyn StateValidity {
        self.inner
    }

    pub(crate) fn bounds(&self) -> &Bounds {
        self.inner.sampling_bounds()
    }
}

/// A tree of positions: each node knows its parent.
#[derive(Clone, Debug)]
pub(crate) struct Tree {
    points: Vec<Point2<f64>>,
    parents: Vec<u32>,
    index: nearest::NearestIndex,
}

impl Tree {
    pub(crate) fn new(root: Point2<f64>, bounds: &Bounds) -> Self {
        let mut index = nearest::NearestIndex::new(bounds);
        index.insert(&root, 0);
        Self {
            points: vec![root],
            parents: vec![0],
            index,
        }
    }

    pub(crate) fn len(&self) -> usize {
        self.points.len()
    }

    pub(crate) fn point(&self, i: usize) -> Point2<f64> {
        self.points[i]
    }

    pub(crate) fn nearest(&mut self, q: &Point2<f64>) -> usize {
        self.index.nearest(q)
    }

    pub(crate) fn add(&mut self, p: Point2<f64>, parent: usize) -> usize {
        let i = self.points.len();
        self.points.push(p);
        self.parents.push(parent as u32);
        self.index.insert(&p, i);
        i
    }

    /// Every (parent, child) edge, in the order the children were added.
    pub(crate) fn edges(&self) -> impl Iterator<Item = [Point2<f64>; 2]> + '_ {
        self.parents
            .iter()
            .zip(&self.points)
            .skip(1)
            .map(|(&parent, &child)| [self.points[parent as usize], child])
    }

    /// Positions from the root to node `i`.
    pub(crate) fn branch(&self, mut i: usize) -> Vec<Point2<f64>> {
        let mut out = vec![self.points[i]];
        while i != 0 {
            i = self.parents[i] as usize;
            out.push(self.points[i]);
        }
        out.reverse();
        out
    }
}

/// `from` moved toward `to` by at most `range`.
pub(crate) fn steer(from: &Point2<f64>, to: &Point2<f64>, range: f64) -> Point2<f64> {
    let d = to - from;
    let len = d.norm();
    if len <= range {
        *to
    } else {
        from + d * (range / len)
    }
}
