//! Looking around and turning what was seen into obstacles.

use nalgebra::{Isometry2, Isometry3, Translation3, UnitQuaternion};
use nudge_perception::{FloorModel, LookChanges, detect_on_floor};

use super::{Interrupt, Runner};
use crate::event::Event;
use crate::record::Observer;
use crate::robot::Robot;

/// Where a head of `(pan, tilt)` at `eye_height` on `base` looks from, for frames without a capture
/// yet.
pub(crate) fn camera_pose(
    base: &Isometry2<f64>,
    head: (f64, f64),
    eye_height: f64,
) -> Isometry3<f64> {
    let t = base.translation.vector;
    Isometry3::from_parts(
        Translation3::new(t.x, t.y, eye_height),
        UnitQuaternion::from_euler_angles(0.0, head.1, base.rotation.angle() + head.0),
    )
}

/// Whether a floor model learnt again, `new`, describes the floor `known` was learnt on: `known` takes
/// the mean of `new` (height and colour) for floor.
fn same_floor(known: &FloorModel, new: &FloorModel) -> bool {
    let c = new.mean_colour();
    let level = |v: f64| v.round().clamp(0.0, 255.0) as u8;
    known.is_floor(new.height(), [level(c.x), level(c.y), level(c.z)])
}

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
        let started = self.robot.now();
        for view in &views {
            self.robot
                .start_point_head(view.pan_deg.to_radians(), view.tilt_deg.to_radians())?;
            self.wait(|r| r.head_status())?;
            let cloud = self.take_frame(true)?;
            self.world.views.push(cloud);
        }
        self.publish_grid();
        self.world.look_time = self.robot.now() - started;
        if let Ok(base) = self.robot.base_pose() {
            self.world
                .looks
                .push(nalgebra::Point2::from(base.value.translation.vector));
        }
        // A look from a viewpoint that left cells it was chosen to show unseen: they are inside
        // something, or hidden from there.
        if let (Some(cells), Some(grid)) = (self.world.pending_view.take(), &self.world.grid) {
            self.world.memory.fail_unseen(grid, &cells);
        }
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
        // What changed while the head turned: a person's earlier places never become obstacles.
        let width = self.world.views.first().map_or(1, |v| v.width().max(1));
        let pitch = self.config.model.camera.h_fov() / width as f64;
        let changes = LookChanges::new(&self.world.views, pitch);
        // Only the look's own views are compared: a look from elsewhere sees edges and thin parts
        // differently enough to read change into a still room.
        let split = changes.split(&self.world.views, None);
        let (fused, arrived) = self.fold_changes(split, &changes);
        self.world.see(&fused);
        // Learn the floor in front of the robot; when that patch shows no floor (facing a wall, an
        // object), keep the model learnt before.
        // A patch that the known floor would not call floor (the bottom of an object the robot stands
        // next to, a mat) does not replace it either.
        let learnt = FloorModel::learn(&fused, &base, &self.config.perception.floor);
        let floor = match (learnt, self.world.floor.clone()) {
            (Ok(new), Some(known)) if !same_floor(&known, &new) => known,
            (Ok(new), _) => new,
            (Err(_), Some(known)) => known,
            (Err(e), None) => return Event::PerceptionFailed(e.to_string()),
        };
        match detect_on_floor(
            &fused,
            floor.clone(),
            &base,
            &self.config.perception,
            &self.world.prisms,
        ) {
            Ok(mut detection) => {
                self.world.number_fresh(&mut detection.prisms);
                let floor_points = floor.split(&fused).0;
                self.world.floor = Some(floor);
                // The look's steep views see the floor near the robot, which the grid leaves out.
                if let Some(grid) = &self.world.grid {
                    let geometry = *grid.geometry();
                    self.world.memory.saw(&geometry, &floor_points);
                    for prism in &detection.prisms {
                        self.world.memory.saw(&geometry, &prism.points);
                    }
                }
                let here = nalgebra::Point2::from(base.translation.vector);
                let movers = self.movers();
                let shown: Vec<Vec<nalgebra::Point2<f64>>> = detection
                    .prisms
                    .iter()
                    .map(|p| p.footprint.clone())
                    .collect();
                self.world
                    .remember(detection.prisms, &floor_points, &here, &self.config);
                self.forget_movers_out_of_sight(&movers, &shown);
                self.note_detected(&shown);
                self.note_arrivals(&arrived);
                self.note_arrived_on_free_floor();
                let stamp = self.robot.now();
                self.observer.prisms(stamp, &self.world.prisms);
                Event::ObjectsDetected {
                    count: self.world.prisms.len(),
                    gone: std::mem::take(&mut self.world.forgotten),
                }
            }
            Err(e) => Event::PerceptionFailed(e.to_string()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry2, Point3};
    use nudge_perception::{CloudFrame, ColourCloud, FloorConfig};

    /// A 1.2 m square of points at height `z` and colour `rgb` in front of a robot at the origin.
    fn patch(z: f32, rgb: [u8; 3], jitter: u8) -> ColourCloud {
        let mut cloud = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        for i in 0..60u8 {
            for j in 0..60u8 {
                let (x, y) = (0.3 + 0.02 * f32::from(i), -0.6 + 0.02 * f32::from(j));
                let d = (i.wrapping_mul(7) ^ j.wrapping_mul(13)) % (2 * jitter + 1);
                let c = rgb.map(|v| v.saturating_add(d).saturating_sub(jitter));
                let dz = 0.002 * (f32::from(d) / f32::from(2 * jitter + 1) - 0.5);
                cloud.push(Point3::new(x, y, z + dz), c);
            }
        }
        cloud
    }

    #[test]
    fn a_floor_learnt_on_an_object_does_not_replace_the_known_floor() {
        // Invariant: a floor model learnt again on the same floor is accepted, one learnt on something else near floor height (an orange cart's bottom 2 cm up) is not.
        let config = FloorConfig::default();
        let pose = Isometry2::identity();
        let known = FloorModel::learn(&patch(0.0, [150, 150, 140], 4), &pose, &config)
            .expect("a floor patch in front of the robot");
        let again = FloorModel::learn(&patch(0.001, [151, 149, 141], 4), &pose, &config)
            .expect("the same floor");
        let cart = FloorModel::learn(&patch(0.023, [200, 120, 30], 4), &pose, &config)
            .expect("points near floor height");
        assert!(same_floor(&known, &again));
        assert!(!same_floor(&known, &cart));
    }
}
