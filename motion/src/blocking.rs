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
