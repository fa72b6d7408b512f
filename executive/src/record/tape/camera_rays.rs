//! A camera's pixel rays and range step: what lets the tape store a point as one range count.

use nudge_robot_model::{CameraModel, RangeCounts};

/// The rays of a [`CameraModel`] and the step of its ranges, computed once. A sensor that reports
/// each pixel's point as its ray times a range on the step grid ([`CameraModel::pixel_rays`],
/// [`RangeCounts::reported`]) has points the tape stores as a count of steps; any other
/// point is stored as it is.
#[derive(Clone, Debug)]
pub struct CameraRays {
    camera: CameraModel,
    rays: Vec<[f32; 3]>,
    counts: RangeCounts,
}

/// The largest count the tape stores (a `u16`): ranges up to 2¹⁶ steps, four times the camera's
/// range limit, so that noise past the limit still fits.
const MAX_COUNT: u32 = u16::MAX as u32;

impl CameraRays {
    /// The rays of `camera`.
    pub fn new(camera: &CameraModel) -> Self {
        Self {
            camera: camera.clone(),
            rays: camera.pixel_rays(),
            counts: camera.range_counts(),
        }
    }

    /// The camera.
    pub fn camera(&self) -> &CameraModel {
        &self.camera
    }

    /// Pixels in the image.
    pub fn len(&self) -> usize {
        self.rays.len()
    }

    /// Whether the image has no pixels.
    pub fn is_empty(&self) -> bool {
        self.rays.is_empty()
    }

    /// The point pixel `i` reports at `count` range steps, to the bit as the sensor computes it: the
    /// range in `f64`, rounded once to `f32`, times each of the ray's `f32` components.
    pub fn point(&self, i: usize, count: u16) -> [f32; 3] {
        let range = self.counts.range_of(i64::from(count)) as f32;
        let [x, y, z] = self.rays[i];
        [x * range, y * range, z * range]
    }

    /// The count of range steps that gives exactly `p` at pixel `i`, if there is one. It runs for
    /// every point of every cloud the tape stores, so it is kept to a dot product and a truncation
    /// before the one comparison that nearly always settles it.
    pub fn count_of(&self, i: usize, p: [f32; 3]) -> Option<u16> {
        // A point on its ray is the ray times its range, so its projection on the unit ray is the
        // range, to within the f32 rounding the ±1 candidates absorb: no square root needed.
        let [rx, ry, rz] = self.rays[i].map(f64::from);
        let [x, y, z] = p.map(f64::from);
        let steps = self.counts.steps(x * rx + y * ry + z * rz) + 0.5;
        if !(0.0..f64::from(MAX_COUNT) + 1.0).contains(&steps) {
            return None;
        }
        let nearest = steps as u32; // truncation of a non-negative number + 0.5: rounding
        let same = |count: u32| {
            count <= MAX_COUNT && {
                let q = self.point(i, count as u16);
                q[0].to_bits() == p[0].to_bits()
                    && q[1].to_bits() == p[1].to_bits()
                    && q[2].to_bits() == p[2].to_bits()
            }
        };
        [nearest, nearest.wrapping_sub(1), nearest + 1]
            .into_iter()
            .find(|&c| same(c))
            .map(|c| c as u16)
    }
}
