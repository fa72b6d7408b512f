//! Looking around and turning what was seen into obstacles.

use nalgebra::{Isometry2, Isometry3, Translation3, UnitQuaternion};
use nudge_perception::{FloorModel, detect_on_floor, fuse};

use super::{Interrupt, Runner};
use crate::event::Event;
use crate::record::Observer;
use crate::robot::Robot;

/// Where a head of `(pan, tilt)` on `base` looks from, for frames without a capture yet.
pub(crate) fn camera_pose(base: &Isometry2<f64>, head: (f64, f64)) -> Isometry3<f64> {
    let t = base.translation.vector;
    Isometry3::from_parts(
        Translation3::new(t.x, t.y, HEAD_HEIGHT),
        UnitQuaternion::from_euler_angles(0.0, head.1, base.rotation.angle() + head.0),
    )
}

/// Nominal camera height for the frames reported to observers (m).
const HEAD_HEIGHT: f64 = 1.4;

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Sweeps the head through the look-around's views, capturing one cloud at each.
    pub(crate) fn look_around(&mut self) -> Event {
        match self.capture_views() {
            Ok(views) => Event::LookedAround { views },
            Err(i) => i.into(),
        }
    }

    fn capture_views(&mut self) -> Result<usize, Interrupt> {
        let views = self.config.perception.look_around.views();
        self.world.views.clear();
        for view in &views {
            self.robot
                .start_point_head(view.pan_deg.to_radians(), view.tilt_deg.to_radians())?;
            self.wait(|r| r.head_status())?;
            let cloud = self.robot.capture()?;
            self.observer.cloud(&cloud);
            self.sense(&cloud, true);
            self.world.views.push(cloud);
        }
        self.publish_grid();
        // Look ahead and down while walking, so the path ahead stays in view.
        self.robot
            .start_point_head(0.0, self.config.grid.watch_tilt)?;
        Ok(views.len())
    }

    /// Runs perception on the latest look-around.
    pub(crate) fn detect_objects(&mut self) -> Event {
        let base = match self.robot.base_pose() {
            Ok(b) => b.value,
            Err(e) => return Interrupt::Robot(e).into(),
        };
        let fused = fuse(&self.world.views);
        self.world.see(&fused);
        // Learn the floor in front of the robot; when that patch shows no floor (facing a wall, an
        // object), keep the model learnt before.
        let floor = match FloorModel::learn(&fused, &base, &self.config.perception.floor) {
            Ok(floor) => floor,
            Err(e) => match self.world.floor.clone() {
                Some(floor) => floor,
                None => return Event::PerceptionFailed(e.to_string()),
            },
        };
        match detect_on_floor(
            &fused,
            floor.clone(),
            &base,
            &self.config.perception,
            &self.world.prisms,
        ) {
            Ok(detection) => {
                let floor_points = floor.split(&fused).0;
                self.world.floor = Some(floor);
                let here = nalgebra::Point2::from(base.translation.vector);
                self.world
                    .remember(detection.prisms, &floor_points, &here, &self.config);
                let stamp = self.robot.now();
                self.observer.prisms(stamp, &self.world.prisms);
                Event::ObjectsDetected {
                    count: self.world.prisms.len(),
                }
            }
            Err(e) => Event::PerceptionFailed(e.to_string()),
        }
    }
}
