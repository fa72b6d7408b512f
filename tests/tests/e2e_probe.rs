//! Exploratory end-to-end run of the paper's room (prints the timeline).

use nudge_executive::CandidatePolicy;
use nudge_executive::record::{LogLevel, Observer};
use nudge_executive::{Edge, State};

struct Printer;
impl Observer for Printer {
    fn transition(&mut self, stamp: f64, from: &State, edge: Edge, to: &State) {
        println!("{stamp:8.2} s  {} -> {} ({edge:?})", from.name(), to.name());
    }
    fn note(&mut self, stamp: f64, _level: LogLevel, text: &str) {
        println!("{stamp:8.2} s  note: {text}");
    }
    fn prisms(&mut self, stamp: f64, prisms: &[nudge_perception::Prism]) {
        for p in prisms {
            let (lo, hi) = p.footprint.iter().fold(((f64::MAX, f64::MAX), (f64::MIN, f64::MIN)), |(lo, hi), q| ((lo.0.min(q.x), lo.1.min(q.y)), (hi.0.max(q.x), hi.1.max(q.y))));
            println!("{stamp:8.2} s  prism {} x {:.2}..{:.2} y {:.2}..{:.2} z {:.2}..{:.2}", p.id, lo.0, hi.0, lo.1, hi.1, p.z_min, p.z_max);
        }
    }
}

#[test]
#[ignore]
fn probe_kakiuchi_room() {
    // Invariant: none — prints the run for inspection.
    let scenario = nudge_tests::scenario("kakiuchi-room").expect("scenario");
    let t = std::time::Instant::now();
    let (report, _robot) = nudge_tests::run(&scenario, 1, CandidatePolicy::Nearest, Printer).expect("run");
    println!("outcome {:?}", report.outcome.name());
    println!("{}", match &report.outcome { State::Aborted(r, e) => format!("{r}\n{e}"), State::NoPathToGoal(e) => format!("{e}"), _ => String::new() });
    println!("knowledge {:#?}", report.knowledge.explanation.tests);
    println!("robot time {:.1} s, wall {:.2} s", report.robot_time, t.elapsed().as_secs_f64());
}
