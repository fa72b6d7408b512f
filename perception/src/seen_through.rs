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
//! Each view becomes an angular range image in its own sensor frame — bins of azimuth and elevation
//! a couple of pixels wide holding the nearest return — built from the view's points themselves, so
//! no lens model is needed beyond the pixel pitch. A point is seen through by a view when the bin it
//! falls in and every neighbouring bin that holds returns hold only returns farther than the point
//! plus a margin: the neighbours keep an edge's points (a chair leg, a handle bar, the rim of a table)
//! and a surface grazed at a shallow angle from being taken for gone, since some return beside them
//! lies at their own range or nearer.

use nalgebra::{Isometry3, Point3};
use rayon::prelude::*;

use crate::cloud::{CloudFrame, ColourCloud};

/// Pixels per bin side: two, so that a point a pixel off between two views (the head does not stop
/// exactly where it stopped before) still lands in the bin of its own surface or the next.
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

/// A view as an angular range image in its sensor frame.
#[derive(Clone, Debug)]
struct RangeImage {
    /// Map → sensor.
    to_sensor: Isometry3<f32>,
    /// Bin side (rad).
    bin: f32,
    /// Azimuth and elevation of bin (0, 0)'s lower edge (rad).
    az0: f32,
    el0: f32,
    cols: usize,
    rows: usize,
    /// Nearest return per bin (m); infinity for none.
    nearest: Vec<f32>,
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
        let polar: Vec<(f32, f32, f32)> = view
            .iter_valid()
            .map(|(_, p, _)| polar(&in_sensor(p)))
            .filter(|(_, _, r)| *r > 0.0)
            .collect();
        if polar.is_empty() || !(bin > 0.0) {
            return None;
        }
        let (mut az_lo, mut az_hi, mut el_lo, mut el_hi) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for &(az, el, _) in &polar {
            az_lo = az_lo.min(az);
            az_hi = az_hi.max(az);
            el_lo = el_lo.min(el);
            el_hi = el_hi.max(el);
        }
        let cols = ((az_hi - az_lo) / bin).floor() as usize + 1;
        let rows = ((el_hi - el_lo) / bin).floor() as usize + 1;
        let mut image = Self {
            to_sensor,
            bin,
            az0: az_lo,
            el0: el_lo,
            cols,
            rows,
            nearest: vec![f32::INFINITY; cols * rows],
        };
        for (az, el, r) in polar {
            if let Some(i) = image.index(az, el) {
                image.nearest[i] = image.nearest[i].min(r);
            }
        }
        Some(image)
    }

    /// A cheap test before the trigonometry: false only for sensor-frame points whose direction lies
    /// outside the image's azimuths and elevations (with a bin's slack), most points of the other
    /// views of a look.
    fn may_hold(&self, q: &Point3<f32>) -> bool {
        let slack = self.bin;
        let (lo, hi) = (
            self.az0 - slack,
            self.az0 + (self.cols as f32 + 1.0) * self.bin,
        );
        let half_pi = std::f32::consts::FRAC_PI_2;
        // Azimuth by the tangent where the image lies in front of the sensor (it always does for
        // a camera narrower than a half turn); otherwise ask the trigonometry.
        if lo > -half_pi && hi < half_pi {
            if q.x <= 0.0 || q.y < q.x * lo.tan() || q.y > q.x * hi.tan() {
                return false;
            }
        }
        let (el_lo, el_hi) = (
            self.el0 - slack,
            self.el0 + (self.rows as f32 + 1.0) * self.bin,
        );
        if el_lo > -half_pi && el_hi < half_pi {
            let h = q.x.hypot(q.y);
            if q.z < h * el_lo.tan() || q.z > h * el_hi.tan() {
                return false;
            }
        }
        true
    }

    fn cell(&self, az: f32, el: f32) -> Option<(usize, usize)> {
        let c = ((az - self.az0) / self.bin).floor();
        let r = ((el - self.el0) / self.bin).floor();
        (c >= 0.0 && r >= 0.0 && (c as usize) < self.cols && (r as usize) < self.rows)
            .then_some((c as usize, r as usize))
    }

    fn index(&self, az: f32, el: f32) -> Option<usize> {
        self.cell(az, el).map(|(c, r)| r * self.cols + c)
    }

    /// Whether this view looked through map point `p`: its bin and every neighbour with returns
    /// returned only from more than `margin` beyond it. A point outside the image, or in a bin
    /// without returns, was not seen through.
    fn looked_through(&self, p: &Point3<f32>, margin: f32) -> bool {
        let q = self.to_sensor * p;
        if !self.may_hold(&q) {
            return false;
        }
        let (az, el, r) = polar(&q);
        let Some((c, row)) = self.cell(az, el) else {
            return false;
        };
        if !self.nearest[row * self.cols + c].is_finite() {
            return false;
        }
        let beyond = r + margin;
        for rr in row.saturating_sub(1)..=(row + 1).min(self.rows - 1) {
            for cc in c.saturating_sub(1)..=(c + 1).min(self.cols - 1) {
                if self.nearest[rr * self.cols + cc] <= beyond {
                    return false;
                }
            }
        }
        true
    }
}

/// Azimuth, elevation and range of a sensor-frame point (x forward, y left, z up).
fn polar(p: &Point3<f32>) -> (f32, f32, f32) {
    let horizontal = p.x.hypot(p.y);
    (p.y.atan2(p.x), p.z.atan2(horizontal), p.coords.norm())
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

    /// Whether any of the views looked through map point `p` (a point known from before the look:
    /// it is gone when one did).
    pub fn any_looked_through(&self, p: &Point3<f32>) -> bool {
        let margin = SEEN_THROUGH_MARGIN as f32;
        self.images
            .iter()
            .flatten()
            .any(|image| image.looked_through(p, margin))
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
