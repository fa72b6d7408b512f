//! The robot's configuration space: positions of the cylinder's axis in a bounded plane.
//!
//! A vertical cylinder looks the same at every heading, so collision checking and path planning live
//! in R² (the axis position). Headings matter only where the robot must face something (a push), and
//! there poses are `nalgebra::Isometry2` built with [`pose`].

use nalgebra::{Isometry2, Point2, Vector2};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// Why a space could not be built.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum SpaceError {
    /// A corner is not finite or `min` is not strictly below `max` on both axes.
    #[error("bounds min {min:?} max {max:?} are not finite with min < max")]
    Degenerate {
        /// The lower corner given.
        min: [f64; 2],
        /// The upper corner given.
        max: [f64; 2],
    },
}

/// An axis-aligned rectangle of the plane (m, map frame): the positions a planner may sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    min: Point2<f64>,
    max: Point2<f64>,
}

impl Bounds {
    /// The rectangle between two corners; both finite and `min < max` on each axis.
    pub fn new(min: Point2<f64>, max: Point2<f64>) -> Result<Self, SpaceError> {
        let ok =
            min.iter().chain(max.iter()).all(|v| v.is_finite()) && min.x < max.x && min.y < max.y;
        if ok {
            Ok(Self { min, max })
        } else {
            Err(SpaceError::Degenerate {
                min: [min.x, min.y],
                max: [max.x, max.y],
            })
        }
    }

    /// The lower-left corner.
    pub fn min(&self) -> Point2<f64> {
        self.min
    }

    /// The upper-right corner.
    pub fn max(&self) -> Point2<f64> {
        self.max
    }

    /// The extent along x and y.
    pub fn size(&self) -> Vector2<f64> {
        self.max - self.min
    }

    /// Whether `p` lies inside or on the border.
    pub fn contains(&self, p: &Point2<f64>) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    /// The rectangle shrunk by `margin` on every side, or `None` when nothing is left.
    pub fn shrunk(&self, margin: f64) -> Option<Self> {
        let m = Vector2::new(margin, margin);
        Self::new(self.min + m, self.max - m).ok()
    }

    /// Distance from `p` to the nearest border, positive inside, negative outside.
    pub fn signed_inner_distance(&self, p: &Point2<f64>) -> f64 {
        (p.x - self.min.x)
            .min(self.max.x - p.x)
            .min(p.y - self.min.y)
            .min(self.max.y - p.y)
    }

    /// A uniformly random point of the rectangle.
    pub fn sample(&self, rng: &mut ChaCha8Rng) -> Point2<f64> {
        let u: f64 = rng.random();
        let v: f64 = rng.random();
        Point2::new(
            self.min.x + u * (self.max.x - self.min.x),
            self.min.y + v * (self.max.y - self.min.y),
        )
    }
}

/// An SE(2) pose at `(x, y)` with heading `yaw` (rad, counter-clockwise from +x).
pub fn pose(x: f64, y: f64, yaw: f64) -> Isometry2<f64> {
    Isometry2::new(Vector2::new(x, y), yaw)
}

/// The heading of an SE(2) pose (rad, in (−π, π]).
pub fn heading(pose: &Isometry2<f64>) -> f64 {
    pose.rotation.angle()
}

/// The point `t` of the way from `a` to `b` (t in 0..=1).
pub fn interpolate(a: &Point2<f64>, b: &Point2<f64>, t: f64) -> Point2<f64> {
    a + (b - a) * t
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn samples_stay_inside_and_degenerate_bounds_are_rejected() {
        // Invariant: sampling never leaves the bounds; empty or non-finite bounds are an error.
        let b = Bounds::new(Point2::new(-1.0, 2.0), Point2::new(3.0, 2.5)).expect("valid bounds");
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for _ in 0..1000 {
            assert!(b.contains(&b.sample(&mut rng)));
        }
        assert!(Bounds::new(Point2::new(0.0, 0.0), Point2::new(0.0, 1.0)).is_err());
        assert!(Bounds::new(Point2::new(f64::NAN, 0.0), Point2::new(1.0, 1.0)).is_err());
        assert!(b.shrunk(0.3).is_none());
        assert!((b.signed_inner_distance(&Point2::new(0.0, 2.1)) - 0.1).abs() < 1e-12);
    }
}
