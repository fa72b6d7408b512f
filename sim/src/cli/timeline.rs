//! Printing a run as it goes: transitions, verdicts and notes, stamped with robot time.

use nudge_executive::record::{LogLevel, Observer};
use nudge_executive::{Edge, PushEvidence, State, Verdict};
use nudge_perception::ObjectId;

/// An observer that prints the timeline to standard output.
pub struct TimelinePrinter {
    /// Print nothing when false.
    pub enabled: bool,
}

impl Observer for TimelinePrinter {
    fn transition(&mut self, stamp: f64, from: Option<&State>, edge: Edge, to: &State) {
        let from = from.map_or("(start)", State::name);
        if self.enabled && from != to.name() {
            println!("{stamp:8.2} s  {from:<17} -> {:<17} {edge:?}", to.name());
        }
    }

    fn verdict(
        &mut self,
        stamp: f64,
        object: ObjectId,
        verdict: &Verdict,
        evidence: &PushEvidence,
    ) {
        if self.enabled {
            println!(
                "{stamp:8.2} s  {object} is {}  ({})",
                verdict_word(verdict),
                evidence_line(evidence)
            );
        }
    }

    fn note(&mut self, stamp: f64, level: LogLevel, text: &str) {
        if self.enabled && level != LogLevel::Info {
            println!("{stamp:8.2} s  {level:?}: {text}");
        }
    }
}

/// "static" / "movable", with the retest caveat.
pub fn verdict_word(verdict: &Verdict) -> &'static str {
    match verdict {
        Verdict::Movable => "movable",
        Verdict::Static {
            after_ambiguity: false,
        } => "static",
        Verdict::Static {
            after_ambiguity: true,
        } => "static (two ambiguous tests)",
    }
}

/// Peak force, ICP displacement and hand travel of one push test.
pub fn evidence_line(e: &PushEvidence) -> String {
    let icp = e.icp.map_or_else(
        || "ICP n/a".to_string(),
        |i| format!("ICP {:.1} mm", i.displacement * 1e3),
    );
    format!(
        "peak {:.1} N of {:.0} N, {icp}, hand {:.1} mm after contact",
        e.peak_force,
        e.force_limit,
        e.hand_travel * 1e3
    )
}
