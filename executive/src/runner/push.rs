//! Pushing: planning a push, the push test (force, hand travel, colour ICP), and clearing the way.

use nalgebra::{Isometry3, Point2, Point3, Translation3, UnitQuaternion, Vector2, Vector3};
use nudge_motion::{
    FloorCheck, GoalRegion, Obstacle, PushError, SeenFloor, StateValidity, plan_push_over,
};
use nudge_perception::{CloudFrame, ColourCloud, IcpConfig, ObjectId, Prism, colour_icp};

use super::unseen::Floor;
use super::{Interrupt, Runner};
use crate::event::Event;
use crate::push_test::{IcpReading, PushEvidence, PushIntent};
use crate::record::Observer;
use crate::robot::{GuardedMove, HandOutcome, Robot, Stamped, Wrench};

/// Clear strokes start this far beyond the body's radius (m): room for the hand and the walk's margin.
const STROKE_STANDOFF: f64 = 0.12;
/// Approach gap before a face whose position the hand measured (m): it is known within a centimetre.
const MEASURED_GAP: f64 = 0.03;
/// Shortest clearing stroke worth making (m): the hand's approach gap over again, so it presses.
const MIN_STROKE: f64 = 0.05;

/// What one guarded stroke measured.
struct Stroke {
    outcome: HandOutcome,
    peak_force: f64,
    contact: bool,
    travel_after_contact: f64,
    end_x: f64,
    trace: Vec<(f64, f64)>,
}

impl<R: Robot, O: Observer> Runner<R, O> {
    fn prism(&self, id: ObjectId) -> Option<&Prism> {
        self.world.prisms.iter().find(|p| p.id == id)
    }

    /// Plans a push of `target` from where the robot stands: standing on seen floor and sweeping the
    /// object over seen floor or its own shadow, unless `allow_unseen` (no viewpoint could show it).
    pub(crate) fn plan_push(&mut self, target: ObjectId, allow_unseen: bool) -> Event {
        let here = match self.robot.base_pose() {
            Ok(p) => Point2::from(p.value.translation.vector),
            Err(e) => return Interrupt::Robot(e).into(),
        };
        let Some(prism) = self.prism(target).cloned() else {
            return Event::NoPushPlan {
                reason: format!("{target} is no longer seen"),
                unseen: false,
            };
        };
        let goal = match GoalRegion::new(self.config.goal, self.config.goal_tolerance) {
            Ok(g) => g,
            Err(e) => {
                return Event::NoPushPlan {
                    reason: e.to_string(),
                    unseen: false,
                };
            }
        };
        let eye = self.config.view.camera.eye_height;
        let own_shadow = self.world.own_shadow(&prism, eye);
        // Full clearance first; where no stand pose is reachable with it (perception's hulls a few
        // centimetres generous in a tight room), half of it, then none: the guarded walk stops short
        // of contact anyway.
        let mut planned = Err(PushError::NoStandPose(target));
        let mut unseen = false;
        for validity in self.world.validities(&here, &self.config) {
            let validity = match validity {
                Ok(v) if v.is_free(&here) => v,
                Ok(_) => continue,
                Err(reason) => {
                    return Event::NoPushPlan {
                        reason,
                        unseen: false,
                    };
                }
            };
            let floor = self.world.grid.as_ref().map(|grid| Floor {
                grid,
                memory: &self.world.memory,
            });
            let check = floor
                .as_ref()
                .filter(|_| !allow_unseen)
                .map(|seen| FloorCheck {
                    seen: seen as &dyn SeenFloor,
                    own_shadow,
                });
            let attempt = plan_push_over(
                &prism,
                &validity,
                &here,
                &goal,
                &self.config.push,
                check,
                &mut self.rng,
            );
            // Floor not yet seen at any clearance is worth a look, whatever the smaller ones say.
            unseen |= matches!(attempt, Err(PushError::UnseenFloor(_)));
            planned = attempt;
            if planned.is_ok() {
                break;
            }
        }
        match planned {
            Ok(plan) => {
                let intent = PushIntent {
                    target,
                    stand: plan.stand_pose,
                    hand_height: plan.hand_height,
                    direction: plan.direction,
                    distance: plan.distance,
                };
                let stamp = self.robot.now();
                self.observer.push(stamp, &intent, None);
                self.world.push_plan = Some(plan);
                Event::PushPlanned(intent)
            }
            Err(e) => {
                // Ruled out for another reason, an object whose surroundings are partly unseen (its
                // hidden side, floor behind it, an outline put together from pieces seen from far)
                // is still worth a look before it is given up.
                let seen_in_part = !allow_unseen && self.seen_in_part(&prism);
                let (outline, from) = self.world.outline_seen(&prism);
                let why = if unseen {
                    PushError::UnseenFloor(target).to_string()
                } else {
                    e.to_string()
                };
                Event::NoPushPlan {
                    reason: format!(
                        "{why} ({:.0} % of its outline seen, from {} place(s))",
                        outline * 100.0,
                        from.len()
                    ),
                    unseen: unseen || seen_in_part,
                }
            }
        }
    }

    /// The contact point in `base_link` (x ahead, y left), from the plan or, failing that, the prism.
    fn contact_in_base(&mut self, intent: &PushIntent) -> Result<Point2<f64>, Interrupt> {
        let base = self.robot.base_pose()?.value;
        let contact = self
            .world
            .push_plan
            .as_ref()
            .filter(|p| p.object == intent.target)
            .map(|p| Point2::new(p.contact_point.x, p.contact_point.y))
            .unwrap_or_else(|| {
                Point2::from(intent.stand.translation.vector) + intent.direction.into_inner() * 0.5
            });
        Ok(base.inverse_transform_point(&contact))
    }

    /// Runs one push test: clouds before, a guarded stroke, clouds after, colour ICP.
    pub(crate) fn push_test(&mut self, intent: &PushIntent) -> Event {
        match self.run_push_test(intent) {
            Ok(evidence) => Event::PushTestDone(evidence),
            Err(i) => i.into(),
        }
    }

    fn run_push_test(&mut self, intent: &PushIntent) -> Result<PushEvidence, Interrupt> {
        let motion = self.config.push_motion.clone();
        let prism = self.prism(intent.target).cloned();
        let before = match &prism {
            Some(p) => Some(self.object_points(p, Vector2::zeros())?),
            None => None,
        };
        let contact = self.contact_in_base(intent)?;
        let from_x = (contact.x - motion.approach_gap).max(motion.near);
        let to_x = (contact.x + motion.test_travel).min(motion.reach);
        let limit = self.config.executive.force_limit;
        let stroke = self.stroke(from_x, to_x, contact.y, intent.hand_height, limit)?;
        if stroke.contact {
            let base = self.robot.base_pose()?.value;
            self.world.touched = Some((intent.target, base * Point2::new(stroke.end_x, contact.y)));
        }
        self.retract()?;
        let direction = intent.direction.into_inner();
        let icp = match (&prism, before) {
            (Some(p), Some(before)) => {
                let shift = direction * stroke.travel_after_contact;
                let after = self.object_points(p, shift)?;
                let reading = icp_reading(&before, &after, shift);
                let classifier = &self.config.executive.classifier;
                // Whatever the finding, a trusted motion reading is where the object is now: a retest
                // plans from there.
                if let Some((icp, moved)) = reading
                    && classifier.trusts(&icp)
                    && icp.displacement >= classifier.still_below
                {
                    self.displace(intent.target, moved);
                }
                reading.map(|r| r.0)
            }
            _ => None,
        };
        let stamp = self.robot.now();
        self.observer
            .push(stamp, intent, Some(-direction * stroke.peak_force));
        Ok(PushEvidence {
            force_limit: self.config.executive.force_limit,
            peak_force: stroke.peak_force,
            reached_limit: matches!(stroke.outcome, HandOutcome::ForceLimit { .. }),
            contact: stroke.contact,
            hand_travel: stroke.travel_after_contact,
            icp,
            force_trace: stroke.trace,
        })
    }

    /// Pushes a movable object along the plan in guarded strokes, walking after it between strokes.
    pub(crate) fn clear_path(&mut self, intent: &PushIntent) -> Event {
        match self.run_clear_path(intent) {
            Ok(event) => event,
            Err(i) => i.into(),
        }
    }

    fn run_clear_path(&mut self, intent: &PushIntent) -> Result<Event, Interrupt> {
        const MAX_STROKES: usize = 12;
        let motion = self.config.push_motion.clone();
        let direction = intent.direction.into_inner();
        // The face on the push line, in the map: where the push test's hand left it, else the plan's.
        // The test's touch holds for this push only, made from the test's stand pose: a later clear of
        // the same object starts from another pose, most likely at another face.
        let (mut face_map, mut measured) = match self.world.touched.take() {
            Some((id, at)) if id == intent.target => (at, true),
            _ => {
                let base = self.robot.base_pose()?.value;
                (base * self.contact_in_base(intent)?, false)
            }
        };
        // Strokes start this close to the body axis: as long as the arm can push in one go.
        let stroke_start = (self.config.robot.radius + STROKE_STANDOFF).max(motion.near);
        let mut moved = 0.0;
        let mut peak: f64 = 0.0;
        for _ in 0..MAX_STROKES {
            let remaining = intent.distance - moved;
            if remaining <= 0.02 {
                break;
            }
            let mut base = self.robot.base_pose()?.value;
            // Walk after the object so the next stroke is a long one, but no further than the rest
            // of the push needs beyond the arm's reach (push planning checked only that much).
            let face_x = base.inverse_transform_point(&face_map).x;
            let gap = if measured {
                MEASURED_GAP
            } else {
                motion.approach_gap
            };
            // At least far enough that a stroke from before the face fits in the arm's reach.
            let at_least = face_x - gap + MIN_STROKE - motion.reach;
            let ahead = (face_x + remaining - motion.reach)
                .max(at_least)
                .min(face_x - stroke_start);
            if ahead > 0.02 {
                self.step_forward(direction, ahead)?;
                base = self.robot.base_pose()?.value;
            }
            let face = base.inverse_transform_point(&face_map);
            let from_x = (face.x - gap).max(motion.near);
            let to_x = (face.x + remaining).min(motion.reach);
            if to_x - from_x < MIN_STROKE {
                // The object is beyond the arm's reach and the body could not walk after it (the
                // walk stopped against something): this push ends here; a look shows where it is.
                break;
            }
            let limit = self.config.executive.clear_force_limit;
            let stroke = self.stroke(from_x, to_x, face.y, intent.hand_height, limit)?;
            peak = peak.max(stroke.peak_force);
            moved += stroke.travel_after_contact;
            self.retract()?;
            if let HandOutcome::ForceLimit { .. } = stroke.outcome {
                return Ok(Event::Jammed {
                    peak_force: peak,
                    moved,
                });
            }
            if stroke.contact {
                face_map = base * Point2::new(stroke.end_x, face.y);
                measured = true;
            } else {
                // The object is beyond the stroke: step up to it and search again.
                face_map += direction * (to_x - face.x).max(0.05);
                measured = false;
            }
        }
        self.displace(intent.target, direction * moved);
        let stamp = self.robot.now();
        self.observer.push(stamp, intent, Some(-direction * peak));
        Ok(Event::Cleared { moved })
    }

    fn step_forward(&mut self, direction: Vector2<f64>, distance: f64) -> Result<(), Interrupt> {
        let here = self.robot.base_pose()?.value;
        let to = Point2::from(here.translation.vector) + direction * distance;
        self.robot.start_walk(&[to])?;
        self.wait(|r| r.walk_status())?;
        Ok(())
    }

    fn retract(&mut self) -> Result<(), Interrupt> {
        self.robot.start_retract()?;
        self.wait(|r| r.hand_status())?;
        Ok(())
    }

    /// One guarded stroke along `base_link` x at lateral offset `y` and height `z` that stops at
    /// `force_limit`, watching the wrist.
    fn stroke(
        &mut self,
        from_x: f64,
        to_x: f64,
        y: f64,
        z: f64,
        force_limit: f64,
    ) -> Result<Stroke, Interrupt> {
        let motion = self.config.push_motion.clone();
        // The plan puts the hand anywhere within the arm's sideways reach, its edges included; a walk
        // that ends a few millimetres off would put the line just outside and the arm would refuse it.
        // Pushing those millimetres off the planned line is harmless.
        let y = clamp_lateral(y, self.config.push.reach_y);
        self.robot.tare()?;
        self.robot.drain_wrenches()?;
        self.robot.start_guarded_move(GuardedMove {
            from: Point3::new(from_x, y, z),
            to: Point3::new(to_x.max(from_x), y, z),
            speed: motion.speed,
            force_limit,
        })?;
        let mut trace = Vec::new();
        let mut hand: Vec<Stamped<Point3<f64>>> = Vec::new();
        let mut contact_stamp: Option<f64> = None;
        let outcome = loop {
            let status = self.robot.hand_status()?;
            hand.push(self.robot.hand_position()?);
            for sample in self.robot.drain_wrenches()? {
                self.record_wrench(&sample, &mut trace);
                let f = sample.value.force_norm();
                if contact_stamp.is_none() && f >= motion.contact_threshold {
                    contact_stamp = Some(sample.stamp);
                }
            }
            if let crate::robot::ActionStatus::Done(outcome) = status {
                break outcome;
            }
            self.tick()?;
        };
        let end_x = hand.last().map_or(from_x, |h| h.value.x);
        let travel_after_contact = contact_stamp.map_or(0.0, |t| {
            let at_contact = hand
                .iter()
                .rev()
                .find(|h| h.stamp <= t)
                .or(hand.first())
                .map_or(end_x, |h| h.value.x);
            (end_x - at_contact).max(0.0)
        });
        let peak_force = trace.iter().map(|(_, f)| *f).fold(0.0, f64::max);
        Ok(Stroke {
            outcome,
            peak_force,
            contact: contact_stamp.is_some(),
            travel_after_contact,
            end_x,
            trace,
        })
    }

    fn record_wrench(&mut self, sample: &Stamped<Wrench>, trace: &mut Vec<(f64, f64)>) {
        self.observer.wrench(sample.stamp, &sample.value);
        trace.push((sample.stamp, sample.value.force_norm()));
    }

    /// Looks at `prism` (moved by `shift`) and returns its points in the map frame.
    fn object_points(
        &mut self,
        prism: &Prism,
        shift: Vector2<f64>,
    ) -> Result<ColourCloud, Interrupt> {
        let base = self.robot.base_pose()?.value;
        let centre = prism
            .footprint
            .iter()
            .fold(Vector2::zeros(), |acc, p| acc + p.coords)
            / prism.footprint.len().max(1) as f64
            + shift;
        let rel = centre - base.translation.vector;
        let pan = wrap(rel.y.atan2(rel.x) - base.rotation.angle());
        let aim_z = 0.5 * (prism.z_min + prism.z_max);
        let eye = self.config.view.camera.eye_height;
        let tilt = (eye - aim_z).atan2(rel.norm().max(0.1));
        self.robot.start_point_head(pan, tilt)?;
        self.wait(|r| r.head_status())?;
        let cloud = self.robot.capture()?;
        self.observer.cloud(&cloud);
        self.sense(&cloud, false);
        Ok(crop(
            &cloud.to_map(),
            prism,
            shift,
            self.config.push_motion.crop_margin,
        ))
    }
}

fn wrap(a: f64) -> f64 {
    (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
}

/// The points of `cloud` (map frame) inside `prism`'s footprint moved by `shift` and grown by `margin`,
/// above the floor and below its top.
fn crop(cloud: &ColourCloud, prism: &Prism, shift: Vector2<f64>, margin: f64) -> ColourCloud {
    let mut out = ColourCloud::empty(CloudFrame::Map, *cloud.sensor_pose(), cloud.stamp());
    let Ok(region) = Obstacle::from_prism(prism).and_then(|o| o.translated(&shift)) else {
        return out;
    };
    for (_, p, c) in cloud.iter_valid() {
        let q = Point2::new(f64::from(p.x), f64::from(p.y));
        let z = f64::from(p.z);
        if z > 0.02
            && z < prism.z_max + 0.05
            && (region.contains(&q) || region.distance_to_point(&q) <= margin)
        {
            out.push(p, c);
        }
    }
    out
}

/// Colour ICP from the points before to the points after, starting from the hand's travel: the reading
/// and the object's planar displacement.
fn icp_reading(
    before: &ColourCloud,
    after: &ColourCloud,
    shift: Vector2<f64>,
) -> Option<(IcpReading, Vector2<f64>)> {
    let initial = Isometry3::from_parts(
        Translation3::new(shift.x, shift.y, 0.0),
        UnitQuaternion::identity(),
    );
    let result = colour_icp(before, after, &initial, &IcpConfig::default()).ok()?;
    let centroid: Point3<f64> = before.centroid()?;
    let moved: Vector3<f64> = result.transform * centroid - centroid;
    let reading = IcpReading {
        displacement: moved.xy().norm(),
        yaw_deg: result.yaw_deg,
        converged: result.converged,
        fitness: result.fitness,
        rmse: result.rmse,
    };
    Some((reading, moved.xy()))
}

/// How far outside the arm's sideways reach (m) a stroke's line is moved back to its edge: the error
/// of a walk to a stand pose, not a plan that asked for more than the arm can do.
const LATERAL_SLACK: f64 = 0.02;

/// `y` moved onto the nearer edge of `reach` when it lies at most [`LATERAL_SLACK`] outside it;
/// otherwise unchanged (the arm then refuses a line the plan never meant).
fn clamp_lateral(y: f64, (lo, hi): (f64, f64)) -> f64 {
    if y < lo && y >= lo - LATERAL_SLACK {
        lo
    } else if y > hi && y <= hi + LATERAL_SLACK {
        hi
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stroke_line_just_outside_the_sideways_reach_is_moved_onto_its_edge() {
        // Invariant: a lateral offset a few millimetres past the reach (a stand pose at the reach's edge, missed by the walk's error) is moved onto the edge; one inside is kept; one far outside is left for the arm to refuse.
        let reach = (-0.4, 0.4);
        assert_eq!(clamp_lateral(-0.4004, reach), -0.4);
        assert_eq!(clamp_lateral(0.4006, reach), 0.4);
        assert_eq!(clamp_lateral(-0.13, reach), -0.13);
        assert_eq!(clamp_lateral(-0.4, reach), -0.4);
        assert_eq!(clamp_lateral(0.55, reach), 0.55);
        assert_eq!(clamp_lateral(-0.55, reach), -0.55);
    }
}
