//! One stroke of the hand: how it gets to its line (the legs, each a guarded move that touches at
//! a low guard and presses on from there) and what the wrist and the hand's travel measured.

use nalgebra::Point3;
use nudge_robot_model::RobotModel;

use super::config::PushMotionConfig;
use super::{Interrupt, Runner};
use crate::record::Observer;
use crate::robot::{GuardedMove, HandOutcome, Robot, Stamped, Wrench};

/// How fast the hand gets to a stroke's line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Approach {
    /// At the arm's free speed, along the line the look showed clear (see [`legs`]).
    Free,
    /// At the free speed to this far (m) short of the line's start along the line, then guarded at
    /// the approach speed: the object is known to lie ahead, but may have turned nearer since it
    /// was measured.
    GuardedLast(f64),
    /// Along guarded moves at the approach speed from where the hand is: the way is not known
    /// clear.
    Guarded,
}

/// By which way the hand gets onto its line's height.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Route {
    /// Straight from where it is to the line's start: a line just below the top of the face it
    /// pushes, with nothing of the object above it that the move could cut through.
    Straight,
    /// To the line's height inside the body's cylinder first, across to the line, then out along
    /// it (see [`beside_body`]), and back the same way after the stroke: a line below the object's
    /// top, where a straight move from the hand's rest above it would cut through whatever
    /// overhangs the face (a table's top, a chair's seat) and strike it at the free speed (25.6 N
    /// on a table's edge in long-hall, seed 7) or land on it from above (a chair's seat, the wrist
    /// leaning 70°, read as tipped).
    BesideBody,
}

impl Route {
    /// The way onto a line that lies `below_top` of the face it pushes, or just below its top.
    pub(super) fn for_line(below_top: bool) -> Self {
        if below_top {
            Route::BesideBody
        } else {
            Route::Straight
        }
    }
}

/// A stroke's line in `base_link` (m): from `from_x` to `to_x` ahead, `y` to the side, at height
/// `z`, where it expects the face at `face_x`, and the way the hand gets onto it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct StrokeLine {
    pub(super) from_x: f64,
    pub(super) face_x: f64,
    pub(super) to_x: f64,
    pub(super) y: f64,
    pub(super) z: f64,
    pub(super) route: Route,
}

/// One guarded move of a stroke: the hand goes (unguarded, at its free speed) to `from`, then
/// guarded to `to` at `speed`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Leg {
    from: Point3<f64>,
    to: Point3<f64>,
    speed: f64,
}

/// What a stroke's guarded moves recorded: the force trace, the hand's positions and the first
/// contact.
#[derive(Default)]
struct StrokeLog {
    trace: Vec<(f64, f64)>,
    hand: Vec<Stamped<Point3<f64>>>,
    contact_stamp: Option<f64>,
}

/// What one guarded stroke measured.
pub(super) struct Stroke {
    pub(super) outcome: HandOutcome,
    pub(super) peak_force: f64,
    pub(super) contact: bool,
    pub(super) travel_after_contact: f64,
    pub(super) end_x: f64,
    pub(super) trace: Vec<(f64, f64)>,
}

impl<R: Robot, O: Observer> Runner<R, O> {
    /// One stroke of the hand along `line` at the push speed, guarded by `force_limit`. The hand
    /// gets to the line's start as `approach` and the line's route say (see [`legs`]): what the
    /// hand met at its free speed it would strike hard. A stroke that reaches the limit on the way
    /// ends there.
    pub(super) fn stroke(
        &mut self,
        line: StrokeLine,
        force_limit: f64,
        approach: Approach,
    ) -> Result<Stroke, Interrupt> {
        let motion = self.config.push_motion.clone();
        // The plan puts the hand anywhere within the arm's sideways reach, its edges included; a walk
        // that ends a few millimetres off would put the line just outside and the arm would refuse it.
        // Pushing those millimetres off the planned line is harmless.
        let line = StrokeLine {
            y: clamp_lateral(line.y, self.config.push.reach_y),
            ..line
        };
        self.robot.tare()?;
        self.robot.discard_wrenches()?;
        let here = self.robot.hand_position()?.value;
        let legs = legs(&here, &line, approach, &motion, &self.config.model);
        let mut log = StrokeLog::default();
        // Each leg touches at a low guard and stops, then presses on from there with the force
        // guard at the limit and the hand's speed ramped up gently: the press is a force ramp, no
        // faster than a guarded approach (a leg at the free speed would otherwise press at it).
        let touch_force = motion.touch_force.min(force_limit);
        let mut outcome = HandOutcome::Reached;
        let count = legs.len();
        for (index, Leg { from, to, speed }) in legs.into_iter().enumerate() {
            let touch = GuardedMove {
                from,
                to,
                speed,
                force_limit: touch_force,
                acceleration: None,
            };
            // A touch on the way along the line, before its start: the face is nearer than
            // expected, and the push goes on from it as far past it as the line was to go past
            // the expected face, at the push speed; nothing of the line after it is left to do.
            let early = index + 1 < count && on_line(&from, &to, &line);
            outcome = match self.guarded(touch, &mut log)? {
                HandOutcome::ForceLimit { at, .. } if touch_force < force_limit => {
                    // From where the hand stopped, put back on the leg's line: the hand sits a
                    // fraction of a millimetre off it on its compliant wrist, and a line's ends
                    // must lie within the arm's reach, as the leg's own do.
                    let from = on_segment(at, from, to);
                    let (to, speed) = if early {
                        let end = (from.x + line.to_x - line.face_x).min(line.to_x);
                        (Point3::new(end.max(from.x), line.y, line.z), motion.speed)
                    } else {
                        (to, speed.min(motion.approach_speed))
                    };
                    let press = GuardedMove {
                        from,
                        to,
                        speed,
                        force_limit,
                        acceleration: Some(motion.press_acceleration),
                    };
                    let pressed = self.guarded(press, &mut log)?;
                    if early {
                        outcome = pressed;
                        break;
                    }
                    pressed
                }
                other => other,
            };
            if outcome != HandOutcome::Reached {
                break;
            }
        }
        let StrokeLog {
            trace,
            hand,
            contact_stamp,
        } = log;
        let end_x = hand.last().map_or(line.from_x, |h| h.value.x);
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
        if line.route == Route::BesideBody {
            let moved = travel_after_contact > motion.approach_gap / 2.0;
            self.retreat(&line, moved, peak_force.max(force_limit) + touch_force)?;
        }
        Ok(Stroke {
            outcome,
            peak_force,
            contact: contact_stamp.is_some(),
            travel_after_contact,
            end_x,
            trace,
        })
    }

    /// Takes the hand back from where it stopped along `line` and into the column of its rest, the
    /// way it came (see [`beside_body`]): under what overhangs the line, the retract's straight way
    /// to rest would strike it (and move the object the stroke just measured). The first centimetre
    /// unloads what the hand pressed, guarded by `unload_guard` (the stroke's peak and a touch
    /// above it); the rest is guarded at the touch force, at the free speed where the way back is
    /// the way in, at the approach speed where the stroke `moved` the object (it may have turned
    /// into the hand's way back: a chair pushed low and turned caught the withdrawing hand with a
    /// leg at 36 N in person-pacing, seed 8). A touch stops it where it is. Its wrenches are
    /// recorded but are not the stroke's.
    fn retreat(
        &mut self,
        line: &StrokeLine,
        moved: bool,
        unload_guard: f64,
    ) -> Result<(), Interrupt> {
        let arm = self.config.model.arm.clone();
        let motion = self.config.push_motion.clone();
        let [column, beside] = beside_body(line, &self.config.model);
        let hand = self.robot.hand_position()?.value;
        let near = |a: f64, b: f64| (a - b).abs() < RETREAT_TOLERANCE;
        // Back the way the hand came, from the leg it stopped on: along the line, then across to
        // the column; across only; or, stopped in the column, no way back but up it.
        let targets: &[Point3<f64>] = if !near(hand.z, line.z) {
            &[]
        } else if near(hand.y, line.y) {
            &[beside, column]
        } else {
            &[column]
        };
        let mut from = Point3::new(
            hand.x.clamp(arm.reach_x[0], arm.reach_x[1]),
            hand.y.clamp(arm.reach_y[0], arm.reach_y[1]),
            hand.z.clamp(arm.reach_z[0], arm.reach_z[1]),
        );
        let speed = if moved {
            motion.approach_speed
        } else {
            arm.free_speed
        };
        let mut way = Vec::with_capacity(3);
        if let Some(first) = targets.first() {
            let length = (first - from).norm();
            if length > UNLOAD {
                let unload = from + (first - from) * (UNLOAD / length);
                way.push((unload, motion.approach_speed, unload_guard));
            }
        }
        way.extend(targets.iter().map(|&to| (to, speed, motion.touch_force)));
        for (to, speed, force_limit) in way {
            if (to - from).norm() > 1e-3 {
                let back = GuardedMove {
                    from,
                    to,
                    speed,
                    force_limit,
                    acceleration: None,
                };
                if self.guarded(back, &mut StrokeLog::default())? != HandOutcome::Reached {
                    break;
                }
            }
            from = to;
        }
        Ok(())
    }

    /// One guarded move of the hand, logged into `log`; its outcome.
    fn guarded(
        &mut self,
        motion: GuardedMove,
        log: &mut StrokeLog,
    ) -> Result<HandOutcome, Interrupt> {
        let threshold = self.config.model.force.contact_threshold;
        self.robot.start_guarded_move(motion)?;
        loop {
            let status = self.robot.hand_status()?;
            log.hand.push(self.robot.hand_position()?);
            for sample in self.robot.drain_wrenches()? {
                self.record_wrench(&sample, &mut log.trace);
                let f = sample.value.force_norm();
                if log.contact_stamp.is_none() && f >= threshold {
                    log.contact_stamp = Some(sample.stamp);
                }
            }
            if let crate::robot::ActionStatus::Done(outcome) = status {
                return Ok(outcome);
            }
            self.tick()?;
        }
    }

    fn record_wrench(&mut self, sample: &Stamped<Wrench>, trace: &mut Vec<(f64, f64)>) {
        self.observer.wrench(sample.stamp, &sample.value);
        trace.push((sample.stamp, sample.value.force_norm()));
    }
}

/// How far back (m) the hand unloads what it pressed before its way back is guarded at a touch:
/// ten times the wrist's compliance at the limit (20 N on 20 kN/m).
const UNLOAD: f64 = 0.01;

/// How far (m) the hand may lie off a leg of its way and still be on it, for the way back: the
/// wrist's compliance at the limit is a millimetre, a stop off the leg's line centimetres.
const RETREAT_TOLERANCE: f64 = 0.01;

/// The way onto `line` beside the body: to the line's height in a column inside the body's
/// cylinder, where nothing else stands (as near the line as the hand's box stays inside it, as near
/// the body as the arm reaches), then across to the line. The line's height is reached before the
/// hand leaves the cylinder: a line far to the side, met straight down from above, would pass
/// whatever stands beside the body (a chair's seat a few centimetres from it, pressed from above in
/// flat-016, seed 18, `--seed 28`). Returns the column's point at the line's height and the line's
/// nearest point.
fn beside_body(line: &StrokeLine, model: &RobotModel) -> [Point3<f64>; 2] {
    let nearest = model.arm.reach_x[0];
    let [hx, hy, _] = model.arm.hand_half;
    // Farthest to the side the hand's box stays inside the cylinder at the nearest reach.
    let inside = (model.body.radius.powi(2) - (nearest + hx).powi(2))
        .max(0.0)
        .sqrt()
        - hy;
    let column_y = line.y.clamp(-inside.max(0.0), inside.max(0.0));
    [
        Point3::new(nearest, column_y, line.z),
        Point3::new(nearest, line.y, line.z),
    ]
}

/// Whether the leg from `from` to `to` runs along `line` (a millimetre off it at most).
fn on_line(from: &Point3<f64>, to: &Point3<f64>, line: &StrokeLine) -> bool {
    [from, to]
        .iter()
        .all(|p| (p.y - line.y).abs() < 1e-3 && (p.z - line.z).abs() < 1e-3)
}

/// The guarded moves of a stroke along `line` from the hand at `here`, the last along the line
/// itself at the push speed. Before it, as `approach` says: down the body's column and across to
/// the line (see [`beside_body`]), then along it at the free speed; the last stretch guarded; or the
/// whole way guarded. A line reached [`Route::BesideBody`] is met through the column whatever the
/// approach; the leg across to the line, which no look judged, is always guarded.
fn legs(
    here: &Point3<f64>,
    line: &StrokeLine,
    approach: Approach,
    motion: &PushMotionConfig,
    model: &RobotModel,
) -> Vec<Leg> {
    let arm = &model.arm;
    let nearest = arm.reach_x[0];
    let at = |x: f64| Point3::new(x.max(nearest), line.y, line.z);
    let start = at(line.from_x);
    let [column, beside] = beside_body(line, model);
    // Out of the cylinder and across to the line the look did not judge: guarded.
    let along = |speed: f64| [(column, speed), (beside, motion.approach_speed)];
    // The way as waypoints, each with the speed of the leg that ends there; the hand gets to the
    // first at its free speed.
    let mut way: Vec<(Point3<f64>, f64)> = match approach {
        // The look judged the line, not the straight way to its start from where the hand is.
        Approach::Free => {
            let mut way = along(arm.free_speed).to_vec();
            way.push((start, arm.free_speed));
            way
        }
        Approach::GuardedLast(d) => {
            let mut way = match line.route {
                Route::BesideBody => along(arm.free_speed).to_vec(),
                Route::Straight => Vec::new(),
            };
            way.push((at(line.from_x - d), arm.free_speed));
            way.push((start, motion.approach_speed));
            way
        }
        // From where the hand is (no nearer the body than a stroke ever starts).
        Approach::Guarded => {
            let here = Point3::new(here.x.max(nearest), here.y, here.z);
            let mut way = vec![(here, motion.approach_speed)];
            if line.route == Route::BesideBody {
                way.extend(along(motion.approach_speed));
            }
            way.push((start, motion.approach_speed));
            way
        }
    };
    way.push((at(line.to_x.max(line.from_x)), motion.speed));
    let mut legs: Vec<Leg> = way
        .windows(2)
        .map(|w| Leg {
            from: w[0].0,
            to: w[1].0,
            speed: w[1].1,
        })
        .collect();
    // A leg of no length is no move (the hand already where it starts); the push itself always
    // stays.
    let push = legs.pop();
    legs.retain(|leg| (leg.to - leg.from).norm() > 1e-3);
    legs.extend(push);
    legs
}

/// How far outside the arm's sideways reach (m) a stroke's line is moved back to its edge: the error
/// of a walk to a stand pose, not a plan that asked for more than the arm can do.
pub(super) const LATERAL_SLACK: f64 = 0.02;

/// The point of the segment `a`–`b` nearest `p`.
fn on_segment(p: Point3<f64>, a: Point3<f64>, b: Point3<f64>) -> Point3<f64> {
    let ab = b - a;
    let t = ((p - a).dot(&ab) / ab.norm_squared().max(1e-12)).clamp(0.0, 1.0);
    a + ab * t
}

/// Whether the arm, with a walk's error absorbed, reaches a line `y` to the side (`base_link`): within
/// `reach` or at most [`LATERAL_SLACK`] outside it, where [`clamp_lateral`] moves it onto the edge.
pub(super) fn reaches_lateral(y: f64, (lo, hi): (f64, f64)) -> bool {
    y >= lo - LATERAL_SLACK && y <= hi + LATERAL_SLACK
}

/// `y` moved onto the nearer edge of `reach` when it lies at most [`LATERAL_SLACK`] outside it;
/// otherwise unchanged (the arm then refuses a line the plan never meant).
pub(super) fn clamp_lateral(y: f64, (lo, hi): (f64, f64)) -> f64 {
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
    use nalgebra::Point2;

    /// A line 0.3 m to the side at 0.3 m, its face 0.45 m ahead, reached as `route`.
    fn low_line(route: Route) -> StrokeLine {
        StrokeLine {
            from_x: 0.37,
            face_x: 0.45,
            to_x: 0.6,
            y: -0.3,
            z: 0.3,
            route,
        }
    }

    fn ways(approach: Approach, route: Route) -> (RobotModel, Vec<Leg>) {
        let model = RobotModel::default();
        let [x, y, z] = model.arm.rest;
        let legs = legs(
            &Point3::new(x, y, z),
            &low_line(route),
            approach,
            &PushMotionConfig::default(),
            &model,
        );
        (model, legs)
    }

    /// Whether the hand's box at `p` lies inside the body's cylinder.
    fn inside_body(p: &Point3<f64>, model: &RobotModel) -> bool {
        let [hx, hy, _] = model.arm.hand_half;
        let corner = Point2::new(p.x.abs() + hx, p.y.abs() + hy);
        corner.coords.norm() <= model.body.radius + 1e-9
    }

    /// Whether the leg runs along `line` or keeps the hand's box inside the body's cylinder (both
    /// ends inside it: the cylinder is convex).
    fn judged_or_inside(leg: &Leg, line: &StrokeLine, model: &RobotModel) -> bool {
        on_line(&leg.from, &leg.to, line)
            || (inside_body(&leg.from, model) && inside_body(&leg.to, model))
    }

    #[test]
    fn a_line_below_the_top_is_reached_inside_the_body_and_out_along_the_line() {
        // Invariant: whatever the approach, a line reached beside the body changes height only inside the body's cylinder (the first waypoint at the line's height lies in it), every later leg runs at the line's height, a leg at the free speed either keeps inside the cylinder or runs along the line the look judged, and the last leg is the push along the line to its end.
        for approach in [
            Approach::Free,
            Approach::GuardedLast(0.1),
            Approach::Guarded,
        ] {
            let (model, legs) = ways(approach, Route::BesideBody);
            let line = low_line(Route::BesideBody);
            let first_low = legs
                .iter()
                .map(|l| l.from)
                .chain(legs.last().map(|l| l.to))
                .find(|p| (p.z - line.z).abs() < 1e-9)
                .expect("the way reaches the line's height");
            assert!(
                inside_body(&first_low, &model),
                "{approach:?}: {first_low:?}"
            );
            let at_height = legs.iter().skip_while(|l| (l.from.z - line.z).abs() > 1e-9);
            for leg in at_height {
                assert!((leg.to.z - line.z).abs() < 1e-9, "{approach:?}: {leg:?}");
            }
            for leg in legs
                .iter()
                .filter(|l| l.speed > PushMotionConfig::default().approach_speed)
            {
                assert!(
                    judged_or_inside(leg, &line, &model),
                    "{approach:?}: {leg:?}"
                );
            }
            let push = legs.last().expect("a push");
            assert_eq!(push.to, Point3::new(line.to_x, line.y, line.z));
            assert_eq!(push.from, Point3::new(line.from_x, line.y, line.z));
        }
    }

    #[test]
    fn a_free_approach_goes_along_the_line_the_look_judged_and_a_guarded_one_straight() {
        // Invariant: a free approach never goes straight from rest to the line's start (the look judged only the line): it joins the line as near the body as the arm reaches, and every leg at the free speed keeps inside the body's cylinder or runs along the line; a guarded approach at the face's top starts where the hand is and goes straight to the start at the approach speed.
        let (model, free) = ways(Approach::Free, Route::Straight);
        let line = low_line(Route::Straight);
        let joins = Point3::new(model.arm.reach_x[0], line.y, line.z);
        assert!(free.iter().any(|l| l.from == joins), "{free:?}");
        for leg in free.iter().filter(|l| l.speed == model.arm.free_speed) {
            assert!(judged_or_inside(leg, &line, &model), "{leg:?}");
        }
        let (_, guarded) = ways(Approach::Guarded, Route::Straight);
        let [x, y, z] = model.arm.rest;
        assert_eq!(guarded.len(), 2, "{guarded:?}");
        assert_eq!(guarded[0].from, Point3::new(x, y, z));
        assert_eq!(guarded[0].to, Point3::new(line.from_x, line.y, line.z));
        assert_eq!(guarded[0].speed, PushMotionConfig::default().approach_speed);
    }

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
