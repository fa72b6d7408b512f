//! Replaying a recording against the current executive: the recording's tape drives a
//! [`ReplayRobot`](nudge_executive::record::tape::ReplayRobot), the scenario, seed and policy it
//! names rebuild the run's configuration ([`run_config`]), and the first call or transition where
//! the new run parts from the recorded one is reported.

use std::collections::BTreeMap;
use std::path::Path;
use std::str::FromStr;

use anyhow::{Context, anyhow};
use nudge_executive::record::RunSummary;
use nudge_executive::record::tape::{Divergence, Replay, read_recording};
use nudge_executive::{CandidatePolicy, RunConfig, RunReport, Runner};

use crate::run::run_config;
use crate::scenario::Scenario;

/// The settings `--set` may change, as typed.
pub const SETTING_KEYS: &str =
    "force_limit (N, the push test's), clear_force_limit (N), push_speed (m/s), max_push_tests";

/// One executive setting changed for a replay (`KEY=VALUE`, keys in [`SETTING_KEYS`]), to see
/// where a change of the executive parts from a recorded run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Setting {
    /// The push test's force limit (N): `ExecutiveConfig::force_limit`.
    ForceLimit(f64),
    /// A clearing stroke's force limit (N): `ExecutiveConfig::clear_force_limit`.
    ClearForceLimit(f64),
    /// The hand's push speed (m/s): `PushMotionConfig::speed`.
    PushSpeed(f64),
    /// Push tests allowed in one run: `ExecutiveConfig::max_push_tests`.
    MaxPushTests(u32),
}

impl FromStr for Setting {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (key, value) = s
            .split_once('=')
            .ok_or_else(|| format!("'{s}' is not KEY=VALUE; keys: {SETTING_KEYS}"))?;
        let (key, value) = (key.trim(), value.trim());
        let number = || {
            value
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite() && *v > 0.0)
                .ok_or_else(|| format!("{key}: '{value}' is not a positive number"))
        };
        match key {
            "force_limit" => Ok(Self::ForceLimit(number()?)),
            "clear_force_limit" => Ok(Self::ClearForceLimit(number()?)),
            "push_speed" => Ok(Self::PushSpeed(number()?)),
            "max_push_tests" => value
                .parse()
                .map(Self::MaxPushTests)
                .map_err(|_| format!("{key}: '{value}' is not a whole number")),
            other => Err(format!("unknown setting '{other}'; keys: {SETTING_KEYS}")),
        }
    }
}

impl Setting {
    /// Changes `config` accordingly.
    pub fn apply(&self, config: &mut RunConfig) {
        match *self {
            Self::ForceLimit(v) => config.model.force.test_limit = v,
            Self::ClearForceLimit(v) => config.model.force.clear_limit = v,
            Self::PushSpeed(v) => config.push_motion.speed = v,
            Self::MaxPushTests(v) => config.executive.max_push_tests = v,
        }
    }
}

/// What a replay found.
#[derive(Debug)]
pub struct Replayed {
    /// The recorded scenario's name.
    pub scenario: String,
    /// The attached scenario file's name.
    pub scenario_file: String,
    /// The recorded seed.
    pub seed: u64,
    /// The recorded policy.
    pub policy: CandidatePolicy,
    /// The nudge version that recorded it.
    pub version: String,
    /// Entries on the tape (calls and transitions).
    pub entries: usize,
    /// Calls that matched.
    pub calls: usize,
    /// Transitions that matched.
    pub transitions: usize,
    /// The first divergence; `None`: every call and transition matched and the outcome is the same.
    pub divergence: Option<Divergence>,
    /// Whether the recording holds a summary to compare the outcome with (not after a killed run).
    pub outcome_recorded: bool,
    /// The new run's report.
    pub report: RunReport,
}

/// Replays the recording at `path` with `settings` changed. Errors (bad file) name the file and say
/// what is wrong; a divergence is not an error but part of the result.
pub fn replay_file(path: &Path, settings: &[Setting]) -> anyhow::Result<Replayed> {
    let name = path.display().to_string();
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {name}"))?;
    let recording = read_recording(&bytes).with_context(|| name.clone())?;
    let (scenario_file, text) = recording.scenario.clone().ok_or_else(|| {
        anyhow!("{name}: no scenario attached (a nudge recording attaches its scenario file)")
    })?;
    let scenario = Scenario::from_toml_str(&text, &format!("{name}, attached {scenario_file}"))?;
    let field = |key: &str| {
        recording.run.get(key).ok_or_else(|| {
            anyhow!("{name}: the run metadata has no '{key}' (not a nudge recording?)")
        })
    };
    let seed: u64 = field("seed")?
        .parse()
        .map_err(|_| anyhow!("{name}: the recorded seed is not a whole number"))?;
    let policy: CandidatePolicy = field("policy")?
        .parse()
        .map_err(|e: String| anyhow!("{name}: {e}"))?;
    let version = field("version")?.clone();
    let mut config = run_config(&scenario, seed, policy);
    for setting in settings {
        setting.apply(&mut config);
    }
    let entries = recording.entries.len();
    let replay = Replay::new(recording.entries);
    let mut runner = Runner::new(replay.robot(), replay.observer(), config);
    let report = runner.run();
    let summary = RunSummary::of(&report);
    let mut divergence = replay.finish(&summary.line());
    if divergence.is_none()
        && let Some(recorded) = &recording.summary
    {
        divergence = outcome_divergence(recorded, &summary.entries(), entries, &report);
    }
    Ok(Replayed {
        scenario: scenario.name.clone(),
        scenario_file,
        seed,
        policy,
        version,
        entries,
        calls: replay.calls(),
        transitions: replay.transitions(),
        divergence,
        outcome_recorded: recording.summary.is_some(),
        report,
    })
}

/// A divergence past the tape's end when the summaries differ (every call matched, yet the outcome
/// did not: a change in what the executive concludes from the same calls).
fn outcome_divergence(
    recorded: &BTreeMap<String, String>,
    new: &BTreeMap<String, String>,
    entries: usize,
    report: &RunReport,
) -> Option<Divergence> {
    let keys: std::collections::BTreeSet<&String> = recorded.keys().chain(new.keys()).collect();
    let differ: Vec<&String> = keys
        .into_iter()
        .filter(|k| recorded.get(*k) != new.get(*k))
        .collect();
    if differ.is_empty() {
        return None;
    }
    let show = |m: &BTreeMap<String, String>| {
        differ
            .iter()
            .map(|k| format!("{k}={}", m.get(*k).map_or("(none)", String::as_str)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    Some(Divergence {
        index: entries,
        robot_time: report.robot_time,
        state: Some(report.outcome.name().to_string()),
        recorded: format!("summary {}", show(recorded)),
        new: format!("summary {}", show(new)),
    })
}
