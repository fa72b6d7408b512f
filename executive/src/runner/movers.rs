//! One truth about what moves: what a look-around saw change (see
//! [`nudge_perception::seen_through`]) goes into the run's memory of motion, and obstacles remembered
//! from earlier looks that this look saw through are forgotten.
//!
//! A person walking through the views leaves points where they were (departed: a later view looked
//! through that place) and where they are (arrived: an earlier view looked through it). The departed
//! points never reach perception; both mark their cells as moved now, in the same per-cell memory
//! the grid's Moving cells write ([`super::world::WorldModel::last_motion`]), so that whatever
//! perception builds there counts as having moved lately — waited for, never push-tested (see the
//! machine's `pick`) — and the grid's stationary cells near it are not taken for walls.

use nalgebra::Point2;
use nudge_motion::PushPlan;
use nudge_perception::grid::{CellIndex, Footprint, GridGeometry};
use nudge_perception::prism::convex_intersection_area;
use nudge_perception::seen_through::{FLOOR_BAND, Sight};
use nudge_perception::{Change, ColourCloud, LookChanges, ObjectId, Prism, SplitLook};

use super::Runner;
use crate::record::{LogLevel, Observer};
use crate::robot::Robot;

/// An obstacle remembered from before is forgotten when this share of its points (above the floor)
/// lies where the new look saw through: more than half, so that the part of an object a person
/// stood in front of, or a few stray points, cannot remove it.
const SEEN_THROUGH_SHARE: f64 = 0.5;

/// How far a push keeps from anything that may be a person (m, between outlines): Hall's intimate
/// distance, 0.45 m, the space people keep from strangers — within it the object, or the hand
/// behind it, is at arm's length of them. A push test or clearing stroke whose object or sweep comes
/// nearer a mover than this does not start.
pub const PERSON_CLEARANCE: f64 = 0.45;

/// Departed or arrived points a grid cell must hold for the look to count motion there: thirty, a
/// fifth of the column a person's body gives in a 5 cm cell (the camera's pixels lie about 2 cm
/// apart at 5 m, so a 1.7 m body is some 80 rows of two columns there, and more nearer); the edge of
/// a table top or a chair's seat seen a pixel differently by two views gives one to three (ten was
/// tried: at the far end of the 14 m hall, one run of `long-hall` in 30 read people into it).
const CELL_POINTS: usize = 30;

/// Arrived points that make an obstacle an arrival: a few dozen, a patch of a few centimetres at a
/// few metres' range (the camera's pixels lie about a centimetre apart there), more than the odd
/// point a surface's edge can give.
const ARRIVED_POINTS: usize = 30;

/// The share of an obstacle's footprint cells the grid must hold Free, when a look first finds it
/// there, for it to have arrived since the grid saw that floor: a third. Furniture that stood there
/// all along hid its floor from most rays (at most 1 % of its cells Free in seed 1 of every shipped
/// scenario, but a tenth or more on some other seeds: a tenth broke still rooms); a person seen from
/// one side is a thin arc of points whose hull spans floor that the grid saw empty before they came
/// (30-95 % in seed 1 of the people scenarios; one pacer in another run stood on 28 %). With a
/// third, the shipped batch of 30 seeds ran every room without people as before.
const ARRIVED_ON_FREE: f64 = 1.0 / 3.0;

/// The most an obstacle may measure across (m, its footprint's extent) to have come by itself onto
/// floor the grid saw free ([`ARRIVED_ON_FREE`]): what one or two people standing together occupy.
/// An adult's shoulders are 0.4–0.5 m across (the 95th percentile's biacromial breadth is 0.43 m;
/// with the arms, 0.5–0.6 m), two side by side 1.2 m. Anything longer seen on floor the grid held
/// free is a thin surface seen obliquely — a wall whose hull is a wedge over the floor in front of it
/// (1.35 m in one generated room), or the room's own wall, whose face cells the grid saw crossed by
/// grazing rays (4 m in another) — and taken for a person, it shut off every push near it.
pub(super) const PERSON_EXTENT: f64 = 1.2;

/// How far outside a footprint an arrived point still counts as the obstacle's (m): the footprint is
/// a hull of 4 cm elevation cells, and its own points lie up to a cell from its outline.
const ARRIVAL_REACH: f64 = 0.05;

/// Least share of an obstacle's points a look must see (through them, or returned from them) to
/// judge whether it is gone: a quarter, so that a few points seen past the edge of what hides the
/// rest cannot remove it, while a person half hidden by a chair's back (the body above a 0.9 m
/// back, of a 1.7 m person) is judged on the half in sight.
const IN_SIGHT_SHARE: f64 = 0.25;

/// Points of an obstacle asked about, at most: evenly spread, enough for its share to within a few
/// per cent.
const SAMPLE: usize = 400;

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Folds a look's changes into the world model and returns the cloud to perceive, with the
    /// points that arrived: departed and arrived points count only in grid cells that hold at least
    /// [`CELL_POINTS`] of them (a body, not a stray pixel at an edge); there they are noted as motion
    /// now, and the departed ones are left out of the cloud; elsewhere the departed go back into it.
    /// The remembered obstacles the look saw through (neither found static by a push test, nor
    /// pushed or found movable by the robot: those stay under their own rules) are forgotten.
    pub(crate) fn fold_changes(
        &mut self,
        split: SplitLook,
        changes: &LookChanges,
    ) -> (ColourCloud, ColourCloud) {
        let SplitLook {
            fused,
            changes: what,
        } = split;
        let departed = self.dense_cells(&fused, &what, Change::Departed);
        let arrived = self.dense_cells(&fused, &what, Change::Arrived);
        self.note_motion(&departed);
        self.note_motion(&arrived);
        let mut kept = ColourCloud::with_capacity(
            fused.frame(),
            *fused.sensor_pose(),
            fused.stamp(),
            fused.len(),
        );
        let mut came = ColourCloud::empty(fused.frame(), *fused.sensor_pose(), fused.stamp());
        let cell_of = self.cell_index();
        for (i, p, rgb) in fused.iter_valid() {
            let change = what.get(i).copied().unwrap_or(Change::Stayed);
            let dense = |cells: &std::collections::BTreeSet<usize>| {
                cell_of(&p).is_some_and(|c| cells.contains(&c))
            };
            match change {
                Change::Departed if dense(&departed) => continue,
                Change::Arrived if dense(&arrived) => came.push(p, rgb),
                _ => {}
            }
            kept.push(p, rgb);
        }
        drop(cell_of);
        self.forget_seen_through(changes);
        (kept, came)
    }

    /// Forgets the remembered obstacles whose points the look saw through (see
    /// [`SEEN_THROUGH_SHARE`]).
    fn forget_seen_through(&mut self, changes: &LookChanges) {
        let prisms = std::mem::take(&mut self.world.prisms);
        let world = &self.world;
        let (gone, kept): (Vec<Prism>, Vec<Prism>) = prisms.into_iter().partition(|p| {
            world.untouched(p.id) && seen_through_share(p, changes) > SEEN_THROUGH_SHARE
        });
        self.world.prisms = kept;
        self.world.forgotten += gone.len();
        // The grid's frames never looked through them as the look did: what they left on its cells
        // (a person who stood still reads as stationary) goes too.
        if let Some(grid) = self.world.grid.as_mut() {
            let stamp = self.robot.now();
            for p in &gone {
                let cells = own_cells(grid.geometry(), p, &self.world.prisms);
                grid.departed(Footprint::Cells(&cells), stamp);
            }
        }
        if !gone.is_empty() {
            let ids: Vec<String> = gone.iter().map(|p| p.id.to_string()).collect();
            let stamp = self.robot.now();
            self.observer.note(
                stamp,
                LogLevel::Info,
                &format!(
                    "forgotten: {} (the look saw through where they stood: they moved away)",
                    ids.join(", ")
                ),
            );
        }
    }

    /// The obstacles that may be people: motion was seen where they stand, and neither passive
    /// evidence nor a push calls them movable or static (see the machine's `pick`).
    pub(crate) fn movers(&self) -> Vec<ObjectId> {
        self.untouched(|p| self.seen_moving(p) && !self.passively_movable(p))
    }

    /// Whether `prism` is someone keeping their distance from the robot: a look saw it arrive
    /// ([`super::object::Knowledge::arrived`]), and it stands within [`PERSON_CLEARANCE`] of the
    /// robot's body where the robot took its last look. People who find the robot in their way stop
    /// at the edge of its intimate zone (Hall's 0.45 m) and wait there; the grid's passive rules read
    /// them as something moved and left at rest, like a cart left behind, and a clearing stroke
    /// would push them (`wanderers-032` seed 35: someone stood 0.18 m off the body for over 30 s
    /// while the robot looked and waited, and was pushed). What a person leaves behind they leave
    /// where they want it, not at arm's length of a robot standing there.
    pub(crate) fn keeps_its_distance(&self, prism: &Prism) -> bool {
        stands_off(
            prism,
            self.world.objects.get(prism.id).arrived,
            self.world.looks.last(),
            self.config.model.body.radius,
        )
    }

    /// The obstacles that the robot has not tested, found static or moved, and that pass `test`.
    fn untouched(&self, test: impl Fn(&Prism) -> bool) -> Vec<ObjectId> {
        self.world
            .prisms
            .iter()
            .filter(|p| self.world.untouched(p.id) && test(p))
            .map(|p| p.id)
            .collect()
    }

    /// Forgets the obstacles among `movers` (taken before the look) that the look's detections
    /// (`shown`, their footprints) did not find again: where a person is, is known only while they
    /// are in view, and an obstacle kept for one out of view is a ghost the planner would go round
    /// for the rest of the run.
    pub(crate) fn forget_movers_out_of_sight(
        &mut self,
        movers: &[ObjectId],
        shown: &[Vec<Point2<f64>>],
    ) {
        let before = self.world.prisms.len();
        self.world.prisms.retain(|p| {
            !movers.contains(&p.id)
                || shown
                    .iter()
                    .any(|o| convex_intersection_area(o, &p.footprint) > 0.0)
        });
        if self.world.prisms.len() < before {
            let stamp = self.robot.now();
            self.observer.note(
                stamp,
                LogLevel::Info,
                &format!(
                    "forgotten: {} obstacle(s) seen moving that the look did not find again",
                    before - self.world.prisms.len()
                ),
            );
        }
    }

    /// Why the push of `prism` planned as `plan` must not start, if it must not: something that may
    /// be a person ([`Self::movers`]) stands within [`PERSON_CLEARANCE`] of the object or of the
    /// floor it sweeps (the hull of its footprint now and after the push).
    pub(crate) fn person_near_push(&self, prism: &Prism, plan: &PushPlan) -> Option<String> {
        let after = Prism {
            footprint: plan.displaced_footprint.clone(),
            ..prism.clone()
        };
        let sweep = prism.merged_with(&after);
        let near: Vec<String> = self
            .movers()
            .into_iter()
            .filter(|id| *id != prism.id)
            .filter_map(|id| self.world.prisms.iter().find(|p| p.id == id))
            .filter(|m| outline_gap(&sweep, m) < PERSON_CLEARANCE)
            .map(|m| m.id.to_string())
            .collect();
        (!near.is_empty()).then(|| {
            format!(
                "{} may be a person (seen moving) within {PERSON_CLEARANCE:.2} m of {}'s sweep: the push waits for them to leave",
                near.join(", "),
                prism.id
            )
        })
    }

    /// Notes the obstacles that hold at least [`ARRIVED_POINTS`] of the look's `arrived` points as
    /// arrivals (see [`super::object::Knowledge::arrived`]).
    pub(crate) fn note_arrivals(&mut self, arrived: &ColourCloud) {
        if arrived.is_empty() {
            return;
        }
        let points: Vec<Point2<f64>> = arrived
            .iter_valid()
            .filter(|(_, p, _)| p.z >= FLOOR_BAND)
            .map(|(_, p, _)| Point2::new(f64::from(p.x), f64::from(p.y)))
            .collect();
        for prism in &self.world.prisms {
            let inside = points
                .iter()
                .filter(|q| prism.distance_xy(q) <= ARRIVAL_REACH)
                .take(ARRIVED_POINTS)
                .count();
            if inside >= ARRIVED_POINTS {
                self.world.objects.learn(prism.id).arrived = true;
            }
        }
    }

    /// Notes as arrivals the obstacles the look found standing on floor the grid saw free before
    /// (at least [`ARRIVED_ON_FREE`] of their cells): nothing the robot tested or moved, no larger
    /// than people ([`PERSON_EXTENT`]), so something that came by itself or was brought — a person,
    /// or what a person left (which passive evidence then calls movable, and which stays a
    /// candidate for a push).
    pub(crate) fn note_arrived_on_free_floor(&mut self) {
        let arrived: Vec<ObjectId> = self.untouched(|p| {
            !self.world.objects.get(p.id).arrived
                && came_onto_free_floor(p, || self.world.free_share(p))
        });
        for id in arrived {
            self.world.objects.learn(id).arrived = true;
        }
    }

    /// Notes that the look's detections (`shown`, their footprints) showed the obstacles they overlap
    /// now.
    pub(crate) fn note_detected(&mut self, shown: &[Vec<Point2<f64>>]) {
        let now = self.robot.elapsed();
        for p in &self.world.prisms {
            if shown
                .iter()
                .any(|o| convex_intersection_area(o, &p.footprint) > 0.0)
            {
                self.world.objects.learn(p.id).last_detected = Some(now);
            }
        }
    }

    /// Keeps the obstacle memory in step with the grid between looks, after every frame of a look or
    /// a walk: an obstacle seen moving that the robot has not tested or moved (a person, or a person
    /// who stopped, to passive evidence the same as a suitcase left behind) is forgotten once no look
    /// has shown it for [`super::config::GridSetup::mover_memory`], or as soon as the grid's frames
    /// since the look that last showed it crossed its place and found nothing there
    /// (`WorldModel::grid_saw_it_gone`) — where people are is known only
    /// while they are in view, and the grid's moving and movable cells still hold what it last saw
    /// there for the planner; any obstacle nobody tested, moved or
    /// found static, taller than the height below which the grid's free cells prove nothing, is
    /// forgotten as soon as the grid holds every cell under it free (a later frame saw floor all
    /// over where it stood); a lower one as soon as, besides, frames since the look that last
    /// showed it saw floor returns in at least half of its cells (the smear of a suitcase pulled
    /// past, or of a person's legs, that no later look came back to).
    pub(crate) fn reconcile(&mut self) {
        let now = self.robot.elapsed();
        let memory = self.config.grid.mover_memory;
        let proves_free_above = self.config.grid.reduction.clear_height;
        let movers = self.untouched(|p| self.seen_moving_ever(p));
        let stale = |id: &ObjectId| {
            movers.contains(id)
                && self
                    .world
                    .objects
                    .get(*id)
                    .last_detected
                    .is_none_or(|t| now - t > memory)
        };
        // Frames are stamped by the robot's clock, detections by the time let pass: the detection
        // as a clock reading, that long before the clock's reading now.
        let clock_now = self.robot.now();
        let looked_gone = |p: &Prism| {
            movers.contains(&p.id) && {
                let since = self
                    .world
                    .objects
                    .get(p.id)
                    .last_detected
                    .map_or(f64::NEG_INFINITY, |t| clock_now - (now - t));
                self.world.grid_saw_it_gone(p, since)
            }
        };
        let gone: Vec<ObjectId> = self
            .world
            .prisms
            .iter()
            .filter(|p| {
                stale(&p.id)
                    || looked_gone(p)
                    || (self.world.untouched(p.id) && self.world.grid_sees_free(p) && {
                        // The grid's Free cells prove nothing below the lowest ray's clearing
                        // height: a lower obstacle goes once frames have also seen the floor it
                        // stood on bare since a look last showed it.
                        p.z_max > proves_free_above || {
                            let since = self.world.objects.get(p.id).last_detected;
                            self.world
                                .floor_seen_since(p, since.unwrap_or(f64::NEG_INFINITY))
                        }
                    })
            })
            .map(|p| p.id)
            .collect();
        self.forget(
            &gone,
            "seen moving and out of sight too long or looked at and gone, or the grid sees floor all over where they stood",
        );
    }

    /// Forgets the obstacles `gone` and notes them, with `why`; nothing when there are none.
    pub(super) fn forget(&mut self, gone: &[ObjectId], why: &str) {
        if gone.is_empty() {
            return;
        }
        self.world.prisms.retain(|p| !gone.contains(&p.id));
        let ids: Vec<String> = gone.iter().map(ToString::to_string).collect();
        let stamp = self.robot.now();
        self.observer.note(
            stamp,
            LogLevel::Info,
            &format!("forgotten: {} ({why})", ids.join(", ")),
        );
    }

    /// The grid cell index of a map point above the floor band, if the grid holds it; never for a run
    /// without a grid.
    fn cell_index(&self) -> impl Fn(&nalgebra::Point3<f32>) -> Option<usize> + '_ {
        let geometry = self.world.grid.as_ref().map(|g| *g.geometry());
        move |p| {
            let geometry = geometry.as_ref()?;
            if p.z < FLOOR_BAND {
                return None;
            }
            geometry
                .cell_of(Point2::new(f64::from(p.x), f64::from(p.y)))
                .and_then(|c| geometry.index(c))
        }
    }

    /// The grid cells holding at least [`CELL_POINTS`] of `fused`'s points that `what` marks as
    /// `change`.
    fn dense_cells(
        &self,
        fused: &ColourCloud,
        what: &[Change],
        change: Change,
    ) -> std::collections::BTreeSet<usize> {
        let cell_of = self.cell_index();
        let mut counts: std::collections::BTreeMap<usize, usize> = Default::default();
        for (i, p, _) in fused.iter_valid() {
            if what.get(i) == Some(&change)
                && let Some(c) = cell_of(&p)
            {
                *counts.entry(c).or_default() += 1;
            }
        }
        counts
            .into_iter()
            .filter(|(_, n)| *n >= CELL_POINTS)
            .map(|(c, _)| c)
            .collect()
    }

    /// Marks `cells` as moved at the current robot time, in the look's own memory of motion and in
    /// the one the grid's Moving cells write.
    fn note_motion(&mut self, cells: &std::collections::BTreeSet<usize>) {
        let now = self.robot.elapsed();
        for &i in cells {
            for stamps in [&mut self.world.look_motion, &mut self.world.last_motion] {
                if let Some(slot) = stamps.get_mut(i) {
                    *slot = now;
                }
            }
        }
    }
}

/// The gap between two footprints in the floor plane (m): zero where they overlap.
fn outline_gap(a: &Prism, b: &Prism) -> f64 {
    if convex_intersection_area(&a.footprint, &b.footprint) > 0.0 {
        return 0.0;
    }
    let one_way = |from: &Prism, to: &Prism| {
        from.footprint
            .iter()
            .map(|v| to.distance_xy(v))
            .fold(f64::INFINITY, f64::min)
    };
    one_way(a, b).min(one_way(b, a))
}

/// The share of `prism`'s points above the floor (an even sample) that the look saw through, of
/// those it saw at all (seen through, or returned at their range); 0 for a prism without such
/// points, or when the look saw fewer than [`IN_SIGHT_SHARE`] of them. A point hidden behind
/// something nearer says nothing of whether the prism is still there: a person who stood behind a
/// chair and walked away leaves the points the chair hides from every later look, and counted as
/// still there they kept the person's obstacle in the way for the rest of the run.
fn seen_through_share(prism: &Prism, changes: &LookChanges) -> f64 {
    let points = &prism.points;
    let above: Vec<usize> = (0..points.len())
        .filter(|&i| points.point(i).is_some_and(|p| p.z >= FLOOR_BAND))
        .collect();
    if above.is_empty() {
        return 0.0;
    }
    let step = above.len().div_ceil(SAMPLE);
    let (mut asked, mut through, mut returned) = (0usize, 0usize, 0usize);
    for &i in above.iter().step_by(step) {
        if let Some(p) = points.point(i) {
            asked += 1;
            match changes.sight_of(&p) {
                Sight::Through => through += 1,
                Sight::Returned => returned += 1,
                Sight::Hidden => {}
            }
        }
    }
    let seen = through + returned;
    if (seen as f64) < IN_SIGHT_SHARE * asked as f64 {
        return 0.0;
    }
    through as f64 / seen.max(1) as f64
}

/// The grid cells whose centres lie within half a cell of `prism`'s footprint and of no obstacle of
/// `others`: what it alone stood on (not the chair a person stood against).
fn own_cells(geometry: &GridGeometry, prism: &Prism, others: &[Prism]) -> Vec<CellIndex> {
    let half = geometry.resolution() / 2.0;
    let (lo, hi) = prism.footprint.iter().fold(
        (
            Point2::new(f64::INFINITY, f64::INFINITY),
            Point2::new(f64::NEG_INFINITY, f64::NEG_INFINITY),
        ),
        |(lo, hi), v| (lo.inf(v), hi.sup(v)),
    );
    let (Some(a), Some(b)) = (geometry.cell_of(lo), geometry.cell_of(hi)) else {
        return Vec::new();
    };
    (a.y..=b.y)
        .flat_map(|y| (a.x..=b.x).map(move |x| CellIndex::new(x, y)))
        .filter(|&c| {
            let centre = geometry.centre(c);
            prism.distance_xy(&centre) <= half
                && !others.iter().any(|k| k.distance_xy(&centre) <= half)
        })
        .collect()
}

/// Whether an obstacle no larger than people ([`PERSON_EXTENT`]) stands on floor the grid saw free
/// before, at least [`ARRIVED_ON_FREE`] of its cells (`free_share`, asked only of such obstacles).
fn came_onto_free_floor(prism: &Prism, free_share: impl FnOnce() -> f64) -> bool {
    prism.extent() <= PERSON_EXTENT && free_share() >= ARRIVED_ON_FREE
}

/// Whether `prism`, which `arrived` or not, stands within [`PERSON_CLEARANCE`] of the body (of
/// `radius`) of a robot standing at `robot` (see [`Runner::keeps_its_distance`]).
fn stands_off(prism: &Prism, arrived: bool, robot: Option<&Point2<f64>>, radius: f64) -> bool {
    arrived && robot.is_some_and(|at| prism.distance_xy(at) - radius < PERSON_CLEARANCE)
}

#[cfg(test)]
mod tests {
    use super::{came_onto_free_floor, stands_off};
    use nalgebra::Point2;

    #[test]
    fn someone_who_arrived_and_stands_at_arms_length_of_the_robot_keeps_their_distance() {
        // Invariant: an obstacle a look saw arrive that stands within 0.45 m of the robot's body (someone who stopped for it) keeps their distance; one that arrived but stands 1.3 m off the body (a cart left in a doorway) does not, nor does one as near that never arrived (furniture beside the robot), nor any when the robot has not looked yet.
        let robot = Point2::new(1.0, 1.0);
        let radius = 0.3;
        let person = box_prism(1, (1.5, 0.8, 1.9, 1.2), 1.7);
        assert!(stands_off(&person, true, Some(&robot), radius));
        assert!(!stands_off(&person, false, Some(&robot), radius));
        assert!(!stands_off(&person, true, None, radius));
        let cart = box_prism(2, (2.6, 0.75, 3.1, 1.25), 1.0);
        assert!(!stands_off(&cart, true, Some(&robot), radius));
    }
    use crate::runner::world::tests::box_prism;

    #[test]
    fn only_something_the_size_of_people_comes_by_itself_onto_free_floor() {
        // Invariant: a person-sized obstacle (a 0.5 m arc seen from one side) on floor the grid saw free (a third or more of its cells) has arrived; a 4 m wall, or a 1.35 m wedge of a wall seen obliquely, on as much free floor has not, and neither has a person-sized one on floor mostly unseen free.
        let person = box_prism(1, (2.0, 1.0, 2.5, 1.2), 1.7);
        assert!(came_onto_free_floor(&person, || 0.5));
        assert!(!came_onto_free_floor(&person, || 0.1));
        let wall = box_prism(2, (1.6, -0.02, 5.7, 0.03), 2.0);
        assert!(!came_onto_free_floor(&wall, || 0.36));
        let wedge = box_prism(3, (4.12, 3.67, 4.75, 4.91), 2.0);
        assert!(!came_onto_free_floor(&wedge, || 0.47));
    }
}
