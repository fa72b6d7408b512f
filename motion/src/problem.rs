//! A planning problem: where the robot starts and the disc it must reach.

use nalgebra::Point2;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// Why a problem could not be built.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ProblemError {
    /// A coordinate or the tolerance is not finite, or the tolerance is negative.
    #[error(
        "start {start:?}, goal {goal:?} and tolerance {tolerance} must be finite, tolerance ≥ 0"
    )]
    NotFinite {
        /// Start given.
        start: [f64; 2],
        /// Goal centre given.
        goal: [f64; 2],
        /// Tolerance given (m).
        tolerance: f64,
    },
}

/// The goal: any position within `tolerance` of `centre`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GoalRegion {
    centre: Point2<f64>,
    tolerance: f64,
}

impl GoalRegion {
    /// The disc of radius `tolerance` (m, finite, ≥ 0) around `centre`.
    pub fn new(centre: Point2<f64>, tolerance: f64) -> Result<Self, ProblemError> {
        Problem::new(centre, centre, tolerance).map(|p| p.goal)
    }

    /// The centre (m, map frame).
    pub fn centre(&self) -> Point2<f64> {
        self.centre
    }

    /// The radius of the disc (m).
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// Whether `p` is in the region.
    pub fn contains(&self, p: &Point2<f64>) -> bool {
        nalgebra::distance(p, &self.centre) <= self.tolerance
    }

    /// A uniformly random point of the disc.
    pub fn sample(&self, rng: &mut ChaCha8Rng) -> Point2<f64> {
        let r = self.tolerance * rng.random::<f64>().sqrt();
        let a = std::f64::consts::TAU * rng.random::<f64>();
        self.centre + nalgebra::Vector2::new(r * a.cos(), r * a.sin())
    }
}

/// Start and goal of one planning query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Problem {
    start: Point2<f64>,
    goal: GoalRegion,
}

impl Problem {
    /// From `start` to within `tolerance` of `goal` (m).
    pub fn new(
        start: Point2<f64>,
        goal: Point2<f64>,
        tolerance: f64,
    ) -> Result<Self, ProblemError> {
        let finite = [start.x, start.y, goal.x, goal.y, tolerance]
            .iter()
            .all(|v| v.is_finite());
        if !finite || tolerance < 0.0 {
            return Err(ProblemError::NotFinite {
                start: [start.x, start.y],
                goal: [goal.x, goal.y],
                tolerance,
            });
        }
        Ok(Self {
            start,
            goal: GoalRegion {
                centre: goal,
                tolerance,
            },
        })
    }

    /// Where the robot starts.
    pub fn start(&self) -> Point2<f64> {
        self.start
    }

    /// The same goal from another start.
    pub fn from_start(&self, start: Point2<f64>) -> Result<Self, ProblemError> {
        Self::new(start, self.goal.centre, self.goal.tolerance)
    }

    /// Where it must get to.
    pub fn goal(&self) -> &GoalRegion {
        &self.goal
    }
}
