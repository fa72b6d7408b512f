//! What changed while the head looked around: a point is gone when another view looked straight
//! through the place it was returned from.
//!
//! A look-around takes its views one after another from one place over about ten seconds. A person
//! walking through them is returned in a different place in each, and the fused cloud holds all of
//! those places at once — a smear that perception would turn into an obstacle where nobody stands.
//! Free-space carving tells the places apart: if a later view's rays pass the place of an earlier
//! return and come back from farther away, nothing stands there any more (the point *departed*); if
//! an earlier view's rays did so, what stands there came during the look (the point *arrived*: a
//! mover, or something that may walk on). A static surface is returned at the same range by every
//! view that sees it, so it is neither.
//!
//! Each view becomes a range image in its own sensor frame — bins of the tangent plane a couple of
//! pixels wide holding the nearest return — built from the view's points themselves, so no lens model
//! is needed beyond the pixel pitch. A pinhole camera's pixels lie evenly on that plane, so a bin
//! holds the same number of pixels across the whole image, and a point's bin costs two divisions
//! where angles would cost two arctangents (a look asks hundreds of thousands of points). A point is
//! seen through by a view when the bin it falls in and every neighbouring bin that holds returns hold
//! only returns farther than the point plus a margin: the neighbours keep an edge's points (a chair
//! leg, a handle bar, the rim of a table) and a surface grazed at a shallow angle from being taken
//! for gone, since some return beside them lies at their own range or nearer.

use nalgebra::{Isometry3, Point3};
use rayon::prelude::*;

use crate::cloud::{CloudFrame, ColourCloud};

/// Pixels per bin side: two, so that a point a pixel off between two views (the head does not stop
/// exactly where it stopped before) still lands in the bin of its own surface or the next. On the
/// tangent plane a pinhole camera's pixels lie `2 tan(fov / 2) / width` apart, a few per cent more
/// than the angular pitch (5 % for a 43.6° field), so a bin spans a little under two pixels and
/// its neighbours cover the rest.
const BIN_PIXELS: f64 = 2.0;

/// How much farther than a point every return around its direction must be for the view to have
/// looked through it (m): ten times the range sensor's noise (about a centimetre on an SR-4000-like
/// camera), and the few centimetres the camera moves as the head turns about its axes (parallax).
/// A person is 0.3–0.5 m thick and stands well in front of what is behind them.
pub const SEEN_THROUGH_MARGIN: f64 = 0.1;

/// Every how many points of a view a sample asks whether an image can hold them at all (see
/// [`LookChanges::split`]): a 176 × 144 image's points sampled every 37th land a few pixels apart
/// along its rows and a fifth of an image apart down it.
const OVERLAP_SAMPLE: usize = 37;

/// Points lower than this are not asked about (m): the floor, which every view returns at its own
/// range along its own rays.
pub const FLOOR_BAND: f32 = 0.05;

/// Depth below which a sensor-frame point is taken to lie beside or behind the camera (m): no
/// camera narrower than a half turn returns it, and its tangents would not be finite.
const MIN_DEPTH: f32 = 1e-3;

/// A view as a range image on its sensor frame's tangent plane (x forward: bins of y/x and z/x).
#[derive(Clone, Debug)]
struct RangeImage {
    /// Map → sensor.
    to_sensor: Isometry3<f32>,
    /// Bin side on the tangent plane.
    bin: f32,
    /// Tangents (y/x, z/x) of bin (0, 0)'s lower edge.
    u0: f32,
    v0: f32,
    cols: usize,
    rows: usize,
    /// Nearest return per bin (m); infinity for none.
    nearest: Vec<f32>,
    /// Per bin, the nearest return of it and its eight neighbours (m), worked out once per image
    /// (every point of a look asks it).
    nearest_around: Vec<f32>,
}

/// Tangents (y/x, z/x) and range of a sensor-frame point (x forward, y left, z up); `None` beside
/// or behind the camera.
fn tangents(q: &Point3<f32>) -> Option<(f32, f32, f32)> {
    (q.x > MIN_DEPTH).then(|| (q.y / q.x, q.z / q.x, q.coords.norm()))
}

impl RangeImage {
    /// The image of `view` (sensor-frame or map-frame points) with pixels `pitch` rad apart; `None`
    /// for a view without points.
    fn new(view: &ColourCloud, pitch: f64) -> Option<Self> {
        let pose = view.sensor_pose().cast::<f32>();
        let to_sensor = pose.inverse();
        let in_sensor = |p: Point3<f32>| match view.frame() {
            CloudFrame::Sensor => p,
            CloudFrame::Map => to_sensor * p,
        };
        let bin = (pitch * BIN_PIXELS) as f32;
        let returns: Vec<(f32, f32, f32)> = view
            .iter_valid()
            .filter_map(|(_, p, _)| tangents(&in_sensor(p)))
            .collect();
        if returns.is_empty() || bin.is_nan() || bin <= 0.0 {
            return None;
        }
        let (mut u_lo, mut u_hi, mut v_lo, mut v_hi) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for &(u, v, _) in &returns {
            u_lo = u_lo.min(u);
            u_hi = u_hi.max(u);
            v_lo = v_lo.min(v);
            v_hi = v_hi.max(v);
        }
        let cols = ((u_hi - u_lo) / bin).floor() as usize + 1;
        let rows = ((v_hi - v_lo) / bin).floor() as usize + 1;
        let mut image = Self {
            to_sensor,
            bin,
            u0: u_lo,
            v0: v_lo,
            cols,
            rows,
            nearest: vec![f32::INFINITY; cols * rows],
            nearest_around: Vec::new(),
        };
        for (u, v, r) in returns {
            if let Some((c, row)) = image.cell(u, v) {
                let i = row * cols + c;
                image.nearest[i] = image.nearest[i].min(r);
            }
        }
        image.nearest_around = image.around();
        Some(image)
    }

    /// Per bin, the least of `nearest` over it and its neighbours (those inside the image).
    fn around(&self) -> Vec<f32> {
        let (cols, rows) = (self.cols, self.rows);
        // Rows first, then columns: a 3 × 3 minimum as two passes of three.
        let mut along = vec![f32::INFINITY; cols * rows];
        for r in 0..rows {
            let line = &self.nearest[r * cols..(r + 1) * cols];
            for c in 0..cols {
                let lo = c.saturating_sub(1);
                let hi = (c + 1).min(cols - 1);
                along[r * cols + c] = line[lo..=hi].iter().copied().fold(f32::INFINITY, f32::min);
            }
        }
        let mut around = vec![f32::INFINITY; cols * rows];
        for r in 0..rows {
            let lo = r.saturating_sub(1);
            let hi = (r + 1).min(rows - 1);
            for c in 0..cols {
                around[r * cols + c] = (lo..=hi)
                    .map(|rr| along[rr * cols + c])
                    .fold(f32::INFINITY, f32::min);
            }
        }
        around
    }

    /// A cheap test: false for sensor-frame points whose direction lies outside the image (with a
    /// bin's slack), most points of the other views of a look.
    fn may_hold(&self, q: &Point3<f32>) -> bool {
        if q.x <= MIN_DEPTH {
            return false;
        }
        let (u, v) = (q.y / q.x, q.z / q.x);
        let c = (u - self.u0) / self.bin;
        let r = (v - self.v0) / self.bin;
        c >= -1.0 && r >= -1.0 && c < self.cols as f32 + 1.0 && r < self.rows as f32 + 1.0
    }

    fn cell(&self, u: f32, v: f32) -> Option<(usize, usize)> {
        let c = (u - self.u0) / self.bin;
        let r = (v - self.v0) / self.bin;
        // Truncation is the floor once both are known non-negative (and needs no libm call where
        // the target has no rounding instruction); NaN fails the comparison.
        (c >= 0.0 && r >= 0.0 && (c as usize) < self.cols && (r as usize) < self.rows)
            .then_some((c as usize, r as usize))
    }

    /// Whether this view looked through map point `p`: its bin and every neighbour with returns
    /// returned only from more than `margin` beyond it. A point outside the image, or in a bin
    /// without returns, was not seen through.
    fn looked_through(&self, p: &Point3<f32>, margin: f32) -> bool {
        self.sight(p, margin) == Some(Sight::Through)
    }

    /// What this view saw of map point `p` (see [`Sight`]); `None` outside the image or in a bin
    /// without returns.
    fn sight(&self, p: &Point3<f32>, margin: f32) -> Option<Sight> {
        let (u, v, r) = tangents(&(self.to_sensor * p))?;
        let (c, row) = self.cell(u, v)?;
        let i = row * self.cols + c;
        if !self.nearest[i].is_finite() {
            return None;
        }
        let around = self.nearest_around[i];
        Some(if around > r + margin {
            Sight::Through
        } else if around >= r - margin {
            Sight::Returned
        } else {
            Sight::Hidden
        })
    }
}

/// What a look saw of a place known from before.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sight {
    /// A view looked through it: nothing stands there now.
    Through,
    /// A view returned from it (within the margin of its range): something stands there still.
    Returned,
    /// No view saw it: every view that held its direction returned from nearer (something stands
    /// in front of it), or none held it at all. The look says nothing of it.
    Hidden,
}

/// A look's views, each as a range image, for asking which views looked through a place.
#[derive(Clone, Debug)]
pub struct LookChanges {
    images: Vec<Option<RangeImage>>,
}

/// What a look saw happen at one point of its fused cloud.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    /// No other view looked through its place (or it lies in the floor band): it stands there.
    Stayed,
    /// An earlier view of the look looked through its place: it came during the look.
    Arrived,
    /// A later view of the look looked through its place: it has gone.
    Departed,
}

/// A look-around's fused cloud with what changed at each point.
#[derive(Debug)]
pub struct SplitLook {
    /// Every valid point of every view in the map frame, exactly as [`crate::fuse`] gives them.
    pub fused: ColourCloud,
    /// Per point of `fused`, what the look saw happen there.
    pub changes: Vec<Change>,
}

impl LookChanges {
    /// The range images of `views` (in capture order), whose pixels lie `pitch` rad apart (the field
    /// of view across the image divided by its width).
    pub fn new(views: &[ColourCloud], pitch: f64) -> Self {
        Self {
            images: views
                .par_iter()
                .map(|v| RangeImage::new(v, pitch))
                .collect(),
        }
    }

    /// What the views saw of map point `p` (a point known from before the look): seen through by
    /// one, else returned by one, else hidden from all of them.
    pub fn sight_of(&self, p: &Point3<f32>) -> Sight {
        let margin = SEEN_THROUGH_MARGIN as f32;
        let mut returned = false;
        for image in self.images.iter().flatten() {
            match image.sight(p, margin) {
                Some(Sight::Through) => return Sight::Through,
                Some(Sight::Returned) => returned = true,
                _ => {}
            }
        }
        if returned {
            Sight::Returned
        } else {
            Sight::Hidden
        }
    }

    /// Fuses `views` (the clouds these images were made from, in the same order) as
    /// [`crate::fuse`] does and says what changed at each point; with `before`, the views of the look
    /// before count as earlier views too (what came since then has arrived). Points below
    /// [`FLOOR_BAND`] stay.
    pub fn split(&self, views: &[ColourCloud], before: Option<&LookChanges>) -> SplitLook {
        let margin = SEEN_THROUGH_MARGIN as f32;
        let fused = crate::fuse(views);
        let mut changes = vec![Change::Stayed; fused.len()];
        // Each view's points fill their own slice of the fused cloud, in view order.
        let mut jobs = Vec::with_capacity(views.len());
        let mut rest = &mut changes[..];
        let mut start = 0;
        for (k, view) in views.iter().enumerate() {
            let n = crate::lookaround::valid_slots(view).min(rest.len());
            let (mine, tail) = rest.split_at_mut(n);
            jobs.push((k, start, mine));
            start += n;
            rest = tail;
        }
        let (xs, ys, zs) = (fused.xs(), fused.ys(), fused.zs());
        let earlier: Vec<&RangeImage> = before
            .map(|b| b.images.iter().flatten().collect())
            .unwrap_or_default();
        jobs.into_par_iter().for_each(|(k, start, mine)| {
            let point = |offset: usize| {
                let i = start + offset;
                Point3::new(xs[i], ys[i], zs[i])
            };
            // The images this view's points can fall in: those a sparse sample of them does. Two
            // views of a look overlap over tens of pixels or not at all, far more than the sample's
            // spacing, so a view's points are asked only of the few images beside it.
            let overlapping = |image: &&RangeImage| {
                (0..mine.len())
                    .step_by(OVERLAP_SAMPLE)
                    .any(|o| image.may_hold(&(image.to_sensor * point(o))))
            };
            let later: Vec<&RangeImage> = self.images[(k + 1).min(self.images.len())..]
                .iter()
                .flatten()
                .filter(overlapping)
                .collect();
            let sooner: Vec<&RangeImage> = self.images[..k.min(self.images.len())]
                .iter()
                .flatten()
                .chain(earlier.iter().copied())
                .filter(overlapping)
                .collect();
            for (offset, change) in mine.iter_mut().enumerate() {
                let p = point(offset);
                if p.z < FLOOR_BAND {
                    continue;
                }
                if later.iter().any(|image| image.looked_through(&p, margin)) {
                    *change = Change::Departed;
                } else if sooner.iter().any(|image| image.looked_through(&p, margin)) {
                    *change = Change::Arrived;
                }
            }
        });
        SplitLook { fused, changes }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion, Vector3};

    /// Pixel pitch of the synthetic camera (rad): 40° over 160 pixels.
    const PITCH: f64 = 0.25 * std::f64::consts::PI / 180.0;

    /// A person: a 0.4 m square column 1.7 m tall centred at `(x, y)`.
    #[derive(Clone, Copy)]
    struct Column(f64, f64);

    /// The distance along the ray from `o` in direction `d` to the column, if it hits.
    fn hit_column(o: &Point3<f64>, d: &Vector3<f64>, c: Column) -> Option<f64> {
        let lo = Vector3::new(c.0 - 0.2, c.1 - 0.2, 0.0);
        let hi = Vector3::new(c.0 + 0.2, c.1 + 0.2, 1.7);
        let (mut near, mut far) = (0.0f64, f64::INFINITY);
        for a in 0..3 {
            if d[a].abs() < 1e-12 {
                if o[a] < lo[a] || o[a] > hi[a] {
                    return None;
                }
                continue;
            }
            let (t1, t2) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
            near = near.max(t1.min(t2));
            far = far.min(t1.max(t2));
        }
        (near <= far).then_some(near)
    }

    /// One view from (0, 0, 1.4) panned `yaw` rad, looking 10° down at a wall at x = 4 and the floor,
    /// with `people` standing in front of the wall; map-frame points, organised 160 × 120.
    fn view(yaw: f64, people: &[Column], stamp: f64) -> ColourCloud {
        let origin = Point3::new(0.0, 0.0, 1.4);
        let rotation = UnitQuaternion::from_euler_angles(0.0, 10f64.to_radians(), yaw);
        let pose = Isometry3::from_parts(Translation3::from(origin.coords), rotation);
        let (w, h) = (160usize, 120usize);
        let (mut x, mut y, mut z) = (Vec::new(), Vec::new(), Vec::new());
        for v in 0..h {
            for u in 0..w {
                let az = (w as f64 / 2.0 - u as f64) * PITCH;
                let el = (h as f64 / 2.0 - v as f64) * PITCH;
                let local = Vector3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
                let d = rotation * local;
                let wall = if d.x > 1e-9 {
                    (4.0 - origin.x) / d.x
                } else {
                    f64::INFINITY
                };
                let floor = if d.z < -1e-9 {
                    -origin.z / d.z
                } else {
                    f64::INFINITY
                };
                let mut t = wall.min(floor);
                for c in people {
                    if let Some(s) = hit_column(&origin, &d, *c) {
                        t = t.min(s);
                    }
                }
                let p = origin + d * t;
                x.push(p.x as f32);
                y.push(p.y as f32);
                z.push(p.z as f32);
            }
        }
        let rgb = vec![[128, 128, 128]; w * h];
        ColourCloud::organised(w, h, x, y, z, rgb, CloudFrame::Map, pose, stamp)
            .expect("a consistent cloud")
    }

    /// The changes of the points within 0.3 m of `(x, y)` above the floor band.
    fn changes_near(split: &SplitLook, x: f32, y: f32) -> Vec<Change> {
        split
            .fused
            .iter_valid()
            .filter(|(_, p, _)| p.z >= FLOOR_BAND && (p.x - x).hypot(p.y - y) < 0.3)
            .map(|(i, _, _)| split.changes[i])
            .collect()
    }

    #[test]
    fn a_place_behind_something_nearer_is_hidden_not_still_there() {
        // Invariant: a later look says Through for where someone stood and nobody stands now, Returned for a place it sees something standing in at its range, and Hidden for a place behind something nearer: it says nothing of it.
        let screen = Column(1.5, -0.3);
        let views = vec![view(0.0, &[screen], 0.0)];
        let look = LookChanges::new(&views, PITCH);
        // Where the person stood, in the open: the wall behind it is returned from far beyond.
        assert_eq!(look.sight_of(&Point3::new(2.8, 0.3, 1.0)), Sight::Through);
        // The near face of the screen itself.
        assert_eq!(look.sight_of(&Point3::new(1.3, -0.3, 1.0)), Sight::Returned);
        // Behind the screen, on the same line of sight.
        assert_eq!(look.sight_of(&Point3::new(3.0, -0.6, 1.0)), Sight::Hidden);
    }

    #[test]
    fn a_walker_seen_in_two_places_departed_from_the_first_and_arrived_at_the_second() {
        // Invariant: a person standing at A in the first view and at B in the second (overlapping) view, with the wall behind both places seen in the other view, is Departed at A and Arrived at B; the wall and a person standing still in both views are Stayed.
        let (a, b, still) = (Column(3.0, 0.3), Column(3.0, -0.3), Column(2.5, 0.9));
        let views = vec![view(0.0, &[a, still], 0.0), view(0.05, &[b, still], 0.7)];
        let changes = LookChanges::new(&views, PITCH);
        let split = changes.split(&views, None);
        let at_a = changes_near(&split, 2.8, 0.3);
        let at_b = changes_near(&split, 2.8, -0.3);
        assert!(!at_a.is_empty() && !at_b.is_empty());
        let share =
            |v: &[Change], c: Change| v.iter().filter(|&&x| x == c).count() as f64 / v.len() as f64;
        assert!(share(&at_a, Change::Departed) > 0.9, "A departed");
        assert!(share(&at_b, Change::Arrived) > 0.9, "B arrived");
        let still_points = changes_near(&split, 2.3, 0.9);
        assert!(
            share(&still_points, Change::Stayed) > 0.99,
            "the one standing still"
        );
        let wall = changes_near(&split, 4.0, 1.2);
        assert!(share(&wall, Change::Stayed) > 0.99, "the wall");
    }

    #[test]
    fn a_still_room_changes_nowhere_and_a_later_look_finds_what_came_since() {
        // Invariant: two overlapping views of a still room leave every point Stayed; a person who came after the look before stands where that look saw through, so their points are Arrived when it is given and Stayed when it is not; the look before saw through the person's place and not through the wall.
        let person = Column(2.6, 0.0);
        let before_views = vec![view(0.0, &[], 0.0), view(0.05, &[], 0.7)];
        let before = LookChanges::new(&before_views, PITCH);
        assert!(
            before
                .split(&before_views, None)
                .changes
                .iter()
                .all(|c| *c == Change::Stayed)
        );
        let now_views = vec![view(0.0, &[person], 10.0), view(0.05, &[person], 10.7)];
        let now = LookChanges::new(&now_views, PITCH);
        let near = |split: &SplitLook| changes_near(split, 2.4, 0.0);
        let alone = now.split(&now_views, None);
        assert!(near(&alone).iter().all(|c| *c == Change::Stayed));
        let after = now.split(&now_views, Some(&before));
        let arrived = near(&after)
            .iter()
            .filter(|c| **c == Change::Arrived)
            .count();
        assert!(arrived as f64 > 0.9 * near(&after).len() as f64);
        // The look before saw through where the person stands now, not through the wall it returned.
        assert_eq!(before.sight_of(&Point3::new(2.4, 0.0, 1.0)), Sight::Through);
        assert_ne!(before.sight_of(&Point3::new(4.0, 0.0, 1.0)), Sight::Through);
    }
}
