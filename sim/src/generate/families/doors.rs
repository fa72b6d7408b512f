//! Families of rooms joined by doors: flats, and a door with a box in it.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::{bare, cm};
use crate::generate::Guarantee;
use crate::generate::furniture::{FloorPlan, heavy, light, partition, with_slide};
use crate::scenario::{ObjectKind, Scenario};
use crate::truth::MOVABLE_MARGIN;

/// Clear disc kept in front of and behind a doorway (m): the robot lines up to pass it.
const DOORWAY_CLEAR: f64 = 0.9;

/// A partition across the room at `x` from y = 0 to `h` with a door from `y0` to `y1`.
fn wall_with_door(s: &mut Scenario, k: usize, x: f64, h: f64, [y0, y1]: [f64; 2]) {
    if y0 > 0.05 {
        s.objects
            .push(partition(format!("wall-{k}-south"), [x, 0.0], [x, y0]));
    }
    if y1 < h - 0.05 {
        s.objects
            .push(partition(format!("wall-{k}-north"), [x, y1], [x, h]));
    }
}

/// `flat`: 2–4 rooms in a row, each 3.5–5 m deep, joined by doors 1.0–1.4 m wide at random places,
/// 1–3 pieces per room (none in a doorway); the start in the first room, the goal in the last.
pub(super) fn flat(rng: &mut ChaCha8Rng) -> (Scenario, Guarantee) {
    let rooms = rng.random_range(2..=4);
    let depths: Vec<f64> = (0..rooms).map(|_| cm(rng.random_range(3.5..5.0))).collect();
    let w = cm(depths.iter().sum());
    let h = cm(rng.random_range(5.0..7.0));
    let start = [1.0, cm(rng.random_range(1.0..h - 1.0)), 0.0];
    let goal = [cm(w - 1.0), cm(rng.random_range(1.0..h - 1.0))];
    let mut s = bare([w, h], start, goal);
    let mut plan = FloorPlan::default();
    plan.keep_clear([start[0], start[1]], DOORWAY_CLEAR);
    plan.keep_clear(goal, DOORWAY_CLEAR);
    let mut x = 0.0;
    let mut bounds = Vec::new();
    for (k, depth) in depths.iter().enumerate() {
        let west = x;
        x = cm(x + depth);
        bounds.push([west, x]);
        if k + 1 == rooms {
            break;
        }
        let width = rng.random_range(1.0..1.4);
        let y0 = cm(rng.random_range(0.3..h - width - 0.3));
        let y1 = cm(y0 + width);
        wall_with_door(&mut s, k, x, h, [y0, y1]);
        let mid = (y0 + y1) / 2.0;
        plan.keep_clear([x - 0.6, mid], DOORWAY_CLEAR);
        plan.keep_clear([x + 0.6, mid], DOORWAY_CLEAR);
    }
    let mut n = 0;
    for [west, east] in bounds {
        for _ in 0..rng.random_range(1..=3) {
            let name = format!("piece-{n}");
            n += 1;
            let mut spec = if rng.random_bool(0.5) {
                light(rng, name)
            } else {
                heavy(rng, name)
            };
            if plan.place(rng, &mut spec, [west + 0.1, east - 0.1], [0.05, h - 0.05]) {
                spec.position = [cm(spec.position[0]), cm(spec.position[1])];
                s.objects.push(spec);
            }
        }
    }
    (s, Guarantee::WayExists)
}

/// What stands in the door of [`blocked_door`].
pub(super) enum Blocker {
    /// A light box (μ m g 6–15 N) or a bolted one, by a coin.
    LightOrBolted,
    /// A free box whose μ m g is 10–16 N or 20–30 N: 0.5–0.8 or 1.0–1.5 × the 20 N push limit. The
    /// band 16–20 N is skipped: the truth calls it static (a margin for the force sensor's noise)
    /// though a push could slide it, so neither answer is scored there.
    NearTheLimit,
}

/// `blocked-door` and `force-limit`: two rooms joined by one door 1.0–1.3 m wide with a box in it
/// that leaves less than the robot's width either side; the start in the west room, the goal in the
/// east. A box that slides is a way once moved; a box that does not shuts the goal off.
pub(super) fn blocked_door(rng: &mut ChaCha8Rng, blocker: Blocker) -> (Scenario, Guarantee) {
    let w = cm(rng.random_range(7.0..10.0));
    let h = cm(rng.random_range(4.5..6.5));
    let x = cm(w / 2.0 + rng.random_range(-0.5..0.5));
    let width = rng.random_range(1.0..1.3);
    let y0 = cm(rng.random_range(0.8..h - width - 0.8));
    let y1 = cm(y0 + width);
    let start = [1.0, cm(rng.random_range(1.0..h - 1.0)), 0.0];
    let goal = [cm(w - 1.0), cm(rng.random_range(1.0..h - 1.0))];
    let mut s = bare([w, h], start, goal);
    wall_with_door(&mut s, 0, x, h, [y0, y1]);
    let mut spec = light(rng, "door-box".into());
    spec.kind = ObjectKind::Box;
    // Across the door: 0.25 m left either side, less than the robot's 0.7 m; 0.5 m deep.
    spec.size = vec![0.5, cm(width - 0.5), 0.8];
    spec.yaw = 0.0;
    spec.position = [x, cm((y0 + y1) / 2.0)];
    let slides = match blocker {
        Blocker::LightOrBolted => {
            let slides = rng.random_bool(0.5);
            if !slides {
                spec.fixed = true;
                spec.mass = 60.0;
            }
            slides
        }
        Blocker::NearTheLimit => {
            spec.mass = rng.random_range(6.0..12.0);
            let slides = rng.random_bool(0.5);
            // 0.5–0.8 × the limit slides by the truth's rule; 1.0–1.5 × does not slide at all. The
            // generated rooms carry the default robot, whose limit this is.
            let limit = nudge_robot_model::ForceModel::default().test_limit;
            let force = if slides {
                rng.random_range(0.5 * limit..MOVABLE_MARGIN * limit)
            } else {
                rng.random_range(limit..1.5 * limit)
            };
            spec = with_slide(spec, force);
            spec.friction = (spec.friction * 1000.0).round() / 1000.0;
            slides
        }
    };
    s.objects.push(spec);
    // A piece or two in each room, away from the door and the ends.
    let mut plan = FloorPlan::default();
    plan.keep_clear([start[0], start[1]], DOORWAY_CLEAR);
    plan.keep_clear(goal, DOORWAY_CLEAR);
    plan.keep_clear([x, (y0 + y1) / 2.0], 1.6);
    for (k, side) in [[0.05, x - 0.2], [x + 0.2, w - 0.05]]
        .into_iter()
        .enumerate()
    {
        let mut piece = heavy(rng, format!("piece-{k}"));
        if plan.place(rng, &mut piece, side, [0.05, h - 0.05]) {
            piece.position = [cm(piece.position[0]), cm(piece.position[1])];
            s.objects.push(piece);
        }
    }
    let guarantee = if slides {
        Guarantee::WayNeeds("door-box".into())
    } else {
        Guarantee::ShutBy("door-box".into())
    };
    (s, guarantee)
}
