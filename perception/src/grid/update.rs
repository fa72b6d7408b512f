//! One range frame into the grid: traverse, classify returns, classify crossed cells, expire motion.

use super::class::CellClass;
use super::evidence::{Rule, is_active, pack_rule};
use super::frame::{Beam, BeamEnd, RangeFrame};
use super::geometry::{GridGeometry, floor};
#[cfg(doc)]
use super::layers::Crossing;
use super::layers::NO_OBJECT;
use super::near_field::{NearField, Reach};
use super::rules::{self, HitDecision, free_space, movable, moving};
use super::traversal::{Cuts, Traversal};
use super::visible::{CellBox, SlotWriter};
use super::{GridError, ObstacleGrid};
use nalgebra::Point2;

/// How a frame's beams are walked (see [`Walk::beams`]).
struct Walk<'a> {
    geom: &'a GridGeometry,
    /// Whether the beams' dense near field may be filled rather than walked.
    near_field: bool,
    sensor: Point2<f64>,
    /// [`GridConfig::clear_margin`](super::GridConfig::clear_margin).
    margin: f64,
    /// [`GridConfig::free_gap`](super::GridConfig::free_gap).
    gap: f64,
    /// [`GridConfig::clear_tail`](super::GridConfig::clear_tail).
    tail: f64,
}

impl Walk<'_> {
    /// Walks `beams`, oring each crossed cell's [`Crossing::level`] into `level`, except where the
    /// beams are dense enough for the near field to mark their cells through `out` (see
    /// `near_field.rs`); returns a box holding every cell marked either way. `reach` is scratch space.
    fn beams(
        &self,
        beams: &[Beam],
        level: &mut [u8],
        out: &mut SlotWriter<'_>,
        reach: &mut Vec<Reach>,
    ) -> CellBox {
        let (geom, sensor) = (self.geom, self.sensor);
        reach.clear();
        reach.extend(beams.iter().map(|b| self.reach(b)));
        let near = NearField::of(geom, sensor, reach).filter(|_| self.near_field);
        if let Some(near) = &near {
            // Every cell the fill marks is one a walk would cross: inside the box below.
            let width = geom.width();
            near.fill(geom, |y, x0, x1| {
                out.or_far_run(y * width + x0, y * width + x1);
            });
        }
        // The sensor's grid coordinates once, and each end's once (for its cell and its walk).
        let from = geom.grid_coords(sensor);
        // The box of the sensor and every beam's end holds every cell a walk can cross: a walk
        // stays in its segment's box, bar a step of floating-point drift at its end (a cell's
        // margin). Per frame, not per walk: a walk's own box cost two integer divisions.
        let (mut lo, mut hi) = (from, from);
        for (k, (beam, r)) in beams.iter().zip(reach.iter()).enumerate() {
            let hit_end = geom.grid_coords(beam.end);
            (lo, hi) = (
                (lo.0.min(hit_end.0), lo.1.min(hit_end.1)),
                (hi.0.max(hit_end.0), hi.1.max(hit_end.1)),
            );
            let hit_cell = match beam.kind {
                BeamEnd::Hit => geom.cell_checked(floor(hit_end.0), floor(hit_end.1)),
                BeamEnd::Clear => None,
            };
            let len = r.length;
            // The last `clear_tail` of a beam without a return is not counted as seen: at the
            // range limit (or the farthest floor point) a return may just have dropped out, and a
            // wall entering the range next frame must not look like something appearing in free
            // space.
            let (end, length) = match beam.kind {
                BeamEnd::Hit => (beam.end, len),
                BeamEnd::Clear if len <= self.tail => continue,
                BeamEnd::Clear => (
                    sensor + (beam.end - sensor) * ((len - self.tail) / len),
                    len - self.tail,
                ),
            };
            // Distances along the beam where its cells change kind: nearer than `seen_from` they lie
            // under the camera's lowest ray (not seen); a crossing is "far" when the ray goes on at
            // least `margin` past the cell's exit and "free" when at least `free_gap` (nearer the
            // return than that, the ray may be crossing the returned surface itself). The end of a
            // clear beam is not a surface: all its crossings are far.
            let (free, far) = match beam.kind {
                BeamEnd::Hit => (len - self.gap, len - self.margin),
                BeamEnd::Clear => (f64::INFINITY, f64::INFINITY),
            };
            if length <= 0.0 {
                continue; // a return at the sensor: nothing crossed but its own, returned cell
            }
            let inv = 1.0 / length;
            let t = |d: f64| d * inv;
            let cuts = Cuts {
                seen: t(beam.seen_from),
                far: t(far),
                free: t(free),
            };
            let skippable = near
                .as_ref()
                .and_then(|n| n.skipped(k, geom.resolution()))
                .map(|(near, far)| (t(near), t(far)));
            let walk = match beam.kind {
                BeamEnd::Hit => Traversal::between(geom, from, hit_end),
                BeamEnd::Clear => Traversal::between(geom, from, geom.grid_coords(end)),
            };
            walk.for_each_cell(geom, hit_cell, &cuts, skippable, |i, bit| {
                if let Some(v) = level.get_mut(i) {
                    *v |= bit;
                }
            });
        }
        CellBox::around(geom, lo, hi)
    }

    /// What the near field needs of `beam`.
    fn reach(&self, beam: &Beam) -> Reach {
        let direction = beam.end - self.sensor;
        let len = direction.norm();
        let far_to = match beam.kind {
            BeamEnd::Hit => len - self.margin,
            BeamEnd::Clear => len - self.tail,
        };
        Reach {
            direction,
            length: len,
            seen_from: beam.seen_from,
            far_to,
        }
    }
}

/// Per-frame lists, kept between frames to reuse their allocations (never swept).
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {
    hits: Vec<u32>,
    /// The moving rule's quiet neighbourhood (cells) of each return in `hits`.
    quiet: Vec<u8>,
    crossed: Vec<u32>,
    decisions: Vec<(u32, HitDecision)>,
    motion: Vec<(i32, i32)>,
    new_moving: Vec<u32>,
    /// Cells something left this frame (see `stamp_vacated`).
    vacated: Vec<u32>,
    /// The frame's crossings as they are walked: per cell, the or of the [`Crossing::level`]s of
    /// the rays that crossed it. A byte a cell, so that a step's write never waits on the one
    /// before (bits of one word would); folded into bit-planes, and zeroed, once all rays are in.
    level: Vec<u8>,
    /// What the near field needs of each beam (see `near_field.rs`).
    reach: Vec<Reach>,
    /// Walk every beam whole, without the near field (to check that it changes nothing).
    walk_whole: bool,
}

impl ObstacleGrid {
    /// Folds one range frame, stamped `now` on the robot clock, into the grid.
    ///
    /// Frames must come in clock order (equal stamps are allowed); a non-finite or earlier stamp is an
    /// error and leaves the grid untouched. Beams outside the grid are clipped; an empty frame still
    /// counts as a frame (nothing seen: moving cells expire).
    pub fn update(&mut self, frame: &RangeFrame, now: f64) -> Result<(), GridError> {
        if !now.is_finite() {
            return Err(GridError::NonFinite);
        }
        if let Some(previous) = self.last_stamp
            && now < previous
        {
            return Err(GridError::TimeWentBack { now, previous });
        }
        self.frame = self.frame.checked_add(1).ok_or(GridError::TooManyFrames)?;
        self.last_stamp = Some(now);
        self.layers.stamps.push(now);
        let mut s = std::mem::take(&mut self.scratch);
        self.appearances
            .observe(frame, &self.geom, self.cfg.appear_gap);
        self.traverse(frame, &mut s);
        self.stamp_previous_motion();
        self.stamp_vacated(&mut s);
        let sensor = self.geom.grid_coords(frame.sensor());
        self.classify_returns(now, sensor, &mut s);
        self.classify_crossed(now, &s);
        self.expire_motion(&mut s);
        self.scratch = s;
        Ok(())
    }

    /// Walks every beam: crossed cells and returned cells of this frame, with their histories.
    fn traverse(&mut self, frame: &RangeFrame, s: &mut Scratch) {
        let f = self.frame;
        let geom = &self.geom;
        let walk = Walk {
            geom,
            near_field: !s.walk_whole,
            sensor: frame.sensor(),
            margin: self.cfg.clear_margin,
            gap: self.cfg.free_gap,
            tail: self.cfg.clear_tail,
        };
        let l = &mut self.layers;
        l.visible.begin(f);
        if s.level.len() != geom.len() {
            s.level = vec![0; geom.len()];
        }
        let Some(mut out) = l.visible.writer(f) else {
            return;
        };
        let walked = walk.beams(frame.beams(), &mut s.level, &mut out, &mut s.reach);
        out.cover(walked);
        self.record_hits(frame, s);
        // The crossed cells that are not free, for classification, in row-major order (free cells
        // seen free again need nothing: their crossings are recorded as bits).
        s.crossed.clear();
        let l = &mut self.layers;
        let free = l.free.as_slice();
        let observed = &mut l.observed;
        let crossed = &mut s.crossed;
        l.visible.fold_levels(f, &mut s.level, walked, |k, bits| {
            if let Some(o) = observed.get_mut(k) {
                *o |= bits;
            }
            let base = k * 64;
            let mut bits = bits & !free.get(k).copied().unwrap_or(0);
            while bits != 0 {
                crossed.push((base + bits.trailing_zeros() as usize) as u32);
                bits &= bits - 1;
            }
        });
    }

    /// Records the frame's returns in their cells (once per cell and frame), in beam order, with
    /// the moving rule's quiet neighbourhood of each.
    fn record_hits(&mut self, frame: &RangeFrame, s: &mut Scratch) {
        let f = self.frame;
        let sensor = frame.sensor();
        let (geom, l) = (&self.geom, &mut self.layers);
        let quiet = moving::QuietRadii::new(mean_beam_step(frame), geom.resolution());
        s.hits.clear();
        s.quiet.clear();
        for beam in frame.beams().iter().filter(|b| b.kind == BeamEnd::Hit) {
            let Some(i) = geom.cell_of(beam.end).and_then(|c| geom.index(c)) else {
                continue;
            };
            if l.record_hit(i, f) {
                l.mark_observed(i);
                s.hits.push(i as u32);
                let len = (beam.end - sensor).norm();
                s.quiet.push(quiet.of(len) as u8);
            }
        }
    }

    /// Stamps the neighbourhood (`moving_step`) of last frame's moving cells.
    fn stamp_previous_motion(&mut self) {
        let f = self.frame;
        let r = (self.cfg.moving_step / self.geom.resolution())
            .ceil()
            .max(1.0) as usize;
        let l = &mut self.layers;
        for &i in &self.moving {
            self.geom
                .for_square(i as usize, r, |j| l.near_moving[j] = f);
            if l.confirmed[i as usize] == f - 1 {
                self.geom
                    .for_square(i as usize, r, |j| l.near_confirmed[j] = f);
            }
        }
    }

    /// Cells something has just left ([`movable::vacated`]) are motion as much as cells something has
    /// just entered: their neighbourhood (`moving_step`) counts as near confirmed motion this frame, so
    /// the side of a pulled suitcase, which slides along itself and looks in place, is seen moving from
    /// the cells its back end leaves (while the person pulling it is in view). They do not count as
    /// motion nearby for the rest test: a person walking past a resting suitcase leaves cells behind it
    /// next to the suitcase longer than it is next to it itself.
    fn stamp_vacated(&mut self, s: &mut Scratch) {
        let f = self.frame;
        s.vacated.clear();
        let r = (self.cfg.moving_step / self.geom.resolution())
            .ceil()
            .max(1.0) as usize;
        for &i in &s.crossed {
            if movable::vacated(&self.layers, &self.geom, i as usize, f) {
                s.vacated.push(i);
                let l = &mut self.layers;
                self.geom.for_square(i as usize, r, |j| {
                    l.near_moving[j] = f;
                    l.near_confirmed[j] = f;
                });
            }
        }
    }

    /// Tamura's Fig. 5 for every return of the frame, then the rest test, then the writes.
    fn classify_returns(&mut self, now: f64, sensor: (f64, f64), s: &mut Scratch) {
        let f = self.frame;
        s.decisions.clear();
        s.motion.clear();
        let w = self.geom.width();

        for (&i, &quiet) in s.hits.iter().zip(&s.quiet) {
            let appeared = self.appearances.contains(i as usize);
            let around = (usize::from(quiet), sensor, appeared);
            let d = rules::decide_hit(&self.layers, &self.geom, i as usize, f, around);
            if let HitDecision::Set(CellClass::Moving, _) = d {
                s.motion
                    .push(((i as usize % w) as i32, (i as usize / w) as i32));
            }
            s.decisions.push((i, d));
        }
        let rest_cells = self.cfg.rest_radius / self.geom.resolution();
        s.new_moving.clear();
        for k in 0..s.decisions.len() {
            let (i, d) = s.decisions[k];
            let i = i as usize;
            let (class, rule) = match d {
                HitDecision::Keep => continue,
                HitDecision::Set(c, r) => (c, r),
                HitDecision::MovingUnlessStill(c, r) => {
                    let cell = ((i % w) as i32, (i / w) as i32);
                    if movable::added(cell, &s.motion, rest_cells) {
                        (c, r)
                    } else {
                        (CellClass::Moving, Rule::MovingContinued)
                    }
                }
                HitDecision::RestCandidate
                | HitDecision::MovableUnlessMotion
                | HitDecision::ExtendUnlessMotion => {
                    let cell = ((i % w) as i32, (i / w) as i32);
                    if !movable::added(cell, &s.motion, rest_cells) {
                        (CellClass::Moving, Rule::MovingContinued)
                    } else if d == HitDecision::RestCandidate {
                        (CellClass::Movable, Rule::MovableAddition)
                    } else if d == HitDecision::ExtendUnlessMotion
                        || self.layers.evidence[i] == pack_rule(Rule::MovableExtension)
                    {
                        (CellClass::Movable, Rule::MovableExtension)
                    } else {
                        (CellClass::Movable, Rule::MovableRetention)
                    }
                }
            };
            if matches!(rule, Rule::Stationary | Rule::Tentative) {
                self.layers.mark_ts(i);
            }
            if class == CellClass::Moving {
                s.new_moving.push(i as u32);
                // Confirmed: motion near last frame's that reached a cell not moving before, and it
                // stays confirmed while the cell stays moving. A return that stays in the cell it
                // appeared in is a blip, however long it stays.
                let l = &mut self.layers;
                let was_moving = l.class[i] == CellClass::Moving as u8;
                if (l.near_moving[i] == f && !was_moving) || (was_moving && l.confirmed[i] == f - 1)
                {
                    l.confirmed[i] = f;
                }
            }
            self.write_passive(i, class, rule, now);
        }
    }

    /// Crossed cells (listed unless already free) that hold no return this frame: the visible area's
    /// consequences.
    fn classify_crossed(&mut self, now: f64, s: &Scratch) {
        let f = self.frame;
        for &i in &s.crossed {
            let i = i as usize;
            let l = &self.layers;
            if l.hit_in(i, f) {
                continue; // a return in the cell wins over rays crossing it
            }
            let class = CellClass::from_code(l.class[i]).unwrap_or(CellClass::Unknown);
            if class == CellClass::Free {
                continue; // the common case: free space seen free again
            }
            let active = is_active(l.evidence[i]);
            let to_free = match class {
                CellClass::Free => None,
                CellClass::Unknown | CellClass::Moving => {
                    (l.crossed_in_frames(i, f, 1) != 0).then_some(Rule::SeenFree)
                }
                CellClass::Movable if !active => {
                    movable::deleted(l, &self.geom, i, f).then_some(Rule::MovableDeletion)
                }
                CellClass::Movable | CellClass::Stationary => {
                    free_space::cleared(l, &self.geom, i, f).then_some(Rule::StationaryCleared)
                }
            };
            if let Some(rule) = to_free {
                self.write_passive(i, CellClass::Free, rule, now);
            }
        }
    }

    /// Last frame's moving cells that are neither returned nor seen free now, with no return in their
    /// 8-neighbourhood either: whatever moved has gone elsewhere, unseen — Unknown, not a ghost
    /// obstacle. A moving cell with a return next to it (the surface jittering across a cell
    /// boundary) stays moving for this frame and keeps feeding the continuation rule.
    fn expire_motion(&mut self, s: &mut Scratch) {
        let f = self.frame;
        for &i in &self.moving {
            let i = i as usize;
            if self.layers.class[i] != CellClass::Moving as u8 || self.layers.hit_in(i, f) {
                continue;
            }
            let mut returned_around = false;
            let l = &self.layers;
            self.geom.for_3x3(i, |j| returned_around |= l.hit_in(j, f));
            if returned_around && !l.crossed_in(i, f) {
                s.new_moving.push(i as u32);
                if l.confirmed[i] == f - 1 {
                    self.layers.confirmed[i] = f;
                }
            } else {
                self.layers.set_class(i, CellClass::Unknown as u8);
                self.layers.evidence[i] = pack_rule(Rule::MovingExpired);
            }
        }
        std::mem::swap(&mut self.moving, &mut s.new_moving);
    }

    /// Writes a passive class: evidence, no object, replanning check.
    fn write_passive(&mut self, i: usize, class: CellClass, rule: Rule, now: f64) {
        let old = self.layers.set_class(i, class as u8);
        self.layers.evidence[i] = pack_rule(rule);
        self.layers.object[i] = NO_OBJECT;
        self.check_watch(i, old, class, now);
    }
}

/// The mean angle (rad) between consecutive beams of `frame`, which come in bearing order from a
/// scanner or a camera's columns; 0 for fewer than two beams. Missing columns only widen it, which
/// widens the moving rule's quiet neighbourhood: the safe side.
fn mean_beam_step(frame: &RangeFrame) -> f64 {
    let o = frame.sensor();
    let beams = frame.beams();
    let sum: f64 = beams
        .windows(2)
        .map(|w| {
            let (a, b) = (w[0].end - o, w[1].end - o);
            let n = a.norm() * b.norm();
            // The sine: the angle itself for beams a fraction of a degree apart, and cheap.
            if n > 0.0 {
                (a.perp(&b) / n).abs().min(1.0)
            } else {
                0.0
            }
        })
        .sum();
    if beams.len() > 1 && sum.is_finite() {
        sum / (beams.len() - 1) as f64
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::{CellIndex, GridConfig, GridGeometry};
    use super::*;
    use nalgebra::Point2;

    /// Two grids fed the same frames: one fills the near field, one walks every beam whole.
    struct FilledAndWalked {
        fast: ObstacleGrid,
        whole: ObstacleGrid,
    }

    impl FilledAndWalked {
        fn new(geom: GridGeometry) -> Self {
            let mut whole = ObstacleGrid::new(geom, GridConfig::default());
            whole.scratch.walk_whole = true;
            Self {
                fast: ObstacleGrid::new(geom, GridConfig::default()),
                whole,
            }
        }

        /// Folds `frame` into both and asserts that every cell was crossed, seen free and crossed
        /// far alike, and that every class agrees.
        fn update(&mut self, frame: &RangeFrame, now: f64, what: &str) {
            self.fast.update(frame, now).expect("in order");
            self.whole.update(frame, now).expect("in order");
            let f = self.fast.frame;
            let (a, b) = (&self.fast.layers.visible, &self.whole.layers.visible);
            for i in 0..self.fast.geom.len() {
                assert_eq!(
                    (a.crossed_in(i, f), a.free(i, f), a.far(i, f)),
                    (b.crossed_in(i, f), b.free(i, f), b.far(i, f)),
                    "{what}, cell {i}"
                );
            }
            assert_eq!(self.fast.layers.class, self.whole.layers.class, "{what}");
        }

        /// Whether the last frame's near field was filled.
        fn filled(&self, sensor: Point2<f64>) -> bool {
            NearField::of(&self.fast.geom, sensor, &self.fast.scratch.reach).is_some()
        }
    }

    #[test]
    fn filling_the_dense_near_field_marks_exactly_what_walking_every_beam_does() {
        // Invariant: with the near field filled instead of walked, every frame leaves every cell
        // crossed, seen free and crossed far exactly as walking every beam whole does, and so every
        // class (and the free bits agree with the classes); over fans of all widths, densities
        // (even and uneven), orders, ranges and blind zones.
        let geom = GridGeometry::with_cells(Point2::new(0.0, 0.0), 240, 200, 0.05).expect("valid");
        let mut r = super::super::test_rng::uniform(0x2545_f491_4f6c_dd1d_u64);
        let mut filled_any = 0;
        for scene in 0..60 {
            let mut grids = FilledAndWalked::new(geom);
            let n = 20 + (r() * 500.0) as usize;
            let span = (0.2 + r() * 4.5).min(std::f64::consts::TAU * 0.99);
            let clockwise = r() < 0.5;
            let blind = if r() < 0.5 { 0.0 } else { r() * 1.5 };
            let near_obstacle = r() < 0.2;
            let mut sensor = Point2::new(2.0 + r() * 8.0, 2.0 + r() * 6.0);
            for k in 0..4 {
                // A quarter of the scenes start their fan exactly along an axis: a beam along the
                // other axis's boundaries never meets one (its parameters saturate).
                let yaw = if scene % 4 == 0 {
                    f64::from(k) * std::f64::consts::FRAC_PI_2
                } else {
                    r() * std::f64::consts::TAU
                };
                let mut frame = RangeFrame::new(sensor).expect("finite");
                for b in 0..n {
                    // A third of the scenes space their beams unevenly (each bearing moved by up
                    // to 30 % of the spacing): parts of the fan then differ in density.
                    let jitter = if scene % 3 == 1 {
                        0.6 * (r() - 0.5)
                    } else {
                        0.0
                    };
                    let u = (b as f64 + jitter) / (n - 1) as f64;
                    let a = yaw + span * if clockwise { 1.0 - u } else { u };
                    let d = nalgebra::Vector2::new(a.cos(), a.sin());
                    let range = if near_obstacle && b == n / 3 {
                        0.3 + r()
                    } else {
                        1.5 + r() * 7.0
                    };
                    frame.push_beam(Beam {
                        end: sensor + d * range,
                        kind: if r() < 0.7 {
                            BeamEnd::Hit
                        } else {
                            BeamEnd::Clear
                        },
                        seen_from: blind * r(),
                    });
                }
                grids.update(&frame, f64::from(k), &format!("scene {scene} frame {k}"));
                // The free bits follow the classes.
                let (f, l) = (grids.fast.frame, &grids.fast.layers);
                assert!((0..geom.len()).all(|i| {
                    (l.free[i / 64] >> (i % 64) & 1 == 1) == (l.class[i] == CellClass::Free as u8)
                }));
                let walked_less =
                    (0..geom.len()).any(|i| l.visible.far(i, f) & 1 != 0) && grids.filled(sensor);
                filled_any += usize::from(walked_less);
                sensor += nalgebra::Vector2::new(r() - 0.5, r() - 0.5) * 0.2;
            }
        }
        assert!(
            filled_any > 60,
            "the near field was filled in {filled_any} frames"
        );
    }

    #[test]
    fn filling_the_near_field_of_room_scans_marks_exactly_what_walking_every_beam_does() {
        // Invariant: for 0.5° scans of rooms (long, smooth ranges, so that the density bound and
        // not the returns ends most of the near field), at any yaw, with boxes standing near and
        // far, filling the near field leaves every cell crossed, seen free and crossed far exactly
        // as walking every beam whole does, and so every class.
        let geom = GridGeometry::with_cells(Point2::new(0.0, 0.0), 420, 420, 0.05).expect("valid");
        let mut r = super::super::test_rng::uniform(0x9e37_79b9_7f4a_7c15_u64);
        // Distance along `d` from `o` to the boundary of the box `lo..hi` (from inside), or to
        // its near side (from outside), if the ray meets it.
        let slab = |o: Point2<f64>, d: nalgebra::Vector2<f64>, lo: [f64; 2], hi: [f64; 2]| {
            let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
            for k in 0..2 {
                let (a, b) = ((lo[k] - o[k]) / d[k], (hi[k] - o[k]) / d[k]);
                t0 = t0.max(a.min(b));
                t1 = t1.min(a.max(b));
            }
            (t0 <= t1 && t1 > 0.0).then_some(if t0 > 0.0 { t0 } else { t1 })
        };
        let mut filled = 0;
        for scene in 0..24 {
            let mut grids = FilledAndWalked::new(geom);
            // Mostly rooms whose walls lie beyond the range limit, so that the density bound,
            // not the returns, ends the near field.
            let size = if scene % 3 == 0 {
                1.2 + r() * 19.5
            } else {
                16.0 + r() * 4.5
            };
            let room = ([0.6, 0.6], [size, size * (0.8 + 0.2 * r())]);
            let boxes: Vec<([f64; 2], [f64; 2])> = (0..(r() * 5.0) as usize)
                .map(|_| {
                    let (x, y) = (1.0 + r() * 18.0, 1.0 + r() * 18.0);
                    ([x, y], [x + 0.2 + r(), y + 0.2 + r()])
                })
                .collect();
            let mut sensor = Point2::new(
                room.0[0] + (room.1[0] - room.0[0]) * (0.35 + 0.3 * r()),
                room.0[1] + (room.1[1] - room.0[1]) * (0.35 + 0.3 * r()),
            );
            for k in 0..3 {
                let yaw = r() * std::f64::consts::TAU;
                let mut frame = RangeFrame::new(sensor).expect("finite");
                for b in 0..361 {
                    let a = yaw + (f64::from(b) * 0.5 - 90.0).to_radians();
                    let d = nalgebra::Vector2::new(a.cos(), a.sin());
                    let range = boxes
                        .iter()
                        .filter_map(|&(lo, hi)| slab(sensor, d, lo, hi))
                        .fold(slab(sensor, d, room.0, room.1).unwrap_or(0.0), f64::min);
                    let (end, kind) = if range > 8.0 {
                        (sensor + d * 8.0, BeamEnd::Clear)
                    } else {
                        (sensor + d * range, BeamEnd::Hit)
                    };
                    frame.push_beam(Beam {
                        end,
                        kind,
                        seen_from: 0.0,
                    });
                }
                grids.update(&frame, f64::from(k), &format!("scene {scene} frame {k}"));
                filled += usize::from(grids.filled(sensor));
                sensor += nalgebra::Vector2::new(r() - 0.5, r() - 0.5) * 0.3;
            }
        }
        assert!(filled > 50, "the near field was filled in {filled} frames");
    }

    #[test]
    fn cells_within_the_free_gap_of_a_return_are_observed_not_freed() {
        // Invariant: along a beam ending in a return, cells left at least `free_gap` before the return
        // become Free; nearer ones stay Unknown (the ray may run inside the surface) yet count as seen.
        let geom = GridGeometry::with_cells(Point2::new(0.0, 0.0), 20, 3, 0.05).expect("valid");
        let cfg = GridConfig {
            free_gap: 0.1,
            clear_tail: 0.0,
            ..GridConfig::default()
        };
        let mut grid = ObstacleGrid::new(geom, cfg);
        let mut frame = RangeFrame::new(Point2::new(0.025, 0.075)).expect("finite");
        // The return at x = 0.825 lies in cell 16; cell 15 is left at x = 0.80 (2.5 cm before it),
        // cell 14 at 0.75 (7.5 cm), cell 13 at 0.70 (12.5 cm).
        frame.push_hit(Point2::new(0.825, 0.075));
        grid.update(&frame, 1.0).expect("in order");
        let class = |x| grid.class(CellIndex::new(x, 1)).expect("in grid");
        assert_eq!(class(13), CellClass::Free);
        assert_eq!(class(14), CellClass::Unknown);
        assert_eq!(class(15), CellClass::Unknown);
        let seen = grid.cell(CellIndex::new(15, 1)).expect("in grid").last_seen;
        assert_eq!(
            seen,
            Some(1.0),
            "a near crossing still renews the cell's age"
        );
    }

    #[test]
    fn a_cell_keeps_its_last_crossing_after_the_ring_moves_on() {
        // Invariant: last_seen is the stamp of the latest frame whose rays crossed the cell, also
        // when that frame is older than the ring of recent visible areas.
        let geom = GridGeometry::with_cells(Point2::new(0.0, 0.0), 20, 3, 0.05).expect("valid");
        let cfg = GridConfig {
            clear_tail: 0.0,
            ..GridConfig::default()
        };
        let mut grid = ObstacleGrid::new(geom, cfg);
        let sensor = Point2::new(0.025, 0.075);
        for k in 1..=9 {
            let mut frame = RangeFrame::new(sensor).expect("finite");
            // The first frame sees to cell 16, later ones only to cell 5.
            let x = if k == 1 { 0.825 } else { 0.275 };
            frame.push_hit(Point2::new(x, 0.075));
            grid.update(&frame, f64::from(k)).expect("in order");
        }
        let seen = |x| grid.cell(CellIndex::new(x, 1)).expect("in grid").last_seen;
        assert_eq!(seen(10), Some(1.0));
        assert_eq!(seen(2), Some(9.0));
        assert_eq!(seen(0), Some(9.0), "the sensor's own cell is crossed");
        assert_eq!(
            grid.cell(CellIndex::new(10, 0)).expect("in grid").last_seen,
            None
        );
    }
}
