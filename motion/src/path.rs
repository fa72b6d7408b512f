//! Paths: polylines of robot positions with their arc length.

use nalgebra::Point2;

use crate::validity::StateValidity;

/// Why a path could not be built.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum PathError {
    /// No waypoints.
    #[error("a path needs at least one waypoint")]
    Empty,
    /// A waypoint is NaN or infinite.
    #[error("waypoint {0} is not finite")]
    NotFinite(usize),
}

/// A polyline of positions (m, map frame) with cumulative arc length.
#[derive(Clone, Debug, PartialEq)]
pub struct Path {
    waypoints: Vec<Point2<f64>>,
    cumulative: Vec<f64>,
}

impl Path {
    /// A path through `waypoints` (at least one, all finite).
    pub fn new(waypoints: Vec<Point2<f64>>) -> Result<Self, PathError> {
        if waypoints.is_empty() {
            return Err(PathError::Empty);
        }
        if let Some(i) = waypoints
            .iter()
            .position(|p| !(p.x.is_finite() && p.y.is_finite()))
        {
            return Err(PathError::NotFinite(i));
        }
        let mut cumulative = Vec::with_capacity(waypoints.len());
        let mut s = 0.0;
        cumulative.push(0.0);
        for w in waypoints.windows(2) {
            s += nalgebra::distance(&w[0], &w[1]);
            cumulative.push(s);
        }
        Ok(Self {
            waypoints,
            cumulative,
        })
    }

    /// The waypoints, start first.
    pub fn waypoints(&self) -> &[Point2<f64>] {
        &self.waypoints
    }

    /// Arc length at each waypoint (m), starting at 0.
    pub fn cumulative(&self) -> &[f64] {
        &self.cumulative
    }

    /// Total length (m).
    pub fn length(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0)
    }

    /// First waypoint.
    pub fn start(&self) -> Point2<f64> {
        self.waypoints[0]
    }

    /// Last waypoint.
    pub fn end(&self) -> Point2<f64> {
        self.waypoints[self.waypoints.len() - 1]
    }

    /// The point at arc length `s` (clamped to the path).
    pub fn point_at(&self, s: f64) -> Point2<f64> {
        let s = s.clamp(0.0, self.length());
        // First waypoint whose cumulative length reaches s.
        let i = self.cumulative.partition_point(|&c| c < s);
        if i == 0 {
            return self.waypoints[0];
        }
        let (c0, c1) = (self.cumulative[i - 1], self.cumulative[i]);
        let t = if c1 > c0 { (s - c0) / (c1 - c0) } else { 0.0 };
        crate::space::interpolate(&self.waypoints[i - 1], &self.waypoints[i], t)
    }

    /// Points every `step` metres along the path, with both ends; a non-positive or non-finite step
    /// gives the waypoints unchanged.
    pub fn resampled(&self, step: f64) -> Path {
        if !(step.is_finite() && step > 0.0) || self.waypoints.len() < 2 {
            return self.clone();
        }
        let n = (self.length() / step).ceil() as usize;
        let points = (0..=n)
            .map(|k| self.point_at((k as f64 * step).min(self.length())))
            .collect::<Vec<_>>();
        let mut points = points;
        points.dedup();
        Self::from_finite(points)
    }

    /// The closest point of the path to `p`: its arc length and distance.
    pub fn project(&self, p: &Point2<f64>) -> (f64, f64) {
        let mut best = (0.0, nalgebra::distance(p, &self.waypoints[0]));
        for (i, w) in self.waypoints.windows(2).enumerate() {
            let d = w[1] - w[0];
            let len2 = d.norm_squared();
            let t = if len2 > 0.0 {
                ((p - w[0]).dot(&d) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let q = w[0] + d * t;
            let dist = nalgebra::distance(p, &q);
            if dist < best.1 {
                best = (self.cumulative[i] + t * d.norm(), dist);
            }
        }
        best
    }

    /// What is left to drive from `p`: the path from `p`'s projection on it to the end.
    pub fn remaining_from(&self, p: &Point2<f64>) -> Path {
        let (s, _) = self.project(p);
        let mut points = vec![self.point_at(s)];
        let next = self.cumulative.partition_point(|&c| c <= s);
        points.extend_from_slice(&self.waypoints[next..]);
        points.dedup();
        Self::from_finite(points)
    }

    /// Whether every straight piece is free for the robot (exact swept-disc checks).
    pub fn is_free(&self, validity: &dyn StateValidity) -> bool {
        validity.is_free(&self.waypoints[0])
            && self
                .waypoints
                .windows(2)
                .all(|w| validity.motion_free(&w[0], &w[1]))
    }

    /// Arc length of the first sample, taken every `step` metres, where the robot collides; `None`
    /// when all samples are free. Independent of the planner's own checks.
    pub fn first_collision(&self, validity: &dyn StateValidity, step: f64) -> Option<f64> {
        let step = if step.is_finite() && step > 0.0 {
            step
        } else {
            0.01
        };
        let n = (self.length() / step).ceil() as usize;
        (0..=n)
            .map(|k| (k as f64 * step).min(self.length()))
            .find(|&s| !validity.is_free(&self.point_at(s)))
    }

    fn from_finite(points: Vec<Point2<f64>>) -> Path {
        // Points interpolated from finite waypoints are finite and there is at least one.
        let mut cumulative = Vec::with_capacity(points.len());
        let mut s = 0.0;
        cumulative.push(0.0);
        for w in points.windows(2) {
            s += nalgebra::distance(&w[0], &w[1]);
            cumulative.push(s);
        }
        Path {
            waypoints: points,
            cumulative,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn l_path() -> Path {
        Path::new(vec![
            Point2::new(0.0, 0.0),
            Point2::new(3.0, 0.0),
            Point2::new(3.0, 4.0),
        ])
        .expect("finite waypoints")
    }

    #[test]
    fn lengths_and_interpolation() {
        // Invariant: cumulative lengths add up and point_at walks along the pieces.
        let p = l_path();
        assert_eq!(p.cumulative(), &[0.0, 3.0, 7.0]);
        assert_eq!(p.point_at(5.0), Point2::new(3.0, 2.0));
        assert_eq!(p.point_at(99.0), Point2::new(3.0, 4.0));
        let r = p.resampled(0.5);
        assert!((r.length() - 7.0).abs() < 1e-12);
        assert_eq!(r.waypoints().len(), 15);
        assert!(Path::new(vec![]).is_err());
        assert!(Path::new(vec![Point2::new(f64::NAN, 0.0)]).is_err());
    }

    #[test]
    fn remaining_part_starts_at_the_projection() {
        // Invariant: the remaining path starts at the pose's projection and ends where the path ends.
        let p = l_path();
        let rest = p.remaining_from(&Point2::new(3.5, 1.0));
        assert_eq!(rest.start(), Point2::new(3.0, 1.0));
        assert_eq!(rest.end(), Point2::new(3.0, 4.0));
        assert!((rest.length() - 3.0).abs() < 1e-12);
        let (s, d) = p.project(&Point2::new(1.0, -2.0));
        assert_eq!((s, d), (1.0, 2.0));
    }
}
