//! The last look before a run ends at the goal: where people walked about, what the robot
//! remembers that may have been someone standing is looked at once more, and what the grid then
//! sees gone is forgotten.
//!
//! A person who stood still through a look becomes an obstacle like a chair, and one seen moving is
//! kept while out of view (see [`super::movers`]); either may walk off where no later frame looks.
//! The walk's frames look ahead along the path, not back at what it went round, so the memory the
//! run hands over would keep them as ghosts. The glances go into the grid like every other frame,
//! and the grid's rules ([`Runner::reconcile`]) forget what they show gone; nothing new is built
//! from them.
//!
//! What the glances could not show — someone who stood beyond the floor the camera returns from
//! the goal, or behind a passer-by at the moment of the glance — is looked at once more from
//! nearer: from where the robot stands when that is near enough, else from a step towards it.
//! The robot then walks back into the goal region. It walks off the goal for this only on its
//! first arrival (an arrival after a failed way back only glances), and each place it looks from
//! lies no farther from the goal than it walks in one look-around's time.

use nalgebra::Point2;
use nudge_perception::{ObjectId, Prism};

use super::movers::PERSON_EXTENT;
use super::navigate::wrap;
use super::{Interrupt, Runner};
use crate::record::Observer;
use crate::robot::Robot;

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Looks once at each remembered obstacle that may have been a person ([`Self::may_be_person`])
    /// within the camera's range of where the robot stands, when the run saw people about; turns the base where the head's
    /// pan cannot reach one. Then looks closer at what the glances left unknown
    /// ([`Self::look_closer`]). Leaves the head in the walking view; whether the robot stands in
    /// the goal region at the end.
    pub(crate) fn recheck_at_goal(&mut self) -> Result<bool, Interrupt> {
        if !self.people_about() {
            return Ok(true);
        }
        let base = self.robot.base_pose()?.value;
        let here = Point2::from(base.translation.vector);
        // One sweep leftwards from the head's rightmost pan: what the head reaches first, then
        // round behind, so the base turns at most once round.
        let right = self.config.model.head.pan_limits[0];
        let sweep = |p: &Prism| {
            p.centroid().map_or(0.0, |c| {
                let rel = c - here;
                (rel.y.atan2(rel.x) - base.rotation.angle() - right)
                    .rem_euclid(std::f64::consts::TAU)
            })
        };
        let mut asked: Vec<(f64, ObjectId)> = self
            .world
            .prisms
            .iter()
            .filter(|p| {
                self.may_be_person(p) && p.distance_xy(&here) <= self.config.model.camera.max_range
            })
            .map(|p| (sweep(p), p.id))
            .collect();
        asked.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let asked: Vec<ObjectId> = asked.into_iter().map(|(_, id)| id).collect();
        // Frames are stamped by the robot's clock, the floor's memory by the time let pass.
        let (clock, elapsed) = (self.robot.now(), self.robot.elapsed());
        for id in &asked {
            // An earlier glance may have shown this one gone already.
            let Some(at) = self
                .world
                .prisms
                .iter()
                .find(|p| p.id == *id)
                .and_then(Prism::centroid)
            else {
                continue;
            };
            self.glance_at(at)?;
            self.forget_looked_gone(&asked, clock, elapsed);
        }
        let (looked, home) = self.look_closer(clock, elapsed)?;
        if !asked.is_empty() || looked {
            self.robot
                .start_point_head(0.0, self.config.grid.watch_tilt)?;
            self.wait(|r| r.head_status())?;
        }
        Ok(home)
    }

    /// Looks again, nearer, at each obstacle that may have been someone standing
    /// ([`Self::may_be_person`], and not the room's structure: what lies at the
    /// edge of everything seen is a wall's end or a corner, which the camera cannot reach from the
    /// goal however long it looks) which no frame since `clock` showed either gone or there,
    /// nearest first: from where the robot stands when the camera returns floor out past its
    /// centre from there ([`Self::proof_reach`]), else from the point on the way to it where it
    /// does, if that lies within the detour ([`Self::detour`]) of the goal. Walks back into the
    /// goal region when it walked off. Whether it glanced at anything, and whether it stands in the
    /// goal region at the end.
    fn look_closer(&mut self, clock: f64, elapsed: f64) -> Result<(bool, bool), Interrupt> {
        let goal = self.config.goal;
        let detour = if self.world.looked_closer {
            0.0
        } else {
            self.detour()
        };
        let reach = self.proof_reach();
        let mut asked: Vec<(f64, ObjectId)> = self
            .world
            .prisms
            .iter()
            .filter(|p| self.may_be_person(p))
            .filter(|p| !self.world.is_structure(p, &self.config))
            .filter(|p| !self.world.grid_saw_it_there(p, clock))
            .filter_map(|p| {
                let d = (p.centroid()? - goal).norm();
                (d <= reach + detour).then_some((d, p.id))
            })
            .collect();
        asked.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let asked: Vec<ObjectId> = asked.into_iter().map(|(_, id)| id).collect();
        let (mut looked, mut walked) = (false, false);
        for id in &asked {
            let Some(prism) = self.world.prisms.iter().find(|p| p.id == *id) else {
                continue;
            };
            if self.world.grid_saw_it_there(prism, clock) {
                continue;
            }
            let Some(at) = prism.centroid() else {
                continue;
            };
            let away = self.position()? - at;
            if away.norm() > reach {
                let from = at + away.normalize() * reach;
                if (from - goal).norm() > detour {
                    continue;
                }
                self.world.looked_closer = true;
                walked = true;
                let stamp = self.robot.now();
                self.observer.note(
                    stamp,
                    crate::record::LogLevel::Info,
                    &format!(
                        "at the goal: walking to ({:.2}, {:.2}) to look closer at {id}, {:.1} m off",
                        from.x,
                        from.y,
                        away.norm()
                    ),
                );
                self.walk_to(Some(from))?;
            }
            self.glance_at(at)?;
            looked = true;
            self.forget_looked_gone(&asked, clock, elapsed);
        }
        if !walked {
            return Ok((looked, true));
        }
        Ok((looked, self.walk_to(None)?))
    }

    /// How far from its centre (m) the robot may stand to see `prism` gone in one frame: the
    /// farthest floor the camera returns, its range less the head's height
    /// (√(5² − 1.4²) ≈ 4.8 m), less the end of a beam with no return that the grid does not
    /// count as seen (its `clear_tail`, 0.3 m) and a grid cell for where the walk stops. The
    /// grid's rules ask for half of its cells ([`super::world::WorldModel::grid_saw_it_gone`],
    /// [`super::world::WorldModel::floor_seen_since`]): those nearer than its centre.
    fn proof_reach(&self) -> f64 {
        let (range, height) = (
            self.config.model.camera.max_range,
            self.config.model.head.height,
        );
        let cell = self
            .world
            .grid
            .as_ref()
            .map_or(0.0, |g| g.geometry().resolution());
        (range * range - height * height).max(0.0).sqrt() - self.config.grid.rules.clear_tail - cell
    }

    /// How far from the goal (m) the robot walks to look closer: as far as it walks in the time
    /// of one look-around (1.5 m in 10 s at the 0.15 m/s gait), so that the last look, there and
    /// back, costs no more than two more look-arounds would.
    fn detour(&self) -> f64 {
        self.world.look_time * self.config.model.body.walk_speed
    }

    /// Forgets the obstacles among `asked` that the glances since `clock` (the robot's clock;
    /// `elapsed`, the same moment as time let pass) showed gone: a tall one whose cells their rays
    /// crossed without a return ([`super::world::WorldModel::grid_saw_it_gone`]); one no taller
    /// than the grid's clearing height, under which its rays prove nothing, once they saw bare floor
    /// in half its cells.
    fn forget_looked_gone(&mut self, asked: &[ObjectId], clock: f64, elapsed: f64) {
        let low = self.config.grid.reduction.clear_height;
        let world = &self.world;
        let gone: Vec<ObjectId> = world
            .prisms
            .iter()
            .filter(|p| asked.contains(&p.id))
            .filter(|p| {
                if p.z_max > low {
                    world.grid_saw_it_gone(p, clock)
                } else {
                    world.floor_seen_since(p, elapsed)
                }
            })
            .map(|p| p.id)
            .collect();
        self.forget(&gone, "at the goal: looked at again and gone");
    }

    /// Whether `prism` may have been someone standing: nothing the robot tested, moved or found
    /// static, and no larger than people ([`PERSON_EXTENT`]).
    fn may_be_person(&self, prism: &Prism) -> bool {
        self.world.untouched(prism.id) && prism.extent() <= PERSON_EXTENT
    }

    /// Points the camera at the floor at `at` (turning the base first where the head's pan cannot
    /// reach) and takes one frame into the grid, tilted no further down than the grid takes frames.
    fn glance_at(&mut self, at: Point2<f64>) -> Result<(), Interrupt> {
        let base = self.robot.base_pose()?.value;
        let rel = at - Point2::from(base.translation.vector);
        let bearing = rel.y.atan2(rel.x);
        let [right, left] = self.config.model.head.pan_limits;
        let mut pan = wrap(bearing - base.rotation.angle());
        if pan < right || pan > left {
            self.turn_to(bearing)?;
            let yaw = self.robot.base_pose()?.value.rotation.angle();
            pan = wrap(bearing - yaw).clamp(right, left);
        }
        let tilt = self
            .config
            .model
            .head
            .height
            .atan2(rel.norm().max(0.1))
            .min(self.config.grid.watch_tilt);
        self.robot.start_point_head(pan, tilt)?;
        self.wait(|r| r.head_status())?;
        self.take_frame(true)?;
        Ok(())
    }
}
