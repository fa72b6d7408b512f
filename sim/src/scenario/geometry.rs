//! Shapes of the scenario's things in the map frame: footprints, heights, poses.
//!
//! Degrees and `Vec<f64>` sizes are how people write files; these helpers turn them into nalgebra
//! values in SI units so nobody converts twice.

use std::fmt;

use nalgebra::{Isometry2, Point2, Rotation2, Vector2, Vector3};

use super::{ActorSpec, Goal, ObjectKind, ObjectSpec, RobotSpec, Room, Scenario};

/// Corners of a circumscribed polygon standing in for a disc in [`Footprint::polygon`].
pub const DISC_POLYGON_CORNERS: usize = 24;

/// Standard gravity (m/s²), the one the world uses, for [`ObjectSpec::sliding_force`].
pub const GRAVITY: f64 = 9.81;

/// How far outside a footprint a point may be and still count as on its boundary (m).
pub const BOUNDARY_TOLERANCE: f64 = 1e-9;

/// An object's solid, from its kind and `size`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// Box, table, chair, mat: extent along the object's own x, y, z (m).
    Cuboid {
        /// Full extents (m).
        size: Vector3<f64>,
    },
    /// An upright cylinder.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Height (m).
        height: f64,
    },
}

/// Where something stands on the floor, in the map frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Footprint {
    /// A rotated rectangle.
    Rectangle {
        /// Centre (m).
        centre: Point2<f64>,
        /// Half extents along the rectangle's own axes (m).
        half_extents: Vector2<f64>,
        /// Heading of the rectangle's x axis (rad).
        yaw: f64,
    },
    /// A disc.
    Disc {
        /// Centre (m).
        centre: Point2<f64>,
        /// Radius (m).
        radius: f64,
    },
}

impl Footprint {
    /// The centre.
    pub fn centre(&self) -> Point2<f64> {
        match self {
            Self::Rectangle { centre, .. } | Self::Disc { centre, .. } => *centre,
        }
    }

    /// A counter-clockwise convex polygon: the rectangle's four corners, or a polygon of
    /// [`DISC_POLYGON_CORNERS`] corners around the disc (it contains the disc, so it is safe as an obstacle).
    pub fn polygon(&self) -> Vec<Point2<f64>> {
        match *self {
            Self::Rectangle {
                centre,
                half_extents: h,
                yaw,
            } => {
                let rotation = Rotation2::new(yaw);
                [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]
                    .iter()
                    .map(|&(sx, sy)| centre + rotation * Vector2::new(sx * h.x, sy * h.y))
                    .collect()
            }
            Self::Disc { centre, radius } => {
                let n = DISC_POLYGON_CORNERS as f64;
                let outer = radius / (std::f64::consts::PI / n).cos();
                (0..DISC_POLYGON_CORNERS)
                    .map(|i| {
                        let angle = std::f64::consts::TAU * i as f64 / n;
                        centre + outer * Vector2::new(angle.cos(), angle.sin())
                    })
                    .collect()
            }
        }
    }

    /// Smallest and largest corner of the axis-aligned box around the footprint.
    pub fn aabb(&self) -> (Point2<f64>, Point2<f64>) {
        match *self {
            Self::Rectangle {
                centre,
                half_extents: h,
                yaw,
            } => {
                let (s, c) = yaw.sin_cos();
                let reach = Vector2::new(
                    (c * h.x).abs() + (s * h.y).abs(),
                    (s * h.x).abs() + (c * h.y).abs(),
                );
                (centre - reach, centre + reach)
            }
            Self::Disc { centre, radius } => {
                let reach = Vector2::repeat(radius);
                (centre - reach, centre + reach)
            }
        }
    }

    /// Distance from `point` to the footprint; 0 on or inside it.
    pub fn distance_to_point(&self, point: &Point2<f64>) -> f64 {
        match *self {
            Self::Rectangle {
                centre,
                half_extents: h,
                yaw,
            } => {
                let local = Rotation2::new(-yaw) * (point - centre);
                let outside = Vector2::new(
                    (local.x.abs() - h.x).max(0.0),
                    (local.y.abs() - h.y).max(0.0),
                );
                outside.norm()
            }
            Self::Disc { centre, radius } => ((point - centre).norm() - radius).max(0.0),
        }
    }

    /// True when `point` is on or inside the footprint, within [`BOUNDARY_TOLERANCE`] (a corner computed
    /// through a rotation is rarely exactly on the edge it came from).
    pub fn contains(&self, point: &Point2<f64>) -> bool {
        self.distance_to_point(point) <= BOUNDARY_TOLERANCE
    }

    /// The gap between two footprints; 0 when they touch or overlap.
    pub fn distance_to(&self, other: &Footprint) -> f64 {
        match (self, other) {
            (Self::Disc { centre, radius }, _) => {
                (other.distance_to_point(centre) - radius).max(0.0)
            }
            (_, Self::Disc { centre, radius }) => {
                (self.distance_to_point(centre) - radius).max(0.0)
            }
            _ if rectangles_overlap(self, other) => 0.0,
            // Two disjoint convex polygons are closest at a corner of one of them.
            _ => self
                .polygon()
                .iter()
                .map(|corner| other.distance_to_point(corner))
                .chain(
                    other
                        .polygon()
                        .iter()
                        .map(|corner| self.distance_to_point(corner)),
                )
                .fold(f64::INFINITY, f64::min),
        }
    }
}

/// Separating-axis test for two rectangles (only their own edge normals can separate them).
fn rectangles_overlap(a: &Footprint, b: &Footprint) -> bool {
    let (pa, pb) = (a.polygon(), b.polygon());
    let axes = edge_normals(&pa)
        .chain(edge_normals(&pb))
        .collect::<Vec<_>>();
    axes.iter().all(|axis| {
        let (a_min, a_max) = project(&pa, axis);
        let (b_min, b_max) = project(&pb, axis);
        a_min <= b_max && b_min <= a_max
    })
}

fn edge_normals(polygon: &[Point2<f64>]) -> impl Iterator<Item = Vector2<f64>> + '_ {
    polygon
        .iter()
        .zip(polygon.iter().cycle().skip(1))
        .map(|(p, q)| {
            let edge = q - p;
            Vector2::new(-edge.y, edge.x)
        })
}

fn project(polygon: &[Point2<f64>], axis: &Vector2<f64>) -> (f64, f64) {
    polygon
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            let t = p.coords.dot(axis);
            (lo.min(t), hi.max(t))
        })
}

impl ObjectKind {
    /// The name used in scenario files.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Box => "box",
            Self::Cylinder => "cylinder",
            Self::Table => "table",
            Self::Chair => "chair",
            Self::Mat => "mat",
        }
    }

    /// How many `size` entries the kind needs, and what they mean.
    pub fn size_entries(self) -> (usize, &'static str) {
        match self {
            Self::Cylinder => (2, "diameter, height"),
            Self::Box | Self::Table | Self::Chair | Self::Mat => (3, "x, y, z"),
        }
    }
}

impl fmt::Display for ObjectKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl ObjectSpec {
    /// The solid from `kind` and `size`; `None` when `size` has the wrong number of entries for the
    /// kind (a loaded scenario never has: loading refuses it).
    pub fn shape(&self) -> Option<Shape> {
        match (self.kind, self.size.as_slice()) {
            (ObjectKind::Cylinder, &[diameter, height]) => Some(Shape::Cylinder {
                radius: diameter / 2.0,
                height,
            }),
            (ObjectKind::Cylinder, _) => None,
            (_, &[x, y, z]) => Some(Shape::Cuboid {
                size: Vector3::new(x, y, z),
            }),
            _ => None,
        }
    }

    /// Heading (rad).
    pub fn yaw_rad(&self) -> f64 {
        self.yaw.to_radians()
    }

    /// Centre of the footprint (m).
    pub fn centre(&self) -> Point2<f64> {
        Point2::new(self.position[0], self.position[1])
    }

    /// Pose of the footprint centre in the map frame.
    pub fn pose(&self) -> Isometry2<f64> {
        Isometry2::new(self.centre().coords, self.yaw_rad())
    }

    /// The footprint in the map frame; `None` when [`ObjectSpec::shape`] is.
    pub fn footprint(&self) -> Option<Footprint> {
        Some(match self.shape()? {
            Shape::Cuboid { size } => Footprint::Rectangle {
                centre: self.centre(),
                half_extents: size.xy() / 2.0,
                yaw: self.yaw_rad(),
            },
            Shape::Cylinder { radius, .. } => Footprint::Disc {
                centre: self.centre(),
                radius,
            },
        })
    }

    /// The object's own height (m), from its underside to its top.
    pub fn height(&self) -> Option<f64> {
        Some(match self.shape()? {
            Shape::Cuboid { size } => size.z,
            Shape::Cylinder { height, .. } => height,
        })
    }

    /// Height of the top above the floor (m): elevation plus height.
    pub fn top(&self) -> Option<f64> {
        Some(self.elevation + self.height()?)
    }

    /// Horizontal force needed to slide the object over the floor (N): Coulomb friction μ·m·g. Infinite
    /// for a bolted object.
    pub fn sliding_force(&self) -> f64 {
        if self.fixed {
            f64::INFINITY
        } else {
            self.friction * self.mass * GRAVITY
        }
    }

    /// True for things that lie flat on the floor and are walked over (mats).
    pub fn is_flat(&self) -> bool {
        self.kind == ObjectKind::Mat
    }

    /// True when a body of `height` standing on the floor cannot pass over or under the object: it is not
    /// flat and its underside is lower than `height`.
    pub fn blocks_height(&self, height: f64) -> bool {
        !self.is_flat() && self.elevation < height
    }
}

impl Scenario {
    /// The object called `name`.
    pub fn object(&self, name: &str) -> Option<&ObjectSpec> {
        self.objects.iter().find(|o| o.name == name)
    }

    /// The actor called `name`.
    pub fn actor(&self, name: &str) -> Option<&ActorSpec> {
        self.actors.iter().find(|a| a.name == name)
    }
}

impl Room {
    /// Extent along x and y (m).
    pub fn extent(&self) -> Vector2<f64> {
        Vector2::new(self.size[0], self.size[1])
    }

    /// Smallest distance from the footprint to a wall (m); negative when it pokes through one.
    pub fn clearance(&self, footprint: &Footprint) -> f64 {
        let (lo, hi) = footprint.aabb();
        let far = self.extent() - hi.coords;
        lo.x.min(lo.y).min(far.x).min(far.y)
    }

    /// True when `point` is on the floor (walls included).
    pub fn contains_point(&self, point: &Point2<f64>) -> bool {
        (0.0..=self.size[0]).contains(&point.x) && (0.0..=self.size[1]).contains(&point.y)
    }
}

impl RobotSpec {
    /// Start position (m).
    pub fn start_position(&self) -> Point2<f64> {
        Point2::new(self.start[0], self.start[1])
    }

    /// Start heading (rad).
    pub fn start_yaw(&self) -> f64 {
        self.start[2].to_radians()
    }

    /// Start pose of `base_link` in the map frame.
    pub fn start_pose(&self) -> Isometry2<f64> {
        Isometry2::new(self.start_position().coords, self.start_yaw())
    }

    /// The robot's disc on the floor at its start.
    pub fn start_footprint(&self) -> Footprint {
        Footprint::Disc {
            centre: self.start_position(),
            radius: self.radius(),
        }
    }
}

impl Goal {
    /// Centre of the goal disc (m).
    pub fn centre(&self) -> Point2<f64> {
        Point2::new(self.position[0], self.position[1])
    }

    /// True when `point` counts as having reached the goal.
    pub fn is_reached_at(&self, point: &Point2<f64>) -> bool {
        (point - self.centre()).norm() <= self.tolerance
    }
}

impl ActorSpec {
    /// The waypoints as points (m).
    pub fn waypoint_points(&self) -> Vec<Point2<f64>> {
        self.waypoints
            .iter()
            .map(|w| Point2::new(w[0], w[1]))
            .collect()
    }
}
