//! Clearing the way: a movable object pushed along its plan in guarded strokes, the body walking after
//! it, the object re-located by colour ICP between strokes, and the push ended for a new plan when the
//! object turned or slid so far off its line that the rest of its sweep would run into something.

use nalgebra::{Isometry2, Isometry3, Point2, Translation3, UnitQuaternion, Vector2};
use nudge_motion::{Obstacle, SweepBlock, SweepMargins, Validity, sweep_blocked};
use nudge_perception::{ColourCloud, ObjectId, Prism};

use super::push::icp_pose;
use super::stroke::{Approach, Route, StrokeLine};
use super::{Interrupt, Runner};
use crate::event::Event;
use crate::push_test::PushIntent;
use crate::record::{LogLevel, Observer};
use crate::robot::{HandOutcome, Robot, WalkOutcome};

/// Clear strokes start this far beyond the body's radius (m): room for the hand and the walk's margin.
const STROKE_STANDOFF: f64 = 0.12;
/// Approach gap before a face whose position the hand measured (m): it is known within a centimetre.
const MEASURED_GAP: f64 = 0.03;
/// Shortest clearing stroke worth making (m): the hand's approach gap over again, so it presses.
const MIN_STROKE: f64 = 0.05;
/// Pushes longer than this many full strokes are followed: the object is looked at and re-located
/// after each stroke, the hand's line moved to its centre, the rest of the sweep checked from where
/// it is. A push of four strokes or fewer (a metre with this arm) ends in the look-around that
/// follows every clearing push before the object can drift far; its own looks would only cost time,
/// and moving the hand's line off the plan's for so short a push changed outcomes in the batches
/// rather than mended them.
const TRACKED_STROKES: f64 = 4.0;

/// Where the pushed object is: its footprint and points as seen before the push, and the rigid motion
/// (map frame) from there to now: the hand's travel, corrected by colour ICP after each stroke.
struct Tracked {
    prism: Prism,
    before: ColourCloud,
    motion: Isometry3<f64>,
}

impl Tracked {
    /// The motion in the floor's plane.
    fn planar(&self) -> Isometry2<f64> {
        planar(&self.motion)
    }

    /// The motion in the floor's plane as a rigid motion of space (see [`floor_motion`]).
    fn floor_motion(&self) -> Isometry3<f64> {
        floor_motion(&self.motion)
    }

    /// The footprint's centre of area before the push (the centre of the object's friction on the
    /// floor, for an object of even weight): the line a stroke pushes through.
    fn centre_before(&self) -> Point2<f64> {
        self.prism.centroid().unwrap_or_else(Point2::origin)
    }

    /// The footprint's centre now.
    fn centre(&self) -> Point2<f64> {
        self.planar() * self.centre_before()
    }

    /// How far the centre has moved (m).
    fn offset(&self) -> Vector2<f64> {
        self.centre() - self.centre_before()
    }

    /// Half the footprint's width across a push along `direction` (m).
    fn half_width(&self, direction: &Vector2<f64>) -> f64 {
        let a = self.prism.footprint.iter().map(|p| across(p, direction));
        let (lo, hi) = a.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        ((hi - lo) / 2.0).max(0.0)
    }

    /// The object where it is now.
    fn obstacle(&self) -> Option<Obstacle> {
        self.obstacle_after(&self.motion)
    }

    /// The object where `motion` puts it.
    fn obstacle_after(&self, motion: &Isometry3<f64>) -> Option<Obstacle> {
        let planar = planar(motion);
        let footprint: Vec<Point2<f64>> = self.prism.footprint.iter().map(|p| planar * p).collect();
        Obstacle::new(
            self.prism.id,
            &footprint,
            self.prism.z_min,
            self.prism.z_max,
        )
        .ok()
    }

    /// How far `motion` moves the footprint's centre (m).
    fn offset_after(&self, motion: &Isometry3<f64>) -> Vector2<f64> {
        let centre = self.centre_before();
        planar(motion) * centre - centre
    }

    /// The motion followed by a further slide of `by` (m, map frame): where the hand's travel puts it.
    fn slid(&self, by: Vector2<f64>) -> Isometry3<f64> {
        Isometry3::from_parts(
            Translation3::new(by.x, by.y, 0.0),
            UnitQuaternion::identity(),
        ) * self.motion
    }
}

/// A motion in the floor's plane: its translation's x and y and its turn about the vertical.
fn planar(motion: &Isometry3<f64>) -> Isometry2<f64> {
    let t = motion.translation.vector;
    let (_, _, yaw) = motion.rotation.euler_angles();
    Isometry2::new(Vector2::new(t.x, t.y), yaw)
}

/// `motion` kept to the floor's plane, as a rigid motion of space: what the world model moves the
/// object's prism by (an ICP's small tilt or lift is noise, not motion of an object on the floor).
fn floor_motion(motion: &Isometry3<f64>) -> Isometry3<f64> {
    let p = planar(motion);
    Isometry3::new(
        nalgebra::Vector3::new(p.translation.x, p.translation.y, 0.0),
        nalgebra::Vector3::z() * p.rotation.angle(),
    )
}

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Pushes a movable object along the plan in guarded strokes, walking after it between strokes.
    pub(crate) fn clear_path(&mut self, intent: &PushIntent) -> Event {
        match self.run_clear_path(intent) {
            Ok(event) => event,
            Err(i) => i.into(),
        }
    }

    fn run_clear_path(&mut self, intent: &PushIntent) -> Result<Event, Interrupt> {
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
        // Strokes are followed by looks only for a long push; the strokes it takes are computed below.
        let stroke_start =
            (self.config.model.body.radius + STROKE_STANDOFF).max(self.config.model.arm.reach_x[0]);
        let full_stroke =
            (self.config.model.arm.reach_x[1] - stroke_start - motion.approach_gap).max(MIN_STROKE);
        let long = intent.distance > TRACKED_STROKES * full_stroke;
        let mut tracked = match self.prism(intent.target).cloned().filter(|_| long) {
            Some(prism) => {
                let before = self.object_points(&prism, Vector2::zeros(), None)?;
                Some(Tracked {
                    prism,
                    before,
                    motion: Isometry3::identity(),
                })
            }
            None => None,
        };
        // Twice the strokes the push needs at the shortest full stroke, and two more: a stroke that
        // meets nothing (the object slid on, or was measured short) steps up and tries again. Strokes
        // start this close to the body axis (`stroke_start`): as long as the arm can push in one go.
        let max_strokes = 2 * (intent.distance / full_stroke).ceil() as usize + 2;
        let mut moved = 0.0;
        let mut peak: f64 = 0.0;
        // Every stroke of a followed push goes through the object's centre of friction (its
        // footprint's centre of area, for an object of even weight), the first one included, not
        // where the plan's stance put the hand: a push at a point off that line turns the object,
        // and a box turned across a corridor blocks it. A short push keeps the plan's line.
        let mut line: Option<f64> = tracked
            .as_ref()
            .map(|t| across(&t.centre_before(), &direction));
        for stroke_index in 0..max_strokes {
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
            let at_least = face_x - gap + MIN_STROKE - self.config.model.arm.reach_x[1];
            let ahead = (face_x + remaining - self.config.model.arm.reach_x[1])
                .max(at_least)
                .min(face_x - stroke_start);
            if ahead > 0.02 {
                self.step_forward(direction, ahead, intent.target)?;
                base = self.robot.base_pose()?.value;
            }
            let face = base.inverse_transform_point(&face_map);
            // The plan's line first, then the line through the object's centre, as far as the arm
            // reaches sideways.
            let y = match line {
                Some(across) => hand_line_y(
                    &base,
                    &face_map,
                    across,
                    &direction,
                    self.config.push.reach_y,
                ),
                None => face.y,
            };
            let from_x = (face.x - gap).max(self.config.model.arm.reach_x[0]);
            let to_x = (face.x + remaining).min(self.config.model.arm.reach_x[1]);
            if to_x - from_x < MIN_STROKE {
                // The object is beyond the arm's reach and the body could not walk after it (the
                // walk stopped against something): this push ends here; a look shows where it is.
                break;
            }
            let limit = self.config.model.force.clear_limit;
            // The first stroke goes by a plan made from a look, its object perhaps turned since (a
            // chair that jammed on a jamb, a corner now beside the hand's way): the hand gets to
            // the line guarded all the way. Later strokes start where the last one measured the
            // object, and only their last stretch is guarded (it may have turned nearer).
            let approach = if stroke_index == 0 {
                Approach::Guarded
            } else {
                Approach::GuardedLast(motion.approach_gap)
            };
            // An object that tipped is cleared below its top (see `Ambiguity::Tipped`): the hand
            // reaches that line beside the body.
            let hand_line = StrokeLine {
                from_x,
                face_x: face.x,
                to_x,
                y,
                z: intent.clear_height,
                route: Route::for_line(self.world.objects.get(intent.target).tipped),
            };
            let stroke = self.stroke(hand_line, limit, approach)?;
            peak = peak.max(stroke.peak_force);
            self.retract()?;
            if let HandOutcome::ForceLimit { .. } = stroke.outcome {
                moved += stroke.travel_after_contact;
                self.displace(intent.target, direction * moved);
                return Ok(Event::Jammed {
                    peak_force: peak,
                    moved,
                });
            }
            if !stroke.contact {
                // The object is beyond the stroke: step up to it and search again.
                face_map += direction * (to_x - face.x).max(0.05);
                measured = false;
                continue;
            }
            face_map = base * Point2::new(stroke.end_x, y);
            measured = true;
            let Some(t) = tracked.as_mut() else {
                moved += stroke.travel_after_contact;
                continue;
            };
            // The world as the model has it, for checking the object's new place: the object itself
            // is left where it was (every check skips it by id).
            let here = Point2::from(self.robot.base_pose()?.value.translation.vector);
            let validity = self.world.validity(&here, &self.config).ok();
            self.relocate(t, direction, stroke.travel_after_contact, validity.as_ref())?;
            moved = t.offset().dot(&direction);
            // The next stroke pushes through the object's centre (the centre of its friction on the
            // floor, for an object of even weight), off it by a lever that turns it back when it
            // has turned: a push at a point is unstable, and a turned face deflects the contact
            // force off the centre, so an object pushed through its centre alone turns on.
            let yaw = t.planar().rotation.angle();
            line = Some(across(&t.centre(), &direction) + steer(yaw, t.half_width(&direction)));
            if let Some(event) =
                self.off_line(t, direction, intent.distance - moved, validity.as_ref())
            {
                self.move_object(intent.target, &t.floor_motion());
                return Ok(event);
            }
        }
        match &tracked {
            Some(t) => self.move_object(intent.target, &t.floor_motion()),
            None => self.displace(intent.target, direction * moved),
        }
        let stamp = self.robot.now();
        self.observer.push(stamp, intent, Some(-direction * peak));
        Ok(Event::Cleared { moved })
    }

    /// Looks at the tracked object where the hand's last stroke, `travel` (m) along `direction`, should
    /// have put it and
    /// corrects its motion by colour ICP; a reading the push test would not trust leaves the hand's
    /// travel standing.
    fn relocate(
        &mut self,
        t: &mut Tracked,
        direction: Vector2<f64>,
        travel: f64,
        validity: Option<&Validity>,
    ) -> Result<(), Interrupt> {
        let expected = t.slid(direction * travel);
        // Looked for where the hand's travel puts it, turned as it was last measured.
        let there = t.prism.transformed(&floor_motion(&expected));
        let after = self.object_points(&there, Vector2::zeros(), None)?;
        let classifier = &self.config.executive.classifier;
        let (motion, source) = match icp_pose(&t.before, &after, &expected) {
            Some((reading, motion))
                if classifier.trusts(&reading)
                    && self.plausible(t, &motion, &expected, &direction, validity) =>
            {
                (motion, "colour ICP")
            }
            _ => (expected, "the hand's travel"),
        };
        t.motion = motion;
        let offset = t.offset();
        let stamp = self.robot.now();
        self.observer.note(
            stamp,
            LogLevel::Info,
            &format!(
                "{} re-located by {source}: moved {:.3} m, turned {:.1}°",
                t.prism.id,
                offset.norm(),
                t.planar().rotation.angle().to_degrees()
            ),
        );
        Ok(())
    }

    /// Whether `motion`, measured by ICP, is one the tracked object can have made where the hand's
    /// travel says it went (`expected`): its progress along the push (`direction`) agrees with the
    /// hand's as the push test's classifier asks of a reading (within its absolute or relative
    /// agreement; across the push, and in turn, it may differ: that is what ICP is for), and its
    /// footprint stays inside the room (within the crop margin: perception's footprint error). ICP on
    /// an object seen by one face can slide along that face, through a wall; such a reading is not
    /// taken.
    fn plausible(
        &self,
        t: &Tracked,
        motion: &Isometry3<f64>,
        expected: &Isometry3<f64>,
        direction: &Vector2<f64>,
        validity: Option<&Validity>,
    ) -> bool {
        let along = |m: &Isometry3<f64>| t.offset_after(m).dot(direction);
        let (measured, hand) = (along(motion), along(expected));
        let classifier = &self.config.executive.classifier;
        let tolerance = classifier
            .agreement_abs
            .max(classifier.agreement_rel * hand.abs());
        if (measured - hand).abs() > tolerance {
            return false;
        }
        let Some(room) =
            validity.and_then(|v| v.walls().shrunk(-self.config.push_motion.crop_margin))
        else {
            return true;
        };
        t.obstacle_after(motion)
            .is_some_and(|now| now.footprint().iter().all(|p| room.contains(p)))
    }

    /// [`Event::OffLine`] when the rest of the push, `remaining` (m) along `direction`, would sweep the
    /// object where it now is into something: it turned or slid off the line the plan checked. The
    /// sweep is checked with half the plan's clearance, so that a measurement a centimetre off the
    /// plan's footprint (perception's and ICP's error) does not end a push whose object is on line.
    fn off_line(
        &self,
        t: &Tracked,
        direction: Vector2<f64>,
        remaining: f64,
        validity: Option<&Validity>,
    ) -> Option<Event> {
        if remaining <= 0.02 {
            return None;
        }
        let (now, validity) = (t.obstacle()?, validity?);
        let margins = SweepMargins {
            clearance: self.config.push.sweep_clearance / 2.0,
            ..self.config.push.sweep_margins()
        };
        let block = sweep_blocked(&now, &(direction * remaining), validity, margins)
            .ok()
            .flatten();
        block.map(|block| {
            let offset = t.offset();
            let along = offset.dot(&direction);
            Event::OffLine {
                moved: along,
                lateral: (offset - direction * along).norm(),
                yaw_deg: t.planar().rotation.angle().to_degrees(),
                blocked_by: match block {
                    SweepBlock::Obstacle(id) => Some(id),
                    SweepBlock::Wall => None,
                },
            }
        })
    }

    /// Walks `distance` along `direction` after the pushed object. A walk refused at once (the body
    /// already within the base's safety margin of something beside it, the push a few degrees off
    /// parallel to a table's edge) slides instead: along `direction` less its part towards the
    /// nearest other obstacle the world model knows there.
    pub(super) fn step_forward(
        &mut self,
        direction: Vector2<f64>,
        distance: f64,
        pushed: ObjectId,
    ) -> Result<(), Interrupt> {
        let here = self.robot.base_pose()?.value;
        let from = Point2::from(here.translation.vector);
        self.robot.start_walk(&[from + direction * distance])?;
        let outcome = self.wait(|r| r.walk_status())?;
        let now = Point2::from(self.robot.base_pose()?.value.translation.vector);
        if !matches!(outcome, WalkOutcome::Blocked { .. }) || (now - from).norm() > SLIDE_AFTER {
            return Ok(());
        }
        let reach = self.config.model.body.radius + SLIDE_NEAR;
        let Some(to) = nearest_other(&self.world.prisms, &from, reach, pushed)
            .and_then(|nearest| slide_target(&from, &direction, distance, &nearest, reach))
        else {
            return Ok(());
        };
        self.robot.start_walk(&[to])?;
        self.wait(|r| r.walk_status())?;
        // Face the push again: the strokes run along the body's axis.
        self.turn_to(direction.y.atan2(direction.x))?;
        Ok(())
    }
}

/// A walk after the object that got no further than this (m) was refused at once.
const SLIDE_AFTER: f64 = 0.01;

/// Obstacles whose footprint lies within this (m) of the body's edge are what a refused walk is
/// slid along: the base's safety margin and perception's few centimetres of footprint error.
const SLIDE_NEAR: f64 = 0.1;

/// Where a walk of `distance` from `from` along `direction` slides to past `nearest`, the nearest
/// point of another obstacle: along it, and away from it until the body's axis is `reach` (m) from it,
/// the base moving only away from what it is within its safety margin of. `None` when the walk does
/// not head into that obstacle or runs straight at it.
fn slide_target(
    from: &Point2<f64>,
    direction: &Vector2<f64>,
    distance: f64,
    nearest: &Point2<f64>,
    reach: f64,
) -> Option<Point2<f64>> {
    let gap = (nearest - from).norm();
    if gap < 1e-9 {
        return None;
    }
    let towards = (nearest - from) / gap;
    let into = direction.dot(&towards);
    let along = direction - towards * into;
    (into > 0.0 && along.norm() >= 1e-3)
        .then(|| from + along.normalize() * distance - towards * (reach - gap).max(0.0))
}

/// The point nearest `at` on the footprint of any obstacle but `except` within `within` (m).
fn nearest_other(
    prisms: &[Prism],
    at: &Point2<f64>,
    within: f64,
    except: ObjectId,
) -> Option<Point2<f64>> {
    prisms
        .iter()
        .filter(|p| p.id != except)
        .filter_map(|p| p.nearest_on_outline(at))
        .map(|q| ((q - at).norm(), q))
        .filter(|(d, _)| *d <= within)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, q)| q)
}

/// Where `p` lies across the push along `direction`: its offset along the direction's left normal (m).
fn across(p: &Point2<f64>, direction: &Vector2<f64>) -> f64 {
    p.coords.dot(&Vector2::new(-direction.y, direction.x))
}

/// How far off the object's centre (m, along the push's left normal) to push an object that has
/// turned by `yaw` (rad, counter-clockwise) and is `half_width` (m) wide on each side of its centre:
/// a push on the side it turned towards turns it back. The lever grows with the turn, twice the turn
/// in radians times the half width (a 5° turn is pushed 17 % of the half width off centre), up to half
/// the half width, so the hand stays well on the face; beyond [`STEER_WITHIN`], none.
fn steer(yaw: f64, half_width: f64) -> f64 {
    if yaw.abs() > STEER_WITHIN {
        return 0.0;
    }
    let most = 0.5 * half_width;
    (2.0 * yaw * half_width).clamp(-most, most)
}

/// Turns up to which [`steer`] pushes an object back (rad). Within them the hand, pushing along the
/// plan's line, meets the face it pushed at first, and a lever along that face turns the object
/// back; turned 45°, the hand would meet the corner between two faces, where a lever along either
/// one makes no sense. 30° keeps that corner 15° away: ICP reads the turn of a box seen in part up to
/// 10° off (corridor runs against the simulation's truth), and a stroke turns it a few degrees more
/// before the next reading. Beyond it the object is pushed through its centre, and the rest of its
/// sweep is checked from where it is. (Held to 10° before, when the centre was the hull's vertices'
/// mean, which lies off the middle of a face seen end-on: a lever about a wrong centre turned boxes
/// further round.)
const STEER_WITHIN: f64 = 30.0 * std::f64::consts::PI / 180.0;

/// The hand's sideways offset in `base_link` (clamped into the arm's sideways `reach`) for a stroke
/// along `direction` on the line `across` (see [`across`]) that meets the face near `face` (map).
fn hand_line_y(
    base: &Isometry2<f64>,
    face: &Point2<f64>,
    across_m: f64,
    direction: &Vector2<f64>,
    (lo, hi): (f64, f64),
) -> f64 {
    let n = Vector2::new(-direction.y, direction.x);
    let on_line = face + n * (across_m - face.coords.dot(&n));
    base.inverse_transform_point(&on_line).y.clamp(lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nudge_perception::CloudFrame;

    /// A 0.6 m square box centred at (2, 1), pushed along +x.
    fn tracked(motion: Isometry3<f64>) -> Tracked {
        let footprint = vec![
            Point2::new(1.7, 0.7),
            Point2::new(2.3, 0.7),
            Point2::new(2.3, 1.3),
            Point2::new(1.7, 1.3),
        ];
        Tracked {
            prism: Prism {
                id: ObjectId(3),
                footprint,
                z_min: 0.0,
                z_max: 0.7,
                points: ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0),
            },
            before: ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0),
            motion,
        }
    }

    #[test]
    fn a_turned_object_is_followed_where_it_is() {
        // Invariant: an object measured turned by 15° about its own centre and slid 0.5 m along and 0.1 m across the push has its centre, its offset and its footprint where that motion puts them: the footprint turned with it, not merely shifted.
        let yaw = 15f64.to_radians();
        let centre = Point2::new(2.0, 1.0);
        let turn = Isometry2::new(Vector2::zeros(), yaw);
        let about_centre = Isometry2::new(centre.coords - (turn * centre).coords, yaw);
        let motion2 = Isometry2::new(Vector2::new(0.5, 0.1), 0.0) * about_centre;
        let t = motion2.translation.vector;
        let t = tracked(Isometry3::new(
            nalgebra::Vector3::new(t.x, t.y, 0.0),
            nalgebra::Vector3::z() * motion2.rotation.angle(),
        ));
        assert!((t.centre() - Point2::new(2.5, 1.1)).norm() < 1e-9);
        assert!((t.offset() - Vector2::new(0.5, 0.1)).norm() < 1e-9);
        assert!((t.planar().rotation.angle() - yaw).abs() < 1e-9);
        let now = t.obstacle().expect("footprint");
        let corner = motion2 * Point2::new(2.3, 0.7);
        assert!(now.footprint().iter().any(|p| (p - corner).norm() < 1e-5));
        // The hand's travel alone slides it on without turning it further.
        let slid = Tracked {
            motion: t.slid(Vector2::new(0.3, 0.0)),
            ..t
        };
        assert!((slid.centre() - Point2::new(2.8, 1.1)).norm() < 1e-9);
        assert!((slid.planar().rotation.angle() - yaw).abs() < 1e-9);
    }

    #[test]
    fn the_next_stroke_pushes_through_the_objects_centre_within_the_arms_reach() {
        // Invariant: after the object slid 0.1 m to the left of a push along +x, the next stroke's hand line (in base_link) passes through its centre, from a base standing off that line and turned a little; a centre beyond the arm's sideways reach puts the hand at the reach's edge.
        let direction = Vector2::new(1.0, 0.0);
        let centre = Point2::new(2.5, 1.1);
        let base = Isometry2::new(Vector2::new(1.6, 0.9), 3f64.to_radians());
        let face = Point2::new(2.2, 1.0);
        let y = hand_line_y(
            &base,
            &face,
            across(&centre, &direction),
            &direction,
            (-0.4, 0.4),
        );
        // The line's point at the face, in base_link, lies on the body's left by the line's offset.
        let on_line = base * Point2::new(base.inverse_transform_point(&face).x, y);
        assert!(
            (on_line.y - centre.y).abs() < 0.02,
            "line at y {} for a centre at {}",
            on_line.y,
            centre.y
        );
        let far = Point2::new(2.5, 1.6);
        let y = hand_line_y(
            &base,
            &face,
            across(&far, &direction),
            &direction,
            (-0.4, 0.4),
        );
        assert_eq!(y, 0.4);
    }

    #[test]
    fn a_box_seen_end_on_is_pushed_through_its_centre_of_area_not_its_vertices_mean() {
        // Invariant: the line a followed push's strokes go through is the footprint's centre of area: a face seen end-on, 0.1 m deep and 1.2 m across the push, whose hull crowds eight vertices round one end, is pushed at its middle (y 0.9), where its vertices' mean (below 0.7) would turn it.
        let mut footprint = vec![Point2::new(5.4, 0.3), Point2::new(5.4, 1.5)];
        footprint.push(Point2::new(5.3, 1.5));
        footprint.extend((0..8).map(|k| {
            let a = std::f64::consts::FRAC_PI_2 * f64::from(k) / 7.0;
            Point2::new(5.35 - 0.05 * a.cos(), 0.35 - 0.05 * a.sin())
        }));
        let mut t = tracked(Isometry3::identity());
        t.prism.footprint = footprint;
        let direction = Vector2::new(1.0, 0.0);
        let line = across(&t.centre_before(), &direction);
        assert!((line - 0.9).abs() < 0.02, "line at {line}");
    }

    #[test]
    fn a_turned_object_is_pushed_back_by_a_lever_until_its_corner_nears() {
        // Invariant: the lever lies on the side the object turned towards (left for a counter-clockwise turn), grows with the turn up to half the half width, and is none beyond 30°, where the hand would come near the corner between two faces.
        let half = 0.6;
        let small = steer(5f64.to_radians(), half);
        assert!(small > 0.0 && small < 0.5 * half, "{small}");
        assert!((steer(-5f64.to_radians(), half) + small).abs() < 1e-12);
        assert_eq!(steer(20f64.to_radians(), half), 0.5 * half);
        assert_eq!(steer(-28f64.to_radians(), half), -0.5 * half);
        assert_eq!(steer(35f64.to_radians(), half), 0.0);
        assert_eq!(steer(0.0, half), 0.0);
    }

    #[test]
    fn a_walk_refused_beside_an_obstacle_slides_along_it_and_off_it() {
        // Invariant: a walk heading a few degrees into an obstacle beside the body slides parallel to it and ends at the reach from it (never nearer than it started); a walk heading away from it, or straight at it, does not slide.
        let from = Point2::new(8.6, 0.83);
        let table = Point2::new(8.6, 1.2);
        let into = Vector2::new(4f64.to_radians().cos(), 4f64.to_radians().sin());
        let to = slide_target(&from, &into, 0.3, &table, 0.45).expect("a slide");
        assert!(
            (to.x - 8.9).abs() < 1e-9 && (to.y - 0.75).abs() < 1e-9,
            "{to:?}"
        );
        let away = Vector2::new(4f64.to_radians().cos(), -4f64.to_radians().sin());
        assert!(slide_target(&from, &away, 0.3, &table, 0.45).is_none());
        assert!(slide_target(&from, &Vector2::new(0.0, 1.0), 0.3, &table, 0.45).is_none());
    }
}
