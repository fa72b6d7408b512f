//! Range frames: what one sensor sweep tells the grid, reduced to 2D beams in the map frame.
//!
//! A [`RangeFrame`] is the sensor's position on the map plus a list of beams. Each beam ends either in
//! a *hit* (an obstacle point above the floor, projected to the plane) or is *clear* up to its end (no
//! obstacle along that bearing up to the range limit, or up to the farthest floor seen). The grid
//! traverses each beam from the sensor (Tamura 3.1's visible area).
//!
//! Three constructors: by hand ([`RangeFrame::push_hit`], [`RangeFrame::push_clear`]), from a classic
//! 2D laser scan ([`RangeFrame::from_laser_scan`]), and from an organised 3D colour cloud
//! ([`RangeFrame::from_cloud`]), which keeps per image column only the nearest obstacle return.

use nalgebra::{Point2, Vector2};

use super::GridError;
use crate::cloud::{CloudFrame, ColourCloud};

/// How a beam ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BeamEnd {
    /// An obstacle was returned at the end point.
    Hit,
    /// Nothing along the beam up to the end point (range limit or farthest floor seen).
    Clear,
}

/// One 2D beam in the map frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Beam {
    /// Where the beam ends (map frame, m).
    pub end: Point2<f64>,
    /// Whether it ends in an obstacle.
    pub kind: BeamEnd,
    /// Distance from the sensor (m) before which the beam proves no cell free: a camera tilted down
    /// sees nothing below its lowest ray, so a low obstacle close by can hide under it. Zero for a
    /// planar laser.
    pub seen_from: f64,
}

/// One sensor sweep as 2D beams from a sensor position, in the map frame.
#[derive(Clone, Debug, PartialEq)]
pub struct RangeFrame {
    sensor: Point2<f64>,
    beams: Vec<Beam>,
}

/// A classic planar laser scan (e.g. a SICK LMS291 or Hokuyo URG): ranges at evenly spaced bearings.
#[derive(Clone, Copy, Debug)]
pub struct LaserScan<'a> {
    /// Sensor position in the map frame (m).
    pub position: Point2<f64>,
    /// Sensor heading in the map frame (rad).
    pub yaw: f64,
    /// Bearing of the first range, relative to the heading (rad).
    pub angle_min: f64,
    /// Bearing step between ranges (rad).
    pub angle_increment: f64,
    /// The range limit `d_ul` (m): ranges at or beyond it, non-finite or non-positive mean no return.
    pub range_max: f64,
    /// Measured ranges (m).
    pub ranges: &'a [f32],
}

/// How an organised 3D cloud is reduced to one beam per image column.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColumnReduction {
    /// Points lower than this above the floor (z = 0 in the map) are floor: free space, not obstacles
    /// (m). Default 0.05 m: above sensor noise on the floor, below a chair's seat or a box's top.
    pub floor_band: f64,
    /// Points higher than this do not block the robot (m); default 1.54 m, the robot's height.
    pub max_height: f64,
    /// Points farther than this horizontally are ignored (m); a column with floor only is clear up to
    /// its farthest floor point, never beyond.
    pub range_max: f64,
    /// A column proves a cell free only where its lowest ray passes below this height (m): nearer
    /// the sensor, something lower could stand under the ray unseen. Default 0.4 m, under a chair's
    /// seat and a suitcase's top; lower things near the robot are left to perception's prisms, so a
    /// person's legs under the ray do not hide them from the moving rule. 0 asks for the floor.
    pub clear_height: f64,
}

impl Default for ColumnReduction {
    fn default() -> Self {
        Self {
            floor_band: 0.05,
            max_height: 1.54,
            range_max: 8.0,
            clear_height: 0.4,
        }
    }
}

impl RangeFrame {
    /// An empty frame seen from `sensor` (map frame); errors on a non-finite position.
    pub fn new(sensor: Point2<f64>) -> Result<Self, GridError> {
        if !(sensor.x.is_finite() && sensor.y.is_finite()) {
            return Err(GridError::NonFinite);
        }
        Ok(Self {
            sensor,
            beams: Vec::new(),
        })
    }

    /// An empty frame with room for `n` beams.
    pub fn with_capacity(sensor: Point2<f64>, n: usize) -> Result<Self, GridError> {
        let mut f = Self::new(sensor)?;
        f.beams.reserve(n);
        Ok(f)
    }

    /// Adds a return at `p` (map frame). Non-finite points are skipped (returns false).
    pub fn push_hit(&mut self, p: Point2<f64>) -> bool {
        self.push(p, BeamEnd::Hit)
    }

    /// Adds a beam with no return up to `p` (map frame). Non-finite points are skipped (returns false).
    pub fn push_clear(&mut self, p: Point2<f64>) -> bool {
        self.push(p, BeamEnd::Clear)
    }

    /// Adds a beam with no return along map-frame `bearing` (rad) up to `range` (m).
    pub fn push_no_return(&mut self, bearing: f64, range: f64) -> bool {
        let end = self.sensor + range * Vector2::new(bearing.cos(), bearing.sin());
        range >= 0.0 && self.push_clear(end)
    }

    fn push(&mut self, end: Point2<f64>, kind: BeamEnd) -> bool {
        self.push_beam(Beam {
            end,
            kind,
            seen_from: 0.0,
        })
    }

    /// Adds `beam`; one with a non-finite end or a negative or non-finite `seen_from` is skipped
    /// (returns false).
    pub fn push_beam(&mut self, beam: Beam) -> bool {
        let ok = beam.end.x.is_finite()
            && beam.end.y.is_finite()
            && beam.seen_from.is_finite()
            && beam.seen_from >= 0.0;
        if ok {
            self.beams.push(beam);
        }
        ok
    }

    /// The sensor position (map frame).
    pub fn sensor(&self) -> Point2<f64> {
        self.sensor
    }

    /// The beams.
    pub fn beams(&self) -> &[Beam] {
        &self.beams
    }

    /// Removes every beam and moves the sensor, keeping the allocation (for a reused frame buffer).
    pub fn reset(&mut self, sensor: Point2<f64>) -> Result<(), GridError> {
        if !(sensor.x.is_finite() && sensor.y.is_finite()) {
            return Err(GridError::NonFinite);
        }
        self.sensor = sensor;
        self.beams.clear();
        Ok(())
    }

    /// A frame from a planar laser scan (Tamura eq. 1): a range under the limit is a hit at
    /// `position + d·(cos(yaw+φ), sin(yaw+φ))`; no return (or a non-finite range) is a clear beam to the
    /// limit, as Tamura 3.1 prescribes for directions without data.
    pub fn from_laser_scan(scan: &LaserScan<'_>) -> Result<Self, GridError> {
        let finite = [
            scan.yaw,
            scan.angle_min,
            scan.angle_increment,
            scan.range_max,
        ]
        .iter()
        .all(|v| v.is_finite());
        if !finite || scan.range_max <= 0.0 {
            return Err(GridError::NonFinite);
        }
        let mut frame = Self::with_capacity(scan.position, scan.ranges.len())?;
        // Each beam's direction turned from the one before by the increment (a rotation: four
        // multiplications), taken afresh from its bearing every `ANCHOR` beams so that rounding
        // cannot build up (it stays within 1e-14): a sine and a cosine per beam cost as much as
        // a twentieth of the whole scan's update.
        const ANCHOR: usize = 32;
        let turn = Vector2::new(scan.angle_increment.cos(), scan.angle_increment.sin());
        let mut dir = Vector2::zeros();
        for (i, &r) in scan.ranges.iter().enumerate() {
            dir = if i % ANCHOR == 0 {
                let bearing = scan.yaw + scan.angle_min + i as f64 * scan.angle_increment;
                Vector2::new(bearing.cos(), bearing.sin())
            } else {
                Vector2::new(
                    dir.x * turn.x - dir.y * turn.y,
                    dir.x * turn.y + dir.y * turn.x,
                )
            };
            let d = f64::from(r);
            if d.is_finite() && d > 0.0 && d < scan.range_max {
                frame.push_hit(scan.position + d * dir);
            } else {
                frame.push_clear(scan.position + scan.range_max * dir);
            }
        }
        Ok(frame)
    }

    /// A frame from an organised colour cloud: one beam per image column.
    ///
    /// Why per column: with the camera level in roll, an image column is a vertical fan of rays in one
    /// vertical plane through the sensor, so all its points share (nearly) one map bearing. The robot
    /// can only be blocked by the *nearest* obstacle point in that plane between the floor band and its
    /// own height; everything behind it along the bearing is unobserved in 2D anyway. Keeping that
    /// point (and, for a column with floor only, a clear beam to its farthest floor point) turns a
    /// 176 × 144 frame (25 344 points) into ≤ 176 beams, so the grid update traverses ~176 rays instead
    /// of 25 000 — the step that keeps a frame under a millisecond. Floor points never block; points
    /// above `max_height` neither block nor prove free space (the robot could pass under them, but a
    /// table top at 0.72 m is within its height and blocks). A column with no valid point adds no beam.
    ///
    /// Works for clouds in the sensor frame (transformed by `sensor_pose`) or already in the map frame.
    /// Errors on an unorganised cloud or a non-finite pose.
    pub fn from_cloud(cloud: &ColourCloud, cfg: &ColumnReduction) -> Result<Self, GridError> {
        if !cloud.is_organised() {
            return Err(GridError::NotOrganised);
        }
        let pose = cloud.sensor_pose();
        let t = pose.translation.vector;
        let sensor = Point2::new(t.x, t.y);
        let mut frame = Self::with_capacity(sensor, cloud.width())?;
        // A rotation matrix (9 multiply-adds per point) rather than the quaternion: this loop runs
        // over every pixel.
        let (rot, shift) = match cloud.frame() {
            CloudFrame::Sensor => {
                let p = pose.cast::<f32>();
                (
                    p.rotation.to_rotation_matrix().into_inner(),
                    p.translation.vector,
                )
            }
            CloudFrame::Map => (nalgebra::Matrix3::identity(), nalgebra::Vector3::zeros()),
        };
        let (sx, sy) = (t.x as f32, t.y as f32);
        let (floor, top) = (cfg.floor_band as f32, cfg.max_height as f32);
        // Share of the way to a column's nearest floor point after which its lowest ray is below
        // `clear_height` (none when the sensor itself is that low).
        let clear_fraction = if t.z > cfg.clear_height {
            1.0 - cfg.clear_height / t.z
        } else {
            0.0
        };
        let r2_max = (cfg.range_max * cfg.range_max) as f32;
        let (w, h) = (cloud.width(), cloud.height());
        let (xs, ys, zs) = (cloud.xs(), cloud.ys(), cloud.zs());
        for u in 0..w {
            // Nearest obstacle (squared horizontal distance, point), nearest and farthest floor in this
            // column.
            let mut nearest: Option<(f32, f32, f32)> = None;
            let mut farthest_floor: Option<(f32, f32, f32)> = None;
            let mut nearest_floor = f32::INFINITY;
            for v in 0..h {
                let i = v * w + u;
                let p = rot * nalgebra::Vector3::new(xs[i], ys[i], zs[i]) + shift;
                if !(p.x.is_finite() && p.y.is_finite() && p.z.is_finite()) {
                    continue;
                }
                let (dx, dy) = (p.x - sx, p.y - sy);
                let r2 = dx * dx + dy * dy;
                if r2 > r2_max {
                    continue;
                }
                if p.z < floor {
                    nearest_floor = nearest_floor.min(r2);
                    if farthest_floor.is_none_or(|(d, _, _)| r2 > d) {
                        farthest_floor = Some((r2, p.x, p.y));
                    }
                } else if p.z <= top && nearest.is_none_or(|(d, _, _)| r2 < d) {
                    nearest = Some((r2, p.x, p.y));
                }
            }
            // Below its lowest ray the column saw nothing. That ray meets the floor at the nearest
            // floor point; it has come down to `clear_height` a fraction (1 − clear_height / sensor
            // height) of the way there, and only from there on is the way known to be clear at every
            // height from `clear_height` to the sensor's.
            let (end, kind, end_r2) = match (nearest, farthest_floor) {
                (Some((r2, x, y)), _) => (Point2::new(x, y), BeamEnd::Hit, r2),
                (None, Some((r2, x, y))) => (Point2::new(x, y), BeamEnd::Clear, r2),
                (None, None) => continue,
            };
            let lowest_ray_down = f64::from(nearest_floor.sqrt()) * clear_fraction;
            frame.push_beam(Beam {
                end: end.cast::<f64>(),
                kind,
                seen_from: lowest_ray_down.min(f64::from(end_r2.sqrt())),
            });
        }
        Ok(frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};

    #[test]
    fn every_laser_beam_lies_on_its_own_bearing() {
        // Invariant: beam i of a long scan ends at position + range·(cos, sin)(yaw + min + i·inc)
        // within 1e-12 m, however far the turned directions run from their last fresh bearing.
        let ranges = vec![29.9_f32; 1081];
        let scan = LaserScan {
            position: Point2::new(-3.0, 7.5),
            yaw: 2.9,
            angle_min: -135_f64.to_radians(),
            angle_increment: 0.25_f64.to_radians(),
            range_max: 30.0,
            ranges: &ranges,
        };
        let f = RangeFrame::from_laser_scan(&scan).expect("valid scan");
        assert_eq!(f.beams().len(), ranges.len());
        for (i, b) in f.beams().iter().enumerate() {
            let bearing = scan.yaw + scan.angle_min + i as f64 * scan.angle_increment;
            let want = scan.position + 29.9_f32 as f64 * Vector2::new(bearing.cos(), bearing.sin());
            assert!(
                (b.end - want).norm() < 1e-12,
                "beam {i}: {:?} vs {want:?}",
                b.end
            );
        }
    }

    #[test]
    fn laser_scan_turns_no_return_into_clear_beams_to_the_limit() {
        // Invariant: ranges under the limit are hits at eq. (1); others are clear to the limit.
        let ranges = [1.0_f32, f32::INFINITY, 10.0, f32::NAN];
        let scan = LaserScan {
            position: Point2::new(1.0, 2.0),
            yaw: std::f64::consts::FRAC_PI_2,
            angle_min: 0.0,
            angle_increment: std::f64::consts::FRAC_PI_2,
            range_max: 4.0,
            ranges: &ranges,
        };
        let f = RangeFrame::from_laser_scan(&scan).expect("valid scan");
        let b = f.beams();
        assert_eq!(b.len(), 4);
        assert_eq!(b[0].kind, BeamEnd::Hit);
        assert!((b[0].end - Point2::new(1.0, 3.0)).norm() < 1e-12);
        assert_eq!(b[1].kind, BeamEnd::Clear);
        assert!((b[1].end - Point2::new(-3.0, 2.0)).norm() < 1e-12);
        assert!(b[2..].iter().all(|b| b.kind == BeamEnd::Clear));
    }

    #[test]
    fn cloud_column_keeps_the_nearest_obstacle_above_the_floor_band() {
        // Invariant: per column, floor points and points above the robot never block; the nearest
        // point in between is the hit; a floor-only column is clear to its farthest floor point.
        let pose =
            Isometry3::from_parts(Translation3::new(1.0, 0.0, 1.4), UnitQuaternion::identity());
        // 2 columns × 3 rows, sensor frame (x forward). Column 0: floor at 2 m, box at 3 m, lamp at 1 m
        // above the robot. Column 1: floor at 1.5 m and 2.5 m only.
        let x = vec![2.0, 2.5, 3.0, 1.5, 1.0, 2.5];
        let y = vec![0.0, 0.5, 0.0, 0.5, 0.0, 0.5];
        let z = vec![-1.39, -1.38, -1.0, 0.5, -1.40, -1.38];
        let cloud = ColourCloud::organised(
            2,
            3,
            x,
            y,
            z,
            vec![[0; 3]; 6],
            CloudFrame::Sensor,
            pose,
            0.0,
        )
        .expect("consistent arrays");
        let f = RangeFrame::from_cloud(&cloud, &ColumnReduction::default()).expect("organised");
        assert_eq!(f.beams().len(), 2);
        assert_eq!(f.beams()[0].kind, BeamEnd::Hit);
        assert!((f.beams()[0].end - Point2::new(4.0, 0.0)).norm() < 1e-6);
        assert_eq!(f.beams()[1].kind, BeamEnd::Clear);
        assert!((f.beams()[1].end - Point2::new(3.5, 0.5)).norm() < 1e-6);
    }

    #[test]
    fn a_column_proves_cells_free_only_where_its_lowest_ray_is_below_the_clear_height() {
        // Invariant: a camera column's beam proves cells free only where its lowest ray has come down
        // below the clear height (an obstacle under the ray nearer the sensor stays unknown), and a
        // grid fed that beam leaves the near cells untouched while the far ones turn Free.
        let pose =
            Isometry3::from_parts(Translation3::new(0.0, 0.0, 1.4), UnitQuaternion::identity());
        // One column: floor seen at 2 m and 4 m only (the lowest ray meets the floor at 2 m).
        let cloud = ColourCloud::organised(
            1,
            2,
            vec![2.0, 4.0],
            vec![0.0, 0.0],
            vec![-1.39, -1.39],
            vec![[0; 3]; 2],
            CloudFrame::Sensor,
            pose,
            0.0,
        )
        .expect("consistent arrays");
        let f = RangeFrame::from_cloud(&cloud, &ColumnReduction::default()).expect("organised");
        assert_eq!(f.beams().len(), 1);
        // The lowest ray falls 1.39 m over 2 m: below 0.4 m after 2 × (1 − 0.4 / 1.4) m.
        let expected = 2.0 * (1.0 - 0.4 / 1.4);
        assert!((f.beams()[0].seen_from - expected).abs() < 1e-6);
        let mut grid =
            crate::grid::ObstacleGrid::from_extent(Point2::new(-1.0, -1.0), [6.0, 2.0], 0.1)
                .expect("valid grid");
        grid.update(&f, 0.0).expect("in order");
        let class = |x: f64| grid.class_at(Point2::new(x, 0.05)).expect("inside");
        assert_eq!(
            class(1.0),
            crate::grid::CellClass::Unknown,
            "under the lowest ray"
        );
        assert_eq!(
            class(3.0),
            crate::grid::CellClass::Free,
            "between floor points"
        );
    }

    #[test]
    fn unorganised_cloud_and_bad_positions_are_errors() {
        // Invariant: inputs the reduction cannot use give errors, not panics.
        let c = ColourCloud::empty(CloudFrame::Sensor, Isometry3::identity(), 0.0);
        assert!(RangeFrame::from_cloud(&c, &ColumnReduction::default()).is_err());
        assert!(RangeFrame::new(Point2::new(f64::NAN, 0.0)).is_err());
        let mut f = RangeFrame::new(Point2::new(0.0, 0.0)).expect("finite");
        assert!(!f.push_hit(Point2::new(f64::INFINITY, 0.0)));
        assert!(f.beams().is_empty());
    }
}
