//! Obstacles as the planner sees them: a prism's convex footprint made into a parry2d shape.
//!
//! parry2d works in `f32` with glam vectors; a footprint is stored around its own centre so that the
//! `f32` coordinates stay small (sub-micrometre rounding in a room) and the map-frame API stays `f64`
//! nalgebra. Conversions happen only in this file and in [`crate::validity`].

use nalgebra::{Point2, Vector2};
use nudge_perception::{ObjectId, Prism};
use parry2d::math::{Pose, Vector};
use parry2d::query::PointQuery;
use parry2d::shape::{ConvexPolygon, Segment};

/// Why a footprint cannot become an obstacle.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ObstacleError {
    /// A vertex or a height is NaN or infinite.
    #[error("obstacle {id} has a non-finite vertex or height")]
    NonFinite {
        /// The obstacle.
        id: ObjectId,
    },
    /// The footprint's convex hull has no area (fewer than three non-collinear vertices).
    #[error("obstacle {id} has a footprint without area")]
    Degenerate {
        /// The obstacle.
        id: ObjectId,
    },
    /// `z_min` is above `z_max`.
    #[error("obstacle {id} has z_min {z_min} above z_max {z_max}")]
    InvertedHeights {
        /// The obstacle.
        id: ObjectId,
        /// Lowest point given (m).
        z_min: f64,
        /// Highest point given (m).
        z_max: f64,
    },
}

/// An axis-aligned box in the map frame (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower-left corner.
    pub min: Point2<f64>,
    /// Upper-right corner.
    pub max: Point2<f64>,
}

impl Aabb {
    /// The smallest box holding all `points` (an empty box at the origin for no points).
    pub fn around(points: &[Point2<f64>]) -> Self {
        let mut min = Point2::new(f64::INFINITY, f64::INFINITY);
        let mut max = Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY);
        for p in points {
            min = min.inf(p);
            max = max.sup(p);
        }
        if points.is_empty() {
            min = Point2::origin();
            max = Point2::origin();
        }
        Self { min, max }
    }

    /// The box grown by `margin` on every side.
    pub fn inflated(&self, margin: f64) -> Self {
        let m = Vector2::new(margin, margin);
        Self {
            min: self.min - m,
            max: self.max + m,
        }
    }

    /// Whether the two boxes overlap (touching counts).
    pub fn overlaps(&self, other: &Aabb) -> bool {
        self.min.x <= other.max.x
            && other.min.x <= self.max.x
            && self.min.y <= other.max.y
            && other.min.y <= self.max.y
    }
}

/// A convex obstacle footprint with its height range, ready for exact distance queries.
#[derive(Clone, Debug)]
pub struct Obstacle {
    id: ObjectId,
    footprint: Vec<Point2<f64>>,
    z_min: f64,
    z_max: f64,
    centre: Point2<f64>,
    /// Unit outward normal of the edge from vertex i to vertex i + 1 (f64, for the hot path).
    normals: Vec<Vector2<f64>>,
    shape: ConvexPolygon,
    aabb: Aabb,
}

impl Obstacle {
    /// An obstacle from a footprint (any order; its convex hull is used) and a height range.
    pub fn new(
        id: ObjectId,
        footprint: &[Point2<f64>],
        z_min: f64,
        z_max: f64,
    ) -> Result<Self, ObstacleError> {
        let finite = footprint.iter().all(|p| p.x.is_finite() && p.y.is_finite())
            && z_min.is_finite()
            && z_max.is_finite();
        if !finite {
            return Err(ObstacleError::NonFinite { id });
        }
        if z_min > z_max {
            return Err(ObstacleError::InvertedHeights { id, z_min, z_max });
        }
        if footprint.len() < 3 {
            return Err(ObstacleError::Degenerate { id });
        }
        let aabb = Aabb::around(footprint);
        let centre = nalgebra::center(&aabb.min, &aabb.max);
        let local: Vec<Vector> = footprint.iter().map(|p| to_local(&centre, p)).collect();
        let shape =
            ConvexPolygon::from_convex_hull(&local).ok_or(ObstacleError::Degenerate { id })?;
        if shape.points().len() < 3 || polygon_area(shape.points()) <= 1e-9 {
            return Err(ObstacleError::Degenerate { id });
        }
        let mut footprint: Vec<Point2<f64>> = shape
            .points()
            .iter()
            .map(|v| centre + Vector2::new(f64::from(v.x), f64::from(v.y)))
            .collect();
        // Repeated vertices would make zero-length edges without a normal.
        footprint.dedup();
        if footprint.len() > 1 && footprint.first() == footprint.last() {
            footprint.pop();
        }
        if footprint.len() < 3 {
            return Err(ObstacleError::Degenerate { id });
        }
        let aabb = Aabb::around(&footprint);
        let n = footprint.len();
        let normals = (0..n)
            .map(|i| {
                let e = footprint[(i + 1) % n] - footprint[i];
                Vector2::new(e.y, -e.x).normalize()
            })
            .collect();
        Ok(Self {
            id,
            footprint,
            z_min,
            z_max,
            centre,
            normals,
            shape,
            aabb,
        })
    }

    /// The obstacle of a perceived prism.
    pub fn from_prism(prism: &Prism) -> Result<Self, ObstacleError> {
        Self::new(prism.id, &prism.footprint, prism.z_min, prism.z_max)
    }

    /// The same obstacle moved by `offset` (m, map frame).
    pub fn translated(&self, offset: &Vector2<f64>) -> Result<Self, ObstacleError> {
        let moved: Vec<Point2<f64>> = self.footprint.iter().map(|p| p + offset).collect();
        Self::new(self.id, &moved, self.z_min, self.z_max)
    }

    /// The region this obstacle sweeps when translated by `offset`: the hull of both footprints.
    pub fn swept(&self, offset: &Vector2<f64>) -> Result<Self, ObstacleError> {
        let mut both = self.footprint.clone();
        both.extend(self.footprint.iter().map(|p| p + offset));
        Self::new(self.id, &both, self.z_min, self.z_max)
    }

    /// Identity of the prism this came from.
    pub fn id(&self) -> ObjectId {
        self.id
    }

    /// Convex footprint, counter-clockwise, map frame (m).
    pub fn footprint(&self) -> &[Point2<f64>] {
        &self.footprint
    }

    /// Lowest point above the floor (m).
    pub fn z_min(&self) -> f64 {
        self.z_min
    }

    /// Highest point above the floor (m).
    pub fn z_max(&self) -> f64 {
        self.z_max
    }

    /// The footprint's bounding box.
    pub fn aabb(&self) -> &Aabb {
        &self.aabb
    }

    /// Whether the two height ranges overlap (share more than a boundary).
    pub fn heights_overlap(&self, other: &Obstacle) -> bool {
        self.z_min < other.z_max && other.z_min < self.z_max
    }

    /// Distance from `p` to the footprint (0 inside).
    pub fn distance_to_point(&self, p: &Point2<f64>) -> f64 {
        let d = self
            .shape
            .distance_to_point(&Pose::IDENTITY, to_local(&self.centre, p), true);
        f64::from(d)
    }

    /// Distance from the segment `a`–`b` to the footprint (0 when they meet).
    pub fn distance_to_segment(&self, a: &Point2<f64>, b: &Point2<f64>) -> f64 {
        if a == b {
            return self.distance_to_point(a);
        }
        let seg = Segment::new(to_local(&self.centre, a), to_local(&self.centre, b));
        let d = parry2d::query::details::distance_support_map_support_map(
            &Pose::IDENTITY,
            &seg,
            &self.shape,
        );
        f64::from(d)
    }

    /// Whether a disc of `radius` at `p` overlaps the footprint (distance below the radius).
    ///
    /// The planners' hot path, in exact `f64` arithmetic rather than parry's `f32` GJK (about ten
    /// times fewer instructions); tests pin it to [`Obstacle::distance_to_point`].
    pub fn disc_hits(&self, p: &Point2<f64>, radius: f64) -> bool {
        let f = &self.footprint;
        let mut inside = true;
        for (v, n) in f.iter().zip(&self.normals) {
            let h = n.dot(&(p - v));
            if h >= radius {
                return false;
            }
            inside &= h <= 0.0;
        }
        if inside {
            return true;
        }
        let r2 = radius * radius;
        (0..f.len()).any(|i| point_segment_d2(p, &f[i], &f[(i + 1) % f.len()]) < r2)
    }

    /// Whether the disc of `radius` swept from `a` to `b` (a capsule) overlaps the footprint:
    /// the exact swept-disc test of a motion, in `f64` (see [`Obstacle::disc_hits`]); tests pin it
    /// to [`Obstacle::distance_to_segment`].
    pub fn capsule_hits(&self, a: &Point2<f64>, b: &Point2<f64>, radius: f64) -> bool {
        // Cyrus–Beck clipping of the segment against the footprint's edges, twice in one pass:
        // pushed out by the radius (a miss there is a miss of the rounded inflation inside it) and
        // as they are (a hit there is a hit). Between the two, the rounded corners decide.
        let d = b - a;
        let (mut grown0, mut grown1) = (0.0_f64, 1.0_f64);
        let (mut own0, mut own1) = (0.0_f64, 1.0_f64);
        for (v, n) in self.footprint.iter().zip(&self.normals) {
            let h = n.dot(&(a - v));
            let s = n.dot(&d);
            if s == 0.0 {
                if h >= radius {
                    return false;
                }
                if h >= 0.0 {
                    own0 = f64::INFINITY;
                }
            } else if s > 0.0 {
                grown1 = grown1.min((radius - h) / s);
                own1 = own1.min(-h / s);
            } else {
                grown0 = grown0.max((radius - h) / s);
                own0 = own0.max(-h / s);
            }
            if grown0 > grown1 {
                return false;
            }
        }
        if own0 <= own1 {
            return true;
        }
        let f = &self.footprint;
        let r2 = radius * radius;
        (0..f.len()).any(|i| segment_segment_d2(a, b, &f[i], &f[(i + 1) % f.len()]) < r2)
    }

    /// Distance between two footprints (0 when they overlap).
    pub fn distance_to_obstacle(&self, other: &Obstacle) -> f64 {
        let offset = other.centre - self.centre;
        let pos12 = Pose::from_translation(Vector::new(offset.x as f32, offset.y as f32));
        f64::from(parry2d::query::details::distance_support_map_support_map(
            &pos12,
            &self.shape,
            &other.shape,
        ))
    }

    /// Signed distance between two footprints (m): the gap when they are apart, minus how deep they
    /// overlap when they do (the shortest translation that would part them).
    pub fn signed_distance_to_obstacle(&self, other: &Obstacle) -> f64 {
        let gap = self.distance_to_obstacle(other);
        if gap > 0.0 {
            return gap;
        }
        let offset = other.centre - self.centre;
        let pos12 = Pose::from_translation(Vector::new(offset.x as f32, offset.y as f32));
        parry2d::query::details::contact_support_map_support_map(
            &pos12,
            &self.shape,
            &other.shape,
            0.0,
        )
        .map_or(0.0, |c| f64::from(c.dist).min(0.0))
    }

    /// Where this footprint and `other` lie within `margin` (m) of each other: the unit normal of
    /// their nearest (or, overlapping, deepest) contact, pointing from this footprint towards
    /// `other`, and their signed distance; `None` when they are farther apart.
    pub fn contact_with(&self, other: &Obstacle, margin: f64) -> Option<(Vector2<f64>, f64)> {
        let offset = other.centre - self.centre;
        let pos12 = Pose::from_translation(Vector::new(offset.x as f32, offset.y as f32));
        let c = parry2d::query::details::contact_support_map_support_map(
            &pos12,
            &self.shape,
            &other.shape,
            margin as f32,
        )?;
        let normal = Vector2::new(f64::from(c.normal1.x), f64::from(c.normal1.y));
        Some((normal, f64::from(c.dist)))
    }

    /// Whether `p` lies inside the footprint or on its border.
    pub fn contains(&self, p: &Point2<f64>) -> bool {
        self.shape
            .contains_point(&Pose::IDENTITY, to_local(&self.centre, p))
    }
}

/// `p` relative to `centre`, as parry's f32 vector; the only f64 → f32 narrowing in the crate.
fn to_local(centre: &Point2<f64>, p: &Point2<f64>) -> Vector {
    Vector::new((p.x - centre.x) as f32, (p.y - centre.y) as f32)
}

/// Squared distance from `p` to the segment `a`–`b`.
fn point_segment_d2(p: &Point2<f64>, a: &Point2<f64>, b: &Point2<f64>) -> f64 {
    let d = b - a;
    let len2 = d.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&d) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t - p).norm_squared()
}

/// Squared distance between segments `a`–`b` and `c`–`d` (0 when they cross).
fn segment_segment_d2(a: &Point2<f64>, b: &Point2<f64>, c: &Point2<f64>, d: &Point2<f64>) -> f64 {
    let cross = |o: &Point2<f64>, p: &Point2<f64>, q: &Point2<f64>| (p - o).perp(&(q - o));
    let (d1, d2) = (cross(c, d, a), cross(c, d, b));
    let (d3, d4) = (cross(a, b, c), cross(a, b, d));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return 0.0;
    }
    point_segment_d2(a, c, d)
        .min(point_segment_d2(b, c, d))
        .min(point_segment_d2(c, a, b))
        .min(point_segment_d2(d, a, b))
}

fn polygon_area(points: &[Vector]) -> f32 {
    let n = points.len();
    (0..n)
        .map(|i| {
            let a = points[i];
            let b = points[(i + 1) % n];
            a.x * b.y - b.x * a.y
        })
        .sum::<f32>()
        * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(id: u32, x0: f64, y0: f64, side: f64) -> Obstacle {
        let pts = [
            Point2::new(x0, y0),
            Point2::new(x0 + side, y0),
            Point2::new(x0 + side, y0 + side),
            Point2::new(x0, y0 + side),
        ];
        Obstacle::new(ObjectId(id), &pts, 0.0, 1.0).expect("a square is a valid footprint")
    }

    #[test]
    fn distances_match_geometry() {
        // Invariant: point, segment and polygon distances agree with hand-computed geometry (1e-5 m).
        let o = square(1, 2.0, 2.0, 1.0);
        assert!((o.distance_to_point(&Point2::new(4.0, 2.5)) - 1.0).abs() < 1e-5);
        assert!(o.distance_to_point(&Point2::new(2.5, 2.5)).abs() < 1e-6);
        let d = o.distance_to_segment(&Point2::new(0.0, 4.0), &Point2::new(5.0, 4.0));
        assert!((d - 1.0).abs() < 1e-5, "{d}");
        let crossing = o.distance_to_segment(&Point2::new(0.0, 2.5), &Point2::new(5.0, 2.5));
        assert!(crossing.abs() < 1e-6);
        let other = square(2, 3.5, 2.0, 1.0);
        assert!((o.distance_to_obstacle(&other) - 0.5).abs() < 1e-5);
    }

    #[test]
    fn f64_hot_path_agrees_with_parry() {
        // Invariant: the f64 disc and capsule tests agree with parry's distances away from ties.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let pts: Vec<Point2<f64>> = (0..7)
            .map(|k| {
                let a = f64::from(k) * 0.9 + 0.3;
                Point2::new(5.0 + 1.3 * a.cos(), 5.0 + 0.7 * a.sin())
            })
            .collect();
        let o = Obstacle::new(ObjectId(1), &pts, 0.0, 1.0).expect("heptagon");
        let mut checked = 0;
        for _ in 0..20_000 {
            let a = Point2::new(rng.random_range(2.0..8.0), rng.random_range(2.0..8.0));
            let b = if rng.random_bool(0.2) {
                a
            } else {
                Point2::new(rng.random_range(2.0..8.0), rng.random_range(2.0..8.0))
            };
            let r = rng.random_range(0.0..1.0);
            let d = o.distance_to_segment(&a, &b);
            if (d - r).abs() < 1e-4 {
                continue;
            }
            checked += 1;
            assert_eq!(o.capsule_hits(&a, &b, r), d < r, "{a} {b} {r} {d}");
            let dp = o.distance_to_point(&a);
            if (dp - r).abs() >= 1e-4 {
                assert_eq!(o.disc_hits(&a, r), dp < r, "{a} {r} {dp}");
            }
        }
        assert!(checked > 19_000);
    }

    #[test]
    fn bad_footprints_are_errors() {
        // Invariant: collinear, short, non-finite and inverted inputs are typed errors, not panics.
        let line = [
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(2.0, 0.0),
        ];
        assert!(Obstacle::new(ObjectId(1), &line, 0.0, 1.0).is_err());
        assert!(Obstacle::new(ObjectId(1), &line[..2], 0.0, 1.0).is_err());
        let nan = [
            Point2::new(f64::NAN, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(0.0, 1.0),
        ];
        assert!(Obstacle::new(ObjectId(1), &nan, 0.0, 1.0).is_err());
        let tri = [
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(0.0, 1.0),
        ];
        assert!(Obstacle::new(ObjectId(1), &tri, 1.0, 0.5).is_err());
        // Clockwise input is accepted and stored counter-clockwise.
        let cw = [
            Point2::new(0.0, 0.0),
            Point2::new(0.0, 1.0),
            Point2::new(1.0, 0.0),
        ];
        let o = Obstacle::new(ObjectId(1), &cw, 0.0, 1.0).expect("clockwise triangle");
        let f = o.footprint();
        let cross = (f[1] - f[0]).perp(&(f[2] - f[1]));
        assert!(cross > 0.0);
    }
}
