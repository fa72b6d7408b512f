//! Push planning: where to stand, where to put the hand, which way and how far to push.
//!
//! Kakiuchi et al. push 800 mm straight ahead from a stand pose chosen by hand. Here every face of
//! the prism is a candidate: the robot stands in front of it, facing it, and pushes along its inward
//! normal. A push is valid when the robot can stand there (free, hand within reach), the object's
//! swept footprint meets no other obstacle (whose height range meets the object's) nor a wall, and
//! the robot following it stays free. Among valid pushes the one that opens a path to the goal with
//! the smallest distance wins (then the shortest approach); when none opens a path the shortest
//! valid push is returned with `opens_path == false` (it still serves as a push *test*). The stand
//! pose must be reachable: a planned approach path from the robot's position must exist.

use nalgebra::{Isometry2, Point2, Point3, Unit, Vector2};
use nudge_perception::{ObjectId, Prism};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::hand_height::{HandHeights, hand_heights_on};
use crate::obstacle::Obstacle;
use crate::path::Path;
use crate::planner::rrt_connect::RrtConnect;
use crate::planner::shortcut::Shortcut;
use crate::planner::{Budget, Planner};
use crate::problem::{GoalRegion, Problem};
use crate::reach::{Change, ReachMemo, certainly_unreachable};
use crate::seen_floor::FloorCheck;
use crate::space::pose;
use crate::sweep::{SweepBlock, SweepMargins, sweep_blocked_among};
use crate::validity::{StateValidity, Validity, ValidityError};
use std::cell::RefCell;

use nudge_robot_model::RobotModel;
use std::collections::BTreeSet;

/// Where the hand can reach and what to try.
#[derive(Clone, Debug, PartialEq)]
pub struct PushConfig {
    /// Push distances to try, shortest first (m); see [`PushConfig::distances_up_to`].
    pub distances: Vec<f64>,
    /// Hand reach ahead of the body axis in `base_link` x (m).
    pub reach_x: (f64, f64),
    /// Hand reach sideways in `base_link` y (m).
    pub reach_y: (f64, f64),
    /// Hand reach in height, `base_link` z (m).
    pub reach_z: (f64, f64),
    /// Lateral offsets of the robot from the contact point to try (m).
    pub lateral_offsets: Vec<f64>,
    /// Positions along a face to try as the contact point, as fractions of its length.
    pub contact_fractions: Vec<f64>,
    /// Steps in which the stand-off (body axis to face) grows from its minimum (m).
    pub standoff_step: f64,
    /// Gap left between the robot's cylinder and the object when standing (m).
    pub standoff_margin: f64,
    /// How far below the top of the facing surface the hand pushes (m).
    pub hand_below_top: f64,
    /// Points within this distance of a face belong to the surface facing the robot (m).
    pub face_band: f64,
    /// Faces shorter than this are not pushed (m).
    pub min_face: f64,
    /// Half the width of the hand (m): its way to the contact keeps this clear of other obstacles.
    pub hand_half_width: f64,
    /// Half the height of the hand (m): the band of a face it presses on, and the step in which
    /// [`hand_heights_on`] looks for a solid band.
    pub hand_half_height: f64,
    /// Most that furniture's feet grip a floor (μ): rubber on dry tile or concrete reaches about 0.8
    /// in handbook tables, wood, plastic and metal on floors 0.2–0.6. It bounds the height at which
    /// a push slides what it could otherwise tip (see [`crate::hand_height`]).
    pub max_floor_friction: f64,
    /// Whether a push test's hand goes no higher than slides what could otherwise tip, where the
    /// face is solid that low ([`crate::hand_height`]); else it pushes at the paper's height, just
    /// below the face's top, as clearing strokes always do. On by default: it sets every verdict of
    /// the push-test sweep right with every movable peak under its midpoint (at the paper's height
    /// a light, tall box tips and locks at the limit), and with the hand reaching a lowered line
    /// beside the body (the executive's stroke) the shipped and generated batches read as at the
    /// paper's height (BENCHMARKS.md, "Push test sweep").
    pub test_below_tipping: bool,
    /// Least gap (m) the object's sweep keeps from every other obstacle. A real object turns a little
    /// as it slides and its footprint is known to a few centimetres: a sweep that grazes a corner
    /// (a wall's end beside a doorway) catches on it and jams or swings into the way.
    pub sweep_clearance: f64,
    /// The push that opens the way is made this much longer (m) where the longer sweep is free too:
    /// an object that turns as it slides (pushed off its centre, or dragging a corner) ends short of
    /// the hand's travel, and a push planned to the centimetre would leave it in the way.
    pub distance_margin: f64,
    /// Whether a push that opens no way by itself is chosen longest first (else shortest first, as
    /// a push test's stroke is). A clearing push that opens nothing alone moves an object out of
    /// the way of what must move next: the box beside it in a doorway, whose own push would slide
    /// along it, or whose stand pose it would fill. Pushed only as far as a short stroke, it stays
    /// beside the next one's sweep. Off by default; the executive turns it on for clearing pushes.
    pub far_when_shut: bool,
    /// Faces whose normals differ by less than this are one push direction (rad).
    pub merge_angle: f64,
    /// Side of the cells a footprint's vertices lie on (m): perception's elevation cell. An edge of
    /// length `L` of such a hull may lean up to `atan(cell / L)` off the face it was made from.
    pub footprint_cell: f64,
    /// Planner for the approach and for the path after the push.
    pub planner: RrtConnect,
    /// Its budget per query.
    pub budget: Budget,
    /// Shortcutting applied to the paths returned.
    pub shortcut: Shortcut,
}

impl Default for PushConfig {
    /// The paper's robot's ([`RobotModel::default`]).
    fn default() -> Self {
        Self::for_robot(&RobotModel::default())
    }
}

impl PushConfig {
    /// Push planning for `robot`: its arm's reach and hand, pushes as long as its camera sees.
    pub fn for_robot(robot: &RobotModel) -> Self {
        let arm = &robot.arm;
        let span = |[lo, hi]: [f64; 2]| (lo, hi);
        Self {
            distances: PushConfig::distances_up_to(robot.camera.max_range),
            reach_x: span(arm.reach_x),
            reach_y: span(arm.reach_y),
            reach_z: span(arm.reach_z),
            lateral_offsets: vec![0.0, 0.1, -0.1, 0.2, -0.2, 0.3, -0.3, 0.4, -0.4],
            contact_fractions: vec![0.5, 0.3, 0.7, 0.15, 0.85],
            standoff_step: 0.05,
            standoff_margin: 0.05,
            hand_below_top: 0.05,
            face_band: 0.05,
            min_face: 0.1,
            hand_half_width: arm.hand_half[1],
            hand_half_height: arm.hand_half[2],
            max_floor_friction: 0.8,
            test_below_tipping: true,
            sweep_clearance: 0.05,
            distance_margin: 0.2,
            far_when_shut: false,
            merge_angle: 10f64.to_radians(),
            footprint_cell: nudge_perception::ElevationConfig::default().cell_size,
            planner: RrtConnect::default(),
            budget: Budget::iterations(5_000),
            shortcut: Shortcut::default(),
        }
    }
}

/// Most friction between two things that touch (μ): dry wood, plastic, cardboard and painted walls
/// on each other lie at 0.2–0.6 in handbook tables, rubber at up to 1. An object pushed against a
/// neighbour slides along it only when the push lies outside their contact's friction cone, more
/// than `atan(μ)` off its normal; with μ up to 1, a push heading into what it touches by less than
/// 45° off parallel slides along it, and one heading in more may jam.
pub const MAX_CONTACT_FRICTION: f64 = 1.0;

/// The longest of the short pushes (m): one to a few strokes, tried every [`SHORT_PUSH_STEP`] (see
/// [`PushConfig::distances_up_to`]); a push test is planned among these.
pub const SHORT_PUSHES: f64 = 1.2;

/// The step between the short pushes tried (m): a few centimetres decide whether the way opens
/// beside an object, and a stroke's error is about that.
pub const SHORT_PUSH_STEP: f64 = 0.1;

impl PushConfig {
    /// What a push's sweep keeps from what it passes: [`Self::sweep_clearance`]; from what it
    /// starts against, a footprint cell closer or deeper at most, heading more along it than into
    /// it (see [`SweepMargins`] and [`MAX_CONTACT_FRICTION`]).
    pub fn sweep_margins(&self) -> SweepMargins {
        SweepMargins {
            clearance: self.sweep_clearance,
            contact: self.footprint_cell,
            lean: (1.0 / MAX_CONTACT_FRICTION).atan(),
        }
    }

    /// Push distances to try, shortest first, up to `longest` (m): every 0.1 m from 0.3 m to 1.2 m
    /// (one to a few strokes, where a few centimetres decide whether the way opens beside the
    /// object), then every 0.2 m (long pushes through a doorway or along a corridor, where the
    /// object's end position is known to a stroke's error anyway). A caller sets `longest` from its
    /// camera's range: floor farther than that cannot have been seen from where the push is planned.
    pub fn distances_up_to(longest: f64) -> Vec<f64> {
        let short = (3..=12).map(|k| f64::from(k) * SHORT_PUSH_STEP);
        let long = (1..)
            .map(|k| SHORT_PUSHES + f64::from(k) * 0.2)
            .take_while(move |d| *d <= longest + 1e-9);
        short.chain(long).filter(|d| *d <= longest + 1e-9).collect()
    }
}

/// A push: stand here, hand there, push this way this far.
#[derive(Clone, Debug, PartialEq)]
pub struct PushPlan {
    /// The object pushed.
    pub object: ObjectId,
    /// Where the robot stands before pushing, facing the push direction (map frame).
    pub stand_pose: Isometry2<f64>,
    /// Height of the hand above the floor in the push test (m): where the face is solid, low enough
    /// that the object slides before it tips, else just below the top of the surface facing the
    /// robot ([`crate::hand_height`]).
    pub hand_height: f64,
    /// Height of the hand above the floor in the strokes that clear the way (m): just below the top
    /// of the surface facing the robot, as the paper pushes.
    pub clear_height: f64,
    /// Direction of the push in the map frame.
    pub direction: Unit<Vector2<f64>>,
    /// How far to push (m).
    pub distance: f64,
    /// Where the hand meets the object (map frame, z = hand height).
    pub contact_point: Point3<f64>,
    /// The object's footprint after the push (map frame).
    pub displaced_footprint: Vec<Point2<f64>>,
    /// Whether, after the push, a path leads from the robot to the goal.
    pub opens_path: bool,
    /// That path, from where the push leaves the robot.
    pub path_after: Option<Path>,
    /// The path from the robot's position to the stand pose.
    pub approach: Path,
    /// Where the push leaves the robot: the body walks after the object only as far as the arm's
    /// reach falls short of the push.
    pub end: Point2<f64>,
    /// Whether a push of this object was refused only because it would sweep floor not yet seen:
    /// when this push does not open the way, a look there (or a push into it) might.
    pub unseen_refused: bool,
}

/// Why no push could be planned.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum PushError {
    /// The object is not among the obstacles that block the robot.
    #[error("{0} is not a blocking obstacle")]
    UnknownObject(ObjectId),
    /// No face is long enough and high enough for the hand.
    #[error("{0} has no face the hand can push")]
    NoPushableFace(ObjectId),
    /// No collision-free pose in front of a pushable face has the hand within reach.
    #[error("no free stand pose in front of {0}")]
    NoStandPose(ObjectId),
    /// Every push sweeps the object into another obstacle or a wall, or the robot cannot follow.
    #[error("every push of {0} runs into {1}")]
    Blocked(ObjectId, RunsInto),
    /// Valid pushes exist, but none opens the way (what a sequence's second push must do).
    #[error("no push of {0} opens the way")]
    OpensNoWay(ObjectId),
    /// No valid stand pose can be reached from the robot's position.
    #[error("no valid push of {0} has a reachable stand pose")]
    Unreachable(ObjectId),
    /// Pushes were found, but each stands on floor nobody has seen or sweeps the object over floor
    /// that neither a look nor the object's own shadow explains.
    #[error("every push of {0} needs floor not yet seen")]
    UnseenFloor(ObjectId),
    /// The world could not be edited.
    #[error(transparent)]
    Validity(#[from] ValidityError),
}

/// A face to push and where to stand in front of it.
#[derive(Clone, Debug)]
struct Stance {
    direction: Unit<Vector2<f64>>,
    stand: Point2<f64>,
    contact: Point2<f64>,
    heights: HandHeights,
}

/// What every push of one object is checked against: the object, the other obstacles its sweep
/// must keep clear of, the world with and without it, the goal and the planner's settings.
#[derive(Clone, Copy)]
struct PushScene<'a, 'v> {
    object: &'a Obstacle,
    others: &'a [&'a Obstacle],
    validity: &'a Validity,
    without: &'a Validity,
    goal: &'a GoalRegion,
    config: &'a PushConfig,
    floor: Option<FloorCheck<'a>>,
    /// The other obstacles known to move (see [`plan_push_among`]).
    movers: &'a [ObjectId],
    /// The flood fills' memo of `validity`: every push's "does it open the way" asks it again with
    /// only the object moved.
    reach: &'a RefCell<ReachMemo<'v>>,
}

/// Why a push was not taken.
enum Miss {
    /// It runs into this (`None`: no free stand pose, or the robot cannot follow).
    Blocked(Option<SweepBlock>),
    /// It needs floor nobody has seen.
    Unseen,
}

/// What the sweeps of an object's refused pushes ran into, for the explanation.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RunsInto {
    /// Other obstacles a sweep met.
    pub obstacles: BTreeSet<ObjectId>,
    /// Whether a sweep left the room.
    pub walls: bool,
    /// Whether the robot's body could not follow a push whose sweep was free.
    pub body: bool,
}

impl RunsInto {
    fn note(&mut self, miss: &Miss) {
        match miss {
            Miss::Blocked(Some(SweepBlock::Obstacle(id))) => {
                self.obstacles.insert(*id);
            }
            Miss::Blocked(Some(SweepBlock::Wall)) => self.walls = true,
            Miss::Blocked(None) => self.body = true,
            Miss::Unseen => {}
        }
    }
}

/// `obj-18 and the room's walls`; `something` when nothing was recorded.
impl std::fmt::Display for RunsInto {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut parts: Vec<String> = self.obstacles.iter().map(ToString::to_string).collect();
        if self.walls {
            parts.push("the room's walls".into());
        }
        if self.body {
            parts.push("a place the robot cannot follow".into());
        }
        match parts.len() {
            0 => write!(f, "something"),
            1 => write!(f, "{}", parts[0]),
            n => write!(f, "{} or {}", parts[..n - 1].join(", "), parts[n - 1]),
        }
    }
}

/// A valid push from a stance.
#[derive(Clone, Debug)]
struct Candidate {
    stance: Stance,
    distance: f64,
    displaced: Vec<Point2<f64>>,
    path_after: Option<Path>,
    /// Whether this push leaves the way to the others known to move (see [`plan_push_among`]).
    leaves_way: LeavesWay,
}

/// Plans a push of `prism` for a robot at `robot` that wants to reach `goal` in `validity`'s world,
/// whatever floor has been seen.
pub fn plan_push(
    prism: &Prism,
    validity: &Validity,
    robot: &Point2<f64>,
    goal: &GoalRegion,
    config: &PushConfig,
    rng: &mut ChaCha8Rng,
) -> Result<PushPlan, PushError> {
    plan_push_over(prism, validity, robot, goal, config, None, rng)
}

/// Whether a push that does not open the way leaves it to be opened by moving the others known to
/// move: `Shut` when, with them gone, the goal is still certainly unreachable (a flood fill).
/// Ordered worst first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum LeavesWay {
    Shut,
    Open,
}

/// Plans a push like [`plan_push_among`], with no other obstacle known to move.
pub fn plan_push_over(
    prism: &Prism,
    validity: &Validity,
    robot: &Point2<f64>,
    goal: &GoalRegion,
    config: &PushConfig,
    floor: Option<FloorCheck<'_>>,
    rng: &mut ChaCha8Rng,
) -> Result<PushPlan, PushError> {
    plan_push_among(prism, validity, robot, goal, config, floor, &[], rng)
}

/// Plans a push like [`plan_push`], keeping the stand pose on seen floor and the sweep on seen floor
/// or in the object's own shadow when `floor` is given. [`PushError::UnseenFloor`] when pushes exist
/// but each needs floor not yet seen.
///
/// When no push opens the way, the one chosen is the shortest, in face order, among those that
/// leave the way to `movers` (the other obstacles known to move: a push test said so): after it,
/// with them gone, the goal is not certainly unreachable (a flood fill); the shortest of all when
/// none does. A push that opens nothing is a step (a push test, or one clearing push of several
/// with a look between): the object still stands in the way, and the next steps move it or the
/// others. A step that leaves it where moving the others cannot get past it (into the gap of a
/// doorway another box has just left) must be undone by a later one, when one can be made at all
/// (a box pushed along a doorway is pushed back only from the doorway's far side). Obstacles not
/// yet tested are not counted on: taking them away too leaves most steps open in a cluttered room
/// (a partition's untested end), and changes which steps are taken where nothing is known yet.
#[allow(clippy::too_many_arguments)]
pub fn plan_push_among(
    prism: &Prism,
    validity: &Validity,
    robot: &Point2<f64>,
    goal: &GoalRegion,
    config: &PushConfig,
    floor: Option<FloorCheck<'_>>,
    movers: &[ObjectId],
    rng: &mut ChaCha8Rng,
) -> Result<PushPlan, PushError> {
    let id = prism.id;
    let object = obstacle_of(prism, validity)?;
    let seed: u64 = rng.random();
    let (stances, mut unseen) = stances_of(&object, prism, validity, config, floor.as_ref())?;
    if stances.is_empty() {
        return Err(if unseen {
            PushError::UnseenFloor(id)
        } else {
            PushError::NoStandPose(id)
        });
    }
    let around = Around::new(object, validity);
    let scene = around.scene(validity, goal, config, floor, movers);
    let mut candidates = Vec::new();
    let mut runs_into = RunsInto::default();
    for (k, stance) in stances.iter().enumerate() {
        let mut own = ChaCha8Rng::seed_from_u64(seed.wrapping_add(k as u64));
        let (valid, unseen_sweep) = valid_pushes(stance, &scene, &mut runs_into, &mut own)?;
        candidates.extend(valid);
        unseen |= unseen_sweep;
    }
    if candidates.is_empty() {
        return Err(if unseen {
            PushError::UnseenFloor(id)
        } else {
            PushError::Blocked(id, runs_into)
        });
    }
    // Openers first, then the steps that leave the way to the others; shortest push first (longest
    // first for a step that opens nothing, with `far_when_shut`); then the push whose line passes
    // nearest the footprint's centre, in whole footprint cells; the stable sort keeps face order
    // for ties.
    let off_centre = off_centre_cells(prism, config.footprint_cell);
    candidates.sort_by(|a, b| {
        b.path_after
            .is_some()
            .cmp(&a.path_after.is_some())
            .then(b.leaves_way.cmp(&a.leaves_way))
            .then(if config.far_when_shut && a.path_after.is_none() {
                b.distance.total_cmp(&a.distance)
            } else {
                a.distance.total_cmp(&b.distance)
            })
            .then(off_centre(&a.stance).cmp(&off_centre(&b.stance)))
    });
    let mut own = ChaCha8Rng::seed_from_u64(seed ^ 0xA5A5_A5A5);
    let first = reachable(candidates, validity, robot, config, &mut own);
    if first.as_ref().is_some_and(|(c, _)| c.path_after.is_some()) {
        return plan_of(id, first, unseen, config).ok_or(PushError::Unreachable(id));
    }
    // No reachable push along a face's normal opens the way: push a little off the normals too. A
    // face seen a few degrees off the way it must go (a box in a corridor whose hull leans 5°)
    // drifts into the wall over a long push along its normal, not along the corridor.
    let (tilted, unseen_tilted) =
        tilted_stances(&around.object, prism, validity, config, floor.as_ref());
    unseen |= unseen_tilted;
    let mut openers = Vec::new();
    for (k, stance) in tilted.iter().enumerate() {
        let mut own = ChaCha8Rng::seed_from_u64(seed.wrapping_add((stances.len() + k) as u64));
        let (valid, unseen_sweep) = valid_pushes(stance, &scene, &mut runs_into, &mut own)?;
        openers.extend(valid.into_iter().filter(|c| c.path_after.is_some()));
        unseen |= unseen_sweep;
    }
    openers.sort_by(|a, b| a.distance.total_cmp(&b.distance));
    let tilted_opener = reachable(openers, validity, robot, config, &mut own);
    plan_of(id, tilted_opener.or(first), unseen, config).ok_or(
        // A reachable push refused only for unseen floor is what a look can change.
        if unseen {
            PushError::UnseenFloor(id)
        } else {
            PushError::Unreachable(id)
        },
    )
}

/// How far (in whole cells of `cell`) a stance's push line passes from the footprint's centre of
/// area, where an object of even weight has its centre of friction. A push through it slides the
/// object without turning it (Mason 1986: the turn grows with the line's offset from that
/// centre), so the object goes where the plan sweeps it, and a test's colour ICP measures a
/// plain slide rather than a slide and a turn on a face seen half edge-on. Counted in cells: a
/// hull's centre is no better known than its cells, and closer lines keep their faces' order.
fn off_centre_cells(prism: &Prism, cell: f64) -> impl Fn(&Stance) -> u64 {
    let centre = prism.centroid();
    let cell = cell.max(1e-3);
    move |stance| {
        centre.map_or(0, |c| {
            let offset = stance.direction.perp(&(c - stance.contact)).abs();
            (offset / cell).round() as u64
        })
    }
}

/// The first of `candidates` whose stand pose the robot can reach from `robot`, with the way there.
fn reachable(
    candidates: Vec<Candidate>,
    validity: &Validity,
    robot: &Point2<f64>,
    config: &PushConfig,
    rng: &mut ChaCha8Rng,
) -> Option<(Candidate, Path)> {
    candidates.into_iter().find_map(|c| {
        plan(validity, robot, &c.stance.stand, 0.0, config, None, rng).map(|path| (c, path))
    })
}

/// The plan of a push of object `id` with its approach; `unseen` says whether some push was
/// refused for floor not yet seen.
fn plan_of(
    id: ObjectId,
    chosen: Option<(Candidate, Path)>,
    unseen: bool,
    config: &PushConfig,
) -> Option<PushPlan> {
    let (c, approach) = chosen?;
    let s = &c.stance;
    Some(PushPlan {
        object: id,
        stand_pose: pose(s.stand.x, s.stand.y, s.direction.y.atan2(s.direction.x)),
        hand_height: s.heights.test,
        clear_height: s.heights.clear,
        direction: s.direction,
        distance: c.distance,
        contact_point: Point3::new(s.contact.x, s.contact.y, s.heights.test),
        displaced_footprint: c.displaced,
        opens_path: c.path_after.is_some(),
        path_after: c.path_after,
        approach,
        end: follow_end(s, c.distance, config),
        unseen_refused: unseen,
    })
}

/// The obstacle `prism` is in `validity`'s world.
fn obstacle_of(prism: &Prism, validity: &Validity) -> Result<Obstacle, PushError> {
    validity
        .obstacle(prism.id)
        .cloned()
        .ok_or(PushError::UnknownObject(prism.id))
}

/// What every push of one object is checked against besides the world: the object, the other
/// obstacles its sweep must keep clear of and the world without it.
struct Around<'v> {
    object: Obstacle,
    others: Vec<&'v Obstacle>,
    without: Validity,
    reach: RefCell<ReachMemo<'v>>,
}

impl<'v> Around<'v> {
    fn new(object: Obstacle, validity: &'v Validity) -> Self {
        let others = validity
            .obstacles()
            .iter()
            .filter(|o| o.id() != object.id() && o.heights_overlap(&object))
            .collect();
        Self {
            without: validity.without(&[object.id()]),
            object,
            others,
            reach: RefCell::new(ReachMemo::new(validity)),
        }
    }

    /// The scene pushes of the object are checked in.
    fn scene<'a>(
        &'a self,
        validity: &'a Validity,
        goal: &'a GoalRegion,
        config: &'a PushConfig,
        floor: Option<FloorCheck<'a>>,
        movers: &'a [ObjectId],
    ) -> PushScene<'a, 'v> {
        PushScene {
            object: &self.object,
            others: &self.others,
            validity,
            without: &self.without,
            goal,
            config,
            floor,
            movers,
            reach: &self.reach,
        }
    }
}

/// A stance in front of each of `object`'s pushable faces that has a free stand pose (on seen floor,
/// with a floor check), and whether some face's only free stand poses lie on floor not yet seen;
/// [`PushError::NoPushableFace`] when it has no face to push.
fn stances_of(
    object: &Obstacle,
    prism: &Prism,
    validity: &Validity,
    config: &PushConfig,
    floor: Option<&FloorCheck<'_>>,
) -> Result<(Vec<Stance>, bool), PushError> {
    let faces = pushable_faces(object, prism, config);
    if faces.is_empty() {
        return Err(PushError::NoPushableFace(object.id()));
    }
    let mut unseen = false;
    let stances = faces
        .iter()
        .filter_map(|f| match stance_for(f, validity, config, floor) {
            Ok(s) => Some(s),
            Err(miss) => {
                unseen |= matches!(miss, Miss::Unseen);
                None
            }
        })
        .collect();
    Ok((stances, unseen))
}

/// Angles (rad) by which a push may leave a face's normal, either way: within the hand's friction
/// cone on the face, so the hand does not slip along it. A friction coefficient of 0.3 between hand
/// and object (plastic on wood, the low end) gives a cone of 16.7° about the normal; half of it
/// keeps a margin for the object turning as it slides.
const FACE_TILTS: [f64; 2] = [0.07, 0.14];

/// Stances for pushes [`FACE_TILTS`] off each pushable face's normal, either way, and whether one
/// was refused for floor not yet seen.
fn tilted_stances(
    object: &Obstacle,
    prism: &Prism,
    validity: &Validity,
    config: &PushConfig,
    floor: Option<&FloorCheck<'_>>,
) -> (Vec<Stance>, bool) {
    let mut unseen = false;
    let mut stances = Vec::new();
    for face in pushable_faces(object, prism, config) {
        for tilt in FACE_TILTS.iter().flat_map(|t| [*t, -*t]) {
            let direction = nalgebra::Rotation2::new(tilt) * face.direction.into_inner();
            let tilted = Face {
                direction: Unit::new_normalize(direction),
                ..face.clone()
            };
            match stance_for(&tilted, validity, config, floor) {
                Ok(s) => stances.push(s),
                Err(miss) => unseen |= matches!(miss, Miss::Unseen),
            }
        }
    }
    (stances, unseen)
}

/// A face of the footprint: its ends, inward push direction and the hand's heights on it.
#[derive(Clone, Debug)]
struct Face {
    object: ObjectId,
    a: Point2<f64>,
    b: Point2<f64>,
    direction: Unit<Vector2<f64>>,
    /// The hand's heights with its middle at each of [`PushConfig::contact_fractions`] along the
    /// face, in that order (`None` where the face there is out of the hand's reach).
    heights: Vec<Option<HandHeights>>,
}

fn pushable_faces(object: &Obstacle, prism: &Prism, config: &PushConfig) -> Vec<Face> {
    let f = object.footprint();
    let n = f.len();
    let mut faces: Vec<Face> = Vec::new();
    for i in 0..n {
        let Some((a, b)) = face_from(f, i, config.min_face) else {
            continue;
        };
        let edge = b - a;
        // Counter-clockwise footprint: the outward normal is the edge turned clockwise.
        let outward = Unit::new_normalize(Vector2::new(edge.y, -edge.x));
        let heights = hand_heights_on(
            &a,
            &b,
            &outward,
            &config.contact_fractions,
            object,
            prism,
            config,
        );
        if heights.iter().all(Option::is_none) {
            continue;
        }
        let face = Face {
            object: object.id(),
            a,
            b,
            direction: Unit::new_unchecked(-outward.into_inner()),
            heights,
        };
        // Nearly parallel faces (a hull of noisy points) are one direction: keep the longest. A short
        // edge beside a face (a hull's corner cut a cell deep) leans off it by up to the angle a
        // footprint cell subtends over its length: one face too, not a push at the object's corner.
        let one_face = |g: &Face| {
            let shorter = (g.b - g.a).norm().min(edge.norm()).max(1e-6);
            let lean = (config.footprint_cell / shorter).atan();
            g.direction.angle(&face.direction) < config.merge_angle.max(lean)
        };
        match faces.iter_mut().find(|g| one_face(g)) {
            Some(g) if (g.b - g.a).norm() < edge.norm() => *g = face,
            Some(_) => {}
            None => faces.push(face),
        }
    }
    faces
}

/// Most a run of short edges may turn in all and still be one face (rad): the arc of a round object
/// (a bin's hull turns by 360° / its vertex count at each vertex) is pushed like a face, a box's
/// corner (90°) is not.
const MAX_ARC_TURN: f64 = std::f64::consts::FRAC_PI_4;

/// The face starting at vertex `i` of the counter-clockwise footprint `f`: its edge when at least
/// `min_face` long, else the chord over the run of short edges from it once the chord is that long,
/// as long as they turn less than [`MAX_ARC_TURN`] in all.
fn face_from(f: &[Point2<f64>], i: usize, min_face: f64) -> Option<(Point2<f64>, Point2<f64>)> {
    let n = f.len();
    let a = f[i];
    let first = f[(i + 1) % n] - a;
    if first.norm() >= min_face {
        return Some((a, f[(i + 1) % n]));
    }
    // A run of short edges only: a long edge is a face of its own, and a short one beside it is a
    // hull's corner, not part of an arc.
    let mut turned = 0.0;
    let mut last = first;
    for k in 1..n {
        let b = f[(i + k) % n];
        let next = f[(i + k + 1) % n] - b;
        if next.norm() >= min_face {
            return None;
        }
        turned += last.angle(&next);
        if turned > MAX_ARC_TURN {
            return None;
        }
        let end = f[(i + k + 1) % n];
        if (end - a).norm() >= min_face {
            return Some((a, end));
        }
        last = next;
    }
    None
}

/// The first free stand pose in front of `face` with the hand within reach, on seen floor when
/// `floor` is given ([`Miss::Unseen`] when free ones exist only on unseen floor).
fn stance_for(
    face: &Face,
    validity: &Validity,
    config: &PushConfig,
    floor: Option<&FloorCheck<'_>>,
) -> Result<Stance, Miss> {
    let d = face.direction.into_inner();
    let tangent = Vector2::new(-d.y, d.x);
    let r = validity.robot().radius;
    let min_standoff = (r + config.standoff_margin).max(config.reach_x.0);
    let steps = ((config.reach_x.1 - min_standoff) / config.standoff_step.max(1e-3)).floor();
    let standoffs =
        (0..=steps.max(-1.0) as i64).map(|k| min_standoff + k as f64 * config.standoff_step);
    let mut miss = Miss::Blocked(None);
    for standoff in standoffs {
        for (&t, heights) in config.contact_fractions.iter().zip(&face.heights) {
            let Some(heights) = *heights else {
                continue;
            };
            let contact = face.a + (face.b - face.a) * t;
            for &lateral in &config.lateral_offsets {
                // The hand is at -lateral in base_link y when the body is shifted by +lateral.
                if !(config.reach_y.0..=config.reach_y.1).contains(&(-lateral)) {
                    continue;
                }
                let stand = contact - d * standoff + tangent * lateral;
                if !validity.is_free(&stand)
                    || !hand_line_clear(face, &contact, &heights, standoff, validity, config)
                {
                    continue;
                }
                if floor.is_some_and(|f| !f.stands(&stand, r)) {
                    miss = Miss::Unseen;
                    continue;
                }
                return Ok(Stance {
                    direction: face.direction,
                    stand,
                    contact,
                    heights,
                });
            }
        }
    }
    Err(miss)
}

/// Whether the hand's way from the body to `contact` (along the push, from its nearest reach) keeps
/// clear of every other obstacle at the hand's heights: a hand reaching past a table's leg to the
/// table's far face, or past one object to the next, would strike the first before any guard.
fn hand_line_clear(
    face: &Face,
    contact: &Point2<f64>,
    heights: &HandHeights,
    standoff: f64,
    validity: &Validity,
    config: &PushConfig,
) -> bool {
    let d = face.direction.into_inner();
    let from = contact - d * (standoff - config.reach_x.0).max(0.0);
    // The contact point itself lies on the object's face, and on nothing else.
    let to = contact - d * config.hand_half_width;
    validity
        .obstacles()
        .iter()
        .filter(|o| o.id() != face.object)
        .filter(|o| {
            [heights.test, heights.clear]
                .iter()
                .any(|z| o.z_min() <= *z && *z <= o.z_max())
        })
        .all(|o| o.distance_to_segment(&from, &to) > config.hand_half_width)
}

/// Valid pushes from `stance`, shortest first: the first that opens a path ends the list, since a
/// longer push along the same face is no better. The flag says whether a push was refused because it
/// sweeps over unseen floor; what the first refused push ran into is noted in `runs_into`.
fn valid_pushes(
    stance: &Stance,
    scene: &PushScene<'_, '_>,
    runs_into: &mut RunsInto,
    rng: &mut ChaCha8Rng,
) -> Result<(Vec<Candidate>, bool), PushError> {
    let config = scene.config;
    let mut out = Vec::new();
    let mut unseen = false;
    for &distance in &config.distances {
        if !(distance.is_finite() && distance > 0.0) {
            continue;
        }
        // Sweeps only grow with distance: once blocked (or over unseen floor), longer pushes are too.
        let candidate = match push_of(stance, distance, scene, rng)? {
            Ok(c) => c,
            Err(Miss::Unseen) => {
                unseen = true;
                break;
            }
            Err(miss) => {
                runs_into.note(&miss);
                break;
            }
        };
        if candidate.path_after.is_none() {
            out.push(candidate);
            continue;
        }
        // The push that opens the way, made longer by the margin where that is free too: an object
        // that turns as it slides ends short of where the hand drove it.
        let longer = if config.distance_margin > 0.0 {
            push_of(stance, distance + config.distance_margin, scene, rng)?
                .ok()
                .filter(|c| c.path_after.is_some())
        } else {
            None
        };
        out.push(longer.unwrap_or(candidate));
        break;
    }
    Ok((out, unseen))
}

/// The push of `object` from `stance` by `distance`, with the path to the goal after it (`None` in
/// it when the push does not open the way); a [`Miss`] when the sweep runs into something or over
/// floor not yet seen.
fn push_of(
    stance: &Stance,
    distance: f64,
    scene: &PushScene<'_, '_>,
    rng: &mut ChaCha8Rng,
) -> Result<Result<Candidate, Miss>, PushError> {
    let (offset, end) = match sweep_of(stance, distance, scene)? {
        Ok(swept) => swept,
        Err(miss) => return Ok(Err(miss)),
    };
    let PushScene {
        object,
        validity,
        goal,
        config,
        movers,
        reach,
        ..
    } = *scene;
    let after = validity.with_moved(object.id(), &offset)?;
    let moved = Change {
        removed: &[],
        moved: Some(object.id()),
    };
    let path_after = plan(
        &after,
        &end,
        &goal.centre(),
        goal.tolerance(),
        config,
        Some((reach, moved)),
        rng,
    );
    let shut_without_movers = || {
        let change = Change {
            removed: movers,
            moved: Some(object.id()),
        };
        reach
            .borrow_mut()
            .certainly_unreachable(&after.without(movers), change, &end, goal)
    };
    let leaves_way = if path_after.is_none() && !movers.is_empty() && shut_without_movers() {
        LeavesWay::Shut
    } else {
        LeavesWay::Open
    };
    Ok(Ok(Candidate {
        stance: stance.clone(),
        distance,
        displaced: object.footprint().iter().map(|p| p + offset).collect(),
        path_after,
        leaves_way,
    }))
}

/// A push's offset of the object (m, map frame) and where it leaves the robot.
type Swept = (Vector2<f64>, Point2<f64>);

/// The offset of the push of `distance` from `stance` and where it leaves the robot, when its sweep
/// keeps clear of everything else, the body can follow it and (with a floor check) it stays on seen
/// floor; else why not.
fn sweep_of(
    stance: &Stance,
    distance: f64,
    scene: &PushScene<'_, '_>,
) -> Result<Result<Swept, Miss>, PushError> {
    let PushScene {
        object,
        others,
        validity,
        without,
        config,
        floor,
        ..
    } = *scene;
    let offset = stance.direction.into_inner() * distance;
    let swept = object.swept(&offset).map_err(ValidityError::from)?;
    let block = sweep_blocked_among(object, &offset, others, validity, config.sweep_margins())
        .map_err(ValidityError::from)?;
    let end = follow_end(stance, distance, config);
    if block.is_some() || !without.motion_free(&stance.stand, &end) {
        return Ok(Err(Miss::Blocked(block)));
    }
    if floor.is_some_and(|f| !sweep_on_seen_floor(object, &swept, &f)) {
        return Ok(Err(Miss::Unseen));
    }
    Ok(Ok((offset, end)))
}

/// Where a push of `distance` from `stance` leaves the robot: the arm pushes as far as it reaches
/// before the body has to walk after the object, and the body follows only the rest (the clearing
/// push walks after it no further than that).
fn follow_end(stance: &Stance, distance: f64, config: &PushConfig) -> Point2<f64> {
    let d = stance.direction.into_inner();
    let arm = config.reach_x.1 - (stance.contact - stance.stand).dot(&d);
    stance.stand + d * (distance - arm).max(0.0)
}

/// A push whose sweep is valid, found without asking whether it opens the way: what a push
/// sequence's first push is chosen from.
#[derive(Clone, Debug)]
pub struct SweptPush {
    /// The object pushed.
    pub object: ObjectId,
    stance: Stance,
    /// How far (m).
    pub distance: f64,
    /// Where the push leaves the robot.
    pub end: Point2<f64>,
}

impl SweptPush {
    /// The object's displacement (m, map frame).
    pub fn offset(&self) -> Vector2<f64> {
        self.stance.direction.into_inner() * self.distance
    }

    /// Where the robot stands to push.
    pub fn stand(&self) -> Point2<f64> {
        self.stance.stand
    }
}

/// Every push of `prism` at `distances` (the face, stand pose and floor rules of [`plan_push_over`])
/// whose sweep keeps clear of everything else and which the body can follow, whether or not it opens
/// the way, stand poses nearest `robot` first. [`PushError`] when the object has no pushable face,
/// no free stand pose, or no such push: [`PushError::Blocked`] saying what the sweeps ran into, or
/// [`PushError::UnseenFloor`] when one was refused for floor not yet seen.
pub fn swept_pushes(
    prism: &Prism,
    validity: &Validity,
    robot: &Point2<f64>,
    goal: &GoalRegion,
    config: &PushConfig,
    floor: Option<FloorCheck<'_>>,
    distances: &[f64],
) -> Result<Vec<SweptPush>, PushError> {
    let id = prism.id;
    let object = obstacle_of(prism, validity)?;
    let (mut stances, _) = stances_of(&object, prism, validity, config, floor.as_ref())?;
    if stances.is_empty() {
        return Err(PushError::NoStandPose(id));
    }
    stances.sort_by(|a, b| {
        (a.stand - robot)
            .norm()
            .total_cmp(&(b.stand - robot).norm())
    });
    let around = Around::new(object, validity);
    let scene = around.scene(validity, goal, config, floor, &[]);
    let mut out = Vec::new();
    let mut runs_into = RunsInto::default();
    let mut unseen = false;
    for stance in &stances {
        for &distance in distances {
            // Sweeps only grow with distance: once one is refused, longer ones are too.
            match sweep_of(stance, distance, &scene)? {
                Ok((_, end)) => out.push(SweptPush {
                    object: id,
                    stance: stance.clone(),
                    distance,
                    end,
                }),
                Err(miss) => {
                    unseen |= matches!(miss, Miss::Unseen);
                    runs_into.note(&miss);
                    break;
                }
            }
        }
    }
    match (out.is_empty(), unseen) {
        (true, true) => Err(PushError::UnseenFloor(id)),
        (true, false) => Err(PushError::Blocked(id, runs_into)),
        (false, _) => Ok(out),
    }
}

/// The plan of `push`, its approach planned from `robot`; `None` when no approach is found.
pub fn plan_of_swept(
    push: &SweptPush,
    prism: &Prism,
    validity: &Validity,
    robot: &Point2<f64>,
    config: &PushConfig,
    rng: &mut ChaCha8Rng,
) -> Option<PushPlan> {
    let s = &push.stance;
    let approach = plan(validity, robot, &s.stand, 0.0, config, None, rng)?;
    let offset = push.offset();
    Some(PushPlan {
        object: push.object,
        stand_pose: pose(s.stand.x, s.stand.y, s.direction.y.atan2(s.direction.x)),
        hand_height: s.heights.test,
        clear_height: s.heights.clear,
        direction: s.direction,
        distance: push.distance,
        contact_point: Point3::new(s.contact.x, s.contact.y, s.heights.test),
        displaced_footprint: prism.footprint.iter().map(|p| p + offset).collect(),
        opens_path: false,
        path_after: None,
        approach,
        end: push.end,
        unseen_refused: false,
    })
}

/// Spacing of the sample points of a sweep checked against the floor seen (m): the obstacle-type
/// grid's cell.
const SWEEP_SAMPLE: f64 = 0.05;

/// Whether the floor `swept` covers beyond the object's footprint was seen, or lies within the
/// object's own shadow of its footprint (sampled on a lattice of [`SWEEP_SAMPLE`]).
fn sweep_on_seen_floor(object: &Obstacle, swept: &Obstacle, floor: &FloorCheck<'_>) -> bool {
    let b = swept.aabb();
    let nx = ((b.max.x - b.min.x) / SWEEP_SAMPLE).ceil() as usize;
    let ny = ((b.max.y - b.min.y) / SWEEP_SAMPLE).ceil() as usize;
    (0..=ny).all(|j| {
        (0..=nx).all(|i| {
            let p = Point2::new(
                b.min.x + i as f64 * SWEEP_SAMPLE,
                b.min.y + j as f64 * SWEEP_SAMPLE,
            );
            floor.seen.seen(&p)
                || !swept.contains(&p)
                || object.contains(&p)
                || (object.distance_to_point(&p) <= floor.own_shadow
                    && object.distance_to_segment(&floor.eye, &p) <= 1e-6)
        })
    })
}

/// A path in `validity` from `from` to within `tolerance` of `to`; `reach`, when given, is a flood
/// fill memo of a world `validity` is a change of.
fn plan(
    validity: &Validity,
    from: &Point2<f64>,
    to: &Point2<f64>,
    tolerance: f64,
    config: &PushConfig,
    reach: Option<(&RefCell<ReachMemo<'_>>, Change<'_>)>,
    rng: &mut ChaCha8Rng,
) -> Option<Path> {
    let problem = Problem::new(*from, *to, tolerance).ok()?;
    // Most pushes tried do not open the way; proving that takes a flood fill, not a planner's
    // whole budget.
    let unreachable = match reach {
        Some((memo, change)) => {
            memo.borrow_mut()
                .certainly_unreachable(validity, change, from, problem.goal())
        }
        None => certainly_unreachable(validity, from, problem.goal()),
    };
    if unreachable {
        return None;
    }
    let mut planner = config.planner;
    let path = planner.solve(&problem, validity, config.budget, rng).ok()?;
    Some(config.shortcut.shorten(&path, validity, rng))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Point3 as P3};
    use nudge_perception::{CloudFrame, ColourCloud};

    /// A chair 0.5 m square at x 0..0.5: seat at 0.45 m, backrest along x = 0.5 up to 0.85 m.
    fn chair() -> (Prism, Obstacle) {
        let mut points = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        for i in 0..=10 {
            let y = f64::from(i) * 0.05;
            for j in 0..=10 {
                let x = f64::from(j) * 0.05;
                points.push(P3::new(x as f32, y as f32, 0.45), [90, 60, 30]);
            }
            for k in 0..=8 {
                let z = 0.45 + f64::from(k) * 0.05;
                points.push(P3::new(0.5, y as f32, z as f32), [90, 60, 30]);
            }
        }
        let footprint = vec![
            Point2::new(0.0, 0.0),
            Point2::new(0.5, 0.0),
            Point2::new(0.5, 0.5),
            Point2::new(0.0, 0.5),
        ];
        let prism = Prism {
            id: ObjectId(1),
            footprint: footprint.clone(),
            z_min: 0.0,
            z_max: 0.85,
            points,
        };
        let obstacle = Obstacle::new(ObjectId(1), &footprint, 0.0, 0.85).expect("square");
        (prism, obstacle)
    }

    #[test]
    fn hand_goes_below_the_top_of_the_facing_surface() {
        // Invariant: the hand height follows the surface facing the robot (seat edge in front,
        // backrest behind), not the prism's overall top.
        let (prism, obstacle) = chair();
        let config = PushConfig::default();
        let faces = pushable_faces(&obstacle, &prism, &config);
        let height_pushing = |dir: Vector2<f64>| {
            faces
                .iter()
                .find(|f| f.direction.into_inner().dot(&dir) > 0.99)
                .and_then(|f| f.heights[0])
                .map(|h| h.clear)
                .expect("a face for this direction")
        };
        // Robot behind the backrest (at x > 0.5) pushes toward -x: backrest top 0.85.
        assert!((height_pushing(Vector2::new(-1.0, 0.0)) - 0.80).abs() < 1e-6);
        // Robot in front of the seat (x < 0) pushes toward +x: seat edge 0.45.
        assert!((height_pushing(Vector2::new(1.0, 0.0)) - 0.40).abs() < 1e-6);
        // Without points: the prism's top.
        let bare = Prism {
            points: ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0),
            ..prism
        };
        let faces = pushable_faces(&obstacle, &bare, &config);
        assert!(faces.iter().all(|f| {
            f.heights
                .iter()
                .flatten()
                .all(|h| (h.clear - 0.80).abs() < 1e-6)
        }));
    }

    #[test]
    fn a_round_object_has_faces_and_a_box_corner_is_not_one() {
        // Invariant: the hull of a bin (a 24-gon of 6.5 cm edges) yields push faces from chords over its short edges, and a square with a 3 cm bevelled corner yields only its four sides.
        let bin: Vec<Point2<f64>> = (0..24)
            .map(|k| {
                let a = std::f64::consts::TAU * f64::from(k) / 24.0;
                Point2::new(0.25 * a.cos(), 0.25 * a.sin())
            })
            .collect();
        let faces: Vec<_> = (0..bin.len())
            .filter_map(|i| face_from(&bin, i, 0.1))
            .collect();
        assert_eq!(faces.len(), 24);
        assert!(
            faces
                .iter()
                .all(|(a, b)| (b - a).norm() >= 0.1 && (b - a).norm() < 0.14)
        );
        let square = vec![
            Point2::new(0.0, 0.0),
            Point2::new(0.5, 0.0),
            Point2::new(0.5, 0.47),
            Point2::new(0.47, 0.5),
            Point2::new(0.0, 0.5),
        ];
        let faces: Vec<_> = (0..square.len())
            .filter_map(|i| face_from(&square, i, 0.1))
            .collect();
        assert_eq!(faces.len(), 4);
    }

    #[test]
    fn a_short_edge_leaning_a_cell_off_a_face_is_that_face_and_a_bevel_is_not() {
        // Invariant: a hull edge 11 cm long leaning 11° off the face beside it (a corner cut one 4 cm footprint cell deep) is no push direction of its own: the object's faces stay its four sides, pushed square; an 11 cm edge cut at 45° is a face of its own.
        let faces_of = |footprint: Vec<Point2<f64>>| {
            let prism = Prism {
                id: ObjectId(1),
                footprint: footprint.clone(),
                z_min: 0.0,
                z_max: 1.0,
                points: ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0),
            };
            let obstacle = Obstacle::new(ObjectId(1), &footprint, 0.0, 1.0).expect("convex");
            pushable_faces(&obstacle, &prism, &PushConfig::default())
        };
        let leaning = faces_of(vec![
            Point2::new(0.0, 0.0),
            Point2::new(0.5, 0.0),
            Point2::new(0.5, 0.5),
            Point2::new(0.11, 0.5),
            Point2::new(0.0, 0.478),
        ]);
        assert_eq!(leaning.len(), 4);
        assert!(leaning.iter().all(|f| {
            let d = f.direction.into_inner();
            d.x.abs() < 1e-9 || d.y.abs() < 1e-9
        }));
        let bevelled = faces_of(vec![
            Point2::new(0.0, 0.0),
            Point2::new(0.5, 0.0),
            Point2::new(0.5, 0.5),
            Point2::new(0.078, 0.5),
            Point2::new(0.0, 0.422),
        ]);
        assert_eq!(bevelled.len(), 5);
    }
}
