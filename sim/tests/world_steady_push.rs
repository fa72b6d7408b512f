//! Steady pushes far below their guard's limit are stepped coarsely; pushes near it, and jams, are not.
mod world_common;

use nalgebra::Point3;
use nudge_executive::robot::{ActionStatus, Arm, Clock, GuardedMove, HandOutcome, WristSensor};
use nudge_sim::adapter::SimRobot;
use nudge_sim::world::COARSE_STEP_US;
use world_common::*;

/// The executive's tick (s): it advances the world in these.
const TICK: f64 = 0.05;
/// The executive's push speed (m/s).
const PUSH_SPEED: f64 = 0.02;

/// What one push did.
struct Push {
    /// Every wrist sample: time and tared force norm.
    forces: Vec<(f64, f64)>,
    outcome: HandOutcome,
    /// Physics steps longer than a fine step taken after the first sample of 2 N or more.
    coarse_after_contact: u64,
}

/// Settles, tares and runs `motion` to its end in the executive's ticks.
fn push(robot: &mut SimRobot, motion: GuardedMove) -> Push {
    robot.advance(0.5).expect("settle");
    robot.tare().expect("tare");
    robot.drain_wrenches().expect("drain");
    robot.start_guarded_move(motion).expect("move accepted");
    let mut forces = Vec::new();
    let mut coarse_after_contact = 0;
    for _ in 0..(30.0 / TICK) as usize {
        let coarse_before = coarse_steps(robot);
        let touched = forces.iter().any(|(_, f)| *f >= 2.0);
        robot.advance(TICK).expect("advance");
        if touched {
            coarse_after_contact += coarse_steps(robot) - coarse_before;
        }
        for w in robot.drain_wrenches().expect("drain") {
            forces.push((w.stamp, w.value.force_norm()));
        }
        if let ActionStatus::Done(outcome) = robot.hand_status().expect("status") {
            return Push {
                forces,
                outcome,
                coarse_after_contact,
            };
        }
    }
    panic!("push did not end in 30 s");
}

fn coarse_steps(robot: &SimRobot) -> u64 {
    robot.world().steps() - robot.world().fine_steps()
}

fn line(limit: f64) -> GuardedMove {
    GuardedMove {
        from: Point3::new(0.4, 0.0, 0.43),
        to: Point3::new(0.75, 0.0, 0.43),
        speed: PUSH_SPEED,
        force_limit: limit,
        acceleration: None,
    }
}

#[test]
fn a_clearing_push_steps_coarsely_and_still_reads_mu_m_g() {
    // A chair pushed at 2 cm/s against a 30 N guard is stepped mostly in 10 ms steps once it slides, and every quarter second of its sliding still reads within 1 N of μ m g, never near the limit.
    let mut robot = SimRobot::new(&robot_and(TEST_CHAIR), 3).expect("world");
    let start = robot.world().object_pose(0).expect("chair");
    let p = push(&mut robot, line(30.0));
    assert_eq!(p.outcome, HandOutcome::Reached);
    let contact = p.forces.iter().find(|(_, f)| *f >= 2.0).expect("contact").0;
    let stop = p.forces.last().expect("samples").0;
    // The chair slides for ~8 s of the line: most of it in coarse steps.
    let sliding_s = stop - contact;
    let coarse_s = p.coarse_after_contact as f64 * COARSE_STEP_US as f64 * 1e-6;
    assert!(
        coarse_s > 0.5 * sliding_s,
        "{coarse_s:.2} s of {sliding_s:.2} s in coarse steps"
    );
    assert_slides_at(&p.forces, contact, stop, TEST_CHAIR_MU_M_G);
    let peak = p.forces.iter().map(|(_, f)| *f).fold(0.0, f64::max);
    println!(
        "clearing push: {coarse_s:.2} s of {sliding_s:.2} s coarse, peak {peak:.2} N, μmg {TEST_CHAIR_MU_M_G:.2} N"
    );
    assert!(peak < 22.0, "peak {peak:.2} N");
    let moved = robot.world().object_pose(0).expect("chair").translation.x - start.translation.x;
    assert!(moved > 0.15, "chair moved {moved:.3} m");
}

#[test]
fn a_push_tests_guard_keeps_every_contact_step_fine() {
    // A chair pushed against a 20 N guard (sliding at ~15.7 N, closer to the limit than the coarse margin) is stepped at 1 ms from first contact to the end of the line: a push test's trace is the sensor's full 1 kHz.
    let mut robot = SimRobot::new(&robot_and(TEST_CHAIR), 3).expect("world");
    let p = push(&mut robot, line(20.0));
    assert!(p.forces.iter().any(|(_, f)| *f >= 2.0), "the hand touched");
    assert_eq!(p.coarse_after_contact, 0);
}

#[test]
fn a_jam_during_a_coarse_push_stops_at_the_limit() {
    // A chair slid at 2 cm/s into a bolted box (jam after 0.1 m) under a 30 N guard is stepped coarsely while it slides, and the guard still stops the hand at the limit, the force never more than 10 % past it.
    // The chair, and a bolted box 0.1 m behind it.
    let s = robot_and(&format!(
        "{TEST_CHAIR}\n[[object]]\nname = \"block\"\nkind = \"box\"\nposition = [2.25, 1.8]\nsize = [0.2, 1.0, 0.6]\nmass = 50.0\nfriction = 0.6\nfixed = true\ncolour = [90, 90, 90]"
    ));
    let mut robot = SimRobot::new(&s, 5).expect("world");
    let p = push(&mut robot, line(30.0));
    let HandOutcome::ForceLimit { wrench, .. } = p.outcome else {
        panic!("expected the jam to stop the hand, got {:?}", p.outcome)
    };
    assert!(wrench.value.force_norm() >= 30.0);
    assert!(
        p.coarse_after_contact > 50,
        "only {} coarse steps while sliding",
        p.coarse_after_contact
    );
    let peak = p.forces.iter().map(|(_, f)| *f).fold(0.0, f64::max);
    let held_peak = peak_while_holding(&mut robot, peak);
    println!(
        "jam: {} coarse steps while sliding, stopped at {:.2} N, peak {held_peak:.2} N",
        p.coarse_after_contact,
        wrench.value.force_norm()
    );
    assert!(held_peak <= 33.0, "peak {held_peak:.2} N");
}
