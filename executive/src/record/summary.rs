//! The run's summary as a recording stores it: plain key/value text, written at the end.

use std::collections::BTreeMap;

use crate::runner::RunReport;
use crate::state::State;

/// Name of the MCAP metadata record holding the run's settings (scenario, seed, version, policy).
pub const RUN_METADATA: &str = "nudge-run";
/// Name of the MCAP metadata record holding the run's summary ([`RunSummary::entries`]).
pub const SUMMARY_METADATA: &str = "nudge-summary";
/// The `name` of the final `foxglove.Log` message that carries [`RunSummary::line`].
pub const RUN_SUMMARY_LOG: &str = "summary";

/// How a run ended and what it learnt, as text fit for MCAP metadata and a log line.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSummary {
    /// The terminal state's name: Goal, NoPathToGoal or Aborted.
    pub outcome: String,
    /// Why it ended there when not at the goal (the planner's reason, the abort reason); may be empty.
    pub detail: String,
    /// Robot time the run took (s).
    pub robot_time: f64,
    /// Push tests run.
    pub push_tests: u32,
    /// One line per push test: object, attempt, peak force, ICP displacement, hand travel, finding.
    pub tests: Vec<String>,
    /// The verdict on each object that has one, by object id ("obj-3" → "Movable").
    pub verdicts: BTreeMap<String, String>,
}

impl RunSummary {
    /// The summary of a finished run.
    pub fn of(report: &RunReport) -> Self {
        let detail = match &report.outcome {
            State::NoPathToGoal(e) => e.no_path.clone().unwrap_or_default(),
            State::Aborted(reason, _) => reason.to_string(),
            _ => String::new(),
        };
        let explanation = &report.knowledge.explanation;
        let tests = explanation.tests.iter().map(ToString::to_string).collect();
        let verdicts = explanation
            .verdicts
            .iter()
            .map(|(id, v)| (id.to_string(), format!("{v:?}")))
            .collect();
        Self {
            outcome: report.outcome.name().to_string(),
            detail,
            robot_time: report.robot_time,
            push_tests: report.knowledge.push_tests,
            tests,
            verdicts,
        }
    }

    /// The summary as key/value pairs: `outcome`, `detail`, `robot_time_s`, `push_tests`,
    /// `test/N` (from 1) and `verdict/ID`.
    pub fn entries(&self) -> BTreeMap<String, String> {
        let mut map = BTreeMap::new();
        map.insert("outcome".to_string(), self.outcome.clone());
        map.insert("detail".to_string(), self.detail.clone());
        map.insert(
            "robot_time_s".to_string(),
            format!("{:.3}", self.robot_time),
        );
        map.insert("push_tests".to_string(), self.push_tests.to_string());
        for (i, line) in self.tests.iter().enumerate() {
            map.insert(format!("test/{}", i + 1), line.clone());
        }
        for (id, verdict) in &self.verdicts {
            map.insert(format!("verdict/{id}"), verdict.clone());
        }
        map
    }

    /// One line: outcome, robot time, push tests and verdicts.
    pub fn line(&self) -> String {
        let verdicts: Vec<String> = self
            .verdicts
            .iter()
            .map(|(id, v)| format!("{id} {v}"))
            .collect();
        let detail = if self.detail.is_empty() {
            String::new()
        } else {
            format!(" ({})", self.detail)
        };
        format!(
            "run ended: {}{detail} after {:.1} s robot time, {} push tests; verdicts: {}",
            self.outcome,
            self.robot_time,
            self.push_tests,
            if verdicts.is_empty() {
                "none".to_string()
            } else {
                verdicts.join(", ")
            }
        )
    }
}
