//! Single-room families: open clutter, rooms beyond the camera's range, corridors, overhangs.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::{bare, cm};
use crate::generate::Guarantee;
use crate::generate::furniture::{FloorPlan, PARTITION, heavy, light, partition};
use crate::scenario::{ObjectKind, ObjectSpec, Scenario, Texture};

/// Clear disc kept around the start and the goal (m): the robot's radius and room to turn and look.
const CLEAR_AROUND: f64 = 0.9;

/// A room of `size` with the start near the west wall and the goal near the east wall.
fn west_to_east(rng: &mut ChaCha8Rng, size: [f64; 2]) -> (Scenario, FloorPlan) {
    let [w, h] = size;
    let start = [1.0, cm(rng.random_range(1.0..h - 1.0)), 0.0];
    let goal = [cm(w - 1.0), cm(rng.random_range(1.0..h - 1.0))];
    let mut plan = FloorPlan::default();
    plan.keep_clear([start[0], start[1]], CLEAR_AROUND);
    plan.keep_clear(goal, CLEAR_AROUND);
    (bare(size, start, goal), plan)
}

/// Puts `count` pieces, each light with probability `light_share`, anywhere in the room.
fn clutter(
    rng: &mut ChaCha8Rng,
    scenario: &mut Scenario,
    plan: &mut FloorPlan,
    count: usize,
    light_share: f64,
) {
    let [w, h] = scenario.room.size;
    for k in 0..count {
        let name = format!("piece-{k}");
        let mut spec = if rng.random_bool(light_share) {
            light(rng, name)
        } else {
            heavy(rng, name)
        };
        if plan.place(rng, &mut spec, [0.05, w - 0.05], [0.05, h - 0.05]) {
            spec.position = [cm(spec.position[0]), cm(spec.position[1])];
            scenario.objects.push(spec);
        }
    }
}

/// `open-clutter`: a 6–9 × 5–7 m room with 3–8 pieces, half of them light.
pub(super) fn open_clutter(rng: &mut ChaCha8Rng) -> (Scenario, Guarantee) {
    let size = [
        cm(rng.random_range(6.0..9.0)),
        cm(rng.random_range(5.0..7.0)),
    ];
    let (mut s, mut plan) = west_to_east(rng, size);
    let count = rng.random_range(3..=8);
    clutter(rng, &mut s, &mut plan, count, 0.5);
    (s, Guarantee::WayExists)
}

/// `large-room`: a 12–16 × 6–9 m room, the goal at least 8 m from the start (the camera sees 5 m),
/// 5–10 pieces.
pub(super) fn large_room(rng: &mut ChaCha8Rng) -> (Scenario, Guarantee) {
    let size = [
        cm(rng.random_range(12.0..16.0)),
        cm(rng.random_range(6.0..9.0)),
    ];
    let (mut s, mut plan) = west_to_east(rng, size);
    let count = rng.random_range(5..=10);
    clutter(rng, &mut s, &mut plan, count, 0.5);
    (s, Guarantee::WayExists)
}

/// `corridor`: a corridor 1.5–2 m wide and 6–9 m long (a bolted wall along its north side) that
/// opens into a hall 1.2 m wider, the goal in the hall; 1–3 heavy things against its walls leave at
/// least 0.9 m (the robot's 0.7 m and a margin). Half the time a light box stands across the
/// corridor 1–2.5 m before the hall, leaving less than the robot's width beside it: the robot must
/// push it along into the hall.
pub(super) fn corridor(rng: &mut ChaCha8Rng) -> (Scenario, Guarantee) {
    let h = cm(rng.random_range(1.5..2.0));
    let narrow = cm(rng.random_range(6.0..9.0));
    let w = cm(narrow + rng.random_range(2.5..3.5));
    let hall = cm(h + 1.2);
    let mut s = bare(
        [w, hall],
        [0.8, cm(h / 2.0), 0.0],
        [cm(w - 0.8), cm(hall / 2.0)],
    );
    s.objects.push(partition(
        "corridor-wall".into(),
        [0.0, h + PARTITION / 2.0],
        [narrow, h + PARTITION / 2.0],
    ));
    let blocker_at = cm(narrow - rng.random_range(1.0..2.5));
    let mut x = 1.6;
    for k in 0..rng.random_range(1..=3) {
        x += rng.random_range(0.5..1.5);
        let length = cm(rng.random_range(0.6..1.2));
        if x + length > blocker_at - 0.8 {
            break;
        }
        let depth = cm(rng.random_range(0.25..(h - 0.9).min(0.45)));
        let north = rng.random_bool(0.5);
        let mut spec = heavy(rng, format!("along-{k}"));
        spec.kind = ObjectKind::Box;
        spec.fixed = true;
        spec.size = vec![length, depth, 1.0];
        spec.yaw = 0.0;
        spec.position = [
            cm(x + length / 2.0),
            cm(if north {
                h - depth / 2.0 - 0.02
            } else {
                depth / 2.0 + 0.02
            }),
        ];
        s.objects.push(spec);
        x += length;
    }
    if rng.random_bool(0.5) {
        let mut spec = light(rng, "blocker".into());
        spec.kind = ObjectKind::Box;
        spec.size = vec![0.5, cm(h - 0.6), 0.7];
        spec.yaw = 0.0;
        spec.position = [blocker_at, cm(h / 2.0)];
        s.objects.push(spec);
        return (s, Guarantee::WayNeeds("blocker".into()));
    }
    (s, Guarantee::WayExists)
}

/// `overhang`: a shelf across the whole room at 1.6–1.9 m, above the robot's 1.54 m, that it walks
/// under; a bolted bench under part of it that it must walk round; a few pieces either side.
pub(super) fn overhang(rng: &mut ChaCha8Rng) -> (Scenario, Guarantee) {
    let size = [
        cm(rng.random_range(6.0..9.0)),
        cm(rng.random_range(4.0..6.0)),
    ];
    let (mut s, mut plan) = west_to_east(rng, size);
    let [w, h] = size;
    let x = cm(w / 2.0 + rng.random_range(-0.8..0.8));
    s.objects.push(ObjectSpec {
        name: "shelf".into(),
        kind: ObjectKind::Box,
        position: [x, cm(h / 2.0)],
        yaw: 0.0,
        size: vec![0.35, h - 0.02, 0.25],
        elevation: cm(rng.random_range(1.6..1.9)),
        mass: 30.0,
        friction: 0.6,
        fixed: true,
        colour: [120, 90, 60],
        texture: Texture::Stripes,
    });
    let bench = cm(rng.random_range(1.0..(h / 2.0)));
    let north = rng.random_bool(0.5);
    s.objects.push(ObjectSpec {
        name: "bench".into(),
        kind: ObjectKind::Box,
        position: [
            x,
            cm(if north {
                h - bench / 2.0 - 0.02
            } else {
                bench / 2.0 + 0.02
            }),
        ],
        yaw: 0.0,
        size: vec![0.45, bench, 0.45],
        elevation: 0.0,
        mass: 40.0,
        friction: 0.6,
        fixed: true,
        colour: [70, 70, 160],
        texture: Texture::Checker,
    });
    // Pieces stand 0.8 m or more either side of the shelf, so the only question there is the
    // overhang.
    for k in 0..rng.random_range(1..=3) {
        let mut spec = if rng.random_bool(0.5) {
            light(rng, format!("piece-{k}"))
        } else {
            heavy(rng, format!("piece-{k}"))
        };
        let side = if rng.random_bool(0.5) {
            [0.05, x - 0.8]
        } else {
            [x + 0.8, w - 0.05]
        };
        if plan.place(rng, &mut spec, side, [0.05, h - 0.05]) {
            spec.position = [cm(spec.position[0]), cm(spec.position[1])];
            s.objects.push(spec);
        }
    }
    (s, Guarantee::WayExists)
}
