//! The whole detection: floor → elevation map and the floor seen free → labelling → prisms → id
//! tracking.

use nalgebra::{Isometry2, Point2, Point3};

use crate::cloud::ColourCloud;
use crate::elevation::{ElevationConfig, ElevationMap};
use crate::error::PerceptionError;
use crate::floor::{FloorConfig, FloorModel};
use crate::lookaround::{LookAroundConfig, fuse};
use crate::prism::{Prism, TRACK_MIN_IOU, track_ids_with};
use crate::prisms::{PrismConfig, build_prisms};
use crate::seen_floor::SeenFloor;
use crate::segment::{SegmentConfig, label};

/// Every stage's parameters (each with documented defaults).
#[derive(Clone, Debug, PartialEq)]
pub struct PerceptionConfig {
    /// The look-around's views.
    pub look_around: LookAroundConfig,
    /// Floor detection.
    pub floor: FloorConfig,
    /// Elevation map.
    pub elevation: ElevationConfig,
    /// Labelling.
    pub segment: SegmentConfig,
    /// Prism building.
    pub prism: PrismConfig,
    /// Smallest footprint IoU to keep an id across looks. Default [`TRACK_MIN_IOU`] (0.3).
    pub track_min_iou: f64,
}

impl Default for PerceptionConfig {
    fn default() -> Self {
        Self {
            look_around: LookAroundConfig::default(),
            floor: FloorConfig::default(),
            elevation: ElevationConfig::default(),
            segment: SegmentConfig::default(),
            prism: PrismConfig::default(),
            track_min_iou: TRACK_MIN_IOU,
        }
    }
}

/// What one detection found.
#[derive(Clone, Debug, PartialEq)]
pub struct Detection {
    /// The floor model learned in front of the robot.
    pub floor: FloorModel,
    /// The obstacles, ids matched to the previous look's.
    pub prisms: Vec<Prism>,
}

/// Runs the pipeline on a fused map-frame cloud and returns only the prisms.
///
/// `base_pose` is the robot's planar pose in the map frame (the known floor lies in front of it);
/// `previous` are the last look's prisms (empty at the first look), whose ids are kept where footprints
/// overlap. A cloud with no valid point or no floor in front is an error.
///
/// ```
/// use nalgebra::{Isometry2, Isometry3, Point3};
/// use nudge_perception::{CloudFrame, ColourCloud, PerceptionConfig, detect_objects};
///
/// // A floor in front of a robot at the origin facing +x, and a 20 cm box 0.5 m tall at x = 2 m.
/// let mut cloud = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
/// for i in 0..60 {
///     for j in 0..40 {
///         let (x, y) = (0.5 + 0.05 * i as f32, -1.0 + 0.05 * j as f32);
///         cloud.push(Point3::new(x, y, 0.0), [150, 150, 140]);
///     }
/// }
/// for i in 0..20 {
///     for j in 0..20 {
///         let (x, y) = (2.0 + 0.01 * i as f32, 0.01 * j as f32);
///         cloud.push(Point3::new(x, y, 0.5), [40, 90, 160]);
///     }
/// }
/// let prisms = detect_objects(&cloud, &Isometry2::identity(), &PerceptionConfig::default(), &[])
///     .expect("there is floor in front of the robot");
/// assert_eq!(prisms.len(), 1);
/// assert!((prisms[0].z_max - 0.5).abs() < 1e-3);
/// assert!((prisms[0].area() - 0.19 * 0.19).abs() < 0.01);
/// ```
pub fn detect_objects(
    fused: &ColourCloud,
    base_pose: &Isometry2<f64>,
    config: &PerceptionConfig,
    previous: &[Prism],
) -> Result<Vec<Prism>, PerceptionError> {
    detect(fused, base_pose, config, previous).map(|d| d.prisms)
}

/// [`detect_objects`] that also returns the floor model.
pub fn detect(
    fused: &ColourCloud,
    base_pose: &Isometry2<f64>,
    config: &PerceptionConfig,
    previous: &[Prism],
) -> Result<Detection, PerceptionError> {
    if fused.valid_count() == 0 {
        return Err(PerceptionError::EmptyCloud);
    }
    let floor = FloorModel::learn(fused, base_pose, &config.floor)?;
    detect_on_floor(fused, floor, base_pose, config, previous)
}

/// [`detect`] with a floor model already known: the floor does not change between looks, while the
/// patch in front of the robot may show no floor when it faces a wall or an object.
pub fn detect_on_floor(
    fused: &ColourCloud,
    floor: FloorModel,
    base_pose: &Isometry2<f64>,
    config: &PerceptionConfig,
    previous: &[Prism],
) -> Result<Detection, PerceptionError> {
    if fused.valid_count() == 0 {
        return Err(PerceptionError::EmptyCloud);
    }
    let (obstacles, is_floor) = floor.non_floor_and_flags(fused);
    let centre = Point2::from(base_pose.translation.vector);
    let map = ElevationMap::build(&obstacles, floor.height(), centre, &config.elevation)?;
    let seen = SeenFloor::build(
        fused,
        &is_floor,
        &map,
        config.elevation.min_points_per_cell,
        config.prism.seen_floor_clearance,
    )
    .seen_from(Point3::from(fused.sensor_pose().translation.vector));
    let clusters = label(&map, &config.segment);
    let mut prisms = build_prisms(&obstacles, &map, &clusters, &seen, &config.prism);
    track_ids_with(previous, &mut prisms, config.track_min_iou);
    Ok(Detection { floor, prisms })
}

/// Fuses the look-around's clouds (sensor or map frame, each with its sensor pose) and detects.
pub fn detect_from_views(
    views: &[ColourCloud],
    base_pose: &Isometry2<f64>,
    config: &PerceptionConfig,
    previous: &[Prism],
) -> Result<Detection, PerceptionError> {
    detect(&fuse(views), base_pose, config, previous)
}
