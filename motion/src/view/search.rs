//! The candidate search behind [`plan_view`](crate::view::plan_view): best first along the
//! walking distances, refined around the best, the few best predicted on the grid's own cells.
//!
//! Predicting a look on the grid's cells costs some ten thousand ray steps, and an 800 × 600 grid
//! has hundreds of candidate positions near a target region, so most are never predicted:
//! 1. Walking distances are searched outwards from the robot (Dijkstra). The candidates every
//!    `2 · spacing` wait, as the search reaches them, with a bound on their score: their
//!    viewshed ([`SightMap::viewshed`]: the target area in sight through walls, allowed 1.5 times
//!    over) over the time to walk there and look. Once nothing unreached could have a larger
//!    bound (the largest viewshed not yet reached over the time to walk as far as the search has
//!    come), the waiting ones are estimated on the coarse raster ([`SightMap::estimate`]), most
//!    promising first, those whose bound cannot beat the best estimate passed over. The search
//!    stops where nothing farther away could beat it.
//! 2. Around the best few, the neighbours every `spacing` not yet estimated are estimated, then
//!    around whichever are best after that, until the best few have all been searched around
//!    (at most 8 rounds): a narrow spot such as a doorway lies between the first candidates.
//! 3. The best few, and the robot's own position, are predicted on the grid's own cells; the
//!    best of those is the answer.
//!
//! Estimates count towards `min_gain` with a quarter's slack (the coarse raster errs low where a
//! gap is narrower than its cells); when none sees any target, the 32 candidates with the largest
//! viewshed per second are predicted on the grid's cells before the answer is Unreachable. Ties
//! go to the earlier candidate (the robot's position first, then row-major): the same inputs give
//! the same answer, bit for bit.

use std::collections::{BTreeSet, BinaryHeap};

use nalgebra::Point2;

use crate::view::geodesic::{DistanceField, STRAIGHT};
use crate::view::lattice::{Lattice, LatticeCell};
use crate::view::planner::{NoView, ViewConfig};
use crate::view::sight::SightMap;
use crate::view::visibility::Scratch;

/// The first candidates lie this many `spacing`s apart.
const FIRST: usize = 2;
/// Candidates whose neighbourhoods are searched.
const REFINED: usize = 6;
/// Candidates predicted on the grid's own cells (and the robot's position).
const FINALISTS: usize = 3;
/// Rounds of searching around the best candidates, at most.
const MAX_ROUNDS: usize = 8;
/// An estimate counts towards `min_gain` with this slack.
const COARSE_SLACK: f64 = 0.75;
/// How much more than its viewshed a position is taken to be able to show: the viewshed counts a
/// block by its centre, which may be hidden while part of the block is not.
const VIEWSHED_SLACK: f64 = 1.5;
/// When no estimate sees a target, this many candidates are predicted on the grid's cells.
const LAST_CHANCE: usize = 32;

/// A position the planner considers.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Candidate {
    pub position: Point2<f64>,
    /// Its lattice cell (`None`: the robot's own position).
    pub cell: Option<LatticeCell>,
    /// Walking distance (m).
    pub walk: f64,
    /// Tie-break: 0 for the robot's position, then row-major lattice order.
    order: usize,
    /// Estimated or predicted gain (m²) and score (m²/s).
    gain: f64,
    score: f64,
}

/// A reached candidate waiting to be estimated: the most promising first, then the earlier.
struct Queued {
    /// The most its score could be (m²/s): its viewshed, with slack, over its time.
    bound: f64,
    c: Candidate,
}

impl PartialEq for Queued {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == std::cmp::Ordering::Equal
    }
}

impl Eq for Queued {}

impl PartialOrd for Queued {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Queued {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.bound
            .total_cmp(&other.bound)
            .then(other.c.order.cmp(&self.c.order))
    }
}

/// The search's state (see the module doc).
pub(crate) struct Search<'a> {
    sight: &'a SightMap,
    lattice: &'a Lattice,
    config: &'a ViewConfig,
    /// Lattice cells between candidates.
    step: usize,
    scratch: Scratch,
    /// The robot's own position, estimated.
    own: Candidate,
    /// Candidates estimated to show enough, ranked after each step.
    pool: Vec<Candidate>,
    /// Candidates passed over, with their bounds.
    passed: Vec<(f64, Candidate)>,
    /// Candidates estimated (by order).
    estimated: BTreeSet<usize>,
    /// The best estimated score so far (m²/s).
    best: f64,
}

impl<'a> Search<'a> {
    /// A search for the robot at `robot`.
    pub fn new(
        sight: &'a SightMap,
        lattice: &'a Lattice,
        config: &'a ViewConfig,
        robot: Point2<f64>,
    ) -> Self {
        let step = ((config.spacing / lattice.cell_size()).round() as usize).max(1);
        let mut s = Self {
            sight,
            lattice,
            config,
            step,
            scratch: Scratch::default(),
            own: Candidate {
                position: robot,
                cell: None,
                walk: 0.0,
                order: 0,
                gain: 0.0,
                score: 0.0,
            },
            pool: Vec::new(),
            passed: Vec::new(),
            estimated: BTreeSet::new(),
            best: 0.0,
        };
        let own = s.own;
        s.own = s.estimate(own);
        s
    }

    /// Robot time to walk `walk` metres and look (s).
    pub fn time(&self, walk: f64) -> f64 {
        walk / self.config.walk_speed + self.config.look_time
    }

    /// Whether an estimate shows enough to stay in the running.
    fn keep(&self, c: &Candidate) -> bool {
        c.gain > 0.0 && c.gain >= COARSE_SLACK * self.config.min_gain
    }

    /// The candidate at `cell`, `walk` metres away, not estimated yet.
    fn at(&self, cell: LatticeCell, walk: f64) -> Candidate {
        Candidate {
            position: self.lattice.centre(cell),
            cell: Some(cell),
            walk,
            order: 1 + cell.y as usize * self.lattice.cols() + cell.x as usize,
            gain: 0.0,
            score: 0.0,
        }
    }

    /// Whether `cell` is a candidate: open, with a target in sight through walls and in range.
    fn open(&self, cell: LatticeCell) -> bool {
        let p = self.lattice.centre(cell);
        self.lattice.is_passable(cell) && self.sight.viewshed(p) > 0.0 && self.sight.within_reach(p)
    }

    /// `c` estimated on the coarse raster, joining the pool if it shows enough.
    fn estimate(&mut self, mut c: Candidate) -> Candidate {
        c.gain = self.sight.estimate(&mut self.scratch, c.position).1;
        c.score = c.gain / self.time(c.walk);
        self.estimated.insert(c.order);
        if self.keep(&c) {
            self.best = self.best.max(c.score);
            self.pool.push(c);
        }
        c
    }

    /// Estimates the queued candidates whose bound is at least `frontier` (what anything not yet
    /// reached could have), most promising first; passes over those that cannot beat the best.
    fn settle(&mut self, queue: &mut BinaryHeap<Queued>, frontier: f64) {
        while queue.peek().is_some_and(|top| top.bound >= frontier) {
            let Some(Queued { bound, c }) = queue.pop() else {
                break;
            };
            if bound <= self.best {
                self.passed.push((bound, c));
            } else {
                self.estimate(c);
            }
        }
    }

    /// The first candidates — every `FIRST · step` cells over the sight window, which holds every
    /// position within reach of a target — as (viewshed, padded index), largest viewshed first.
    fn firsts(&self) -> Vec<(f64, usize)> {
        let mut firsts = Vec::new();
        let (lo, hi) = self.sight.window_bounds();
        let step = FIRST * self.step;
        if let (Some(a), Some(b)) = (self.lattice.cell_of(lo), self.lattice.cell_of(hi)) {
            let first = |v: u32| (v as usize).div_ceil(step) * step;
            for y in (first(a.y)..=b.y as usize).step_by(step) {
                for x in (first(a.x)..=b.x as usize).step_by(step) {
                    let cell = LatticeCell::new(x as u32, y as u32);
                    if let Some(i) = self.lattice.padded_index(cell)
                        && self.open(cell)
                    {
                        firsts.push((self.sight.viewshed(self.lattice.centre(cell)), i));
                    }
                }
            }
        }
        firsts.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        firsts
    }

    /// Step 1: the walking distances, searched as far as they can matter, with the first
    /// candidates estimated best first on the way.
    pub fn best_first(&mut self) -> Result<DistanceField<'a>, NoView> {
        let lattice = self.lattice;
        let mut firsts = self.firsts();
        // Half the memory of a u32 per lattice cell (fresh pages cost as much as the search);
        // a window holds far fewer first candidates than that.
        firsts.truncate(usize::from(u16::MAX));
        let mut slot = vec![u16::MAX; lattice.padded_len()];
        for (k, &(_, i)) in firsts.iter().enumerate() {
            if let Some(s) = slot.get_mut(i) {
                *s = k as u16;
            }
        }
        let mut reached = vec![false; firsts.len()];
        let mut unreached = 0; // the first of `firsts` not reached yet
        let mut queue: BinaryHeap<Queued> = BinaryHeap::new();
        let per_cost = lattice.cell_size() / f64::from(STRAIGHT);
        let w = lattice.cols() + 2;
        let area = self.sight.target_area();
        let field = lattice.distances_indexed(self.own.position, |i, cost| {
            let walk = f64::from(cost) * per_cost;
            let time = self.time(walk);
            if let Some(&k) = slot.get(i)
                && let Some(flag) = reached.get_mut(k as usize)
            {
                *flag = true;
                // Padded index: column x − 1, row y − 1 of the lattice.
                let cell = LatticeCell::new((i % w - 1) as u32, (i / w - 1) as u32);
                let bound = VIEWSHED_SLACK * firsts[k as usize].0 / time;
                queue.push(Queued {
                    bound,
                    c: self.at(cell, walk),
                });
                while reached.get(unreached) == Some(&true) {
                    unreached += 1;
                }
            }
            // Nothing reached from here on shows more than the largest viewshed still unreached
            // (with slack) over at least this long.
            let most = firsts.get(unreached).map_or(0.0, |f| VIEWSHED_SLACK * f.0);
            let frontier = most.min(area) / time;
            self.settle(&mut queue, frontier);
            !(self.best > 0.0 && frontier < self.best)
        })?;
        self.settle(&mut queue, f64::NEG_INFINITY);
        rank(&mut self.pool);
        Ok(field)
    }

    /// Step 2: the neighbours of the best few, then of whichever are best after that.
    pub fn refine(&mut self, field: &DistanceField<'_>) {
        let (cols, rows) = (self.lattice.cols() as i64, self.lattice.rows() as i64);
        let s = self.step as i64;
        let mut searched: BTreeSet<usize> = BTreeSet::new();
        for _ in 0..MAX_ROUNDS {
            let around: Vec<LatticeCell> = self
                .pool
                .iter()
                .take(REFINED)
                .filter(|c| searched.insert(c.order))
                .filter_map(|c| c.cell)
                .collect();
            if around.is_empty() {
                break;
            }
            let mut near: Vec<LatticeCell> = Vec::new();
            for c in around {
                for dy in [-s, 0, s] {
                    for dx in [-s, 0, s] {
                        let (x, y) = (i64::from(c.x) + dx, i64::from(c.y) + dy);
                        if (dx, dy) != (0, 0) && x >= 0 && y >= 0 && x < cols && y < rows {
                            near.push(LatticeCell::new(x as u32, y as u32));
                        }
                    }
                }
            }
            near.sort_unstable_by_key(|c| (c.y, c.x));
            near.dedup();
            for cell in near {
                let Some(walk) = field.distance(cell) else {
                    continue;
                };
                let c = self.at(cell, walk);
                if !self.estimated.contains(&c.order) && self.open(cell) {
                    self.estimate(c);
                }
            }
            rank(&mut self.pool);
        }
    }

    /// Step 3: the best few and the robot's position predicted on the grid's own cells; the best
    /// of them, with its rays still cast (for its prediction), or why there is none.
    pub fn choose(mut self) -> Result<(Candidate, Scratch), NoView> {
        let mut finalists: Vec<Candidate> = self.pool.iter().take(FINALISTS).copied().collect();
        if !finalists.iter().any(|c| c.order == 0) {
            finalists.push(self.own);
        }
        if self.pool.is_empty() {
            // Nothing estimated to show enough: a gap narrower than a coarse cell may still show
            // some, so the most promising candidates are predicted on the grid's own cells.
            let passed = &mut self.passed;
            passed.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.order.cmp(&b.1.order)));
            finalists.extend(passed.iter().take(LAST_CHANCE).map(|p| p.1));
        }
        let mut best_gain = self
            .pool
            .iter()
            .map(|c| c.gain)
            .fold(self.own.gain, f64::max);
        let mut best: Option<Candidate> = None;
        let mut kept = Scratch::default();
        for mut c in finalists {
            c.gain = self.sight.gain_with(&mut self.scratch, c.position).1;
            c.score = c.gain / self.time(c.walk);
            best_gain = best_gain.max(c.gain);
            if c.gain <= 0.0 || c.gain < self.config.min_gain {
                continue;
            }
            let better =
                best.is_none_or(|b| c.score > b.score || (c.score == b.score && c.order < b.order));
            if better {
                best = Some(c);
                std::mem::swap(&mut self.scratch, &mut kept);
            }
        }
        match best {
            Some(c) => Ok((c, kept)),
            None if best_gain > 0.0 => Err(NoView::TooLittle {
                best_gain,
                min_gain: self.config.min_gain,
            }),
            None => Err(NoView::Unreachable {
                targets: self.sight.target_cells(),
            }),
        }
    }
}

/// Best score first, ties to the earlier candidate.
fn rank(pool: &mut [Candidate]) {
    pool.sort_by(|a, b| b.score.total_cmp(&a.score).then(a.order.cmp(&b.order)));
}
