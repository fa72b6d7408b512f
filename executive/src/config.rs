//! The executive's parameters.

use crate::push_test::ClassifierConfig;

/// How push candidates are ordered.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CandidatePolicy {
    /// The obstacle nearest the robot first (the paper's rule).
    #[default]
    Nearest,
    /// The obstacle whose removal opens the cheapest path first.
    Blocking,
}

impl std::str::FromStr for CandidatePolicy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "nearest" => Ok(Self::Nearest),
            "blocking" => Ok(Self::Blocking),
            other => Err(format!(
                "unknown policy '{other}': expected nearest or blocking"
            )),
        }
    }
}

/// Limits and thresholds of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct ExecutiveConfig {
    /// How push candidates are ordered.
    pub policy: CandidatePolicy,
    /// Push tests allowed in one run (retests included).
    pub max_push_tests: u32,
    /// Replans allowed in one run (blocked walks and invalidated paths).
    pub max_replans: u32,
    /// Robot time allowed for the run (s).
    pub max_robot_time: f64,
    /// Jams while clearing, or blocked walks to its stand pose, after which an object is no longer
    /// tried.
    pub max_jams: u32,
    /// Clearing pushes of one object after which it is no longer tried.
    pub max_clears_per_object: u32,
    /// Looks around (about 10 s each) per obstacle before pushing one the grid saw moving lately or
    /// calls movable on passive evidence alone, or giving up on one that is in the way: Tamura's rule
    /// calls a person who stopped movable too, and a person usually walks on.
    pub passive_waits: u32,
    /// Looks around (about 10 s each) in one run spent waiting for things seen moving (people,
    /// perhaps) when nothing else in the way can be pushed: six, about a minute, since a person who
    /// stands in the way longer than that is not about to leave; a budget like `max_views`, so a run
    /// with people pacing about still ends.
    pub mover_waits: u32,
    /// Viewpoints the robot may walk to in one run to look from (moving to see). Each costs a walk
    /// and a look-around (about 10 s); a budget like `max_replans`, so a run always ends.
    pub max_views: u32,
    /// Viewpoints per object whose push needs floor not yet seen, before it is pushed over that
    /// floor anyway (guarded) or given up: one look from the best place, and one more where the first
    /// showed part of it.
    pub views_per_push: u32,
    /// The fused decision's thresholds.
    pub classifier: ClassifierConfig,
}

impl Default for ExecutiveConfig {
    fn default() -> Self {
        Self {
            policy: CandidatePolicy::Nearest,
            max_push_tests: 8,
            max_replans: 20,
            max_robot_time: 1800.0,
            max_jams: 2,
            max_clears_per_object: 3,
            passive_waits: 2,
            mover_waits: 6,
            max_views: 12,
            views_per_push: 2,
            classifier: ClassifierConfig::default(),
        }
    }
}
