//! Scoring verdicts against ground truth at the moment they were reached.
mod world_common;

use std::collections::BTreeMap;

use nalgebra::Point3;
use nudge_executive::robot::{ActionStatus, Arm, Clock, GuardedMove};
use nudge_executive::runner::Decision;
use nudge_executive::{Knowledge, RunReport, State, Verdict};
use nudge_perception::{ObjectId, Prism};
use nudge_sim::adapter::SimRobot;
use nudge_sim::score::score;
use world_common::*;

/// A report whose one verdict is `obstacle` found static, reached at `decided` when given.
fn report(obstacle: Prism, decided: Option<f64>) -> RunReport {
    let mut knowledge = Knowledge::default();
    let id = obstacle.id;
    knowledge.explanation.verdicts.insert(
        id,
        Verdict::Static {
            after_ambiguity: false,
        },
    );
    let decisions: BTreeMap<ObjectId, Decision> = decided
        .map(|stamp| {
            (
                id,
                Decision {
                    stamp,
                    prism: obstacle.clone(),
                },
            )
        })
        .into_iter()
        .collect();
    RunReport {
        outcome: State::Goal,
        knowledge,
        robot_time: 10.0,
        timeline: Vec::new(),
        obstacles: vec![obstacle],
        grid: None,
        joined: BTreeMap::new(),
        sequences: Vec::new(),
        decisions,
    }
}

#[test]
fn a_verdict_is_scored_against_where_things_stood_when_it_was_reached() {
    // Invariant: an obstacle found static over a bolted crate is scored against the crate, even
    // when a chair pushed afterwards ends up covering more of that obstacle than the crate does;
    // without the record of when the verdict was reached, the end of the run decides (the chair).
    let s = robot_and(&format!(
        "{TEST_CHAIR}\n\n[[object]]\nname = \"crate\"\nkind = \"box\"\nposition = [2.6, 1.8]\nsize = [0.3, 1.0, 1.0]\nmass = 50.0\nfriction = 0.8\nfixed = true\ncolour = [200, 190, 180]"
    ));
    let mut robot = SimRobot::new(&s, 3).expect("world");
    robot.advance(0.5).expect("settle");
    let decided = robot.now();
    // The obstacle lies between the chair (x up to 2.05) and the crate (from 2.45), over 5 cm of
    // the crate's face.
    let obstacle = rectangle(7, 2.1, 2.5, 1.55, 2.05);
    // Push the chair 0.35 m further along x, into the obstacle's floor.
    let start = robot.world().object_pose(0).expect("chair").translation.x;
    robot
        .start_guarded_move(GuardedMove {
            from: Point3::new(0.4, 0.0, 0.43),
            to: Point3::new(0.75, 0.0, 0.43),
            speed: 0.05,
            force_limit: 40.0,
            acceleration: None,
        })
        .expect("move accepted");
    for _ in 0..20_000 {
        robot.advance(0.001).expect("advance");
        if matches!(robot.hand_status().expect("status"), ActionStatus::Done(_)) {
            break;
        }
    }
    let end = robot.world().object_pose(0).expect("chair").translation.x;
    assert!(end - start > 0.15, "the chair moved {} m", end - start);
    assert!(
        (robot
            .world()
            .object_pose_at(0, decided)
            .expect("logged")
            .translation
            .x
            - start)
            .abs()
            < 0.011,
        "the log holds where the chair stood when the verdict was reached"
    );

    let then = score(&report(obstacle.clone(), Some(decided)), &robot);
    assert_eq!(then[0].object.as_deref(), Some("crate"));
    assert!(then[0].correct, "static is right about the crate");

    let at_end = score(&report(obstacle, None), &robot);
    assert_eq!(at_end[0].object.as_deref(), Some("chair"));
    assert!(!at_end[0].correct);
}
