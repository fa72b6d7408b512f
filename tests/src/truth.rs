//! Scoring a run against the simulation's ground truth (the scoring itself lives in
//! `nudge_sim::score`, where the `nudge` command uses it too).

pub use nudge_sim::score::{MATCH_DISTANCE, Scored, score};
