//! Exploratory end-to-end run of the paper's room (prints the timeline).

use nudge_executive::CandidatePolicy;
use nudge_executive::record::{LogLevel, Observer};
use nudge_executive::{Edge, State};

struct Printer(nalgebra::Isometry2<f64>);
impl Observer for Printer {
    fn transition(&mut self, stamp: f64, from: &State, edge: Edge, to: &State) {
        let t = self.0.translation;
        println!(
            "{stamp:8.2} s  {} -> {} ({edge:?})  robot ({:.2}, {:.2}, {:.0} deg)",
            from.name(),
            to.name(),
            t.x,
            t.y,
            self.0.rotation.angle().to_degrees()
        );
        if let State::ApproachPushPose {
            phase: nudge_executive::Approach::Walking(i),
            ..
        } = to
        {
            println!(
                "           stand {:?} dir {:?} h {:.2} d {:.2}",
                i.stand.translation.vector.as_slice(),
                i.direction.as_slice(),
                i.hand_height,
                i.distance
            );
        }
    }
    fn verdict(
        &mut self,
        _stamp: f64,
        object: nudge_perception::ObjectId,
        _verdict: &nudge_executive::Verdict,
        e: &nudge_executive::PushEvidence,
    ) {
        println!("    {object} icp {:?}", e.icp);
        let t0 = e
            .force_trace
            .iter()
            .find(|(_, f)| *f > 3.0)
            .map_or(0.0, |(t, _)| *t);
        let tp = e
            .force_trace
            .iter()
            .fold((0.0, 0.0), |a, &(t, f)| if f > a.1 { (t, f) } else { a })
            .0;
        println!(
            "    contact at {t0:.3}, peak at {tp:.3}, end {:.3}",
            e.force_trace.last().map_or(0.0, |x| x.0)
        );
        let samples: Vec<String> = e
            .force_trace
            .iter()
            .filter(|(t, _)| *t >= tp - 0.3)
            .step_by(20)
            .take(40)
            .map(|(t, f)| format!("{:.2}:{:.1}", t - t0, f))
            .collect();
        println!("    trace {}", samples.join(" "));
    }
    fn frames(&mut self, _stamp: f64, frames: &nudge_executive::record::RobotFrames) {
        self.0 = frames.base;
    }
    fn path(&mut self, stamp: f64, waypoints: &[nalgebra::Point2<f64>]) {
        let w: Vec<String> = waypoints
            .iter()
            .map(|p| format!("({:.2},{:.2})", p.x, p.y))
            .collect();
        println!("{stamp:8.2} s  path {}", w.join(" "));
    }
    fn note(&mut self, stamp: f64, _level: LogLevel, text: &str) {
        println!("{stamp:8.2} s  note: {text}");
    }
    fn prisms(&mut self, stamp: f64, prisms: &[nudge_perception::Prism]) {
        for p in prisms {
            if p.z_max > 0.6 && p.z_max < 0.8 {
                let v: Vec<String> = p
                    .footprint
                    .iter()
                    .map(|q| format!("({:.3},{:.3})", q.x, q.y))
                    .collect();
                println!("    table hull {}", v.join(" "));
            }
            let (lo, hi) = p.footprint.iter().fold(
                ((f64::MAX, f64::MAX), (f64::MIN, f64::MIN)),
                |(lo, hi), q| {
                    (
                        (lo.0.min(q.x), lo.1.min(q.y)),
                        (hi.0.max(q.x), hi.1.max(q.y)),
                    )
                },
            );
            println!(
                "{stamp:8.2} s  prism {} x {:.2}..{:.2} y {:.2}..{:.2} z {:.2}..{:.2}",
                p.id, lo.0, hi.0, lo.1, hi.1, p.z_min, p.z_max
            );
        }
    }
}

#[test]
#[ignore]
fn probe_kakiuchi_room() {
    // Invariant: none — prints the run for inspection.
    let scenario = nudge_tests::scenario("kakiuchi-room").expect("scenario");
    let t = std::time::Instant::now();
    let (report, _robot) = nudge_tests::run(
        &scenario,
        1,
        CandidatePolicy::Nearest,
        Printer(nalgebra::Isometry2::identity()),
    )
    .expect("run");
    println!("outcome {:?}", report.outcome.name());
    println!(
        "{}",
        match &report.outcome {
            State::Aborted(r, e) => format!("{r}\n{e}"),
            State::NoPathToGoal(e) => format!("{e}"),
            _ => String::new(),
        }
    );
    println!("knowledge {:#?}", report.knowledge.explanation.tests);
    println!(
        "robot time {:.1} s, wall {:.2} s",
        report.robot_time,
        t.elapsed().as_secs_f64()
    );
}
