//! The colour range sensor: a time-of-flight range camera with colour registered onto every return.
//!
//! After the paper's head sensor (Kakiuchi et al. 2010, §IV-A): a SwissRanger SR-4000 (176 × 144 pixels,
//! 43.6° × 34.6° field of view) between two colour cameras that colour each range pixel. The model:
//!
//! - **Geometry.** One ray per pixel through a pinhole (tangent-plane) grid, like a real camera: pixel
//!   centres are equally spaced on the image plane, not in angle. Rays are cast into the rapier scene
//!   in parallel, one image row per rayon task. The default caster gathers the shapes in the view
//!   frustum through the broad phase once per frame and culls them per row (a row's rays share a
//!   plane); rapier's query pipeline (one per worker) is the reference it is tested against. The body
//!   carrying the sensor is never seen; the robot's other parts are self-filtered (their pixels lost).
//! - **Range.** The sensor measures the distance along the ray. Noise is Gaussian along the ray with
//!   `σ = σ_ref · (r / r_ref)^a / cos(θ)^b` (θ the angle of incidence): a ToF camera's noise falls with
//!   the returned amplitude, which drops with distance and with obliquity. Defaults: σ = 4 mm at 1.3 m,
//!   a = 1, b = 0.5: shot-noise-limited, which matches the SR-4000's ~1 cm spread at its 5 m limit;
//!   a = 2 (background-limited, σ ≈ 6 cm at 5 m) is available for a harsher sensor. Returns nearer than `min_range`, beyond `max_range` (no phase wrap is modelled:
//!   the sensor's amplitude filter drops them) or at grazing incidence are lost.
//! - **Colour.** The colour of the true surface point, from [`Surface::colour_at`] in the collider's own
//!   frame (so textures move with objects), plus Gaussian noise per channel.
//! - **Determinism.** Every ray draws its noise from a counter-based generator keyed by
//!   `(frame_seed, ray index)`: the same scene, pose and seed give the same cloud bit for bit, whatever
//!   the thread count or scheduling.
//!
//! The output is an organised [`ColourCloud`] in the sensor frame (x forward along the optical axis,
//! y left, z up): row 0 at the top, column 0 at the left as seen looking along +x; a lost return holds
//! NaN coordinates and colour `[0, 0, 0]`.

use std::convert::Infallible;

use nalgebra::{Isometry3, Point3, Vector3};
use nudge_perception::{CloudFrame, ColourCloud};
use rand::TryRng;
use rand_distr::{Distribution, StandardNormal};
use rapier3d::dynamics::{RigidBodyHandle, RigidBodySet};
use rapier3d::geometry::{Aabb, BroadPhaseBvh, Collider, ColliderHandle, ColliderSet, Ray};
use rapier3d::math::{Matrix, Pose, Real, Rotation, Vector};
use rapier3d::parry::bounding_volume::BoundingVolume;
use rapier3d::parry::query::DefaultQueryDispatcher;
use rapier3d::parry::shape::{Compound, Shape};
use rapier3d::pipeline::{QueryFilter, QueryFilterFlags, QueryPipeline};
use rayon::prelude::*;

use crate::surface::{Owner, Surface};

/// Parameters of the colour range sensor; [`Default`] is the paper's SR-4000 with colour cameras.
#[derive(Clone, Debug, PartialEq)]
pub struct ColourRangeConfig {
    /// Pixel columns (SR-4000: 176).
    pub width: usize,
    /// Pixel rows (SR-4000: 144).
    pub height: usize,
    /// Horizontal field of view, edge to edge (deg; SR-4000: 43.6).
    pub h_fov_deg: f64,
    /// Vertical field of view, edge to edge (deg; SR-4000: 34.6).
    pub v_fov_deg: f64,
    /// Returns nearer than this are lost (m).
    pub min_range: f64,
    /// Returns farther than this are lost (m; the SR-4000's 5 m non-ambiguity range).
    pub max_range: f64,
    /// Range noise σ at `range_sigma_ref_distance`, normal incidence (m).
    pub range_sigma_ref: f64,
    /// The distance at which `range_sigma_ref` holds (m).
    pub range_sigma_ref_distance: f64,
    /// Exponent `a` of the distance term: σ ∝ (r / r_ref)^a. 2 = background-limited ToF noise
    /// (σ ∝ 1 / amplitude ∝ r²); 1 = shot-noise-limited.
    pub range_sigma_distance_exponent: f64,
    /// Exponent `b` of the obliquity term: σ ∝ 1 / cos(θ)^b (θ = angle of incidence).
    pub range_sigma_incidence_exponent: f64,
    /// Returns from surfaces seen more obliquely than this are lost (deg from the surface normal).
    pub max_incidence_deg: f64,
    /// Colour noise σ per channel (0–255 units).
    pub colour_noise_sigma: f64,
    /// Colour of returns from colliders the surface lookup does not know.
    pub unknown_colour: [u8; 3],
    /// Drop returns from the robot's own parts (surface owner [`Owner::Robot`]), like ROS's
    /// robot_self_filter: the pixel is lost, not seen through. The body carrying the sensor is
    /// excluded altogether through [`SensorScene::exclude`].
    pub self_filter: bool,
    /// How rays find their nearest surface.
    pub caster: RayCaster,
}

/// How the sensor finds the nearest surface along each ray. Both give the same returns up to float
/// rounding at silhouette edges.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RayCaster {
    /// Per frame, gather the leaf shapes inside the view frustum (through the broad phase) and cull
    /// them per image row: a row's rays lie in one plane, so each leaf covers a column span of it and
    /// a ray tests only the leaves whose span holds it. Fast for room-sized scenes.
    #[default]
    RowCulled,
    /// Cast every ray through rapier's query pipeline (the broad phase's BVH): the reference.
    QueryPipeline,
}

impl Default for ColourRangeConfig {
    fn default() -> Self {
        Self {
            width: 176,
            height: 144,
            h_fov_deg: 43.6,
            v_fov_deg: 34.6,
            min_range: 0.1,
            max_range: 5.0,
            range_sigma_ref: 0.004,
            range_sigma_ref_distance: 1.3,
            range_sigma_distance_exponent: 1.0,
            range_sigma_incidence_exponent: 0.5,
            max_incidence_deg: 80.0,
            colour_noise_sigma: 3.0,
            unknown_colour: [128, 128, 128],
            self_filter: true,
            caster: RayCaster::RowCulled,
        }
    }
}

/// The most pixels a sensor may have (a 4096 × 4096 image): beyond this a typo, not a camera.
pub const MAX_PIXELS: usize = 1 << 24;

/// Why a [`ColourRangeConfig`] cannot describe a sensor.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum ColourRangeConfigError {
    /// The image has no pixels, or more than [`MAX_PIXELS`].
    #[error("image size {width} × {height} must have between 1 and {MAX_PIXELS} pixels")]
    ImageSize {
        /// Columns asked for.
        width: usize,
        /// Rows asked for.
        height: usize,
    },
    /// A field of view outside (0°, 180°).
    #[error("field of view {h_fov_deg}° × {v_fov_deg}° must lie in (0°, 180°) on both axes")]
    FieldOfView {
        /// Horizontal field of view asked for (deg).
        h_fov_deg: f64,
        /// Vertical field of view asked for (deg).
        v_fov_deg: f64,
    },
    /// Range limits that are not `0 ≤ min < max < ∞`.
    #[error("range limits [{min_range}, {max_range}] m must satisfy 0 ≤ min < max < ∞")]
    RangeLimits {
        /// Minimum range asked for (m).
        min_range: f64,
        /// Maximum range asked for (m).
        max_range: f64,
    },
    /// A noise parameter that is negative or not finite.
    #[error("noise parameter {name} = {value} must be finite and non-negative")]
    Noise {
        /// Name of the field.
        name: &'static str,
        /// Its value.
        value: f64,
    },
    /// A maximum incidence angle outside (0°, 90°].
    #[error("maximum incidence {0}° must lie in (0°, 90°]")]
    Incidence(f64),
}

impl ColourRangeConfig {
    /// Checks that the configuration describes a sensor that can see something.
    pub fn validate(&self) -> Result<(), ColourRangeConfigError> {
        if self.width == 0
            || self.height == 0
            || self
                .width
                .checked_mul(self.height)
                .is_none_or(|n| n > MAX_PIXELS)
        {
            return Err(ColourRangeConfigError::ImageSize {
                width: self.width,
                height: self.height,
            });
        }
        let fov_ok = |deg: f64| deg > 0.0 && deg < 180.0;
        if !(fov_ok(self.h_fov_deg) && fov_ok(self.v_fov_deg)) {
            return Err(ColourRangeConfigError::FieldOfView {
                h_fov_deg: self.h_fov_deg,
                v_fov_deg: self.v_fov_deg,
            });
        }
        if !(self.min_range >= 0.0 && self.min_range < self.max_range && self.max_range.is_finite())
        {
            return Err(ColourRangeConfigError::RangeLimits {
                min_range: self.min_range,
                max_range: self.max_range,
            });
        }
        for (name, value) in [
            ("range_sigma_ref", self.range_sigma_ref),
            (
                "range_sigma_distance_exponent",
                self.range_sigma_distance_exponent,
            ),
            (
                "range_sigma_incidence_exponent",
                self.range_sigma_incidence_exponent,
            ),
            ("colour_noise_sigma", self.colour_noise_sigma),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(ColourRangeConfigError::Noise { name, value });
            }
        }
        if !(self.range_sigma_ref_distance.is_finite() && self.range_sigma_ref_distance > 0.0) {
            return Err(ColourRangeConfigError::Noise {
                name: "range_sigma_ref_distance",
                value: self.range_sigma_ref_distance,
            });
        }
        if !(self.max_incidence_deg > 0.0 && self.max_incidence_deg <= 90.0) {
            return Err(ColourRangeConfigError::Incidence(self.max_incidence_deg));
        }
        Ok(())
    }

    /// The range noise σ (m) of a return at distance `range` (m) whose surface normal makes
    /// `cos_incidence` with the ray.
    pub fn range_sigma(&self, range: f64, cos_incidence: f64) -> f64 {
        let distance_term = power(
            range / self.range_sigma_ref_distance,
            self.range_sigma_distance_exponent,
        );
        let incidence_term = power(cos_incidence, self.range_sigma_incidence_exponent);
        self.range_sigma_ref * distance_term / incidence_term
    }
}

/// `x^e`, with the exponents the noise model uses most spelled out: `powf` per ray is costly.
fn power(x: f64, e: f64) -> f64 {
    if e == 2.0 {
        x * x
    } else if e == 1.0 {
        x
    } else if e == 0.5 {
        x.sqrt()
    } else if e == 0.0 {
        1.0
    } else {
        x.powf(e)
    }
}

/// Looks up what a collider looks like; `None` for colliders without a known surface.
pub type SurfaceLookup<'a> = dyn Fn(ColliderHandle) -> Option<Surface> + Sync + 'a;

/// The part of a rapier world the sensor looks at, borrowed for one capture.
///
/// The broad phase must be up to date with the colliders' poses (step the pipeline, or update the
/// broad phase after moving bodies by hand) — the sensor sees what the broad phase indexes.
pub struct SensorScene<'a> {
    /// The world's rigid bodies.
    pub bodies: &'a RigidBodySet,
    /// The world's colliders.
    pub colliders: &'a ColliderSet,
    /// The world's broad phase, whose BVH the rays traverse.
    pub broad_phase: &'a BroadPhaseBvh,
    /// What each collider looks like.
    pub surface: &'a SurfaceLookup<'a>,
    /// Seed of the surface textures (the scenario seed): fixed for a run, so textures stay put from
    /// frame to frame.
    pub texture_seed: u64,
    /// A body the sensor never sees: the robot carrying it.
    pub exclude: Option<RigidBodyHandle>,
}

impl SensorScene<'_> {
    /// A query pipeline over this scene that skips the excluded body and trigger volumes.
    ///
    /// Cheap (a bundle of references); not `Sync`, so each rayon worker builds its own.
    fn query_pipeline(&self) -> QueryPipeline<'_> {
        let filter = QueryFilter {
            flags: QueryFilterFlags::EXCLUDE_SENSORS,
            exclude_rigid_body: self.exclude,
            ..QueryFilter::default()
        };
        self.broad_phase.as_query_pipeline(
            &DefaultQueryDispatcher,
            self.bodies,
            self.colliders,
            filter,
        )
    }
}

/// The colour range sensor: a configuration and its precomputed ray directions.
///
/// # Example
///
/// A red box 2 m ahead of a sensor 1 m above the origin, looking along +x:
///
/// ```
/// use nalgebra::Isometry3;
/// use nudge_sim::scenario::Texture;
/// use nudge_sim::sensors::colour_range::{ColourRangeConfig, ColourRangeSensor, SensorScene};
/// use nudge_sim::surface::{Owner, Surface};
/// use rapier3d::prelude::*;
///
/// let mut world = PhysicsWorld::new();
/// let (_, box_collider) = world.insert(
///     RigidBodyBuilder::fixed().translation(Vector::new(2.25, 0.0, 1.0)),
///     ColliderBuilder::cuboid(0.25, 0.5, 0.5),
/// );
/// world.detect_collisions(&(), &()); // the sensor sees what the broad phase indexes
///
/// let red = Surface::new([200, 30, 30], Texture::Plain, Owner::Object(0));
/// let lookup = move |h: ColliderHandle| (h == box_collider).then_some(red);
/// let scene = SensorScene {
///     bodies: &world.bodies,
///     colliders: &world.colliders,
///     broad_phase: &world.broad_phase,
///     surface: &lookup,
///     texture_seed: 1,
///     exclude: None,
/// };
/// let sensor = ColourRangeSensor::new(ColourRangeConfig::default());
/// let pose = Isometry3::translation(0.0, 0.0, 1.0);
/// let cloud = sensor.capture(&scene, &pose, 0.0, 7);
///
/// // The pixel at the image centre sees the box face 2 m ahead (noise σ ≈ 1 cm there).
/// let centre = 72 * 176 + 88;
/// let p = cloud.point(centre).expect("the box returns");
/// assert!((p.x - 2.0).abs() < 0.05 && p.y.abs() < 0.02 && p.z.abs() < 0.02);
/// let [r, g, b] = cloud.colours()[centre];
/// assert!(r > 180 && g < 50 && b < 50);
/// ```
#[derive(Clone, Debug)]
pub struct ColourRangeSensor {
    config: ColourRangeConfig,
    /// Unit ray directions in the sensor frame, row-major like the image.
    directions: Vec<Vector>,
    /// Cosine of `max_incidence_deg`: returns with a smaller cosine are lost.
    min_cos_incidence: Real,
}

impl ColourRangeSensor {
    /// A sensor with `config`. An invalid configuration (see [`ColourRangeConfig::validate`]) gives a
    /// sensor whose captures are empty clouds; use [`Self::try_new`] to be told instead.
    pub fn new(config: ColourRangeConfig) -> Self {
        let directions = if config.validate().is_ok() {
            pixel_directions(&config)
        } else {
            Vec::new()
        };
        let min_cos_incidence = config.max_incidence_deg.to_radians().cos().max(0.0) as Real;
        Self {
            config,
            directions,
            min_cos_incidence,
        }
    }

    /// A sensor with `config`, or why the configuration cannot describe one.
    pub fn try_new(config: ColourRangeConfig) -> Result<Self, ColourRangeConfigError> {
        config.validate()?;
        Ok(Self::new(config))
    }

    /// The sensor's configuration.
    pub fn config(&self) -> &ColourRangeConfig {
        &self.config
    }

    /// The unit direction of the ray through pixel (`row`, `col`) in the sensor frame, or `None`
    /// outside the image.
    pub fn ray_direction(&self, row: usize, col: usize) -> Option<Vector3<f64>> {
        if row >= self.config.height || col >= self.config.width {
            return None;
        }
        let d = self.directions.get(row * self.config.width + col)?;
        Some(Vector3::new(f64::from(d.x), f64::from(d.y), f64::from(d.z)))
    }

    /// One frame seen from `sensor_pose` (sensor → map) at `stamp` (robot clock, s), with the noise
    /// fixed by `frame_seed`.
    ///
    /// Returns an organised `width × height` cloud in the sensor frame. A non-finite pose gives a
    /// cloud without valid returns; a sensor with an invalid configuration gives an empty cloud.
    pub fn capture(
        &self,
        scene: &SensorScene<'_>,
        sensor_pose: &Isometry3<f64>,
        stamp: f64,
        frame_seed: u64,
    ) -> ColourCloud {
        let (width, height) = (self.config.width, self.config.height);
        let n = self.directions.len();
        if n == 0 {
            // Only an invalid configuration leaves the sensor without rays.
            return ColourCloud::empty(CloudFrame::Sensor, *sensor_pose, stamp);
        }
        let mut xs = vec![f32::NAN; n];
        let mut ys = vec![f32::NAN; n];
        let mut zs = vec![f32::NAN; n];
        let mut rgb = vec![[0u8; 3]; n];

        let pose = to_pose(sensor_pose);
        if pose.is_finite() {
            let frame = Frame {
                sensor: self,
                scene,
                pose,
                frame_seed,
            };
            let rows = xs
                .par_chunks_mut(width)
                .zip(ys.par_chunks_mut(width))
                .zip(zs.par_chunks_mut(width))
                .zip(rgb.par_chunks_mut(width))
                .enumerate();
            match self.config.caster {
                RayCaster::RowCulled => {
                    let leaves = Leaves::gather(&frame);
                    rows.for_each_init(
                        || CulledCaster::new(&leaves),
                        |caster, (row, (((x, y), z), c))| {
                            frame.trace_row(caster, row, RowOut { x, y, z, rgb: c });
                        },
                    );
                }
                RayCaster::QueryPipeline => rows.for_each_init(
                    || PipelineCaster::new(scene),
                    |caster, (row, (((x, y), z), c))| {
                        frame.trace_row(caster, row, RowOut { x, y, z, rgb: c });
                    },
                ),
            }
        }

        match ColourCloud::organised(
            width,
            height,
            xs,
            ys,
            zs,
            rgb,
            CloudFrame::Sensor,
            *sensor_pose,
            stamp,
        ) {
            Ok(cloud) => cloud,
            // The arrays are built with width × height slots; this arm only guards that invariant.
            Err(_) => ColourCloud::empty(CloudFrame::Sensor, *sensor_pose, stamp),
        }
    }
}

/// Pixel-centre ray directions on a tangent-plane grid, row-major, row 0 at the top, column 0 at the
/// left (+y) when looking along +x.
fn pixel_directions(config: &ColourRangeConfig) -> Vec<Vector> {
    let half_w = (config.h_fov_deg.to_radians() / 2.0).tan();
    let half_h = (config.v_fov_deg.to_radians() / 2.0).tan();
    let (w, h) = (config.width as f64, config.height as f64);
    let mut dirs = Vec::with_capacity(config.width * config.height);
    for row in 0..config.height {
        let up = half_h * (1.0 - (2.0 * row as f64 + 1.0) / h);
        for col in 0..config.width {
            let left = half_w * (1.0 - (2.0 * col as f64 + 1.0) / w);
            let d = Vector3::new(1.0, left, up).normalize();
            dirs.push(Vector::new(d.x as Real, d.y as Real, d.z as Real));
        }
    }
    dirs
}

/// A nalgebra pose as rapier's single-precision pose.
fn to_pose(iso: &Isometry3<f64>) -> Pose {
    let t = iso.translation.vector;
    let q = iso.rotation.quaternion();
    Pose::from_parts(
        Vector::new(t.x as Real, t.y as Real, t.z as Real),
        Rotation::from_xyzw(q.i as Real, q.j as Real, q.k as Real, q.w as Real),
    )
}

/// One row's slices of the output arrays.
struct RowOut<'r> {
    x: &'r mut [f32],
    y: &'r mut [f32],
    z: &'r mut [f32],
    rgb: &'r mut [[u8; 3]],
}

/// Everything one capture shares between rows.
struct Frame<'f> {
    sensor: &'f ColourRangeSensor,
    scene: &'f SensorScene<'f>,
    pose: Pose,
    frame_seed: u64,
}

/// The nearest surface a ray meets.
struct Hit {
    /// The frame the surface's pattern is fixed to: the pose of the collider, or of the compound's
    /// part, that was hit.
    frame: Pose,
    surface: Option<Surface>,
    /// Distance along the ray (m).
    toi: Real,
    /// World-frame surface normal at the hit.
    normal: Vector,
}

/// Finds the nearest surface along each ray of a row; one per rayon worker.
trait RowCaster<'c> {
    /// Prepares for the rays of `row`.
    fn begin_row(&mut self, row: usize);
    /// The nearest surface within `max_range` along `ray`, the ray of column `col`.
    fn first_hit(&mut self, col: usize, ray: &Ray, max_range: Real) -> Option<Hit>;
}

impl Frame<'_> {
    /// Traces every pixel of `row` and writes its return (or NaN) into `out`.
    fn trace_row<'c>(&self, caster: &mut impl RowCaster<'c>, row: usize, out: RowOut<'_>) {
        let config = &self.sensor.config;
        let width = config.width;
        let min_range = config.min_range as Real;
        let max_range = config.max_range as Real;
        let first = row * width;
        let dirs = &self.sensor.directions[first..first + width];
        caster.begin_row(row);
        let rotation = Matrix::from_quat(self.pose.rotation);

        for (col, dir) in dirs.iter().enumerate() {
            let world_dir = rotation * *dir;
            let ray = Ray::new(self.pose.translation, world_dir);
            let Some(hit) = caster.first_hit(col, &ray, max_range) else {
                continue;
            };
            let toi = hit.toi;
            let cos_incidence = hit.normal.dot(world_dir).abs();
            let own_part =
                config.self_filter && hit.surface.is_some_and(|s| matches!(s.owner, Owner::Robot));
            if toi < min_range || cos_incidence < self.sensor.min_cos_incidence || own_part {
                continue;
            }

            let mut noise = RayRng::new(self.frame_seed, first + col);
            let true_range = f64::from(toi);
            let sigma = config.range_sigma(true_range, f64::from(cos_incidence));
            let range = true_range + sigma * gaussian(&mut noise);
            let p = *dir * range as Real;
            out.x[col] = p.x;
            out.y[col] = p.y;
            out.z[col] = p.z;

            let base = match &hit.surface {
                Some(surface) => {
                    let world_hit = ray.origin + world_dir * toi;
                    let local = hit.frame.inverse_transform_point(world_hit);
                    let local =
                        Point3::new(f64::from(local.x), f64::from(local.y), f64::from(local.z));
                    surface.colour_at(local, self.scene.texture_seed)
                }
                None => config.unknown_colour,
            };
            out.rgb[col] = base.map(|c| {
                let v = f64::from(c) + config.colour_noise_sigma * gaussian(&mut noise);
                // Rounds half up; the float-to-int cast saturates, which clamps to 0–255.
                (v + 0.5) as u8
            });
        }
    }
}

/// Rays through rapier's query pipeline (the broad phase's BVH), the reference caster.
struct PipelineCaster<'c> {
    scene: &'c SensorScene<'c>,
    pipeline: QueryPipeline<'c>,
    /// The last collider hit and its surface: neighbouring pixels mostly share a collider.
    last: Option<(ColliderHandle, &'c Collider, Option<Surface>)>,
}

impl<'c> PipelineCaster<'c> {
    fn new(scene: &'c SensorScene<'c>) -> Self {
        Self {
            scene,
            pipeline: scene.query_pipeline(),
            last: None,
        }
    }
}

impl<'c> RowCaster<'c> for PipelineCaster<'c> {
    fn begin_row(&mut self, _row: usize) {}

    fn first_hit(&mut self, _col: usize, ray: &Ray, max_range: Real) -> Option<Hit> {
        // The BVH's ray cast without normals takes parry's SIMD path; the normal then comes from
        // the one collider hit.
        let (handle, _) = self.pipeline.cast_ray(ray, max_range, true)?;
        let (collider, surface) = match self.last {
            Some((h, co, surface)) if h == handle => (co, surface),
            _ => {
                let co = self.scene.colliders.get(handle)?;
                let surface = (self.scene.surface)(handle);
                self.last = Some((handle, co, surface));
                (co, surface)
            }
        };
        let intersection =
            collider
                .shape()
                .cast_ray_and_get_normal(collider.position(), ray, max_range, true)?;
        let (frame, surface) = match collider.shape().as_compound() {
            Some(compound) => {
                let (k, pose) = part_hit(compound, collider, ray, max_range);
                (pose, surface.map(|s| s.of_part(k)))
            }
            None => (*collider.position(), surface),
        };
        Some(Hit {
            frame,
            surface,
            toi: intersection.time_of_impact,
            normal: intersection.normal,
        })
    }
}

/// The part of a compound collider that `ray` meets first, and its pose (part 0 if none does).
fn part_hit(compound: &Compound, collider: &Collider, ray: &Ray, max_range: Real) -> (usize, Pose) {
    let pose_of = |part_pose: &Pose| *collider.position() * *part_pose;
    let mut best = (0, Real::INFINITY);
    for (k, (part_pose, part)) in compound.shapes().iter().enumerate() {
        if let Some(t) = part.cast_ray(&pose_of(part_pose), ray, max_range, true)
            && t < best.1
        {
            best = (k, t);
        }
    }
    let part_pose = compound
        .shapes()
        .get(best.0)
        .map_or(Pose::IDENTITY, |(p, _)| *p);
    (best.0, pose_of(&part_pose))
}

/// One piece of a visible collider (a compound's part, or the whole shape) in world coordinates,
/// with its bounding box corners in the sensor frame for culling.
struct Leaf<'c> {
    /// The pose of the collider or compound part (the surface pattern's frame).
    frame: Pose,
    surface: Option<Surface>,
    geometry: LeafGeometry<'c>,
    /// World AABB corners, in the sensor frame.
    corners: [Vector; 8],
    /// Distance from the sensor to the leaf's AABB: no ray meets the leaf nearer than this.
    near: Real,
}

/// How a leaf meets a ray.
enum LeafGeometry<'c> {
    /// A box, traced with a slab test in its own frame: most of a room is boxes, and this is several
    /// times cheaper than the generic shape cast.
    Cuboid {
        half: Vector,
        /// World → box rotation.
        to_local: Matrix,
        /// Box → world rotation.
        to_world: Matrix,
        /// The sensor's position in the box frame (every ray of a frame starts there).
        origin: Vector,
    },
    /// An upright cylinder (a person, a bin), traced in closed form in its own frame (axis along
    /// its local y, parry's convention): parry casts rays at cylinders through GJK, which cost
    /// about two thirds of a run's time in a room with a person walking in view.
    Cylinder {
        half_height: Real,
        radius: Real,
        /// World → cylinder rotation.
        to_local: Matrix,
        /// Cylinder → world rotation.
        to_world: Matrix,
        /// The sensor's position in the cylinder frame.
        origin: Vector,
    },
    /// Any other shape, through parry.
    Shape { shape: &'c dyn Shape, pose: Pose },
}

impl LeafGeometry<'_> {
    fn new<'s>(shape: &'s dyn Shape, pose: Pose, sensor_origin: Vector) -> LeafGeometry<'s> {
        let to_local = Matrix::from_quat(pose.rotation.inverse());
        let to_world = Matrix::from_quat(pose.rotation);
        let origin = pose.inverse_transform_point(sensor_origin);
        if let Some(cuboid) = shape.as_cuboid() {
            LeafGeometry::Cuboid {
                half: cuboid.half_extents,
                to_local,
                to_world,
                origin,
            }
        } else if let Some(cylinder) = shape.as_cylinder() {
            LeafGeometry::Cylinder {
                half_height: cylinder.half_height,
                radius: cylinder.radius,
                to_local,
                to_world,
                origin,
            }
        } else {
            LeafGeometry::Shape { shape, pose }
        }
    }

    /// Distance along `ray` (direction `ray.dir`, unit) to the leaf if under `limit`; 0 when the
    /// ray starts inside.
    fn toi(&self, ray: &Ray, limit: Real) -> Option<Real> {
        match self {
            LeafGeometry::Cuboid {
                half,
                to_local,
                origin,
                ..
            } => {
                let inv = (*to_local * ray.dir).recip();
                let t1 = (-*half - *origin) * inv;
                let t2 = (*half - *origin) * inv;
                let enter = t1.min(t2).max_element().max(0.0);
                let exit = t1.max(t2).min_element();
                (enter <= exit && enter <= limit).then_some(enter)
            }
            LeafGeometry::Cylinder {
                half_height,
                radius,
                to_local,
                origin,
                ..
            } => cylinder_toi(*origin, *to_local * ray.dir, *half_height, *radius)
                .filter(|&t| t <= limit),
            LeafGeometry::Shape { shape, pose } => shape.cast_ray(pose, ray, limit, true),
        }
    }

    /// The world-frame normal where `ray` meets the leaf at `toi`, or `None` if it does not.
    fn normal(&self, ray: &Ray, toi: Real, max_range: Real) -> Option<Vector> {
        match self {
            LeafGeometry::Cuboid {
                half,
                to_local,
                to_world,
                origin,
            } => {
                // The face the local hit point is nearest to, relative to the box's size.
                let p = *origin + (*to_local * ray.dir) * toi;
                let rel = (p / *half).abs();
                let axis = if rel.x >= rel.y && rel.x >= rel.z {
                    Vector::X * p.x.signum()
                } else if rel.y >= rel.z {
                    Vector::Y * p.y.signum()
                } else {
                    Vector::Z * p.z.signum()
                };
                Some(*to_world * axis)
            }
            LeafGeometry::Cylinder {
                half_height,
                radius,
                to_local,
                to_world,
                origin,
            } => {
                if toi == 0.0 {
                    // The sensor is inside: no surface faces it (parry answers the same).
                    return Some(Vector::ZERO);
                }
                // The cap or the side, whichever the local hit point is nearer to relative to
                // the cylinder's size.
                let p = *origin + (*to_local * ray.dir) * toi;
                let radial = Vector::new(p.x, 0.0, p.z);
                let axis = if p.y.abs() / *half_height >= radial.length() / *radius {
                    Vector::Y * p.y.signum()
                } else {
                    radial.normalize_or_zero()
                };
                Some(*to_world * axis)
            }
            LeafGeometry::Shape { shape, pose } => shape
                .cast_ray_and_get_normal(pose, ray, max_range, true)
                .map(|hit| hit.normal),
        }
    }
}

/// Distance along the ray `origin + t·dir` (in the cylinder's frame, axis along y) to the solid
/// cylinder of `half_height` and `radius` centred at the origin; 0 when the ray starts inside.
fn cylinder_toi(origin: Vector, dir: Vector, half_height: Real, radius: Real) -> Option<Real> {
    let (o, d) = (origin, dir);
    let r2 = radius * radius;
    if o.y.abs() <= half_height && o.x * o.x + o.z * o.z <= r2 {
        return Some(0.0);
    }
    let mut best = Real::INFINITY;
    // The side: |(o + t·d)_xz| = r, entered at the smaller root, within the height.
    let a = d.x * d.x + d.z * d.z;
    if a > Real::EPSILON {
        let b = o.x * d.x + o.z * d.z;
        let c = o.x * o.x + o.z * o.z - r2;
        let disc = b * b - a * c;
        if disc >= 0.0 {
            let t = (-b - disc.sqrt()) / a;
            if t >= 0.0 && (o.y + t * d.y).abs() <= half_height {
                best = t;
            }
        }
    }
    // The caps: the plane y = ±h, within the radius.
    if d.y != 0.0 {
        for cap in [-half_height, half_height] {
            let t = (cap - o.y) / d.y;
            if t >= 0.0 && t < best {
                let (x, z) = (o.x + t * d.x, o.z + t * d.z);
                if x * x + z * z <= r2 {
                    best = t;
                }
            }
        }
    }
    best.is_finite().then_some(best)
}

/// Every leaf a frame's rays can reach.
struct Leaves<'c> {
    leaves: Vec<Leaf<'c>>,
    /// Tangent of half the horizontal field of view.
    half_w: Real,
    /// Tangent of half the vertical field of view.
    half_h: Real,
    width: usize,
    height: usize,
}

impl<'c> Leaves<'c> {
    /// The leaves of the colliders the broad phase finds inside the view frustum's bounding box, with
    /// the scene's filter (robot body excluded, trigger volumes skipped).
    fn gather(frame: &Frame<'c>) -> Self {
        let config = &frame.sensor.config;
        let half_w = (config.h_fov_deg.to_radians() / 2.0).tan() as Real;
        let half_h = (config.v_fov_deg.to_radians() / 2.0).tan() as Real;
        let max_range = config.max_range as Real;
        // Every point within max_range along a ray of the frustum lies in the pyramid from the
        // sensor to the far rectangle at x = max_range.
        let mut frustum_points = vec![frame.pose.translation];
        for (sy, sz) in [(-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)] {
            let far = Vector::new(max_range, sy * half_w * max_range, sz * half_h * max_range);
            frustum_points.push(frame.pose.transform_point(far));
        }
        let frustum = Aabb::from_points(frustum_points);

        let scene = frame.scene;
        let pipeline = scene.query_pipeline();
        let mut leaves = Vec::new();
        let handles: Vec<ColliderHandle> = pipeline
            .intersect_aabb_conservative(frustum)
            .map(|(handle, _)| handle)
            .collect();
        for handle in handles {
            let Some(collider) = scene.colliders.get(handle) else {
                continue;
            };
            let surface = (scene.surface)(handle);
            let mut push = |shape: &'c dyn Shape, pose: Pose, surface: Option<Surface>| {
                let aabb = shape.compute_aabb(&pose);
                if !aabb.intersects(&frustum) {
                    return;
                }
                // Corner i takes maxs on the axes whose bit is set in i (x = 1, y = 2, z = 4), so
                // box edges join corners whose indices differ in one bit.
                let corners: [Vector; 8] = std::array::from_fn(|i| {
                    let pick = |bit: usize, lo: Real, hi: Real| if i & bit == 0 { lo } else { hi };
                    let v = Vector::new(
                        pick(1, aabb.mins.x, aabb.maxs.x),
                        pick(2, aabb.mins.y, aabb.maxs.y),
                        pick(4, aabb.mins.z, aabb.maxs.z),
                    );
                    frame.pose.inverse_transform_point(v)
                });
                leaves.push(Leaf {
                    frame: pose,
                    surface,
                    geometry: LeafGeometry::new(shape, pose, frame.pose.translation),
                    corners,
                    near: (frame.pose.translation
                        - frame.pose.translation.clamp(aabb.mins, aabb.maxs))
                    .length(),
                });
            };
            match collider.shape().as_compound() {
                Some(compound) => {
                    for (k, (part_pose, part)) in compound.shapes().iter().enumerate() {
                        let look = surface.map(|s| s.of_part(k));
                        push(part.as_ref(), *collider.position() * *part_pose, look);
                    }
                }
                None => push(collider.shape(), *collider.position(), surface),
            }
        }
        // Nearest first (ties keep the broad phase's order, so the order is deterministic).
        leaves.sort_by(|a, b| a.near.total_cmp(&b.near));
        Self {
            leaves,
            half_w,
            half_h,
            width: config.width,
            height: config.height,
        }
    }

    /// The columns `[lo, hi]` of `row` whose rays may meet `leaf`, or `None` if none may.
    ///
    /// A row's rays all lie in one plane through the sensor; the leaf's box meets that plane in a
    /// convex polygon, and the rays that can hit it are those within the polygon's angular span.
    fn columns(&self, leaf: &Leaf<'_>, row: usize) -> Option<(usize, usize)> {
        let up = self.half_h * (1.0 - (2.0 * row as Real + 1.0) / self.height as Real);
        // Rays (1, y, up) satisfy z - up·x = 0.
        let side = leaf.corners.map(|c| c.z - up * c.x);
        let (mut y_min, mut y_max) = (Real::INFINITY, Real::NEG_INFINITY);
        let mut behind = false;
        let mut any = false;
        let mut visit = |p: Vector| {
            any = true;
            if p.x <= 1e-6 {
                behind = true;
            } else {
                let y = p.y / p.x;
                y_min = y_min.min(y);
                y_max = y_max.max(y);
            }
        };
        for (i, &si) in side.iter().enumerate() {
            if si == 0.0 {
                visit(leaf.corners[i]);
            }
            // Box edges join corners whose indices differ in one bit.
            for bit in [1, 2, 4] {
                let j = i ^ bit;
                if j > i && si * side[j] < 0.0 {
                    let t = si / (si - side[j]);
                    visit(leaf.corners[i] + (leaf.corners[j] - leaf.corners[i]) * t);
                }
            }
        }
        if !any {
            return None;
        }
        if behind {
            // The section reaches beside or behind the sensor: do not cull within the row.
            return Some((0, self.width - 1));
        }
        // Column c looks along y = half_w · (1 − (2c + 1) / width); y falls as c grows.
        let col_of = |y: Real| ((1.0 - y / self.half_w) * self.width as Real - 1.0) / 2.0;
        let lo = (col_of(y_max).floor() - 1.0).max(0.0);
        let hi = (col_of(y_min).ceil() + 1.0).min(self.width as Real - 1.0);
        (lo <= hi).then_some((lo as usize, hi as usize))
    }
}

/// Rays against a frame's leaves, culled per row: each ray only tests the few leaves whose column
/// span in its row contains it.
struct CulledCaster<'l, 'c> {
    leaves: &'l Leaves<'c>,
    /// (first column, last column, leaf index) of the leaves the current row may see.
    candidates: Vec<(usize, usize, usize)>,
}

impl<'l, 'c> CulledCaster<'l, 'c> {
    fn new(leaves: &'l Leaves<'c>) -> Self {
        Self {
            leaves,
            candidates: Vec::with_capacity(leaves.leaves.len()),
        }
    }
}

impl<'c> RowCaster<'c> for CulledCaster<'_, 'c> {
    fn begin_row(&mut self, row: usize) {
        self.candidates.clear();
        for (i, leaf) in self.leaves.leaves.iter().enumerate() {
            if let Some((lo, hi)) = self.leaves.columns(leaf, row) {
                self.candidates.push((lo, hi, i));
            }
        }
    }

    fn first_hit(&mut self, col: usize, ray: &Ray, max_range: Real) -> Option<Hit> {
        let mut best: Option<(usize, Real)> = None;
        for &(lo, hi, i) in &self.candidates {
            if col < lo || col > hi {
                continue;
            }
            // Leaves come nearest first (see `Leaves::gather`): past the best hit, none can beat it.
            if best.is_some_and(|(_, t)| self.leaves.leaves[i].near > t) {
                break;
            }
            let limit = best.map_or(max_range, |(_, t)| t);
            if let Some(t) = self.leaves.leaves[i].geometry.toi(ray, limit)
                && best.is_none_or(|(_, b)| t < b)
            {
                best = Some((i, t));
            }
        }
        let (i, toi) = best?;
        let leaf = &self.leaves.leaves[i];
        let normal = leaf.geometry.normal(ray, toi, max_range)?;
        Some(Hit {
            frame: leaf.frame,
            surface: leaf.surface,
            toi,
            normal,
        })
    }
}

/// A standard normal draw.
fn gaussian(rng: &mut RayRng) -> f64 {
    StandardNormal.sample(rng)
}

/// SplitMix64 keyed by (frame seed, ray index): a counter-based stream per ray, so a ray's noise never
/// depends on which thread traced it or on what the other rays hit.
struct RayRng {
    state: u64,
}

/// SplitMix64's increment (2^64 / φ).
const GOLDEN_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// SplitMix64's output finaliser: a bijective, well-mixed hash of one word.
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl RayRng {
    fn new(frame_seed: u64, ray: usize) -> Self {
        let key = mix64(frame_seed.wrapping_add(GOLDEN_GAMMA));
        Self {
            state: mix64(key ^ mix64((ray as u64).wrapping_mul(GOLDEN_GAMMA))),
        }
    }
}

impl TryRng for RayRng {
    type Error = Infallible;

    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        self.try_next_u64().map(|v| (v >> 32) as u32)
    }

    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        self.state = self.state.wrapping_add(GOLDEN_GAMMA);
        Ok(mix64(self.state))
    }

    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
        for chunk in dst.chunks_mut(8) {
            let bytes = self.try_next_u64()?.to_le_bytes();
            chunk.copy_from_slice(&bytes[..chunk.len()]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_closed_form_cylinder_meets_rays_where_parry_does() {
        // Invariant: the culled caster's cylinder returns the exact point where each ray enters a
        // tilted cylinder (from outside or inside), and parry's GJK cast finds the same surface
        // point and normal to within its own tolerance, so the sensor sees the same scene.
        use rapier3d::parry::query::RayCast;
        use rapier3d::parry::shape::Cylinder;
        let (half_height, radius) = (0.85, 0.25);
        let cylinder = Cylinder::new(half_height, radius);
        let pose = Pose::from_parts(
            Vector::new(1.0, -0.5, 0.9),
            Rotation::from_scaled_axis(Vector::new(1.3, 0.2, -0.4)),
        );
        // How far a world point lies outside the solid (negative inside, exact near a face).
        let outside = |world: Vector| {
            let p = pose.inverse_transform_point(world);
            ((p.x * p.x + p.z * p.z).sqrt() - radius).max(p.y.abs() - half_height)
        };
        let mut rng = RayRng::new(7, 0);
        let mut uniform = |lo: Real, hi: Real| {
            lo + (hi - lo) * (rng.try_next_u64().unwrap_or(0) >> 11) as Real / (1u64 << 53) as Real
        };
        let (mut hits, mut inside, mut grazing) = (0, 0, 0);
        for _ in 0..20_000 {
            let origin = Vector::new(uniform(-3.0, 3.0), uniform(-3.0, 3.0), uniform(-1.0, 2.5));
            let target = pose.transform_point(Vector::new(
                uniform(-0.4, 0.4),
                uniform(-1.0, 1.0),
                uniform(-0.4, 0.4),
            ));
            let ray = Ray::new(origin, (target - origin).normalize());
            let at = |t: Real| ray.origin + ray.dir * t;
            let leaf = LeafGeometry::new(&cylinder, pose, origin);
            let ours = leaf.toi(&ray, 10.0);
            let parry = cylinder.cast_ray_and_get_normal(&pose, &ray, 10.0, true);
            match (ours, parry) {
                (Some(0.0), Some(hit)) => {
                    inside += 1;
                    assert!(outside(origin) <= 0.0 && hit.time_of_impact == 0.0);
                }
                (Some(t), Some(hit)) => {
                    hits += 1;
                    // Ours lies on the surface to f32 rounding, and just before it the ray is out.
                    assert!(
                        outside(at(t)).abs() < 1e-5 * (1.0 + t),
                        "{t} is off the surface"
                    );
                    assert!(
                        outside(at(t - 1e-4)) > 0.0,
                        "{t} is not where the ray enters"
                    );
                    // Parry's GJK stops millimetres off the surface where a ray grazes a face or
                    // rim, which along the ray can be centimetres: its point is checked there.
                    assert!(outside(at(hit.time_of_impact)).abs() < 5e-3, "{hit:?}");
                    let normal = leaf.normal(&ray, t, 10.0).unwrap_or(Vector::ZERO);
                    let cos = normal.dot(ray.dir).abs();
                    if cos > 0.2 {
                        assert!((t - hit.time_of_impact).abs() < 1e-2, "{t} vs {hit:?}");
                    }
                    let p = pose.inverse_transform_point(at(t));
                    // Parry blends the two faces' normals near a rim.
                    let on_rim = (p.y.abs() - half_height).abs() < 1e-2
                        && ((p.x * p.x + p.z * p.z).sqrt() - radius).abs() < 1e-2;
                    if !on_rim && cos > 0.2 {
                        assert!(normal.dot(hit.normal) > 0.999, "{normal} vs {}", hit.normal);
                    }
                }
                (None, None) => {}
                // A ray that grazes the surface may be a hit for one and a miss for the other.
                (Some(t), None) => {
                    assert!(outside(at(t)).abs() < 1e-5 * (1.0 + t));
                    grazing += 1;
                }
                (None, Some(hit)) => {
                    assert!(outside(at(hit.time_of_impact)) < 5e-3, "we missed {hit:?}");
                    grazing += 1;
                }
            }
        }
        assert!(
            hits > 10_000,
            "{hits} hits: the rays should mostly meet the cylinder"
        );
        assert!(inside > 0, "no ray started inside");
        assert!(grazing < 20, "{grazing} grazing disagreements");
    }

    #[test]
    fn default_config_is_the_sr4000_and_valid() {
        // The default configuration is the paper's SR-4000 (176 × 144, 43.6° × 34.6°) and validates.
        let c = ColourRangeConfig::default();
        assert_eq!((c.width, c.height), (176, 144));
        assert_eq!((c.h_fov_deg, c.v_fov_deg), (43.6, 34.6));
        assert!(c.validate().is_ok());
        assert!((c.range_sigma(1.3, 1.0) - 0.004).abs() < 1e-12);
    }

    #[test]
    fn invalid_configs_are_refused_and_give_empty_captures_not_panics() {
        // Bad configurations are errors from try_new and never make new() panic.
        for bad in [
            ColourRangeConfig {
                width: 0,
                ..Default::default()
            },
            ColourRangeConfig {
                width: usize::MAX,
                height: 2,
                ..Default::default()
            },
            ColourRangeConfig {
                h_fov_deg: 180.0,
                ..Default::default()
            },
            ColourRangeConfig {
                min_range: 6.0,
                ..Default::default()
            },
            ColourRangeConfig {
                colour_noise_sigma: f64::NAN,
                ..Default::default()
            },
            ColourRangeConfig {
                max_incidence_deg: 0.0,
                ..Default::default()
            },
        ] {
            assert!(ColourRangeSensor::try_new(bad.clone()).is_err(), "{bad:?}");
            assert!(ColourRangeSensor::new(bad).directions.is_empty());
        }
    }

    #[test]
    fn pixel_grid_is_a_centred_pinhole_grid() {
        // Corner rays reach the field-of-view edges (minus half a pixel) on the image plane, column 0 is
        // left (+y), row 0 is up (+z), and every direction is a unit vector.
        let sensor = ColourRangeSensor::new(ColourRangeConfig::default());
        let c = sensor.config().clone();
        let top_left = sensor.ray_direction(0, 0).expect("inside the image");
        let bottom_right = sensor
            .ray_direction(c.height - 1, c.width - 1)
            .expect("inside the image");
        let half_w = (c.h_fov_deg.to_radians() / 2.0).tan();
        let half_h = (c.v_fov_deg.to_radians() / 2.0).tan();
        let pixel_w = 2.0 * half_w / c.width as f64;
        let pixel_h = 2.0 * half_h / c.height as f64;
        assert!((top_left.y / top_left.x - (half_w - pixel_w / 2.0)).abs() < 1e-6);
        assert!((top_left.z / top_left.x - (half_h - pixel_h / 2.0)).abs() < 1e-6);
        assert!((bottom_right.y / bottom_right.x + (half_w - pixel_w / 2.0)).abs() < 1e-6);
        assert!((bottom_right.z / bottom_right.x + (half_h - pixel_h / 2.0)).abs() < 1e-6);
        assert!(
            sensor
                .directions
                .iter()
                .all(|d| (d.length() - 1.0).abs() < 1e-6)
        );
        assert!(sensor.ray_direction(c.height, 0).is_none());
    }

    #[test]
    fn ray_noise_streams_depend_only_on_seed_and_ray() {
        // A ray's stream is fixed by (seed, ray) and differs between rays and between seeds.
        let draw = |seed, ray| {
            let mut r = RayRng::new(seed, ray);
            [gaussian(&mut r), gaussian(&mut r)]
        };
        assert_eq!(draw(7, 100), draw(7, 100));
        assert_ne!(draw(7, 100), draw(7, 101));
        assert_ne!(draw(7, 100), draw(8, 100));
    }

    #[test]
    fn ray_noise_is_standard_normal() {
        // Draws across many rays have mean ≈ 0 and variance ≈ 1.
        let n = 200_000;
        let draws: Vec<f64> = (0..n).map(|i| gaussian(&mut RayRng::new(3, i))).collect();
        let mean = draws.iter().sum::<f64>() / n as f64;
        let var = draws.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.01, "mean {mean}");
        assert!((var - 1.0).abs() < 0.02, "variance {var}");
    }
}
