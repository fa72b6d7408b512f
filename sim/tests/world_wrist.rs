//! The wrist sensor against known loads.
mod world_common;

use nudge_sim::humanoid::HAND_MASS;
use world_common::*;

#[test]
fn hanging_hand_reads_its_weight() {
    // The joint impulse → force convention (impulse × substeps / dt) gives the hanging hand's weight,
    // pointing down, on the wrist: the true reading at rest is (0, 0, −m g) within 1 %.
    let s = robot_and(
        "name = \"far\"\nkind = \"box\"\nposition = [5.0, 3.0]\nsize = [0.2, 0.2, 0.2]\nmass = 1.0\ncolour = [1, 2, 3]",
    );
    let mut w = world(&s);
    for dt in [0.001, 0.01] {
        w.advance(1.0).expect("advance");
        // Hold the step length fixed at `dt` by advancing exactly one step.
        w.advance(dt).expect("advance");
        let f = w.wrist_truth().force;
        let weight = HAND_MASS * 9.81;
        assert!(
            (f.z + weight).abs() < 0.01 * weight,
            "dt {dt}: force {f:?}, weight {weight}"
        );
        assert!(
            f.x.abs() < 0.01 * weight && f.y.abs() < 0.01 * weight,
            "dt {dt}: force {f:?}"
        );
    }
}
