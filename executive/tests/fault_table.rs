//! Fault × state: every fault decorator, injected while the executive is in each state it passes
//! through on its way to the goal, on the fake robot in the door room with a sliding box that must be
//! push-tested and cleared. Each run is bounded in robot time and in adapter calls, so a hang is a
//! failure and not a stuck test; the table is written to `target/fault_table.md` and printed.
//!
//! Regenerate: `cargo test --release -p nudge-executive --test fault_table -- --nocapture`.

mod fake_world;

use std::cell::OnceCell;
use std::fmt::Write as _;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use fake_world::{GOAL, SLIDING, config, door_room, robot_in};
use nalgebra::{Point2, Vector3};
use nudge_executive::record::Observer;
use nudge_executive::robot::faults::{
    ActionHang, ArmStall, Bounded, CallError, CameraDropout, ClockJump, EmptyCloud, ErrorKind,
    Fault, FaultWindow, NanCloud, NanWrench, ScrambledCloud, ShortWalk, StateProbe, StuckWrench,
    Trigger, WrenchSpike,
};
use nudge_executive::robot::{Base, FakeRobot, ObjectResponse};
use nudge_executive::{AbortReason, Edge, RunReport, Runner, State};

/// The camera's resolution in these runs: an eighth of the SR-4000's pixels. The unfaulted run passes
/// through the same states, with the same verdict on the box, as at full resolution (it stops to look
/// a little less often), at a fifth of the cost, and the table runs some 150 of them.
const CAMERA: (usize, usize) = (64, 52);

/// A run may take this many times the unfaulted run's robot time and adapter calls before it counts
/// as hung: a fault may cost the run a few more looks and walks, never an unbounded wait.
const BOUND_FACTOR: f64 = 3.0;

/// How far past the force limit the contact force may go (the adapter's guard acts per control
/// period, so it overshoots by one step of the force).
const FORCE_MARGIN: f64 = 1.1;

/// An arrival counts within the goal tolerance and this much more (m): the runner's own slack for a
/// walk's error.
const ARRIVAL_SLACK: f64 = 0.05;

/// The robot in the door room, the box sliding at 12 N: push-tested movable, cleared, then the goal.
fn robot() -> FakeRobot {
    let mut scene = door_room(ObjectResponse::Sliding { force: SLIDING });
    (scene.camera.width, scene.camera.height) = CAMERA;
    robot_in(scene)
}

/// How a run ended, as the table shows it, or why it broke the invariant.
#[derive(Clone, Debug, PartialEq)]
enum Cell {
    /// The fault never got its chance in this state: the run was the unfaulted one.
    NotApplicable,
    /// The fault acted; the run ended cleanly, thus.
    Ended(String),
    /// The invariant broke.
    Broken(String),
}

/// Cancels a run once its fault has expired without acting: a decorator changes nothing until it
/// fires, so the rest of the run is the unfaulted one, and need not be run again.
struct StopUnfired {
    window: FaultWindow,
    cancel: Rc<OnceCell<Arc<AtomicBool>>>,
}

impl Observer for StopUnfired {
    fn transition(&mut self, _stamp: f64, _from: Option<&State>, _edge: Edge, _to: &State) {
        if self.window.first().is_none()
            && self.window.expired()
            && let Some(flag) = self.cancel.get()
        {
            flag.store(true, Ordering::Relaxed);
        }
    }
}

/// What one bounded run gave.
struct Run {
    report: RunReport,
    fired: bool,
    robot: FakeRobot,
    exceeded: bool,
    time: f64,
    calls: u64,
}

/// Bounds of a run: robot time (s) and adapter calls.
#[derive(Clone, Copy)]
struct Bounds {
    time: f64,
    calls: u64,
}

/// Runs `robot` (a fault around the fake) to its end inside `bounds`, `probe` watching the states.
fn run<F: Fault<Inner = FakeRobot>>(
    robot: F,
    probe: StateProbe,
    bounds: Bounds,
) -> Result<Run, String> {
    let window = robot.window().clone();
    let cancel = Rc::new(OnceCell::new());
    let stop = StopUnfired {
        window,
        cancel: Rc::clone(&cancel),
    };
    let bounded = Bounded::new(robot, bounds.time, bounds.calls);
    let mut runner = Runner::new(bounded, (probe, stop), config());
    let _ = cancel.set(runner.cancel_flag());
    let report = catch_unwind(AssertUnwindSafe(|| runner.run())).map_err(|e| {
        e.downcast_ref::<String>()
            .cloned()
            .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_else(|| "a panic".into())
    })?;
    let (bounded, _) = runner.into_parts();
    let (exceeded, time, calls) = (bounded.exceeded(), bounded.time(), bounded.calls());
    let fault = bounded.into_inner();
    let fired = fault.window().first().is_some();
    Ok(Run {
        report,
        fired,
        robot: fault.into_inner(),
        exceeded,
        time,
        calls,
    })
}

/// The table's word for a clean end.
fn outcome(state: &State) -> String {
    match state {
        State::Goal => "goal".into(),
        State::NoPathToGoal(_) => "no path to goal".into(),
        State::Aborted(AbortReason::Robot(e), _) => {
            format!("aborted: {}", e.split(':').next().unwrap_or(e))
        }
        State::Aborted(AbortReason::Perception(_), _) => "aborted: perception failed".into(),
        State::Aborted(reason, _) => format!("aborted: {reason}"),
        other => other.name().into(),
    }
}

/// The full reason of an end, for the notes under the table.
fn reason(state: &State) -> String {
    match state {
        State::Aborted(reason, _) => reason.to_string(),
        State::NoPathToGoal(e) => {
            let given_up: Vec<String> = e
                .unpushable
                .iter()
                .map(|(id, why)| format!("{id}: {why}"))
                .collect();
            format!(
                "no path ({}); {} obstacle(s) judged; given up: {}",
                e.no_path.as_deref().unwrap_or("none recorded"),
                e.verdicts.len(),
                if given_up.is_empty() {
                    "none".into()
                } else {
                    given_up.join("; ")
                }
            )
        }
        other => other.name().into(),
    }
}

/// Checks the invariant on a finished run: no hang, a terminal state that explains itself (a goal
/// the robot truly stands in), the arm retracted, the contact force within the margin.
fn judge(run: &Run, limit: f64) -> Result<String, String> {
    if run.exceeded {
        return Err(format!(
            "hang: passed the bound ({:.0} s, {} calls)",
            run.time, run.calls
        ));
    }
    let state = &run.report.outcome;
    match state {
        State::Goal => {
            let at = run.robot.clone().base_pose().map_err(|e| e.to_string())?;
            let off = (at.value.translation.vector - Point2::new(GOAL.0, GOAL.1).coords).norm();
            if off > config().goal_tolerance + ARRIVAL_SLACK {
                return Err(format!("goal claimed {off:.2} m from the goal"));
            }
        }
        State::NoPathToGoal(_) => {}
        State::Aborted(AbortReason::Internal(e), _) => return Err(format!("internal: {e}")),
        State::Aborted(reason, _) if reason.to_string().trim().is_empty() => {
            return Err("aborted without a reason".into());
        }
        State::Aborted(..) => {}
        other => return Err(format!("stopped in {}, not a terminal state", other.name())),
    }
    if !run.robot.hand_at_rest() {
        return Err(format!("{}: the arm is not retracted", outcome(state)));
    }
    for p in run.robot.force_peaks() {
        let allowed = FORCE_MARGIN * p.force_limit.max(limit);
        if p.peak > allowed {
            return Err(format!(
                "{}: contact force {:.1} N over {allowed:.1} N",
                outcome(state),
                p.peak
            ));
        }
    }
    Ok(outcome(state))
}

/// Wraps the fake robot in a fault acting when the trigger holds, and runs it, watched by the probe,
/// inside the bounds.
type Row = fn(FakeRobot, Trigger, StateProbe, Bounds) -> Result<Run, String>;

/// The faults, one row each: its name and how to wrap the robot in it.
fn rows() -> Vec<(&'static str, Row)> {
    vec![
        ("camera dropout", |r, t, p, b| {
            run(CameraDropout::new(r, FaultWindow::every(t)), p, b)
        }),
        ("empty cloud", |r, t, p, b| {
            run(EmptyCloud::new(r, FaultWindow::every(t)), p, b)
        }),
        ("NaN cloud (every 2nd point)", |r, t, p, b| {
            run(NanCloud::new(r, FaultWindow::every(t), 2), p, b)
        }),
        ("ICP cannot converge (noise after a push)", |r, t, p, b| {
            run(ScrambledCloud::new(r, FaultWindow::every(t), 7), p, b)
        }),
        ("wrench spike (500 N, one sample)", |r, t, p, b| {
            let spike = Vector3::new(-500.0, 0.0, 0.0);
            run(WrenchSpike::new(r, FaultWindow::once(t), spike), p, b)
        }),
        ("NaN wrench", |r, t, p, b| {
            run(NanWrench::new(r, FaultWindow::every(t)), p, b)
        }),
        ("stuck wrench", |r, t, p, b| {
            run(StuckWrench::new(r, FaultWindow::once(t)), p, b)
        }),
        ("walk stops short (after 0.5 s)", |r, t, p, b| {
            run(ShortWalk::new(r, FaultWindow::once(t), 0.5), p, b)
        }),
        ("arm stalls (after 3 s of a motion)", |r, t, p, b| {
            run(ArmStall::new(r, FaultWindow::once(t), 3.0), p, b)
        }),
        ("action never completes", |r, t, p, b| {
            run(ActionHang::new(r, FaultWindow::once(t)), p, b)
        }),
        ("call errors", |r, t, p, b| {
            run(
                CallError::new(r, FaultWindow::once(t), ErrorKind::Fault),
                p,
                b,
            )
        }),
        ("call errors (the 400th in the state)", |r, t, p, b| {
            let window = FaultWindow::once(t).skip(399);
            run(CallError::new(r, window, ErrorKind::Fault), p, b)
        }),
        ("call times out", |r, t, p, b| {
            let kind = ErrorKind::Timeout { seconds: 2.0 };
            run(CallError::new(r, FaultWindow::once(t), kind), p, b)
        }),
        ("clock jumps +1 h", |r, t, p, b| {
            run(ClockJump::new(r, FaultWindow::once(t), 3600.0), p, b)
        }),
        ("clock jumps −1 h", |r, t, p, b| {
            run(ClockJump::new(r, FaultWindow::once(t), -3600.0), p, b)
        }),
    ]
}

/// The states the unfaulted run passes through, in the order it first enters them.
fn states(report: &RunReport) -> Vec<&'static str> {
    let mut seen = Vec::new();
    for entry in &report.timeline {
        let terminal = matches!(entry.to, "Goal" | "NoPathToGoal" | "Aborted");
        if !terminal && !seen.contains(&entry.to) {
            seen.push(entry.to);
        }
    }
    seen
}

#[test]
fn every_fault_in_every_state_ends_explained_with_the_arm_retracted_and_the_force_bounded() {
    // Invariant: for every fault decorator acting on the first visit of every state the unfaulted run passes through, the run neither panics nor hangs (bounded robot time and calls) and ends in Goal (the robot truly there), NoPathToGoal, or Aborted with a reason other than an internal error, with the arm retracted and no guarded move's contact force past 1.1 × its limit (the run's push-test limit, or the move's own where higher); a fault that never got its chance leaves the run as the unfaulted one (up to where it is cut short).
    let limit = config().model.force.test_limit;
    let generous = Bounds {
        time: config().executive.max_robot_time,
        calls: u64::MAX,
    };
    let never = |p: &StateProbe| Trigger::InState {
        probe: p.clone(),
        state: "never",
        visit: 1,
    };
    // The unfaulted run, through the same harness: a decorator whose state never comes.
    let probe = StateProbe::new();
    let baseline = CameraDropout::new(robot(), FaultWindow::every(never(&probe)));
    let baseline = run(baseline, probe, generous).expect("the unfaulted run does not panic");
    assert_eq!(
        judge(&baseline, limit).as_deref(),
        Ok("goal"),
        "the unfaulted run reaches the goal"
    );
    let bounds = Bounds {
        time: BOUND_FACTOR * baseline.time,
        calls: (BOUND_FACTOR * baseline.calls as f64) as u64,
    };
    let columns = states(&baseline.report);
    let rows = rows();
    let cells: Vec<(usize, usize)> = (0..rows.len())
        .flat_map(|r| (0..columns.len()).map(move |c| (r, c)))
        .collect();
    let results: Mutex<Vec<Option<(Cell, String)>>> = Mutex::new(vec![None; cells.len()]);
    let next = AtomicUsize::new(0);
    let workers = std::thread::available_parallelism().map_or(1, |n| n.get().min(4));
    std::thread::scope(|scope| {
        for _ in 0..workers {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&(r, c)) = cells.get(i) else { break };
                    let probe = StateProbe::new();
                    let trigger = Trigger::InState {
                        probe: probe.clone(),
                        state: columns[c],
                        visit: 1,
                    };
                    let result = match rows[r].1(robot(), trigger, probe, bounds) {
                        Err(panic) => (Cell::Broken(format!("panic: {panic}")), panic),
                        Ok(run) if !run.fired => {
                            // Cancelled once the fault expired; up to there, the unfaulted run.
                            let timeline = &run.report.timeline;
                            let before = timeline
                                .iter()
                                .position(|t| t.edge == Edge::Cancel)
                                .unwrap_or(timeline.len());
                            let same =
                                timeline.get(..before) == baseline.report.timeline.get(..before);
                            let cell = if same {
                                Cell::NotApplicable
                            } else {
                                Cell::Broken("never fired, yet the run changed".into())
                            };
                            (cell, String::new())
                        }
                        Ok(run) => {
                            let detail = format!(
                                "{} ({:.0} s of robot time)",
                                reason(&run.report.outcome),
                                run.time
                            );
                            match judge(&run, limit) {
                                Ok(word) => (Cell::Ended(word), detail),
                                Err(why) => (Cell::Broken(why), detail),
                            }
                        }
                    };
                    results.lock().expect("no worker panics")[i] = Some(result);
                }
            });
        }
    });
    let results = results.into_inner().expect("no worker panics");

    let mut table = String::new();
    let _ = writeln!(table, "| fault \\ state | {} |", columns.join(" | "));
    let _ = writeln!(table, "|---|{}", "---|".repeat(columns.len()));
    let mut notes = String::new();
    let mut broken = Vec::new();
    for (r, (name, _)) in rows.iter().enumerate() {
        let mut line = format!("| {name} |");
        for (c, column) in columns.iter().enumerate() {
            let i = r * columns.len() + c;
            let Some((cell, detail)) = &results[i] else {
                broken.push(format!("{name} × {column}: not run"));
                continue;
            };
            let word = match cell {
                Cell::NotApplicable => "n/a".to_string(),
                Cell::Ended(word) => word.clone(),
                Cell::Broken(why) => {
                    broken.push(format!("{name} × {column}: {why} ({detail})"));
                    format!("**FAILED: {why}**")
                }
            };
            if matches!(cell, Cell::Ended(w) if w != "goal") {
                let _ = writeln!(notes, "- {name} × {column}: {detail}");
            }
            let _ = write!(line, " {word} |");
        }
        let _ = writeln!(table, "{line}");
    }
    let text = format!(
        "{table}\nEach fault acts only while the executive is in the column's state on its first \
         visit; n/a: it never got its chance there. Unfaulted run: goal after {:.0} s of robot time; \
         a run was allowed {:.0} s and {} adapter calls.\n\nWhy the runs that did not reach the \
         goal ended:\n\n{notes}",
        baseline.time, bounds.time, bounds.calls
    );
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .map(|target| target.join("fault_table.md"));
    if let Some(path) = &path {
        std::fs::write(path, &text).expect("the table is written");
    }
    println!("{text}");
    assert!(broken.is_empty(), "broken cells:\n{}", broken.join("\n"));
}
