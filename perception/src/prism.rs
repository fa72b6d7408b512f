//! Prisms: the obstacles nudge plans around and pushes.
//!
//! A prism is the convex hull of a cluster's points projected on the floor plane, extruded from its
//! lowest to its highest point. It keeps the cluster's coloured points so that colour ICP can follow
//! the object when it is pushed.

use nalgebra::{Isometry3, Point2, Point3};

use crate::cloud::ColourCloud;
use crate::hue::ColourSum;

/// An object's identity, stable across look-arounds (matched by footprint overlap).
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize,
)]
pub struct ObjectId(pub u32);

impl std::fmt::Display for ObjectId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "obj-{}", self.0)
    }
}

/// An obstacle: a convex footprint in the map frame extruded between two heights.
#[derive(Clone, Debug, PartialEq)]
pub struct Prism {
    /// Identity, stable across looks.
    pub id: ObjectId,
    /// Convex footprint in the map frame (m), counter-clockwise, first vertex not repeated.
    pub footprint: Vec<Point2<f64>>,
    /// Height of the lowest point above the floor (m); above zero for overhangs such as a shelf.
    pub z_min: f64,
    /// Height of the highest point above the floor (m).
    pub z_max: f64,
    /// The cluster's coloured points in the map frame, kept for colour ICP.
    pub points: ColourCloud,
}

impl Prism {
    /// Footprint area (m²); zero for a degenerate footprint.
    pub fn area(&self) -> f64 {
        polygon_area(&self.footprint).abs()
    }

    /// The footprint's centre of area (map frame): where an object of even weight has its centre of
    /// friction on the floor. Not the vertices' mean: a hull's vertices crowd where its points were
    /// noisy (the rounded corners of a face seen end-on), and their mean lies off the middle by as
    /// much as a quarter of the object. The vertices' mean for a footprint with no area; `None` for
    /// an empty one.
    pub fn centroid(&self) -> Option<Point2<f64>> {
        polygon_centroid(&self.footprint)
    }

    /// The footprint's extent: the largest distance between two of its vertices (m).
    pub fn extent(&self) -> f64 {
        let f = &self.footprint;
        f.iter()
            .flat_map(|a| f.iter().map(move |b| (a - b).norm()))
            .fold(0.0, f64::max)
    }

    /// Height of the prism's top above the floor (m); the same as `z_max`.
    pub fn top(&self) -> f64 {
        self.z_max
    }

    /// The colours of the prism's points, summed: what its surface's chromaticity is
    /// ([`crate::hue`]).
    pub fn colour(&self) -> ColourSum {
        let mut sum = ColourSum::default();
        for (_, _, c) in self.points.iter_valid() {
            sum.add(c);
        }
        sum
    }

    /// Intersection over union of the two footprints (0 when either is degenerate).
    pub fn footprint_iou(&self, other: &Prism) -> f64 {
        convex_iou(&self.footprint, &other.footprint)
    }

    /// True when the map-frame point lies inside the footprint (boundary included).
    pub fn contains_xy(&self, p: &Point2<f64>) -> bool {
        let n = self.footprint.len();
        n >= 3
            && (0..n).all(|i| {
                let (a, b) = (self.footprint[i], self.footprint[(i + 1) % n]);
                (b - a).perp(&(p - a)) >= -1e-12
            })
    }

    /// The prism grown to cover `other` too: the convex hull of both footprints, both height ranges, and
    /// this prism's id and points. For one object seen in parts from different places.
    pub fn merged_with(&self, other: &Prism) -> Prism {
        Prism {
            id: self.id,
            footprint: self.merged_footprint(other),
            z_min: self.z_min.min(other.z_min),
            z_max: self.z_max.max(other.z_max),
            points: self.points.clone(),
        }
    }

    /// The prism made of those of its points that `keep` accepts: the footprint is their convex hull
    /// (at least `min_thickness` thick), the heights theirs. For a detection that joined a moved object
    /// to something it came to rest against (a cart pushed up to a wall's end, closer than perception
    /// tells apart): the points that belong to what did not move are left out. `None` when fewer than
    /// three points are kept.
    pub fn with_points_where(
        &self,
        keep: impl Fn(&Point3<f32>) -> bool,
        min_thickness: f64,
    ) -> Option<Prism> {
        let mut points = ColourCloud::empty(
            self.points.frame(),
            *self.points.sensor_pose(),
            self.points.stamp(),
        );
        let (mut z_min, mut z_max) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut xy = Vec::new();
        for (_, p, c) in self.points.iter_valid().filter(|(_, p, _)| keep(p)) {
            points.push(p, c);
            z_min = z_min.min(f64::from(p.z));
            z_max = z_max.max(f64::from(p.z));
            xy.push(parry2d::math::Vector2::new(p.x, p.y));
        }
        (xy.len() >= 3).then(|| Prism {
            id: self.id,
            footprint: crate::prisms::convex_footprint(&xy, min_thickness),
            z_min: z_min.max(0.0),
            z_max,
            points,
        })
    }

    /// Distance (m) in the floor plane from `p` to the footprint: zero inside or on it.
    pub fn distance_xy(&self, p: &Point2<f64>) -> f64 {
        if self.contains_xy(p) {
            return 0.0;
        }
        self.nearest_on_outline(p)
            .map_or(f64::INFINITY, |q| (q - p).norm())
    }

    /// The point of the footprint's outline nearest `p` (the first such, edge by edge); `None` for an
    /// empty footprint.
    pub fn nearest_on_outline(&self, p: &Point2<f64>) -> Option<Point2<f64>> {
        let f = &self.footprint;
        let n = f.len();
        (0..n)
            .map(|i| {
                let (a, b) = (f[i], f[(i + 1) % n]);
                let ab = b - a;
                let t = if ab.norm_squared() > 1e-18 {
                    ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                a + ab * t
            })
            .min_by(|a, b| (a - p).norm().total_cmp(&(b - p).norm()))
    }

    /// Grows the footprint to the convex hull of itself and `p`: the object is known to reach there
    /// (a robot's body was stopped against it) though its points fell short. The points are kept.
    pub fn grow_to(&mut self, p: &Point2<f64>) {
        if self.contains_xy(p) {
            return;
        }
        let pts: Vec<parry2d::math::Vector2> = self
            .footprint
            .iter()
            .chain(std::iter::once(p))
            .map(|q| parry2d::math::Vector2::new(q.x as f32, q.y as f32))
            .collect();
        self.footprint = crate::prisms::convex_footprint(&pts, 0.0);
    }

    /// The convex hull of both footprints: [`Self::merged_with`]'s footprint, without copying points.
    pub fn merged_footprint(&self, other: &Prism) -> Vec<Point2<f64>> {
        let pts: Vec<parry2d::math::Vector2> = self
            .footprint
            .iter()
            .chain(other.footprint.iter())
            .map(|p| parry2d::math::Vector2::new(p.x as f32, p.y as f32))
            .collect();
        crate::prisms::convex_footprint(&pts, 0.0)
    }

    /// The prism after the object moved by `motion` (a map-frame rigid motion, e.g. a colour-ICP
    /// result): footprint and points move with it. Heights are kept, the motion being a push on the
    /// floor; pass the moved prism to [`track_ids`] so the object keeps its id after a push.
    pub fn transformed(&self, motion: &Isometry3<f64>) -> Prism {
        let footprint = self
            .footprint
            .iter()
            .map(|p| {
                let q = motion * Point3::new(p.x, p.y, 0.0);
                Point2::new(q.x, q.y)
            })
            .collect();
        Prism {
            id: self.id,
            footprint,
            z_min: self.z_min,
            z_max: self.z_max,
            points: self.points.transformed(motion),
        }
    }
}

/// Default smallest footprint IoU for [`track_ids`] to call two prisms the same object.
pub const TRACK_MIN_IOU: f64 = 0.3;

/// Gives `current` prisms the ids of the `previous` prisms they overlap most (footprint IoU ≥
/// [`TRACK_MIN_IOU`]); the others get fresh ids above every previous one.
///
/// Matching is greedy by decreasing IoU (ties by index), one-to-one, so it is deterministic; fresh ids are
/// handed out in `current` order.
pub fn track_ids(previous: &[Prism], current: &mut [Prism]) {
    track_ids_with(previous, current, TRACK_MIN_IOU);
}

/// [`track_ids`] with an explicit IoU threshold.
pub fn track_ids_with(previous: &[Prism], current: &mut [Prism], min_iou: f64) {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (j, cur) in current.iter().enumerate() {
        for (i, prev) in previous.iter().enumerate() {
            let iou = cur.footprint_iou(prev);
            if iou >= min_iou && iou > 0.0 {
                pairs.push((iou, i, j));
            }
        }
    }
    pairs.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut prev_used = vec![false; previous.len()];
    let mut assigned: Vec<Option<ObjectId>> = vec![None; current.len()];
    for (_, i, j) in pairs {
        if !prev_used[i] && assigned[j].is_none() {
            prev_used[i] = true;
            assigned[j] = Some(previous[i].id);
        }
    }
    let mut next = previous.iter().map(|p| p.id.0 + 1).max().unwrap_or(0);
    for (cur, id) in current.iter_mut().zip(assigned) {
        cur.id = id.unwrap_or_else(|| {
            let fresh = ObjectId(next);
            next = next.saturating_add(1);
            fresh
        });
    }
}

/// Signed area of a polygon (positive when counter-clockwise).
pub fn polygon_area(poly: &[Point2<f64>]) -> f64 {
    let n = poly.len();
    if n < 3 {
        return 0.0;
    }
    0.5 * (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
}

/// The centre of area of a simple polygon; the vertices' mean when it has no area (fewer than three
/// vertices, or all on a line); `None` when it has no vertex.
pub fn polygon_centroid(poly: &[Point2<f64>]) -> Option<Point2<f64>> {
    let first = *poly.first()?;
    let n = poly.len();
    // About the first vertex, so that coordinates far from the origin lose no precision.
    let (mut twice_area, mut moment) = (0.0, nalgebra::Vector2::zeros());
    for i in 0..n {
        let (a, b) = (poly[i] - first, poly[(i + 1) % n] - first);
        let cross = a.x * b.y - b.x * a.y;
        twice_area += cross;
        moment += (a + b) * cross;
    }
    if twice_area.abs() > 1e-12 {
        return Some(first + moment / (3.0 * twice_area));
    }
    let sum = poly
        .iter()
        .fold(nalgebra::Vector2::zeros(), |acc, p| acc + p.coords);
    Some(Point2::from(sum / n as f64))
}

/// Intersection over union of two convex counter-clockwise polygons.
pub fn convex_iou(a: &[Point2<f64>], b: &[Point2<f64>]) -> f64 {
    let (area_a, area_b) = (polygon_area(a).abs(), polygon_area(b).abs());
    if area_a <= 0.0 || area_b <= 0.0 {
        return 0.0;
    }
    let inter = polygon_area(&clip_convex(a, b)).abs();
    let union = area_a + area_b - inter;
    if union > 0.0 { inter / union } else { 0.0 }
}

/// Area of the intersection of two convex counter-clockwise polygons.
pub fn convex_intersection_area(a: &[Point2<f64>], b: &[Point2<f64>]) -> f64 {
    if a.len() < 3 || b.len() < 3 {
        return 0.0;
    }
    polygon_area(&clip_convex(a, b)).abs()
}

/// Sutherland–Hodgman: the part of convex polygon `subject` inside convex CCW polygon `clip`.
fn clip_convex(subject: &[Point2<f64>], clip: &[Point2<f64>]) -> Vec<Point2<f64>> {
    let mut out: Vec<Point2<f64>> = subject.to_vec();
    let n = clip.len();
    for i in 0..n {
        if out.is_empty() {
            break;
        }
        let (a, b) = (clip[i], clip[(i + 1) % n]);
        let side = |p: &Point2<f64>| (b - a).perp(&(p - a));
        let input = std::mem::take(&mut out);
        for k in 0..input.len() {
            let (p, q) = (input[k], input[(k + 1) % input.len()]);
            let (sp, sq) = (side(&p), side(&q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push(p + (q - p) * t);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::CloudFrame;

    fn square(id: u32, x: f64, y: f64, side: f64) -> Prism {
        Prism {
            id: ObjectId(id),
            footprint: vec![
                Point2::new(x, y),
                Point2::new(x + side, y),
                Point2::new(x + side, y + side),
                Point2::new(x, y + side),
            ],
            z_min: 0.0,
            z_max: 1.0,
            points: ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0),
        }
    }

    #[test]
    fn a_footprint_with_crowded_vertices_has_its_centroid_in_its_middle() {
        // Invariant: the centroid is the footprint's centre of area, wherever its vertices crowd: a
        // face seen end-on, 0.1 m deep and 1.2 m long, whose hull has eight vertices round one end.
        let mut footprint = vec![Point2::new(5.4, 0.3), Point2::new(5.4, 1.5)];
        footprint.push(Point2::new(5.3, 1.5));
        footprint.extend((0..8).map(|k| {
            let a = std::f64::consts::FRAC_PI_2 * f64::from(k) / 7.0;
            Point2::new(5.35 - 0.05 * a.cos(), 0.35 - 0.05 * a.sin())
        }));
        // Counter-clockwise: the right edge up, the top leftwards, the rounded corner down and back.
        let mut prism = square(0, 0.0, 0.0, 1.0);
        prism.footprint = footprint;
        let c = prism.centroid().expect("a footprint");
        let mean = prism.footprint.iter().map(|p| p.y).sum::<f64>() / prism.footprint.len() as f64;
        assert!((c.y - 0.9).abs() < 0.02, "centroid {c}");
        assert!((c.x - 5.35).abs() < 0.01, "centroid {c}");
        assert!(
            mean < 0.7,
            "the vertices' mean {mean} lies near the crowded end"
        );
        assert_eq!(
            square(1, 2.0, 3.0, 2.0).centroid(),
            Some(Point2::new(3.0, 4.0))
        );
        let line = [Point2::new(0.0, 0.0), Point2::new(2.0, 0.0)];
        assert_eq!(polygon_centroid(&line), Some(Point2::new(1.0, 0.0)));
        assert_eq!(polygon_centroid(&[]), None);
    }

    #[test]
    fn iou_of_half_shifted_squares_is_one_third() {
        // Invariant: IoU is intersection area over union area of the footprints.
        let a = square(0, 0.0, 0.0, 1.0);
        let b = square(1, 0.5, 0.0, 1.0);
        assert!((a.footprint_iou(&b) - 1.0 / 3.0).abs() < 1e-12);
        assert_eq!(a.footprint_iou(&square(2, 5.0, 5.0, 1.0)), 0.0);
    }

    #[test]
    fn tracking_keeps_ids_of_overlapping_prisms_and_numbers_new_ones_above() {
        // Invariant: an object that overlaps its previous footprint keeps its id; a new one gets a fresh
        // id above every previous id; the result does not depend on anything but the input.
        let previous = vec![square(4, 0.0, 0.0, 1.0), square(9, 3.0, 0.0, 1.0)];
        let mut current = vec![
            square(0, 5.0, 5.0, 1.0),
            square(0, 3.1, 0.0, 1.0),
            square(0, 0.05, 0.05, 1.0),
        ];
        track_ids(&previous, &mut current);
        let ids: Vec<u32> = current.iter().map(|p| p.id.0).collect();
        assert_eq!(ids, vec![10, 9, 4]);
    }

    #[test]
    fn a_moved_prism_keeps_its_id_when_tracked_after_the_push() {
        // Invariant: transforming the previous prism by the push motion lets tracking keep the id.
        let chair = square(3, 3.55, 0.6, 0.5);
        let push = Isometry3::translation(0.8, 0.0, 0.0);
        let mut after = vec![square(0, 4.35, 0.6, 0.5)];
        track_ids(std::slice::from_ref(&chair), &mut after);
        assert_eq!(
            after[0].id,
            ObjectId(4),
            "without the motion the chair looks new"
        );
        track_ids(&[chair.transformed(&push)], &mut after);
        assert_eq!(after[0].id, ObjectId(3));
        assert!(after[0].contains_xy(&Point2::new(4.6, 0.85)));
    }

    #[test]
    fn a_footprint_grown_to_a_point_covers_it_and_all_it_covered() {
        // Invariant: growing to a point outside adds it to the footprint's hull (the old footprint is still covered, the point now is) and a point inside changes nothing.
        let mut prism = square(1, 0.0, 0.0, 1.0);
        let outside = Point2::new(0.5, -0.1);
        prism.grow_to(&outside);
        assert!(prism.distance_xy(&outside) < 1e-6, "{:?}", prism.footprint);
        for corner in square(1, 0.0, 0.0, 1.0).footprint {
            assert!(prism.distance_xy(&corner) < 1e-6, "{corner} left out");
        }
        assert!((prism.area() - 1.05).abs() < 1e-5, "area {}", prism.area());
        let before = prism.footprint.clone();
        prism.grow_to(&Point2::new(0.5, 0.5));
        assert_eq!(prism.footprint, before);
    }
}
