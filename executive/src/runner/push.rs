//! Pushing: planning a push, the push test (force, hand travel, colour ICP), and clearing the way.

use nalgebra::{Isometry3, Point2, Point3, Translation3, UnitQuaternion, Vector2, Vector3};
use nudge_motion::push::SHORT_PUSHES;
use nudge_motion::{
    FloorCheck, GoalRegion, Obstacle, PairRecord, PushConfig, PushError, SeenFloor, Sequence,
    StateValidity, Validity, plan_push_among, plan_sequence, single_removal_opens,
};
use nudge_perception::{CloudFrame, ColourCloud, IcpConfig, ObjectId, Prism, colour_icp};
use rand_chacha::ChaCha8Rng;

use super::config::RunConfig;
use super::navigate::{nearest_free, wrap};
use super::split::TestClouds;
use super::stroke::{Approach, Route, StrokeLine};
use super::unseen::Floor;
use super::world::WorldModel;
use super::{Interrupt, Runner};
use crate::event::Event;
use crate::push_test::{IcpReading, PushEvidence, PushIntent};
use crate::record::{LogLevel, Observer};
use crate::robot::{HandOutcome, Robot};
use crate::state::Purpose;

impl<R: Robot, O: Observer> Runner<R, O> {
    pub(super) fn prism(&self, id: ObjectId) -> Option<&Prism> {
        self.world.prisms.iter().find(|p| p.id == id)
    }

    /// Plans a push of `target` from where the robot stands: standing on seen floor and sweeping the
    /// object over seen floor or its own shadow, unless `allow_unseen` (no viewpoint could show it).
    ///
    /// A push test is planned among the short pushes only (up to [`SHORT_PUSHES`]), and without
    /// sequences: before the object is known to move, the robot commits to no long walk to a far
    /// face, and the test's stroke is the same whatever push follows it. Once the object is known
    /// movable, its clearing push is planned over the whole range, or as the first of two pushes.
    pub(crate) fn plan_push(
        &mut self,
        target: ObjectId,
        purpose: Purpose,
        allow_unseen: bool,
    ) -> Event {
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
        let eye = self.config.model.head.height;
        let (own_shadow, shadow_eye) = self.world.own_shadow(&prism, eye);
        // Full clearance first; where no stand pose is reachable with it (perception's hulls a few
        // centimetres generous in a tight room), half of it, then none: the guarded walk stops short
        // of contact anyway.
        let testing = purpose == Purpose::Test;
        let mut push_config = if testing {
            PushConfig {
                distances: self
                    .config
                    .push
                    .distances
                    .iter()
                    .copied()
                    .filter(|d| *d <= SHORT_PUSHES + 1e-9)
                    .collect(),
                ..self.config.push.clone()
            }
        } else {
            PushConfig {
                far_when_shut: true,
                ..self.config.push.clone()
            }
        };
        // An object that tipped under the hand is pushed at no more than half its height from then
        // on, as its retest was (see `Ambiguity::Tipped`).
        if self.world.objects.get(target).tipped {
            let (low, high) = push_config.reach_z;
            push_config.reach_z = (low, high.min((prism.z_max / 2.0).max(low)));
        }
        let mut validities = Vec::new();
        for validity in self.world.validities(&here, &self.config) {
            match validity {
                Ok(v) => validities.push(v),
                Err(reason) => {
                    return Event::NoPushPlan {
                        reason,
                        unseen: false,
                    };
                }
            }
        }
        let starts = push_starts(&here, validities);
        let movers = self.world.known_movers(target);
        let mut planned = Err(PushError::NoStandPose(target));
        let mut unseen = false;
        let mut searched = None;
        for (validity, from) in starts {
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
                    eye: shadow_eye,
                });
            let attempt = plan_push_among(
                &prism,
                &validity,
                &from,
                &goal,
                &push_config,
                check,
                &movers,
                &mut self.rng,
            );
            // A push that does not open the way may still be the first of two that do.
            let attempt = match attempt {
                Ok(single) if !single.opens_path && !testing => {
                    let found = search_sequence(
                        &self.world,
                        &self.config,
                        &validity,
                        &from,
                        &goal,
                        check,
                        single.object,
                        &mut self.rng,
                    );
                    let plan = match &found {
                        Ok(sequence) => Ok(sequence.first.clone()),
                        // A push that does not open the way, where a longer one was refused only
                        // for floor not yet seen: look there first (or, with nothing to look
                        // from, push into it), rather than push short and look again.
                        Err(_) if single.unseen_refused => {
                            unseen = true;
                            Err(PushError::UnseenFloor(target))
                        }
                        Err(_) => Ok(single),
                    };
                    searched = Some(found);
                    plan
                }
                other => other,
            };
            // A push at this clearance refused only for floor not yet seen is worth a look: the
            // smaller clearances are for stand poses a tight room leaves no room for, not a way
            // around a look (what they open is a way a few centimetres wide).
            unseen |= matches!(attempt, Err(PushError::UnseenFloor(_)));
            planned = attempt;
            if planned.is_ok() || unseen {
                break;
            }
        }
        if let Some(found) = searched {
            self.note_sequence(found);
        }
        if let Some(why) = planned
            .as_ref()
            .ok()
            .and_then(|plan| self.person_near_push(&prism, plan))
        {
            return Event::PersonNearPush { reason: why };
        }
        match planned {
            Ok(plan) => {
                let intent = PushIntent {
                    target,
                    stand: plan.stand_pose,
                    hand_height: plan.hand_height,
                    clear_height: plan.clear_height,
                    direction: plan.direction,
                    distance: plan.distance,
                    opens_way: plan.opens_path,
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

    /// Notes what a sequence search found, and keeps the pairs it considered when it found none.
    fn note_sequence(&mut self, found: Result<Sequence, Vec<PairRecord>>) {
        match found {
            Ok(sequence) => {
                let stamp = self.robot.now();
                self.observer.note(
                    stamp,
                    LogLevel::Info,
                    &format!(
                        "no single push opens the way: pushing {} {:.1} m, then {} {:.1} m, does",
                        sequence.first.object,
                        sequence.first.distance,
                        sequence.second.object,
                        sequence.second.distance
                    ),
                );
                self.world.sequences.clear();
            }
            Err(records) => self.world.sequences = records,
        }
    }

    /// How far (m) along the push this object's face lies beyond where the world model has it, as
    /// the hand last touched it (the push test before this one, whose colour ICP may not have been
    /// trusted to move the model), where that is more than half the approach gap (perception's few
    /// centimetres): `None` for an object the hand has not touched since, or whose model stands
    /// where the hand left it.
    fn slid_since_touched(&mut self, intent: &PushIntent) -> Result<Option<f64>, Interrupt> {
        let Some(at) = self
            .world
            .touched
            .filter(|(id, _)| *id == intent.target)
            .map(|(_, at)| at)
        else {
            return Ok(None);
        };
        let Some(prism) = self.prism(intent.target) else {
            return Ok(None);
        };
        let d = intent.direction.into_inner();
        // Along the hand's line through the touch, from a metre before it.
        let from = at - d;
        let Some(entry) = entry_along(&prism.footprint, &from, &d) else {
            return Ok(None);
        };
        let along = 1.0 - entry;
        Ok((along > self.config.push_motion.approach_gap / 2.0).then_some(along))
    }

    /// The contact point in `base_link` (x ahead, y left), from the plan or, failing that, the prism.
    pub(super) fn contact_in_base(
        &mut self,
        intent: &PushIntent,
    ) -> Result<Point2<f64>, Interrupt> {
        let base = self.robot.base_pose()?.value;
        Ok(base.inverse_transform_point(&self.planned_contact(intent)))
    }

    /// Where the hand of `intent` is planned to meet the object's face (map frame).
    pub(super) fn planned_contact(&self, intent: &PushIntent) -> Point2<f64> {
        self.world
            .push_plan
            .as_ref()
            .filter(|p| p.object == intent.target)
            .map(|p| Point2::new(p.contact_point.x, p.contact_point.y))
            .unwrap_or_else(|| {
                Point2::from(intent.stand.translation.vector) + intent.direction.into_inner() * 0.5
            })
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
        // Only a line lowered below the face's top band has to be brought into view.
        let hand_z = (intent.hand_height < intent.clear_height).then_some(intent.hand_height);
        // The face must lie near enough for the stroke to push it the test's travel within the
        // arm's reach. Where the hand last touched this object (the test before this one) is where
        // its face was when the hand left it, measured: an object that test slid away from the plan
        // (its colour ICP perhaps untrusted, so the world model did not move it) is looked for
        // there, and followed along the push first when that lies beyond a full test stroke, as a
        // clearing stroke follows. Else the stroke would touch it at the end of the arm's travel and
        // learn nothing (a "test" that neither moved nor resisted, which a second ambiguity then
        // takes for static).
        let direction = intent.direction.into_inner();
        let slid = self.slid_since_touched(intent)?;
        if let Some(d) = slid {
            let planned = self.contact_in_base(intent)?;
            if planned.x + d > self.config.model.arm.reach_x[1] - motion.test_travel {
                self.step_forward(direction, d, intent.target)?;
            }
        }
        let slid_by = direction * slid.unwrap_or(0.0);
        let view = match &prism {
            Some(p) => Some(self.look_at_object(p, slid_by, hand_z)?),
            None => None,
        };
        let before = match (&prism, &view) {
            (Some(p), Some(view)) => Some(crop(view, p, slid_by, motion.crop_margin)),
            _ => None,
        };
        let base_now = self.robot.base_pose()?.value;
        let planned =
            self.contact_in_base(intent)? + base_now.rotation.inverse_transform_vector(&slid_by);
        // The object's face on the hand's line as the look just taken shows it, where that is well
        // nearer than planned: a face planned on a hull's edge across a part never seen (a chair's back seen
        // only at its ends) may lie centimetres behind the real one, and a stroke started past the
        // real face would drive the hand into the object.
        let seen = match &before {
            Some(cloud) => {
                let half = self.config.push.hand_half_width;
                face_on_line(cloud, &base_now, planned.y, intent.hand_height, half, 0.0)
            }
            None => None,
        };
        // The approach gap absorbs a face up to half of it off the plan (perception's few
        // centimetres); only a face farther off than that moves the stroke: nearer, its start; farther
        // (an object a test before this one slid away), its start and end, or the stroke would end
        // where the hand first touches.
        let moved = seen.filter(|x| (x - planned.x).abs() > motion.approach_gap / 2.0);
        // No farther than the arm reaches with the approach gap before it: an object that slid out
        // of reach is touched, if at all, at the end of the arm's travel.
        let within_reach = self.config.model.arm.reach_x[1] - motion.approach_gap;
        let contact = Point2::new(
            moved.unwrap_or(planned.x).min(within_reach.max(planned.x)),
            planned.y,
        );
        // The hand goes to the line's start at its free speed, unguarded in effect: what it meets on
        // the way it strikes at that speed (the wrist's damping alone reads 40 N at 0.2 m/s). So the
        // line starts short of anything the look shows on the hand's way, the object's face as
        // perceived or not (a face beyond the crop around a hull seen in part).
        let first_in_way = match &view {
            Some(cloud) => {
                let base = self.robot.base_pose()?.value;
                let half = self.config.push.hand_half_width + HAND_WAY_MARGIN;
                // Nearer than the hand ever comes are the robot's own arm and hand.
                face_on_line(
                    cloud,
                    &base,
                    planned.y,
                    intent.hand_height,
                    half,
                    self.config.model.arm.reach_x[0],
                )
            }
            None => None,
        };
        let from_x = (contact.x.min(first_in_way.unwrap_or(f64::INFINITY)) - motion.approach_gap)
            .max(self.config.model.arm.reach_x[0]);
        // The way to the line's start is known clear where the look shows the object's face on the
        // line and nothing nearer than the stroke starts; else the hand gets there guarded.
        let clear =
            seen.is_some() && first_in_way.is_some_and(|x| x >= from_x + motion.approach_gap / 2.0);
        // Where the look shows the face well beyond where the plan put it and no test before this
        // one slid it there, the look may be what is wrong (a face seen above where its nearer
        // part stands: a box 22 cm nearer, struck at the free speed in force-limit-010, seed 11,
        // `--seed 28`): the hand goes free only as far as the plan's line start, guarded from there.
        let plan_start = (planned.x - motion.approach_gap).max(self.config.model.arm.reach_x[0]);
        let beyond_plan = slid.is_none() && from_x > plan_start + motion.approach_gap / 2.0;
        let approach = match (clear, beyond_plan) {
            (true, false) => Approach::Free,
            (true, true) => Approach::GuardedLast(from_x - plan_start),
            (false, _) => Approach::Guarded,
        };
        let to_x = (contact.x + motion.test_travel).min(self.config.model.arm.reach_x[1]);
        let limit = self.config.model.force.test_limit;
        // A retest lowered after the object tipped may ask for less than the arm reaches down to.
        let (low, high) = self.config.push.reach_z;
        let z = intent.hand_height.clamp(low, high);
        // A line below the face's top band (lowered below tipping, or retested at half the height
        // after the object tipped) is reached beside the body: the object may overhang it.
        let below_top = hand_z.is_some() || self.world.objects.get(intent.target).tipped;
        let line = StrokeLine {
            from_x,
            face_x: contact.x,
            to_x,
            y: contact.y,
            z,
            route: Route::for_line(below_top),
        };
        let stroke = self.stroke(line, limit, approach)?;
        let stop_lean = match &stroke.outcome {
            HandOutcome::ForceLimit { wrench, .. } => {
                let f = wrench.value.force;
                Some(f.z.abs().atan2(f.x.hypot(f.y)))
            }
            _ => None,
        };

        if stroke.contact {
            let base = self.robot.base_pose()?.value;
            self.world.touched = Some((intent.target, base * Point2::new(stroke.end_x, contact.y)));
        }
        self.retract()?;
        let icp = match (&prism, before) {
            (Some(p), Some(before)) => {
                let shift = direction * stroke.travel_after_contact;
                let view = self.look_at_object(p, slid_by + shift, hand_z)?;
                let after = crop(&view, p, slid_by + shift, motion.crop_margin);
                let mut reading = icp_reading(&before, &after, shift);
                // Where the hand moved only part of what perception took for one obstacle, the
                // part that moved is the object tested, read on its own points.
                if stroke.contact {
                    let base = self.robot.base_pose()?.value;
                    let seen = TestClouds {
                        prism: p,
                        before: &before,
                        view: &view,
                        slid_by,
                        shift,
                        face: base * Point2::new(stroke.end_x, contact.y) - shift,
                    };
                    if let Some(split) = self.split_what_moved(intent, &seen) {
                        reading = split.reading;
                    }
                }
                let classifier = &self.config.executive.classifier;
                // Whatever the finding, a trusted motion reading is where the object is now: a retest
                // plans from there.
                if let Some((icp, moved)) = reading
                    && classifier.trusts(&icp)
                    && icp.displacement >= classifier.still_below
                {
                    self.displace(intent.target, slid_by + moved);
                }
                reading.map(|r| r.0)
            }
            _ => None,
        };
        let stamp = self.robot.now();
        self.observer
            .push(stamp, intent, Some(-direction * stroke.peak_force));
        let evidence = PushEvidence {
            force_limit: self.config.model.force.test_limit,
            peak_force: stroke.peak_force,
            reached_limit: matches!(stroke.outcome, HandOutcome::ForceLimit { .. }),
            contact: stroke.contact,
            hand_travel: stroke.travel_after_contact,
            icp,
            stop_lean,
            force_trace: stroke.trace,
        };
        if self.config.executive.classifier.tipped(&evidence).is_some() {
            self.world.objects.learn(intent.target).tipped = true;
        }
        Ok(evidence)
    }

    pub(super) fn retract(&mut self) -> Result<(), Interrupt> {
        self.robot.start_retract()?;
        self.wait(|r| r.hand_status())?;
        Ok(())
    }

    /// Looks at `prism` (moved by `shift`) with the hand's line at `hand_z`, where given, in view (see
    /// [`Self::look_at_object`]) and returns its points in the map frame.
    pub(super) fn object_points(
        &mut self,
        prism: &Prism,
        shift: Vector2<f64>,
        hand_z: Option<f64>,
    ) -> Result<ColourCloud, Interrupt> {
        let view = self.look_at_object(prism, shift, hand_z)?;
        Ok(crop(
            &view,
            prism,
            shift,
            self.config.push_motion.crop_margin,
        ))
    }

    /// Points the head at `prism` (moved by `shift`) and captures: aimed at its middle, but tilted no
    /// further down than keeps the top of its nearest face in view, unless that leaves the hand's
    /// line at height `hand_z`, where given, on that face below the view: then just far enough
    /// down to show it.
    /// The stroke's way to the face is judged from this look. Returns the whole view in the map
    /// frame.
    pub(super) fn look_at_object(
        &mut self,
        prism: &Prism,
        shift: Vector2<f64>,
        hand_z: Option<f64>,
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
        let eye = self.config.model.head.height;
        let at_middle = (eye - aim_z).atan2(rel.norm().max(0.1));
        let nearest = prism
            .footprint
            .iter()
            .map(|p| (p.coords + shift - base.translation.vector).norm())
            .fold(f64::INFINITY, f64::min)
            .max(0.1);
        let half_view = self.config.model.camera.v_fov() / 2.0;
        let top_in_view = (eye - prism.z_max).atan2(nearest) + half_view - VIEW_EDGE_MARGIN;
        let tilt = at_middle.min(top_in_view);
        let tilt = match hand_z {
            Some(z) => {
                let line = (eye - z.min(prism.z_max)).atan2(nearest);
                tilt.max(line - half_view + VIEW_EDGE_MARGIN)
            }
            None => tilt,
        };
        self.robot.start_point_head(pan, tilt)?;
        self.wait(|r| r.head_status())?;
        let cloud = self.take_frame(false)?;
        Ok(cloud.to_map())
    }
}

/// The points of `cloud` (map frame) inside `prism`'s footprint moved by `shift` and grown by `margin`,
/// above the floor and below its top.
pub(super) fn crop(
    cloud: &ColourCloud,
    prism: &Prism,
    shift: Vector2<f64>,
    margin: f64,
) -> ColourCloud {
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
pub(super) fn icp_reading(
    before: &ColourCloud,
    after: &ColourCloud,
    shift: Vector2<f64>,
) -> Option<(IcpReading, Vector2<f64>)> {
    let initial = Isometry3::from_parts(
        Translation3::new(shift.x, shift.y, 0.0),
        UnitQuaternion::identity(),
    );
    let (reading, transform) = icp_pose(before, after, &initial)?;
    let centroid: Point3<f64> = before.centroid()?;
    let moved: Vector3<f64> = transform * centroid - centroid;
    Some((reading, moved.xy()))
}

/// Colour ICP from the points before to the points after, starting from `initial`: the reading (its
/// displacement that of the points' centroid) and the rigid motion found (map frame).
pub(super) fn icp_pose(
    before: &ColourCloud,
    after: &ColourCloud,
    initial: &Isometry3<f64>,
) -> Option<(IcpReading, Isometry3<f64>)> {
    let result = colour_icp(before, after, initial, &IcpConfig::default()).ok()?;
    let centroid: Point3<f64> = before.centroid()?;
    let moved: Vector3<f64> = result.transform * centroid - centroid;
    let reading = IcpReading {
        displacement: moved.xy().norm(),
        yaw_deg: result.yaw_deg,
        converged: result.converged,
        fitness: result.fitness,
        rmse: result.rmse,
    };
    Some((reading, result.transform))
}

/// The nearest point (`base_link` x) of `cloud` (map frame) on the hand's line at lateral offset `y`
/// and height `z`: within `half` (m) of it sideways and in height, the hand's face being a square of
/// that half side, and farther than `beyond` (m) ahead. `None` when no such point lies on the line.
fn face_on_line(
    cloud: &ColourCloud,
    base: &nalgebra::Isometry2<f64>,
    y: f64,
    z: f64,
    half: f64,
    beyond: f64,
) -> Option<f64> {
    cloud
        .iter_valid()
        .filter(|(_, p, _)| (f64::from(p.z) - z).abs() <= half)
        .map(|(_, p, _)| base.inverse_transform_point(&Point2::new(f64::from(p.x), f64::from(p.y))))
        .filter(|q| q.x > beyond && (q.y - y).abs() <= half)
        .map(|q| q.x)
        .min_by(f64::total_cmp)
}

/// How far inside the field of view's edges (rad) a look at an object keeps the band of its nearest
/// face the hand pushes on: the head's pointing error and a row or two of pixels.
const VIEW_EDGE_MARGIN: f64 = 0.035;

/// Sideways margin (m) added to the hand's half width when looking for what lies on its way: the
/// range noise (about a centimetre) and a little more.
const HAND_WAY_MARGIN: f64 = 0.02;

/// Two pushes, `first` pushed first, that together open the way (see [`plan_sequence`]); the pairs
/// considered when there are none. The other candidates are the obstacles the ranking would push (not
/// structure, not found static), nearest first. Nothing is searched (no pairs) while the removal of
/// some one candidate alone may open the way: a single push may do, and the loop tries those first.
#[allow(clippy::too_many_arguments)]
fn search_sequence(
    world: &WorldModel,
    config: &RunConfig,
    validity: &Validity,
    here: &Point2<f64>,
    goal: &GoalRegion,
    floor: Option<FloorCheck<'_>>,
    first: ObjectId,
    rng: &mut ChaCha8Rng,
) -> Result<Sequence, Vec<PairRecord>> {
    let mut candidates: Vec<(f64, &Prism)> = world
        .prisms
        .iter()
        .filter(|p| p.id == first || world.might_move(p, config))
        .filter_map(|p| {
            validity
                .obstacle(p.id)
                .map(|o| (o.distance_to_point(here), p))
        })
        .collect();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.id.cmp(&b.1.id)));
    let prisms: Vec<&Prism> = candidates.into_iter().map(|(_, p)| p).collect();
    if single_removal_opens(&prisms, validity, here, goal) {
        return Err(Vec::new());
    }
    plan_sequence(
        &prisms,
        validity,
        here,
        goal,
        &config.push,
        &config.sequence,
        floor,
        Some(first),
        rng,
    )
}

/// How far (m) from `from` along the unit `direction` the line first meets the convex `footprint`;
/// `None` when it misses it.
fn entry_along(
    footprint: &[Point2<f64>],
    from: &Point2<f64>,
    direction: &Vector2<f64>,
) -> Option<f64> {
    let n = footprint.len();
    (0..n)
        .filter_map(|i| {
            let (a, b) = (footprint[i], footprint[(i + 1) % n]);
            let edge = b - a;
            let denom = direction.perp(&edge);
            if denom.abs() < 1e-12 {
                return None;
            }
            let rel = a - from;
            let t = rel.perp(&edge) / denom;
            let u = rel.perp(direction) / denom;
            (t >= 0.0 && (0.0..=1.0).contains(&u)).then_some(t)
        })
        .min_by(f64::total_cmp)
}

/// The worlds (clearances, widest first) a push is planned in, each with where the robot sets out
/// from: where it stands, in each world in which it stands free; where it stands free in none
/// (pressed against a face it has just pushed, or beside a hull a few centimetres generous), from
/// the nearest free spot in each, as a walk sets out (`nearest_free`), the approach stepping there
/// first. Otherwise every push would read "no free stand pose" for the robot's own spot.
fn push_starts(here: &Point2<f64>, validities: Vec<Validity>) -> Vec<(Validity, Point2<f64>)> {
    if validities.iter().any(|v| v.is_free(here)) {
        return validities
            .into_iter()
            .filter(|v| v.is_free(here))
            .map(|v| (v, *here))
            .collect();
    }
    validities
        .into_iter()
        .filter_map(|v| nearest_free(here, &v).map(|from| (v, from)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runner::navigate::tests::validity_with_box as world_with_box;

    #[test]
    fn a_line_enters_a_footprint_at_its_first_face_along_the_push() {
        // Invariant: the distance along the line to the footprint is to the first face it crosses (the near one, whatever the vertices' order), and a line that passes beside the footprint or points away from it has none.
        let square = [
            Point2::new(2.0, 0.0),
            Point2::new(3.0, 0.0),
            Point2::new(3.0, 1.0),
            Point2::new(2.0, 1.0),
        ];
        let along = Vector2::new(1.0, 0.0);
        let t = entry_along(&square, &Point2::new(0.5, 0.4), &along).expect("enters");
        assert!((t - 1.5).abs() < 1e-12, "{t}");
        let reversed: Vec<_> = square.iter().rev().copied().collect();
        let t = entry_along(&reversed, &Point2::new(0.5, 0.4), &along).expect("enters");
        assert!((t - 1.5).abs() < 1e-12, "{t}");
        assert_eq!(entry_along(&square, &Point2::new(0.5, 1.4), &along), None);
        assert_eq!(entry_along(&square, &Point2::new(4.0, 0.4), &along), None);
    }

    #[test]
    fn a_push_is_planned_from_where_the_robot_stands_free_else_from_the_nearest_free_spot() {
        // Invariant: worlds in which the robot's spot is free are planned from that spot, the others left out; where it is free in none, each world is planned from a free spot within the escape radius.
        let here = Point2::origin();
        // The face 0.3 m ahead: a 0.25 m robot stands free, a 0.35 m one overlaps it by 5 cm.
        let starts = push_starts(
            &here,
            vec![world_with_box(0.3, 0.35), world_with_box(0.3, 0.25)],
        );
        assert_eq!(starts.len(), 1);
        assert_eq!(starts[0].1, here);
        assert!((starts[0].0.robot().radius - 0.25).abs() < 1e-12);
        let pressed = push_starts(
            &here,
            vec![world_with_box(0.3, 0.35), world_with_box(0.3, 0.33)],
        );
        assert_eq!(pressed.len(), 2);
        for (world, from) in &pressed {
            assert!(!world.is_free(&here));
            assert!(world.is_free(from), "{from} is free");
            assert!((from - here).norm() <= 0.25 + 1e-9);
        }
    }

    #[test]
    fn the_face_on_the_hands_line_is_the_nearest_point_ahead_within_the_hands_square() {
        // Invariant: the face the hand meets is the nearest point ahead of the body within the hand's half side of its line, sideways and in height; points beside the line, above or below the hand, or behind the body do not count, and no point on the line means no face.
        let base = nalgebra::Isometry2::new(Vector2::new(2.0, 1.0), std::f64::consts::FRAC_PI_2);
        let mut cloud = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        // base_link (x, y) is map (2 - y, 1 + x) for a base at (2, 1) facing +y.
        let at = |x: f64, y: f64, z: f64| Point3::new((2.0 - y) as f32, (1.0 + x) as f32, z as f32);
        cloud.push(at(0.52, 0.0, 0.45), [1, 2, 3]);
        cloud.push(at(0.47, 0.04, 0.42), [1, 2, 3]);
        cloud.push(at(0.30, 0.20, 0.45), [1, 2, 3]);
        cloud.push(at(0.30, 0.0, 0.70), [1, 2, 3]);
        cloud.push(at(-0.20, 0.0, 0.45), [1, 2, 3]);
        let x = face_on_line(&cloud, &base, 0.0, 0.45, 0.05, 0.0).expect("a face on the line");
        assert!((x - 0.47).abs() < 1e-5, "{x}");
        assert!(face_on_line(&cloud, &base, -0.3, 0.45, 0.05, 0.0).is_none());
    }
}
