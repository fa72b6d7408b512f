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
//! - **Colour.** The colour of the true surface point, from [`crate::surface::Surface::colour_at`] in the collider's own
//!   frame (so textures move with objects), plus Gaussian noise per channel.
//! - **Determinism.** Every ray draws its noise from a counter-based generator keyed by
//!   `(frame_seed, ray index)`: the same scene, pose and seed give the same cloud bit for bit, whatever
//!   the thread count or scheduling.
//!
//! The output is an organised [`ColourCloud`] in the sensor frame (x forward along the optical axis,
//! y left, z up): row 0 at the top, column 0 at the left as seen looking along +x; a lost return holds
//! NaN coordinates and colour `[0, 0, 0]`.

mod config;
mod culled_caster;
mod leaf;
mod noise;
mod pipeline_caster;
mod scene;
mod trace;

pub use config::{ColourRangeConfig, ColourRangeConfigError, MAX_PIXELS, RayCaster};
pub use scene::{SensorScene, SurfaceLookup};

use nalgebra::{Isometry3, Vector3};
use nudge_perception::{CloudFrame, ColourCloud};
use rapier3d::math::{Pose, Real, Rotation, Vector};
use rayon::prelude::*;

use culled_caster::{CulledCaster, Leaves};
use pipeline_caster::PipelineCaster;
use trace::{Frame, RowOut};

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
            config
                .camera
                .pixel_rays()
                .into_iter()
                .map(|[x, y, z]| Vector::new(x, y, z))
                .collect()
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
        if row >= self.config.camera.height || col >= self.config.camera.width {
            return None;
        }
        let d = self.directions.get(row * self.config.camera.width + col)?;
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
        let (width, height) = (self.config.camera.width, self.config.camera.height);
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

impl ColourRangeSensor {
    /// Who owns the surface each pixel of a frame from `sensor_pose` returns, row-major like the
    /// image (`None`: no return): the ground truth a segmentation is scored against. The rays and
    /// the rules that keep a return are [`Self::capture`]'s, so a capture from the same pose in the
    /// same scene has a point exactly where this has an owner.
    pub fn owners(
        &self,
        scene: &SensorScene<'_>,
        sensor_pose: &Isometry3<f64>,
    ) -> Vec<Option<crate::surface::Owner>> {
        let width = self.config.camera.width;
        let mut out = vec![None; self.directions.len()];
        let pose = to_pose(sensor_pose);
        if self.directions.is_empty() || !pose.is_finite() {
            return out;
        }
        let frame = Frame {
            sensor: self,
            scene,
            pose,
            frame_seed: 0,
        };
        let rows = out.par_chunks_mut(width).enumerate();
        match self.config.caster {
            RayCaster::RowCulled => {
                let leaves = Leaves::gather(&frame);
                rows.for_each_init(
                    || CulledCaster::new(&leaves),
                    |caster, (row, o)| frame.owners_row(caster, row, o),
                );
            }
            RayCaster::QueryPipeline => rows.for_each_init(
                || PipelineCaster::new(scene),
                |caster, (row, o)| frame.owners_row(caster, row, o),
            ),
        }
        out
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn invalid_configs_are_refused_and_give_empty_captures_not_panics() {
        use nudge_robot_model::CameraModel;
        // Bad configurations are errors from try_new and never make new() panic.
        for bad in [
            ColourRangeConfig {
                camera: CameraModel {
                    width: 0,
                    ..CameraModel::default()
                },
                ..Default::default()
            },
            ColourRangeConfig {
                camera: CameraModel {
                    width: usize::MAX,
                    height: 2,
                    ..CameraModel::default()
                },
                ..Default::default()
            },
            ColourRangeConfig {
                camera: CameraModel {
                    h_fov_deg: 180.0,
                    ..CameraModel::default()
                },
                ..Default::default()
            },
            ColourRangeConfig {
                camera: CameraModel {
                    min_range: 6.0,
                    ..CameraModel::default()
                },
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
            .ray_direction(c.camera.height - 1, c.camera.width - 1)
            .expect("inside the image");
        let half_w = (c.camera.h_fov_deg.to_radians() / 2.0).tan();
        let half_h = (c.camera.v_fov_deg.to_radians() / 2.0).tan();
        let pixel_w = 2.0 * half_w / c.camera.width as f64;
        let pixel_h = 2.0 * half_h / c.camera.height as f64;
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
        assert!(sensor.ray_direction(c.camera.height, 0).is_none());
    }
}
