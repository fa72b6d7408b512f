//! Which obstacles block the way: plan with one obstacle removed at a time.
//!
//! The executive orders its push candidates with this: an obstacle whose removal opens a short path
//! is worth testing first. Each removal is planned with RRT-Connect plus shortcutting under its own
//! seed (derived from the caller's generator and the obstacle id), so a report does not depend on the
//! order of the candidates.

use nudge_perception::ObjectId;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::path::Path;
use crate::planner::rrt_connect::RrtConnect;
use crate::planner::shortcut::Shortcut;
use crate::planner::{Budget, NoPath, Planner};
use crate::problem::Problem;
use crate::validity::Validity;

/// How hard to try for each removal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BlockingConfig {
    /// The planner used with each obstacle removed.
    pub planner: RrtConnect,
    /// Its budget per removal.
    pub budget: Budget,
    /// Shortcutting applied to each path found, so lengths compare fairly.
    pub shortcut: Shortcut,
}

impl Default for BlockingConfig {
    fn default() -> Self {
        Self {
            planner: RrtConnect::default(),
            budget: Budget::iterations(5_000),
            shortcut: Shortcut::default(),
        }
    }
}

/// What removing one obstacle does to the planning problem.
#[derive(Clone, Debug, PartialEq)]
pub struct BlockingReport {
    /// The obstacle removed.
    pub object: ObjectId,
    /// The (shortcut) path found without it, or why there is none.
    pub outcome: Result<Path, NoPath>,
}

impl BlockingReport {
    /// Whether removing the obstacle opens a path.
    pub fn opens_path(&self) -> bool {
        self.outcome.is_ok()
    }

    /// Length of the path it opens (m), if any.
    pub fn path_length(&self) -> Option<f64> {
        self.outcome.as_ref().ok().map(Path::length)
    }
}

/// For each of `candidates` (ids among the validity's blocking obstacles; others are skipped),
/// whether removing it alone opens a path, sorted: openers first by path length, then the rest, ties
/// by id.
pub fn blocking_obstacles(
    problem: &Problem,
    validity: &Validity,
    candidates: &[ObjectId],
    config: &BlockingConfig,
    rng: &mut ChaCha8Rng,
) -> Vec<BlockingReport> {
    let base: u64 = rng.random();
    let mut ids: Vec<ObjectId> = candidates
        .iter()
        .copied()
        .filter(|id| validity.obstacle(*id).is_some())
        .collect();
    ids.sort_unstable();
    ids.dedup();
    let mut reports: Vec<BlockingReport> = ids
        .into_iter()
        .map(|id| {
            let mut own = ChaCha8Rng::seed_from_u64(
                base ^ u64::from(id.0).wrapping_mul(0x9E37_79B9_7F4A_7C15),
            );
            let world = validity.without(&[id]);
            let mut planner = config.planner;
            let outcome = planner
                .solve(problem, &world, config.budget, &mut own)
                .map(|p| config.shortcut.shorten(&p, &world, &mut own));
            BlockingReport {
                object: id,
                outcome,
            }
        })
        .collect();
    reports.sort_by(|a, b| {
        let key = |r: &BlockingReport| r.path_length().unwrap_or(f64::INFINITY);
        key(a).total_cmp(&key(b)).then(a.object.cmp(&b.object))
    });
    reports
}

/// How the cost-to-go grid treats obstacles that may move.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CrossingConfig {
    /// Grid spacing (m).
    pub resolution: f64,
    /// Extra cost per metre driven through a passable obstacle (on top of the metre itself).
    pub penalty: f64,
}

impl Default for CrossingConfig {
    fn default() -> Self {
        Self {
            resolution: 0.05,
            penalty: 10.0,
        }
    }
}

/// The cheapest way to the goal when some obstacles may be driven through at a cost.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// Grid path from the start to the goal region.
    pub path: Path,
    /// Its cost: metres, plus the penalty for each metre inside passable obstacles.
    pub cost: f64,
    /// The passable obstacles the path goes through, in the order it meets them.
    pub crossed: Vec<ObjectId>,
}

/// Dijkstra on a grid over the sampling bounds, where cells blocked only by `passable` obstacles
/// (movable or not yet tested) cost `1 + penalty` per metre and other blocked cells are walls.
/// Answers "which obstacles block the cheapest path", in the order the path meets them.
pub fn cheapest_crossing(
    problem: &Problem,
    validity: &Validity,
    passable: &[ObjectId],
    config: &CrossingConfig,
) -> Result<Crossing, NoPath> {
    use crate::validity::StateValidity;
    use nalgebra::Point2;
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;

    let res = if config.resolution.is_finite() && config.resolution > 0.0 {
        config.resolution
    } else {
        0.05
    };
    let bounds = *validity.sampling_bounds();
    let size = bounds.size();
    let nx = (size.x / res).floor() as usize + 1;
    let ny = (size.y / res).floor() as usize + 1;
    let at = |i: usize| {
        bounds.min() + nalgebra::Vector2::new((i % nx) as f64 * res, (i / nx) as f64 * res)
    };
    // Per cell: None = impassable, Some(ids) = passable crossing those obstacles (empty = free).
    let cells: Vec<Option<Vec<ObjectId>>> = (0..nx * ny)
        .map(|i| {
            let p = at(i);
            if validity.is_free(&p) {
                return Some(Vec::new());
            }
            let hits = validity.colliding(&p);
            (!hits.is_empty() && hits.iter().all(|id| passable.contains(id))).then_some(hits)
        })
        .collect();
    let factor = |c: &Option<Vec<ObjectId>>| match c {
        Some(ids) if ids.is_empty() => 1.0,
        _ => 1.0 + config.penalty.max(0.0),
    };
    let cell_of = |p: &Point2<f64>| {
        let x = ((p.x - bounds.min().x) / res)
            .round()
            .clamp(0.0, (nx - 1) as f64) as usize;
        let y = ((p.y - bounds.min().y) / res)
            .round()
            .clamp(0.0, (ny - 1) as f64) as usize;
        y * nx + x
    };
    let start = cell_of(&problem.start());
    if cells[start].is_none() {
        return Err(NoPath::StartInCollision);
    }
    let goal = problem.goal();
    let is_goal = |i: usize| goal.contains(&at(i)) || i == cell_of(&goal.centre());
    if !(0..nx * ny).any(|i| is_goal(i) && cells[i].is_some()) {
        return Err(NoPath::GoalInCollision);
    }
    let mut dist = vec![f64::INFINITY; nx * ny];
    let mut parent = vec![usize::MAX; nx * ny];
    // Costs are non-negative finite floats: their bit patterns order like the values.
    let mut heap = BinaryHeap::new();
    dist[start] = 0.0;
    heap.push(Reverse((0.0f64.to_bits(), start)));
    let mut expanded = 0usize;
    let mut reached = None;
    while let Some(Reverse((bits, i))) = heap.pop() {
        let d = f64::from_bits(bits);
        if d > dist[i] {
            continue;
        }
        expanded += 1;
        if is_goal(i) {
            reached = Some(i);
            break;
        }
        let (x, y) = ((i % nx) as isize, (i / nx) as isize);
        for (dx, dy) in crate::reach::NEIGHBOURS.map(|(dx, dy)| (dx as isize, dy as isize)) {
            let (x2, y2) = (x + dx, y + dy);
            if x2 < 0 || y2 < 0 || x2 >= nx as isize || y2 >= ny as isize {
                continue;
            }
            let j = y2 as usize * nx + x2 as usize;
            let Some(_) = &cells[j] else { continue };
            let step = res
                * if dx != 0 && dy != 0 {
                    std::f64::consts::SQRT_2
                } else {
                    1.0
                };
            let nd = d + step * 0.5 * (factor(&cells[i]) + factor(&cells[j]));
            if nd < dist[j] {
                dist[j] = nd;
                parent[j] = i;
                heap.push(Reverse((nd.to_bits(), j)));
            }
        }
    }
    let Some(end) = reached else {
        return Err(NoPath::NotFound {
            iterations: expanded,
        });
    };
    let mut chain = vec![end];
    while let Some(&last) = chain.last() {
        if last == start {
            break;
        }
        chain.push(parent[last]);
    }
    chain.reverse();
    let mut crossed = Vec::new();
    for i in &chain {
        for id in cells[*i].iter().flatten() {
            if !crossed.contains(id) {
                crossed.push(*id);
            }
        }
    }
    let mut points: Vec<Point2<f64>> = chain.iter().map(|&i| at(i)).collect();
    points[0] = problem.start();
    let path = Path::new(points).map_err(|_| NoPath::StartInCollision)?;
    Ok(Crossing {
        path,
        cost: dist[end],
        crossed,
    })
}
