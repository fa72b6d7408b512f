//! Result lines of `nudge batch` (one JSON object per run) and the per-scenario summary table that
//! `nudge batch` and `nudge report` print.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::Context;
use serde::{Deserialize, Serialize};

use super::pool::{Done, Job};
use crate::score::{Outcome, compare};

/// One run of a batch, as one JSON line. Everything but `wall_time` depends only on the scenario,
/// the seed and the policy.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunLine {
    /// Scenario name.
    pub scenario: String,
    /// Scenario file name.
    pub file: String,
    /// The run's seed.
    pub seed: u64,
    /// Candidate policy ("nearest" or "blocking").
    pub policy: String,
    /// "goal", "no_path" or "aborted".
    pub outcome: String,
    /// Push tests run.
    pub push_tests: u32,
    /// Verdicts that match the simulation's ground truth.
    pub right: u32,
    /// Verdicts that do not (or that matched no scenario object).
    pub wrong: u32,
    /// Robot time of the run (s).
    pub robot_time: f64,
    /// Wall-clock time of the run (s); the one field that differs between equal runs.
    pub wall_time: f64,
    /// Largest wrist force of the run (N).
    pub peak_force: f64,
    /// The scenario's family (`nudge generate`), or its own name for a hand-made one.
    #[serde(default)]
    pub family: String,
    /// Whether the run met its scenario's `[expect]` block (outcome and named verdicts); absent for
    /// a scenario without one.
    #[serde(default)]
    pub expect_met: Option<bool>,
    /// Distance the base walked (m).
    #[serde(default)]
    pub walked: f64,
    /// Shortest way to the goal with every movable object taken away (m); absent where static
    /// things shut the goal off.
    #[serde(default)]
    pub ideal_path: Option<f64>,
    /// Success weighted by path length (iGibson's path efficiency).
    #[serde(default)]
    pub spl: Option<f64>,
    /// Σ mass × displacement of the objects the robot moved (kg·m).
    #[serde(default)]
    pub displaced: f64,
    /// Work the hand exchanged with what it touched (J).
    #[serde(default)]
    pub hand_work: f64,
    /// Impulse of the hand's horizontal force on what it touched (N·s).
    #[serde(default)]
    pub hand_impulse: f64,
    /// iGibson's effort efficiency.
    #[serde(default)]
    pub effort_efficiency: f64,
    /// Interactive Navigation Score (α = 0.5); absent where there is no ideal path.
    #[serde(default)]
    pub ins: Option<f64>,
    /// Movable objects called static.
    #[serde(default)]
    pub false_static: u32,
    /// Static objects called movable.
    #[serde(default)]
    pub false_movable: u32,
    /// New contacts with people; absent in a scenario without people.
    #[serde(default)]
    pub people_contacts: Option<u32>,
    /// New contacts of a pushed object with people; absent in a scenario without people.
    #[serde(default)]
    pub pushed_into_people: Option<u32>,
    /// Largest wrist force while the hand pushed (push tests and clearing strokes) as a share of the
    /// force limit in force then (1 = at the limit); absent when the hand never pushed.
    #[serde(default)]
    pub force_share: Option<f64>,
    /// Obstacles kept at the end where the truth has nothing; absent in lines written before ghosts
    /// were counted.
    #[serde(default)]
    pub ghosts: Option<u32>,
}

impl RunLine {
    /// The line of a finished job.
    pub fn of(job: &Job<'_>, done: &Done) -> Self {
        let right = done.scored.iter().filter(|s| s.correct).count() as u32;
        let m = &done.metrics;
        Self {
            scenario: job.scenario.name.clone(),
            file: job.file.to_string(),
            seed: job.seed,
            policy: super::policy_word(job.policy).to_string(),
            outcome: Outcome::of(&done.report.outcome).word().to_string(),
            push_tests: done.report.knowledge.push_tests,
            right,
            wrong: done.scored.len() as u32 - right,
            robot_time: done.report.robot_time,
            wall_time: done.wall,
            peak_force: done.peak_force,
            family: job
                .scenario
                .family
                .clone()
                .unwrap_or_else(|| job.scenario.name.clone()),
            expect_met: job
                .scenario
                .expect
                .as_ref()
                .map(|e| compare(e, Outcome::of(&done.report.outcome), &done.scored).is_empty()),
            walked: m.walked,
            ideal_path: m.ideal_path,
            spl: m.spl,
            displaced: m.displaced,
            hand_work: m.hand_work,
            hand_impulse: m.hand_impulse,
            effort_efficiency: m.effort_efficiency,
            ins: m.ins,
            false_static: m.false_static,
            false_movable: m.false_movable,
            people_contacts: m.people_contacts,
            pushed_into_people: m.pushed_into_people,
            force_share: done.force_share,
            ghosts: Some(m.ghosts),
        }
    }

    /// The family the line is summed under: its own, or its scenario's name in files written before
    /// lines had families.
    pub fn family(&self) -> &str {
        if self.family.is_empty() {
            &self.scenario
        } else {
            &self.family
        }
    }

    /// What identifies a run: the same key means the same run.
    pub fn key(&self) -> (String, String, String, u64) {
        (
            self.scenario.clone(),
            self.file.clone(),
            self.policy.clone(),
            self.seed,
        )
    }
}

/// Reads result lines from `path`; blank lines are skipped, anything else that is not a result line
/// is an error naming the file and line.
pub fn read(path: &Path) -> anyhow::Result<Vec<RunLine>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| {
            serde_json::from_str(l)
                .with_context(|| format!("{}:{}: not a nudge result line", path.display(), i + 1))
        })
        .collect()
}

/// What the table's rows sum: each scenario, or each family of scenarios.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Group {
    /// One row per family (a hand-made scenario is a family of its own).
    Family,
    /// One row per scenario.
    Scenario,
}

#[derive(Default)]
struct Tally {
    runs: u32,
    goal: u32,
    no_path: u32,
    aborted: u32,
    push_tests: u64,
    right: u64,
    wrong: u64,
    false_static: u64,
    false_movable: u64,
    robot_time: f64,
    peak_force: f64,
    force_share: Option<f64>,
    spl: Mean,
    ins: Mean,
    displaced: f64,
    hand_work: f64,
    people_contacts: Option<u64>,
    pushed_into_people: Option<u64>,
    ghosts: Option<u64>,
    expect_met: u32,
    expect_runs: u32,
}

/// A mean over the runs where a value exists.
#[derive(Default)]
struct Mean {
    sum: f64,
    count: u32,
}

impl Mean {
    fn add(&mut self, v: Option<f64>) {
        if let Some(v) = v {
            self.sum += v;
            self.count += 1;
        }
    }

    fn show(&self) -> String {
        if self.count == 0 {
            "-".to_string()
        } else {
            format!("{:.3}", self.sum / f64::from(self.count))
        }
    }
}

/// The summary table, one row per family (or scenario) and policy: runs, runs that met their
/// `[expect]` block, outcomes, success rate, mean SPL and INS (over the runs that have them), mean
/// mass displaced and hand work, mean push tests, classification accuracy (right / all verdicts),
/// false-static and false-movable verdicts, mean robot time, largest force, largest force while
/// pushing as a share of the limit in force, and contacts with people.
pub fn table(lines: &[RunLine], group: Group) -> String {
    let mut tallies: BTreeMap<(&str, &str), Tally> = BTreeMap::new();
    for l in lines {
        let name = match group {
            Group::Family => l.family(),
            Group::Scenario => &l.scenario,
        };
        let t = tallies.entry((name, &l.policy)).or_default();
        t.runs += 1;
        match l.outcome.as_str() {
            "goal" => t.goal += 1,
            "no_path" => t.no_path += 1,
            _ => t.aborted += 1,
        }
        t.push_tests += u64::from(l.push_tests);
        t.right += u64::from(l.right);
        t.wrong += u64::from(l.wrong);
        t.robot_time += l.robot_time;
        t.peak_force = t.peak_force.max(l.peak_force);
        if let Some(share) = l.force_share {
            t.force_share = Some(t.force_share.unwrap_or(0.0).max(share));
        }
        t.false_static += u64::from(l.false_static);
        t.false_movable += u64::from(l.false_movable);
        t.spl.add(l.spl);
        t.ins.add(l.ins);
        t.displaced += l.displaced;
        t.hand_work += l.hand_work;
        if let Some(met) = l.expect_met {
            t.expect_runs += 1;
            t.expect_met += u32::from(met);
        }
        if let Some(c) = l.people_contacts {
            *t.people_contacts.get_or_insert(0) += u64::from(c);
        }
        if let Some(c) = l.pushed_into_people {
            *t.pushed_into_people.get_or_insert(0) += u64::from(c);
        }
        if let Some(g) = l.ghosts {
            *t.ghosts.get_or_insert(0) += u64::from(g);
        }
    }
    let width = tallies
        .keys()
        .map(|(s, _)| s.len())
        .max()
        .unwrap_or(0)
        .max(8);
    let mut out = format!(
        "{:<width$}  {:<8}  {:>4}  {:>7}  {:>4}  {:>7}  {:>7}  {:>7}  {:>5}  {:>5}  {:>8}  {:>7}  {:>10}  {:>8}  {:>5}  {:>10}  {:>9}  {:>7}  {:>8}  {:>6}\n",
        match group {
            Group::Family => "family",
            Group::Scenario => "scenario",
        },
        "policy",
        "runs",
        "expect",
        "goal",
        "no_path",
        "aborted",
        "success",
        "SPL",
        "INS",
        "moved kg·m",
        "work J",
        "push tests",
        "accuracy",
        "F-S/M",
        "robot time",
        "max force",
        "F/limit",
        "contacts",
        "ghosts"
    );
    for ((scenario, policy), t) in &tallies {
        let runs = f64::from(t.runs.max(1));
        let verdicts = t.right + t.wrong;
        let accuracy = if verdicts == 0 {
            "-".to_string()
        } else {
            format!("{:.1}%", 100.0 * t.right as f64 / verdicts as f64)
        };
        let mistakes = format!("{}/{}", t.false_static, t.false_movable);
        let expect = if t.expect_runs == 0 {
            "-".to_string()
        } else {
            format!("{}/{}", t.expect_met, t.expect_runs)
        };
        let share = t
            .force_share
            .map_or_else(|| "-".to_string(), |f| format!("{f:.2}"));
        // Contacts of the robot with people, then of pushed objects with people where lines say.
        let contacts = match (t.people_contacts, t.pushed_into_people) {
            (None, _) => "-".to_string(),
            (Some(c), None) => c.to_string(),
            (Some(c), Some(p)) => format!("{c}/{p}"),
        };
        let ghosts = t.ghosts.map_or_else(|| "-".to_string(), |g| g.to_string());
        out.push_str(&format!(
            "{scenario:<width$}  {policy:<8}  {:>4}  {expect:>7}  {:>4}  {:>7}  {:>7}  {:>6.1}%  {:>5}  {:>5}  {:>10.1}  {:>7.1}  {:>10.2}  {accuracy:>8}  {mistakes:>5}  {:>8.1} s  {:>7.1} N  {share:>7}  {contacts:>8}  {ghosts:>6}\n",
            t.runs,
            t.goal,
            t.no_path,
            t.aborted,
            100.0 * f64::from(t.goal) / runs,
            t.spl.show(),
            t.ins.show(),
            t.displaced / runs,
            t.hand_work / runs,
            t.push_tests as f64 / runs,
            t.robot_time / runs,
            t.peak_force,
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(scenario: &str, seed: u64, outcome: &str, right: u32, wrong: u32) -> RunLine {
        RunLine {
            scenario: scenario.into(),
            file: format!("{scenario}.toml"),
            seed,
            policy: "nearest".into(),
            outcome: outcome.into(),
            push_tests: 2,
            right,
            wrong,
            robot_time: 100.0,
            wall_time: 1.0,
            peak_force: 18.0,
            family: String::new(),
            expect_met: Some(true),
            walked: 10.0,
            ideal_path: Some(8.0),
            spl: Some(0.8),
            displaced: 0.0,
            hand_work: 0.0,
            hand_impulse: 0.0,
            effort_efficiency: 1.0,
            ins: Some(0.9),
            false_static: 0,
            false_movable: 0,
            people_contacts: None,
            ghosts: None,
            pushed_into_people: None,
            force_share: Some(0.9),
        }
    }

    #[test]
    fn the_table_rates_success_and_accuracy_per_scenario() {
        // Invariant: success = goal runs / runs, accuracy = right / (right + wrong) and expect = runs that met their [expect] block / runs with one, per scenario.
        let mut lines = [
            line("room", 1, "goal", 2, 0),
            line("room", 2, "no_path", 1, 1),
            line("hall", 1, "goal", 0, 0),
        ];
        lines[1].expect_met = Some(false);
        let t = table(&lines, Group::Scenario);
        let room = t.lines().find(|l| l.starts_with("room")).expect("room row");
        assert!(
            room.contains(" 1/2 "),
            "one of two runs met its [expect]: {room}"
        );
        assert!(room.contains(" 50.0%"), "{room}");
        assert!(room.contains(" 75.0%"), "{room}");
        let hall = t.lines().find(|l| l.starts_with("hall")).expect("hall row");
        assert!(hall.contains("100.0%"), "{hall}");
        assert!(hall.contains("       -"), "no verdicts shows '-': {hall}");
    }

    #[test]
    fn the_table_sums_contacts_with_people_and_of_pushed_objects_with_people() {
        // Invariant: a row's contacts are the runs' contacts of the robot with people, then of pushed objects with people ("robot/pushed"), and its ghosts the runs' ghosts summed; lines written before the pushed count show the robot's alone, lines written before ghosts were counted and rows without people show "-".
        let mut lines = [
            line("crowd", 1, "goal", 0, 0),
            line("crowd", 2, "goal", 0, 0),
            line("old", 1, "goal", 0, 0),
            line("empty", 1, "goal", 0, 0),
        ];
        (lines[0].people_contacts, lines[0].pushed_into_people) = (Some(3), Some(1));
        (lines[1].people_contacts, lines[1].pushed_into_people) = (Some(4), Some(0));
        (lines[0].ghosts, lines[1].ghosts) = (Some(2), Some(1));
        lines[2].people_contacts = Some(5);
        let t = table(&lines, Group::Scenario);
        let last_two = |name: &str| {
            let row = t.lines().find(|l| l.starts_with(name)).expect("row");
            let words: Vec<&str> = row.split_whitespace().collect();
            words[words.len() - 2..].join(" ")
        };
        assert_eq!(last_two("crowd"), "7/1 3");
        assert_eq!(last_two("old"), "5 -");
        assert_eq!(last_two("empty"), "- -");
    }

    #[test]
    fn result_lines_round_trip_and_bad_lines_name_their_place() {
        // Invariant: a written line reads back equal; a malformed line is an error with file and line number.
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("r.jsonl");
        let good = serde_json::to_string(&line("room", 3, "goal", 1, 0)).expect("serialise");
        std::fs::write(&path, format!("{good}\n\n{{\"scenario\": 1}}\n")).expect("write");
        let err = read(&path).expect_err("bad second line");
        assert!(
            format!("{err}").ends_with("r.jsonl:3: not a nudge result line"),
            "{err}"
        );
        std::fs::write(&path, format!("{good}\n")).expect("write");
        assert_eq!(
            read(&path).expect("reads"),
            vec![line("room", 3, "goal", 1, 0)]
        );
    }
}
