//! A look's floor points binned on the floor plane, so that asking which of them lie in a small box
//! (inside one obstacle, between two pieces of one) costs the points near the box, not all 10⁵.

use nalgebra::Point2;
use nudge_perception::ColourCloud;

/// Side of the bins (m): about an obstacle's size, so a box query reads a few bins.
const BIN: f64 = 0.5;

/// Floor points (map frame, xy) by [`BIN`]-square bins over their bounding box, stored bin after
/// bin (a counting sort: two passes over the points, no hashing).
#[derive(Debug, Default)]
pub(super) struct FloorIndex {
    /// Lower corner of bin (0, 0).
    origin: Point2<f64>,
    /// Bins along x and y.
    size: (usize, usize),
    /// Bin `k`'s points are `points[start[k]..start[k + 1]]`.
    start: Vec<usize>,
    points: Vec<Point2<f64>>,
}

impl FloorIndex {
    /// Bins the valid points of `floor`.
    pub fn new(floor: &ColourCloud) -> Self {
        let xy: Vec<Point2<f64>> = floor
            .iter_valid()
            .map(|(_, p, _)| Point2::new(f64::from(p.x), f64::from(p.y)))
            .collect();
        let Some(first) = xy.first() else {
            return Self::default();
        };
        let (lo, hi) = xy.iter().fold((*first, *first), |(lo, hi), q| {
            (
                Point2::new(lo.x.min(q.x), lo.y.min(q.y)),
                Point2::new(hi.x.max(q.x), hi.y.max(q.y)),
            )
        });
        let size = (
            ((hi.x - lo.x) / BIN) as usize + 1,
            ((hi.y - lo.y) / BIN) as usize + 1,
        );
        let mut index = Self {
            origin: lo,
            size,
            start: vec![0; size.0 * size.1 + 1],
            points: vec![Point2::origin(); xy.len()],
        };
        let bins: Vec<usize> = xy.iter().map(|q| index.bin(q)).collect();
        for &k in &bins {
            index.start[k + 1] += 1;
        }
        for k in 0..size.0 * size.1 {
            index.start[k + 1] += index.start[k];
        }
        let mut next = index.start.clone();
        for (q, &k) in xy.iter().zip(&bins) {
            index.points[next[k]] = *q;
            next[k] += 1;
        }
        index
    }

    /// The points in the box `lo`..`hi` (edges included), bin by bin.
    pub fn in_box(&self, lo: Point2<f64>, hi: Point2<f64>) -> impl Iterator<Item = &Point2<f64>> {
        let (nx, ny) = self.size;
        let cell = |v: f64, o: f64, n: usize| (((v - o) / BIN).max(0.0) as usize).min(n.max(1) - 1);
        let empty = self.points.is_empty() || hi.x < lo.x || hi.y < lo.y;
        let (x0, x1) = (cell(lo.x, self.origin.x, nx), cell(hi.x, self.origin.x, nx));
        let (y0, y1) = (cell(lo.y, self.origin.y, ny), cell(hi.y, self.origin.y, ny));
        let rows = if empty { 0..0 } else { y0..y1 + 1 };
        rows.flat_map(move |y| {
            let (a, b) = (y * nx + x0, y * nx + x1);
            self.points[self.start[a]..self.start[b + 1]].iter()
        })
        .filter(move |q| q.x >= lo.x && q.y >= lo.y && q.x <= hi.x && q.y <= hi.y)
    }

    /// The bin of a point inside the bounding box.
    fn bin(&self, q: &Point2<f64>) -> usize {
        let x = (((q.x - self.origin.x) / BIN) as usize).min(self.size.0 - 1);
        let y = (((q.y - self.origin.y) / BIN) as usize).min(self.size.1 - 1);
        y * self.size.0 + x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Point3};
    use nudge_perception::CloudFrame;

    #[test]
    fn a_box_query_returns_exactly_the_points_in_the_box() {
        // Invariant: the points a box query returns are exactly those of the cloud inside the box, edges included, whichever bins they fall in (negative coordinates too).
        let mut cloud = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        let mut all = Vec::new();
        for i in -20..20 {
            for j in -20..20 {
                let p = Point2::new(f64::from(i) * 0.13, f64::from(j) * 0.07);
                cloud.push(Point3::new(p.x as f32, p.y as f32, 0.0), [1, 1, 1]);
                all.push(Point2::new(f64::from(p.x as f32), f64::from(p.y as f32)));
            }
        }
        let index = FloorIndex::new(&cloud);
        let (lo, hi) = (Point2::new(-1.0, -0.3), Point2::new(0.6, 0.9));
        let mut got: Vec<(i64, i64)> = index
            .in_box(lo, hi)
            .map(|q| ((q.x * 1e6) as i64, (q.y * 1e6) as i64))
            .collect();
        let mut want: Vec<(i64, i64)> = all
            .iter()
            .filter(|q| q.x >= lo.x && q.y >= lo.y && q.x <= hi.x && q.y <= hi.y)
            .map(|q| ((q.x * 1e6) as i64, (q.y * 1e6) as i64))
            .collect();
        got.sort_unstable();
        want.sort_unstable();
        assert!(!want.is_empty());
        assert_eq!(got, want);
    }
}
