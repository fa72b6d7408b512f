//! What the run has not seen, and which of it matters to the decision at hand.
//!
//! A grid cell is *seen* once a ray crossed it or a return landed in it (the obstacle-type grid
//! keeps that), once a look-around's points landed in it (its steep views, which the grid leaves out,
//! see the floor near the robot), or once the robot's body covered it (no camera sees under the robot,
//! but it stood there). An unseen cell stays *open* until looks that were predicted to show it failed to
//! [`MAX_FAILED_LOOKS`] times: then it is taken for the inside of an object or floor hidden from
//! everywhere the robot can go, and no longer asked about.
//!
//! Each [`Question`](crate::view::Question) names its own cells: the unseen floor under the path
//! ahead, around and under an object to push, or inside the outlines that close the way.

use nalgebra::{Point2, Vector2};
use nudge_motion::SeenFloor;
use nudge_perception::grid::{CellIndex, GridGeometry, ObstacleGrid};
use nudge_perception::{ColourCloud, Prism};

use crate::view::{UnseenRegion, UnseenWhy};

/// Looks predicted to show a cell that may fail before the cell is no longer asked about: one may
/// fail because something not yet seen stood in the way (the prediction sees through unseen floor);
/// a second, from a place chosen with that obstacle known, means the cell cannot be seen.
pub(crate) const MAX_FAILED_LOOKS: u8 = 2;

/// The run's memory of what it has seen, over the obstacle-type grid's cells.
#[derive(Clone, Debug, Default)]
pub(crate) struct SeenMemory {
    /// Bit `i % 64` of word `i / 64`: cell `i` was seen other than by the grid's frames (a look's
    /// points landed in it, or the robot's body covered it).
    pub seen: Vec<u64>,
    /// Per cell: looks predicted to show it that did not.
    pub failed_looks: Vec<u8>,
    /// Per cell, when a frame's floor returns last landed in it, as robot time let pass
    /// ([`super::watchdog::Watchdog::elapsed`], NaN: never). Floor seen in a cell proves that
    /// nothing stood on that spot then, at any height: what the grid's Free cells cannot prove below
    /// the lowest ray's clearing height (see `ColumnReduction::clear_height`).
    pub floor_seen: Vec<f64>,
}

impl SeenMemory {
    /// An empty memory for a grid of `n` cells.
    pub fn new(n: usize) -> Self {
        Self {
            seen: vec![0; n.div_ceil(64)],
            failed_looks: vec![0; n],
            floor_seen: vec![f64::NAN; n],
        }
    }

    /// Marks the cells under a disc of `radius` at `centre` as seen (the robot stands there).
    pub fn tread(&mut self, geometry: &GridGeometry, centre: Point2<f64>, radius: f64) {
        for_cells_in_disc(geometry, centre, radius, |i| self.mark(i));
    }

    /// Marks the cells holding `points` (map frame) as seen.
    pub fn saw(&mut self, geometry: &GridGeometry, points: &ColourCloud) {
        // A look holds some 10⁵ floor points: a run of points in one cell (neighbouring pixels)
        // marks it once.
        let cells = CellLookup::new(geometry);
        let mut last = usize::MAX;
        for (x, y) in points.xs().iter().zip(points.ys()) {
            if let Some(i) = cells.index(*x, *y)
                && i != last
            {
                self.mark(i);
                last = i;
            }
        }
    }

    /// Notes `now` (robot time let pass) as when floor was last seen in the cells holding the
    /// points of `cloud` lower than `floor_band` above the map's floor (z = 0): the grid's own test
    /// for floor (`ColumnReduction::floor_band`).
    pub fn saw_floor(
        &mut self,
        geometry: &GridGeometry,
        cloud: &ColourCloud,
        floor_band: f64,
        now: f64,
    ) {
        let pose = cloud.sensor_pose().cast::<f32>();
        // A rotation matrix rather than the quaternion: this runs over every pixel of every frame.
        let (rot, shift) = match cloud.frame() {
            nudge_perception::CloudFrame::Sensor => (
                pose.rotation.to_rotation_matrix().into_inner(),
                pose.translation.vector,
            ),
            nudge_perception::CloudFrame::Map => {
                (nalgebra::Matrix3::identity(), nalgebra::Vector3::zeros())
            }
        };
        let cells = CellLookup::new(geometry);
        let band = floor_band as f32;
        let mut last = usize::MAX;
        let (rx, ry, rz) = (rot.row(0), rot.row(1), rot.row(2));
        for ((x, y), z) in cloud.xs().iter().zip(cloud.ys()).zip(cloud.zs()) {
            let v = nalgebra::Vector3::new(*x, *y, *z);
            // Height first: most of a frame is not floor. A slot with no return is NaN.
            let height = rz.dot(&v.transpose()) + shift.z;
            if height.is_nan() || height >= band {
                continue;
            }
            let (mx, my) = (
                rx.dot(&v.transpose()) + shift.x,
                ry.dot(&v.transpose()) + shift.y,
            );
            if let Some(i) = cells.index(mx, my)
                && i != last
            {
                if let Some(t) = self.floor_seen.get_mut(i) {
                    *t = now;
                }
                last = i;
            }
        }
    }

    fn mark(&mut self, i: usize) {
        if let Some(w) = self.seen.get_mut(i / 64) {
            *w |= 1 << (i % 64);
        }
    }

    /// Whether cell `i` was seen other than by the grid's frames.
    fn marked(&self, i: usize) -> bool {
        self.seen
            .get(i / 64)
            .is_some_and(|w| w & (1 << (i % 64)) != 0)
    }

    /// Counts a failed look for every cell of `predicted` that `grid` still has not seen.
    pub fn fail_unseen(&mut self, grid: &ObstacleGrid, predicted: &[usize]) {
        for &i in predicted {
            if !self.seen(grid, i)
                && let Some(n) = self.failed_looks.get_mut(i)
            {
                *n = n.saturating_add(1);
            }
        }
    }

    /// Whether cell `i` was seen (by the grid's frames, a look's points, or the robot's body).
    pub fn seen(&self, grid: &ObstacleGrid, i: usize) -> bool {
        self.marked(i)
            || grid
                .observed_words()
                .get(i / 64)
                .is_some_and(|w| w & (1 << (i % 64)) != 0)
    }

    /// Whether cell `i` is unseen and still worth a look.
    pub fn open(&self, grid: &ObstacleGrid, i: usize) -> bool {
        !self.seen(grid, i) && self.failed_looks.get(i).copied().unwrap_or(0) < MAX_FAILED_LOOKS
    }

    /// Why an unseen cell is no longer asked about, or `None` while it is open.
    pub fn why(&self, i: usize) -> UnseenWhy {
        match self.failed_looks.get(i).copied().unwrap_or(0) {
            0 => UnseenWhy::NoViewpoint,
            n => UnseenWhy::LookedAt(u32::from(n)),
        }
    }
}

/// The grid cell of a map point by one multiplication per coordinate: what runs over every point of
/// a look or a frame.
struct CellLookup {
    origin: Point2<f64>,
    inverse: f64,
    width: i64,
    height: i64,
}

impl CellLookup {
    fn new(geometry: &GridGeometry) -> Self {
        Self {
            origin: geometry.origin(),
            inverse: 1.0 / geometry.resolution(),
            width: geometry.width() as i64,
            height: geometry.height() as i64,
        }
    }

    /// The index of the cell holding (`x`, `y`); `None` off the grid or for a non-finite point.
    fn index(&self, x: f32, y: f32) -> Option<usize> {
        let fx = (f64::from(x) - self.origin.x) * self.inverse;
        let fy = (f64::from(y) - self.origin.y) * self.inverse;
        // Off the grid's low edges (or NaN) first: above them, truncation is the floor.
        if !(fx >= 0.0 && fy >= 0.0) {
            return None;
        }
        let (cx, cy) = (fx as i64, fy as i64);
        (cx < self.width && cy < self.height).then(|| (cy * self.width + cx) as usize)
    }
}

/// The floor seen so far, for push planning: observed by the camera or trodden.
pub(crate) struct Floor<'a> {
    /// The grid.
    pub grid: &'a ObstacleGrid,
    /// The run's memory.
    pub memory: &'a SeenMemory,
}

impl SeenFloor for Floor<'_> {
    fn seen(&self, p: &Point2<f64>) -> bool {
        let g = self.grid.geometry();
        g.cell_of(*p)
            .and_then(|c| g.index(c))
            // Outside the grid nothing was seen.
            .is_some_and(|i| self.memory.seen(self.grid, i))
    }
}

/// Calls `each` with the index of every grid cell whose centre lies within `radius` of `centre`.
pub(crate) fn for_cells_in_disc(
    geometry: &GridGeometry,
    centre: Point2<f64>,
    radius: f64,
    mut each: impl FnMut(usize),
) {
    let r = Vector2::repeat(radius);
    let (Some(a), Some(b)) = (
        clamp_cell(geometry, centre - r),
        clamp_cell(geometry, centre + r),
    ) else {
        return;
    };
    for y in a.y..=b.y {
        for x in a.x..=b.x {
            let c = CellIndex::new(x, y);
            if (geometry.centre(c) - centre).norm() <= radius
                && let Some(i) = geometry.index(c)
            {
                each(i);
            }
        }
    }
}

/// The cell holding `p`, or the nearest cell of the grid to it.
fn clamp_cell(geometry: &GridGeometry, p: Point2<f64>) -> Option<CellIndex> {
    let o = geometry.origin();
    let res = geometry.resolution();
    let far = Point2::new(
        o.x + (geometry.width() as f64 - 0.5) * res,
        o.y + (geometry.height() as f64 - 0.5) * res,
    );
    geometry.cell_of(p.sup(&(o + Vector2::repeat(0.5 * res))).inf(&far))
}

/// Whether `p` lies inside any of `prisms`' footprints.
pub(crate) fn inside_any(prisms: &[Prism], p: &Point2<f64>) -> bool {
    prisms.iter().any(|q| q.contains_xy(p))
}

/// Points every `step` along the polyline `path` from its start, each with its distance along it.
fn along(path: &[Point2<f64>], step: f64) -> impl Iterator<Item = (f64, Point2<f64>)> + '_ {
    let mut walked = 0.0;
    path.windows(2).flat_map(move |w| {
        let (a, b) = (w[0], w[1]);
        let len = (b - a).norm();
        let n = (len / step).ceil().max(1.0) as usize;
        let start = walked;
        walked += len;
        (0..n).map(move |k| {
            let t = k as f64 / n as f64;
            (start + t * len, a + (b - a) * t)
        })
    })
}

/// The point `distance` along `path` (its last point past the end, the origin for an empty one).
pub(crate) fn point_along(path: &[Point2<f64>], distance: f64) -> Point2<f64> {
    let mut left = distance.max(0.0);
    for w in path.windows(2) {
        let len = (w[1] - w[0]).norm();
        if left <= len && len > 0.0 {
            return w[0] + (w[1] - w[0]) * (left / len);
        }
        left -= len;
    }
    path.last().copied().unwrap_or_else(Point2::origin)
}

/// Distance from `p` to the polyline `path` (infinite for an empty one; a single point's distance
/// for one point).
pub(crate) fn distance_to_path(path: &[Point2<f64>], p: &Point2<f64>) -> f64 {
    if let [only] = path {
        return (only - p).norm();
    }
    path.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let ab = b - a;
            let t = if ab.norm_squared() > 0.0 {
                ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + ab * t - p).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The part of `path` from the point nearest `here` on (with `here` as its first point).
pub(crate) fn rest_of_path(path: &[Point2<f64>], here: Point2<f64>) -> Vec<Point2<f64>> {
    let mut best = (f64::INFINITY, 0usize);
    for (k, w) in path.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let ab = b - a;
        let t = if ab.norm_squared() > 0.0 {
            ((here - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let d = (a + ab * t - here).norm();
        if d < best.0 {
            best = (d, k);
        }
    }
    let mut out = vec![here];
    out.extend(path.iter().skip(best.1 + 1).copied());
    out
}

/// Distance along `path` (from its start) at which the open unseen cells within `band` of it,
/// counted from `near` on, first add up to `min_area` (m²), looked for up to `far`; cells inside
/// obstacles are not floor the robot would stand on.
pub(crate) fn first_unseen_along(
    grid: &ObstacleGrid,
    memory: &SeenMemory,
    prisms: &[Prism],
    path: &[Point2<f64>],
    (near, far): (f64, f64),
    band: f64,
    min_area: f64,
) -> Option<f64> {
    let geometry = grid.geometry();
    let cell_area = geometry.resolution() * geometry.resolution();
    let step = 0.5 * geometry.resolution();
    let mut counted: Vec<usize> = Vec::new();
    for (s, p) in along(path, step) {
        if s < near {
            continue;
        }
        if s > far {
            break;
        }
        for_cells_in_disc(geometry, p, band, |i| {
            if memory.open(grid, i)
                && !counted.contains(&i)
                && geometry
                    .cell_at(i)
                    .is_some_and(|c| !inside_any(prisms, &geometry.centre(c)))
            {
                counted.push(i);
            }
        });
        if counted.len() as f64 * cell_area >= min_area {
            return Some(s);
        }
    }
    None
}

/// The open unseen cells within `band` of `path` up to `horizon` along it, outside obstacles, sorted.
pub(crate) fn unseen_along(
    grid: &ObstacleGrid,
    memory: &SeenMemory,
    prisms: &[Prism],
    path: &[Point2<f64>],
    band: f64,
    horizon: f64,
) -> Vec<usize> {
    let geometry = grid.geometry();
    let mut cells = Vec::new();
    for (s, p) in along(path, 0.5 * geometry.resolution()) {
        if s > horizon {
            break;
        }
        for_cells_in_disc(geometry, p, band, |i| {
            if memory.open(grid, i) {
                cells.push(i);
            }
        });
    }
    cells.sort_unstable();
    cells.dedup();
    cells.retain(|&i| {
        geometry
            .cell_at(i)
            .is_some_and(|c| !inside_any(prisms, &geometry.centre(c)))
    });
    cells
}

/// The open unseen cells within `ring` of `prism`'s footprint and outside every obstacle (its own
/// inside is never seen, nor anything else's): where the robot would stand to push it and where it
/// would go, and beyond its hidden sides.
pub(crate) fn unseen_around(
    grid: &ObstacleGrid,
    memory: &SeenMemory,
    prism: &Prism,
    prisms: &[Prism],
    ring: f64,
) -> Vec<usize> {
    let geometry = grid.geometry();
    let Some(first) = prism.footprint.first() else {
        return Vec::new();
    };
    let (lo, hi) = prism
        .footprint
        .iter()
        .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
    let centre = nalgebra::center(&lo, &hi);
    let reach = (hi - lo).norm() / 2.0 + ring;
    let Ok(outline) = nudge_motion::Obstacle::from_prism(prism) else {
        return Vec::new();
    };
    let mut cells = Vec::new();
    for_cells_in_disc(geometry, centre, reach, |i| {
        if !memory.open(grid, i) {
            return;
        }
        let Some(c) = geometry.cell_at(i) else {
            return;
        };
        let p = geometry.centre(c);
        if outline.distance_to_point(&p) <= ring && !inside_any(prisms, &p) {
            cells.push(i);
        }
    });
    cells.sort_unstable();
    cells
}

/// The unseen cells (outside obstacles) within `radius` of `goal`, sorted: the goal region's floor
/// nobody has seen. Empty when it was seen.
pub(crate) fn unseen_around_goal(
    grid: &ObstacleGrid,
    memory: &SeenMemory,
    prisms: &[Prism],
    goal: Point2<f64>,
    radius: f64,
) -> Vec<usize> {
    let geometry = grid.geometry();
    let mut cells = Vec::new();
    for_cells_in_disc(geometry, goal, radius, |i| {
        if !memory.seen(grid, i)
            && geometry
                .cell_at(i)
                .is_some_and(|c| !inside_any(prisms, &geometry.centre(c)))
        {
            cells.push(i);
        }
    });
    cells.sort_unstable();
    cells
}

/// The 8-connected regions of `cells` (sorted grid indices), largest first, each with `why`.
pub(crate) fn regions(
    geometry: &GridGeometry,
    cells: &[usize],
    why: impl Fn(usize) -> UnseenWhy,
) -> Vec<UnseenRegion> {
    let member = |i: usize| cells.binary_search(&i).is_ok();
    let mut done = vec![false; cells.len()];
    let mut out = Vec::new();
    let area = geometry.resolution() * geometry.resolution();
    for start in 0..cells.len() {
        if done[start] {
            continue;
        }
        done[start] = true;
        let mut stack = vec![cells[start]];
        let mut members = Vec::new();
        while let Some(i) = stack.pop() {
            members.push(i);
            let Some(c) = geometry.cell_at(i) else {
                continue;
            };
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let (x, y) = (i64::from(c.x) + dx, i64::from(c.y) + dy);
                    if x < 0 || y < 0 {
                        continue;
                    }
                    let Some(j) = geometry.index(CellIndex::new(x as u32, y as u32)) else {
                        continue;
                    };
                    if let Ok(k) = cells.binary_search(&j)
                        && !done[k]
                        && member(j)
                    {
                        done[k] = true;
                        stack.push(j);
                    }
                }
            }
        }
        let points: Vec<Point2<f64>> = members
            .iter()
            .filter_map(|&i| geometry.cell_at(i).map(|c| geometry.centre(c)))
            .collect();
        let Some(first) = points.first() else {
            continue;
        };
        let (lo, hi) = points
            .iter()
            .fold((*first, *first), |(lo, hi), p| (lo.inf(p), hi.sup(p)));
        let sum = points.iter().fold(Vector2::zeros(), |s, p| s + p.coords);
        let half = Vector2::repeat(geometry.resolution() / 2.0);
        // The most frequent reason among its cells stands for the region.
        let mut reasons: Vec<UnseenWhy> = members.iter().map(|&i| why(i)).collect();
        reasons.sort_by_key(|w| match w {
            UnseenWhy::NoViewpoint | UnseenWhy::BehindObstacles => 0u32,
            UnseenWhy::LookedAt(n) => *n,
            UnseenWhy::ViewLimit => u32::MAX,
        });
        let why = reasons[reasons.len() / 2];
        out.push(UnseenRegion {
            centre: Point2::from(sum / points.len() as f64),
            bounds: (lo - half, hi + half),
            area: members.len() as f64 * area,
            why,
        });
    }
    out.sort_by(|a, b| b.area.total_cmp(&a.area));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runner::world::tests::box_prism;

    fn geometry() -> GridGeometry {
        GridGeometry::new(Point2::origin(), [2.0, 1.0], 0.05).expect("a grid")
    }

    #[test]
    fn unseen_cells_split_into_connected_regions_largest_first() {
        // Invariant: 8-connected cells form one region (diagonal neighbours included), separate blobs are separate regions, the largest comes first, and the area is the cells' count times a cell's area.
        let g = geometry();
        let idx = |x: u32, y: u32| g.index(CellIndex::new(x, y)).expect("in the grid");
        let mut cells = vec![idx(1, 1), idx(2, 2), idx(3, 3), idx(30, 10), idx(31, 10)];
        cells.extend((0..5).map(|k| idx(10 + k, 5)));
        cells.sort_unstable();
        let r = regions(&g, &cells, |_| UnseenWhy::NoViewpoint);
        assert_eq!(r.len(), 3);
        assert!((r[0].area - 5.0 * 0.0025).abs() < 1e-12);
        assert!((r[1].area - 3.0 * 0.0025).abs() < 1e-12);
        assert!((r[2].area - 2.0 * 0.0025).abs() < 1e-12);
        assert!((r[0].centre - Point2::new(0.625, 0.275)).norm() < 1e-9);
    }

    #[test]
    fn the_rest_of_a_path_starts_where_the_robot_is() {
        // Invariant: the rest of a path starts at the robot and goes on from the segment nearest it.
        let path = [
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(1.0, 1.0),
        ];
        let rest = rest_of_path(&path, Point2::new(1.02, 0.5));
        assert_eq!(rest, vec![Point2::new(1.02, 0.5), Point2::new(1.0, 1.0)]);
        let samples: Vec<(f64, Point2<f64>)> = along(&path, 0.5).collect();
        assert_eq!(samples.len(), 4);
        assert!((samples[3].0 - 1.5).abs() < 1e-12);
    }

    /// A 4 × 2 m grid with a memory that has seen every cell but those for which `unseen` holds.
    fn seen_but(unseen: impl Fn(Point2<f64>) -> bool) -> (ObstacleGrid, SeenMemory) {
        let geometry = GridGeometry::new(Point2::origin(), [4.0, 2.0], 0.05).expect("a grid");
        let grid = ObstacleGrid::new(geometry, nudge_perception::grid::GridConfig::default());
        let mut memory = SeenMemory::new(geometry.len());
        for i in 0..geometry.len() {
            let c = geometry.cell_at(i).expect("a cell");
            if !unseen(geometry.centre(c)) {
                memory.mark(i);
            }
        }
        (grid, memory)
    }

    #[test]
    fn a_walk_stops_only_for_a_strip_of_unseen_floor_across_its_way() {
        // Invariant: unseen floor under the path counts once it adds up to the least area worth a look (here 0.035 m²), between the near and far distances only; a lone unseen cell or unseen floor beside the band does not count.
        let path = [Point2::new(0.5, 1.0), Point2::new(3.5, 1.0)];
        let ask = |grid: &ObstacleGrid, memory: &SeenMemory, window: (f64, f64)| {
            first_unseen_along(grid, memory, &[], &path, window, 0.175, 0.035)
        };
        let (grid, memory) = seen_but(|p| (p - Point2::new(2.0, 1.0)).norm() < 0.03);
        assert_eq!(ask(&grid, &memory, (0.0, 3.0)), None);
        let (grid, memory) = seen_but(|p| (p.y - 1.6).abs() < 0.2);
        assert_eq!(ask(&grid, &memory, (0.0, 3.0)), None);
        let strip = |p: Point2<f64>| (2.0..2.15).contains(&p.x);
        let (grid, memory) = seen_but(strip);
        let at = ask(&grid, &memory, (0.0, 3.0)).expect("a strip across the way");
        assert!((1.3..1.85).contains(&at), "{at}");
        assert_eq!(ask(&grid, &memory, (0.0, 1.0)), None);
        assert_eq!(ask(&grid, &memory, (1.9, 3.0)), None);
    }

    #[test]
    fn the_floor_that_matters_to_a_push_leaves_out_the_insides_of_obstacles() {
        // Invariant: the unseen floor around an object to push lies within the ring of its footprint and outside every obstacle, its own inside and its neighbour's included.
        let (grid, memory) = seen_but(|p| p.x > 1.0);
        let object = box_prism(1, (1.5, 0.8, 2.0, 1.3), 0.8);
        let beside = box_prism(2, (2.3, 0.8, 2.8, 1.3), 0.8);
        let cells = unseen_around(
            &grid,
            &memory,
            &object,
            &[object.clone(), beside.clone()],
            0.5,
        );
        assert!(!cells.is_empty());
        let geometry = grid.geometry();
        for &i in &cells {
            let p = geometry.centre(geometry.cell_at(i).expect("a cell"));
            assert!(!object.contains_xy(&p) && !beside.contains_xy(&p), "{p}");
            let outline = nudge_motion::Obstacle::from_prism(&object).expect("an outline");
            assert!(outline.distance_to_point(&p) <= 0.5 + 1e-9, "{p}");
        }
    }

    #[test]
    fn a_cell_two_looks_failed_to_show_is_given_up() {
        // Invariant: an unseen cell stays open after one look predicted to show it failed, and is given up after the second, with the count as its reason; a cell seen meanwhile is not counted.
        let (grid, mut memory) = seen_but(|p| p.x < 0.2);
        let unseen = 0;
        let seen = grid.geometry().len() - 1;
        memory.fail_unseen(&grid, &[unseen, seen]);
        assert!(memory.open(&grid, unseen));
        assert_eq!(memory.failed_looks[seen], 0);
        memory.fail_unseen(&grid, &[unseen]);
        assert!(!memory.open(&grid, unseen));
        assert_eq!(memory.why(unseen), UnseenWhy::LookedAt(2));
    }
}
