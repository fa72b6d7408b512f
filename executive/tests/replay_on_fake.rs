//! Replay on the fake robot, no rapier: a run taped through `Taped`, driven again from the tape alone
//! by `ReplayRobot`, matches call for call; with one setting changed it parts where that setting is
//! first used.

mod fake_world;

use fake_world::{SLIDING, config, door_room, robot_in};
use nudge_executive::record::tape::{Entry, Replay, Reply, Request, Tape, Taped, decode_batch};
use nudge_executive::robot::ObjectResponse;
use nudge_executive::{RunConfig, RunReport, Runner};

/// Runs the door room (a box that slides) taped; the report and the tape's entries.
fn recorded() -> (RunReport, Vec<Entry>) {
    let tape = Tape::new();
    let robot = Taped::new(
        robot_in(door_room(ObjectResponse::Sliding { force: SLIDING })),
        tape.clone(),
    );
    let mut runner = Runner::new(robot, tape.clone(), config());
    let report = runner.run();
    let (_, bytes) = tape.take().expect("the run put entries on the tape");
    let entries = decode_batch(&bytes).expect("the tape decodes");
    assert_eq!(entries.len() as u64, tape.entries());
    (report, entries)
}

fn replay(entries: Vec<Entry>, config: RunConfig) -> (RunReport, Replay) {
    let replay = Replay::new(entries);
    let mut runner = Runner::new(replay.robot(), replay.observer(), config);
    let report = runner.run();
    (report, replay)
}

#[test]
fn a_fake_run_replayed_on_the_same_build_matches_every_call_and_transition() {
    // Invariant: replaying a taped run with the same configuration consumes the whole tape with no divergence, takes the same transitions and ends in the same outcome at the same robot time.
    let (recorded, entries) = recorded();
    let len = entries.len();
    let transitions = entries
        .iter()
        .filter(|e| matches!(e, Entry::Transition(_)))
        .count();
    let (report, replay) = replay(entries, config());
    assert_eq!(replay.finish(report.outcome.name()), None);
    assert_eq!(replay.calls() + replay.transitions(), len);
    assert_eq!(replay.transitions(), transitions);
    assert_eq!(report.timeline.len(), recorded.timeline.len());
    assert_eq!(report.outcome, recorded.outcome);
    assert_eq!(report.robot_time.to_bits(), recorded.robot_time.to_bits());
    assert_eq!(
        report.knowledge.explanation.verdicts,
        recorded.knowledge.explanation.verdicts
    );
}

#[test]
fn a_changed_force_limit_parts_at_the_first_guarded_move_that_carries_it() {
    // Invariant: with the push test's force limit raised, the replay parts at the recording's first guarded move carrying the old limit, at the robot time of the clock reading before it, in PushTest, and no later call is consumed.
    let (_, entries) = recorded();
    let limit = config().model.force.test_limit;
    let index = entries
        .iter()
        .position(
            |e| matches!(e, Entry::Call(Request::StartGuardedMove(m), _) if m.force_limit == limit),
        )
        .expect("the run pushed with the test's limit");
    let clock = entries[..index]
        .iter()
        .rev()
        .find_map(|e| match e {
            Entry::Call(Request::Now, Reply::Time(t)) => Some(*t),
            _ => None,
        })
        .expect("a clock reading before the push");
    let mut changed = config();
    changed.model.force.test_limit = limit + 5.0;
    let (_, replay) = replay(entries, changed);
    let d = replay.finish("ended").expect("a divergence");
    assert_eq!(d.index, index, "{d}");
    assert_eq!(d.robot_time.to_bits(), clock.to_bits(), "{d}");
    assert_eq!(d.state.as_deref(), Some("PushTest"), "{d}");
    assert!(d.recorded.contains("force_limit 20,"), "{d}");
    assert!(d.new.contains("force_limit 25,"), "{d}");
    assert_eq!(replay.calls() + replay.transitions(), index);
}
