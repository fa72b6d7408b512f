//! Explained outcomes: what the executive tested and why no plan exists.

use std::collections::BTreeMap;

use nudge_perception::ObjectId;

use crate::push_test::{Finding, Verdict};
use crate::view::{UnseenRegion, ViewRecord};

/// One push test, summarised for reports.
#[derive(Clone, Debug, PartialEq)]
pub struct TestRecord {
    /// The object tested.
    pub object: ObjectId,
    /// 1 for the first test of this object, 2 for the retest.
    pub attempt: u8,
    /// Peak wrist force (N).
    pub peak_force: f64,
    /// Colour-ICP displacement (mm), if ICP ran.
    pub icp_mm: Option<f64>,
    /// Hand travel after contact (mm).
    pub hand_travel_mm: f64,
    /// Whether the guarded move stopped at the force limit.
    pub reached_limit: bool,
    /// How far the wrench leaned out of the horizontal where the stroke stopped at the limit (°).
    pub stop_lean_deg: Option<f64>,
    /// What this test found.
    pub finding: Finding,
}

/// `obj-4 #1: peak 18.0 N, ICP 138.7 mm, hand 141.7 mm -> Movable` (with the stop's lean after the
/// peak where the stroke stopped at the limit): one line for logs and reports.
impl std::fmt::Display for TestRecord {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let icp = self
            .icp_mm
            .map_or_else(|| "n/a".to_string(), |mm| format!("{mm:.1} mm"));
        let lean = self
            .stop_lean_deg
            .map_or_else(String::new, |deg| format!(", leaning {deg:.0}°"));
        write!(
            f,
            "{} #{}: peak {:.1} N{lean}, ICP {icp}, hand {:.1} mm -> {:?}",
            self.object, self.attempt, self.peak_force, self.hand_travel_mm, self.finding
        )
    }
}

/// What the executive knew when the run ended, for `NoPathToGoal` and `Aborted`.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Explanation {
    /// Every push test, in order.
    pub tests: Vec<TestRecord>,
    /// The verdict on each object that has one.
    pub verdicts: BTreeMap<ObjectId, Verdict>,
    /// Objects no push could be planned for, with the planner's reason.
    pub unpushable: BTreeMap<ObjectId, String>,
    /// Obstacles in the way that the last ranking left out for their size, with why.
    pub set_aside: BTreeMap<ObjectId, String>,
    /// Objects that jammed while being cleared, with how often.
    pub jams: BTreeMap<ObjectId, u32>,
    /// The planner's last reason for finding no path.
    pub no_path: Option<String>,
    /// The viewpoints the robot walked to, to look from, in order.
    pub views: Vec<ViewRecord>,
    /// Unseen floor that mattered to the last decision, and why no look showed it.
    pub unseen: Vec<UnseenRegion>,
}

impl Explanation {
    /// Objects found static.
    pub fn static_objects(&self) -> Vec<ObjectId> {
        self.verdicts
            .iter()
            .filter(|(_, v)| !v.is_movable())
            .map(|(id, _)| *id)
            .collect()
    }

    /// Objects found movable.
    pub fn movable_objects(&self) -> Vec<ObjectId> {
        self.verdicts
            .iter()
            .filter(|(_, v)| v.is_movable())
            .map(|(id, _)| *id)
            .collect()
    }
}

impl std::fmt::Display for Explanation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if let Some(reason) = &self.no_path {
            writeln!(f, "no path: {reason}")?;
        }
        for t in &self.tests {
            writeln!(f, "push test {t}")?;
        }
        for (id, v) in &self.verdicts {
            writeln!(f, "{id}: {v:?}")?;
        }
        for (id, why) in &self.unpushable {
            writeln!(f, "{id}: no push plan ({why})")?;
        }
        for (id, why) in &self.set_aside {
            writeln!(f, "{id}: set aside ({why})")?;
        }
        for (id, n) in &self.jams {
            writeln!(f, "{id}: jammed {n} time(s) while clearing")?;
        }
        for v in &self.views {
            writeln!(
                f,
                "looked from ({:.2}, {:.2}) for {} ({:.2} m² predicted)",
                v.view.position.x,
                v.view.position.y,
                v.question.name(),
                v.view.gain
            )?;
        }
        for r in &self.unseen {
            writeln!(f, "unseen {r}")?;
        }
        Ok(())
    }
}
