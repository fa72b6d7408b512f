//! `touching`: things standing as people leave them, in the one opening between two rooms (or
//! across a hall): flush against a wall, two abreast, against a bolted cabinet, turned in a doorway,
//! low in front of a wall. Every room needs its blocker pushed (or proves it bolted), and nothing
//! leaves the generous gaps of the other families.
//!
//! Every width comes from the robot and the planner, not from a room that was run:
//!
//! - an opening the robot must pass once it is cleared is at least `2 (r + c) + s` wide, `r` the
//!   body's radius, `c` the clearance the executive plans with and `s` the cell of the true world's
//!   reachability search (a way it finds is a way for the robot, whatever the raster);
//! - what stays beside a blocker is at most `2 r − s`: the robot cannot squeeze by, and the search
//!   agrees.
//!
//! The pushes each room needs are named ([`NeededPush`]) and checked on the true world
//! (`crate::generate::pushable`): a reachable stand pose for each, a sweep that fits, and a way once
//! they are made.

use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::{bare, cm};
use crate::generate::Guarantee;
use crate::generate::furniture::{FloorPlan, PARTITION, colour, heavy, partition, with_slide};
use crate::generate::pushable::{NeededPush, PushKind};
use crate::metrics::ideal_path::CELL;
use crate::scenario::{ObjectKind, ObjectSpec, Scenario, Texture};

/// Share of rooms whose blocker is bolted: the run must then prove it static and end in no path.
const BOLTED_SHARE: f64 = 0.25;
/// Closest a blocker stands to what it is against (m): flush to 3 cm, as furniture is put.
const FLUSH: (f64, f64) = (0.0, 0.03);
/// Spare each side of a crate turned in a doorway (m).
const TURNED_SPARE: (f64, f64) = (0.03, 0.10);

/// How the blocker stands.
#[derive(Clone, Copy, Debug)]
enum Stand {
    /// Against a room wall, in the gap a partition leaves.
    Flush,
    /// Two side by side in a doorway, each alone leaving less than the robot's width.
    Abreast,
    /// Against a bolted cabinet in a doorway or across a hall.
    AgainstBolted,
    /// Turned 0–45° in a doorway with a few centimetres to spare.
    Turned,
    /// A low box against a partition's face, reaching into the doorway beside it.
    LowBeforeTall,
}

/// Widths the robot decides by (m).
struct Widths {
    /// Narrowest opening the robot must pass once it is cleared.
    open: f64,
    /// Widest gap left beside a blocker.
    shut: f64,
}

impl Widths {
    fn of(scenario: &Scenario) -> Self {
        let model = scenario.robot.model();
        let r = model.body.radius;
        let goal = nalgebra::Point2::new(scenario.goal.position[0], scenario.goal.position[1]);
        let run = nudge_executive::RunConfig::new(model, goal, scenario.goal.tolerance, 1);
        Self {
            open: 2.0 * (r + run.clearance) + CELL,
            shut: 2.0 * r - CELL,
        }
    }
}

/// One draw of the family: the scenario, its guarantee, and the pushes it needs.
pub(super) fn touching(rng: &mut ChaCha8Rng) -> (Scenario, Guarantee, Vec<NeededPush>) {
    let stand = match rng.random_range(0..5) {
        0 => Stand::Flush,
        1 => Stand::Abreast,
        2 => Stand::AgainstBolted,
        3 => Stand::Turned,
        _ => Stand::LowBeforeTall,
    };
    let bolted = rng.random_bool(BOLTED_SHARE);
    match stand {
        Stand::AgainstBolted if rng.random_bool(0.5) => hall(rng, bolted),
        _ => two_rooms(rng, stand, bolted),
    }
}

/// Two rooms, west and east, split by a partition at `x` with one opening the blocker stands in.
fn two_rooms(
    rng: &mut ChaCha8Rng,
    stand: Stand,
    bolted: bool,
) -> (Scenario, Guarantee, Vec<NeededPush>) {
    let w = cm(rng.random_range(7.0..9.0));
    let h = cm(rng.random_range(4.5..6.0));
    let x = cm(w / 2.0 + rng.random_range(-0.5..0.5));
    let start = [1.0, cm(rng.random_range(1.0..h - 1.0)), 0.0];
    let goal = [cm(w - 1.0), cm(rng.random_range(1.0..h - 1.0))];
    let mut s = bare([w, h], start, goal);
    let widths = Widths::of(&s);
    let (opening, blockers) = match stand {
        Stand::Flush => flush(rng, &mut s, &widths, x),
        Stand::Abreast => abreast(rng, &mut s, &widths, x),
        Stand::AgainstBolted => against_bolted(rng, &mut s, &widths, x),
        Stand::Turned => turned(rng, &mut s, &widths, x),
        Stand::LowBeforeTall => low_before_tall(rng, &mut s, &widths, x),
    };
    let (guarantee, needs) = finish(rng, &mut s, blockers, bolted);
    // A piece or two in each room, away from the opening, the start and the goal.
    let mut plan = FloorPlan::default();
    plan.keep_clear([start[0], start[1]], 0.9);
    plan.keep_clear(goal, 0.9);
    plan.keep_clear(opening, 1.8);
    for (k, side) in [[0.05, x - 0.2], [x + 0.2, w - 0.05]]
        .into_iter()
        .enumerate()
    {
        if rng.random_bool(0.5) {
            let mut piece = heavy(rng, format!("piece-{k}"));
            if plan.place(rng, &mut piece, side, [0.05, h - 0.05]) {
                piece.position = [cm(piece.position[0]), cm(piece.position[1])];
                s.objects.push(piece);
            }
        }
    }
    (s, guarantee, needs)
}

/// A hall 10–13 m long and a little wider than the robot's opening, a bolted cabinet against one
/// wall 6–10 m from the start (beyond the camera's 5 m at the first look) and the blocker against
/// its end, leaving less than the robot's width to the other wall.
fn hall(rng: &mut ChaCha8Rng, bolted: bool) -> (Scenario, Guarantee, Vec<NeededPush>) {
    let w = cm(rng.random_range(10.0..13.0));
    let h = cm(rng.random_range(1.7..2.3));
    let x = cm(rng.random_range(7.0..w - 2.5));
    let start = [1.0, cm(h / 2.0), 0.0];
    let goal = [cm(w - 0.8), cm(h / 2.0)];
    let mut s = bare([w, h], start, goal);
    let widths = Widths::of(&s);
    let mut blocker = light_box(rng, "box", (0.4, 0.6), (0.45, 0.65));
    let wy = blocker.size[1];
    let f = rng.random_range(FLUSH.0..FLUSH.1);
    // What the cabinet leaves must pass the robot, what the box then leaves must not.
    let free = rng.random_range(widths.open..(wy + f + widths.shut).max(widths.open + 0.01));
    let south = rng.random_bool(0.5);
    let length = h - free;
    let mut cabinet = bolted_cabinet(rng, "cabinet", length);
    let (cab_y, box_y) = if south {
        (length / 2.0, length + f + wy / 2.0)
    } else {
        (h - length / 2.0, h - length - f - wy / 2.0)
    };
    cabinet.position = [x, cab_y];
    blocker.position = [x + rng.random_range(-0.1..0.1), box_y];
    s.objects.push(cabinet);
    let (guarantee, needs) = finish(rng, &mut s, vec![(blocker, EAST)], bolted);
    (s, guarantee, needs)
}

/// The partition from the south wall to `y0` and from `y1` to the north wall (either may be empty).
fn door(s: &mut Scenario, x: f64, [y0, y1]: [f64; 2]) {
    let h = s.room.size[1];
    if y0 > 0.05 {
        s.objects
            .push(partition("wall-south".into(), [x, 0.0], [x, cm(y0)]));
    }
    if y1 < h - 0.05 {
        s.objects
            .push(partition("wall-north".into(), [x, cm(y1)], [x, h]));
    }
}

/// A light thing flush against the south or north room wall in the gap a partition leaves there.
fn flush(rng: &mut ChaCha8Rng, s: &mut Scenario, widths: &Widths, x: f64) -> Opening {
    let h = s.room.size[1];
    let mut blocker = light_thing(rng, "blocker");
    let wy = across_y(&blocker);
    let f = rng.random_range(FLUSH.0..FLUSH.1);
    let g = rng.random_range(widths.open..(f + wy + widths.shut).max(widths.open + 0.01));
    let south = rng.random_bool(0.5);
    let (gap, y) = if south {
        ([0.0, g], f + wy / 2.0)
    } else {
        ([h - g, h], h - f - wy / 2.0)
    };
    door(s, x, gap);
    blocker.position = [x + rng.random_range(-0.1..0.1), y];
    ([x, (gap[0] + gap[1]) / 2.0], vec![(blocker, EAST)])
}

/// Two light things abreast in a doorway, 0–5 cm apart and from the jambs.
fn abreast(rng: &mut ChaCha8Rng, s: &mut Scenario, widths: &Widths, x: f64) -> Opening {
    let h = s.room.size[1];
    let mut a = light_box(rng, "blocker-a", (0.4, 0.6), (0.4, 0.55));
    let mut b = light_box(rng, "blocker-b", (0.4, 0.6), (0.4, 0.55));
    let (wa, wb) = (a.size[1], b.size[1]);
    let (e, m) = (rng.random_range(0.0..0.05), rng.random_range(0.0..0.05));
    // Each alone leaves less than the robot's width: the doorway is at most the narrower plus what
    // the robot cannot pass.
    let lo = widths.open.max(wa + wb + e + m);
    let hi = wa.min(wb) + widths.shut;
    let g = if lo < hi {
        rng.random_range(lo..hi)
    } else {
        lo
    };
    let y0 = rng.random_range(0.8..h - g - 0.8);
    door(s, x, [y0, y0 + g]);
    a.position = [x, y0 + e + wa / 2.0];
    b.position = [x, y0 + e + wa + m + wb / 2.0];
    ([x, y0 + g / 2.0], vec![(a, EAST), (b, EAST)])
}

/// A bolted cabinet in a doorway against one jamb, a light thing against the cabinet.
fn against_bolted(rng: &mut ChaCha8Rng, s: &mut Scenario, widths: &Widths, x: f64) -> Opening {
    let h = s.room.size[1];
    let mut blocker = light_thing(rng, "blocker");
    let wy = across_y(&blocker);
    let f = rng.random_range(FLUSH.0..FLUSH.1);
    let free = rng.random_range(widths.open..(wy + f + widths.shut).max(widths.open + 0.01));
    let length = cm(rng.random_range(0.6..1.2));
    let g = length + free;
    let y0 = rng.random_range(0.8..(h - g - 0.8).max(0.81));
    door(s, x, [y0, y0 + g]);
    let mut cabinet = bolted_cabinet(rng, "cabinet", length);
    let south = rng.random_bool(0.5);
    let (cab_y, box_y) = if south {
        (y0 + length / 2.0, y0 + length + f + wy / 2.0)
    } else {
        (y0 + g - length / 2.0, y0 + g - length - f - wy / 2.0)
    };
    cabinet.position = [x, cab_y];
    blocker.position = [x + rng.random_range(-0.1..0.1), box_y];
    s.objects.push(cabinet);
    ([x, y0 + g / 2.0], vec![(blocker, EAST)])
}

/// A crate turned 0–45° either way in a doorway, 3–10 cm to spare at each jamb.
fn turned(rng: &mut ChaCha8Rng, s: &mut Scenario, widths: &Widths, x: f64) -> Opening {
    let h = s.room.size[1];
    let mut crate_ = light_box(rng, "crate", (0.4, 0.6), (0.7, 0.9));
    let yaw: f64 = rng.random_range(0.0..45.0) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let (sx, sy) = (crate_.size[0], crate_.size[1]);
    let t = yaw.to_radians();
    let across = sx * t.sin().abs() + sy * t.cos();
    let (s1, s2) = (
        rng.random_range(TURNED_SPARE.0..TURNED_SPARE.1),
        rng.random_range(TURNED_SPARE.0..TURNED_SPARE.1),
    );
    // The crate cleared, the doorway must pass the robot: a crate too short across is made longer.
    let stretch = (widths.open - (across + s1 + s2)).max(0.0) / t.cos();
    crate_.size[1] = sy + stretch;
    let across = sx * t.sin().abs() + crate_.size[1] * t.cos();
    let g = across + s1 + s2;
    let y0 = rng.random_range(0.8..h - g - 0.8);
    door(s, x, [y0, y0 + g]);
    crate_.yaw = yaw;
    crate_.position = [x + rng.random_range(-0.05..0.05), y0 + s1 + across / 2.0];
    ([x, y0 + g / 2.0], vec![(crate_, EAST)])
}

/// A low box flush against the partition's west face, reaching past a jamb into the doorway.
fn low_before_tall(rng: &mut ChaCha8Rng, s: &mut Scenario, widths: &Widths, x: f64) -> Opening {
    let h = s.room.size[1];
    let mut low = light_box(rng, "low-box", (0.35, 0.5), (0.6, 0.9));
    low.size[2] = cm(rng.random_range(0.3..0.5));
    let (sx, sy) = (low.size[0], low.size[1]);
    let g = rng.random_range(widths.open..widths.open + 0.2);
    // It reaches into the doorway far enough to shut it, and stands at least 10 cm before the wall.
    let lo = g - widths.shut;
    let reach = rng.random_range(lo..(sy - 0.1).min(g).max(lo + 0.01));
    let south = rng.random_bool(0.5);
    let y0 = rng.random_range(1.4..h - g - 1.4);
    door(s, x, [y0, y0 + g]);
    let f = rng.random_range(FLUSH.0..FLUSH.1);
    let bx = x - PARTITION / 2.0 - f - sx / 2.0;
    let by = if south {
        y0 + reach - sy / 2.0
    } else {
        y0 + g - reach + sy / 2.0
    };
    low.position = [bx, by];
    // Along the partition's face, away from the doorway it reaches into.
    let away = if south { [0.0, -1.0] } else { [0.0, 1.0] };
    ([x, y0 + g / 2.0], vec![(low, away)])
}

/// The way every room's blockers are cleared: into the east room, where the goal is.
const EAST: [f64; 2] = [1.0, 0.0];

/// A blocker and the way it is pushed to clear the opening.
type Blocker = (ObjectSpec, [f64; 2]);

/// Where an opening is, and what blocks it.
type Opening = ([f64; 2], Vec<Blocker>);

/// Puts the blockers in, bolting one of them when `bolted`, and says what the room guarantees and
/// needs: each blocker pushed its way, or the bolted one push-tested.
fn finish(
    rng: &mut ChaCha8Rng,
    s: &mut Scenario,
    mut blockers: Vec<Blocker>,
    bolted: bool,
) -> (Guarantee, Vec<NeededPush>) {
    if bolted {
        let k = rng.random_range(0..blockers.len());
        let (b, direction) = &mut blockers[k];
        b.fixed = true;
        b.mass = cm(rng.random_range(40.0..90.0));
        b.texture = Texture::Checker;
        let need = NeededPush {
            object: b.name.clone(),
            direction: *direction,
            kind: PushKind::Test,
        };
        let name = b.name.clone();
        s.objects.extend(blockers.into_iter().map(|(b, _)| b));
        return (Guarantee::ShutBy(name), vec![need]);
    }
    let needs: Vec<NeededPush> = blockers
        .iter()
        .map(|(b, direction)| NeededPush {
            object: b.name.clone(),
            direction: *direction,
            kind: PushKind::Clear,
        })
        .collect();
    let names: Vec<String> = blockers.iter().map(|(b, _)| b.name.clone()).collect();
    s.objects.extend(blockers.into_iter().map(|(b, _)| b));
    let guarantee = match names.len() {
        1 => Guarantee::WayNeeds(names[0].clone()),
        _ => Guarantee::WayNeedsEach(names),
    };
    (guarantee, needs)
}

/// A light box `sx` deep (along x) and `sy` across, 0.5–0.9 m tall, sliding at 6–15 N.
fn light_box(rng: &mut ChaCha8Rng, name: &str, sx: (f64, f64), sy: (f64, f64)) -> ObjectSpec {
    let size = vec![
        cm(rng.random_range(sx.0..sx.1)),
        cm(rng.random_range(sy.0..sy.1)),
        cm(rng.random_range(0.5..0.9)),
    ];
    light_of(rng, name, ObjectKind::Box, size, 0.0)
}

/// A light box, or a chair turned square to the walls.
fn light_thing(rng: &mut ChaCha8Rng, name: &str) -> ObjectSpec {
    if rng.random_bool(0.5) {
        return light_box(rng, name, (0.4, 0.6), (0.45, 0.65));
    }
    let yaw = f64::from(rng.random_range(0..4_u8)) * 90.0;
    light_of(rng, name, ObjectKind::Chair, vec![0.5, 0.5, 0.85], yaw)
}

/// A light thing of `kind`, `size` and `yaw`: 3–6 kg, textured, sliding at 6–15 N.
fn light_of(
    rng: &mut ChaCha8Rng,
    name: &str,
    kind: ObjectKind,
    size: Vec<f64>,
    yaw: f64,
) -> ObjectSpec {
    let spec = ObjectSpec {
        name: name.to_string(),
        kind,
        position: [0.0, 0.0],
        yaw,
        size,
        elevation: 0.0,
        mass: cm(rng.random_range(3.0..6.0)),
        friction: 0.6,
        fixed: false,
        colour: colour(rng),
        texture: Texture::Noise,
    };
    with_slide(spec, rng.random_range(6.0..15.0))
}

/// A bolted cabinet `length` long across the opening (along y), 0.4–0.6 m deep, 0.8–1.8 m tall.
fn bolted_cabinet(rng: &mut ChaCha8Rng, name: &str, length: f64) -> ObjectSpec {
    ObjectSpec {
        name: name.to_string(),
        kind: ObjectKind::Box,
        position: [0.0, 0.0],
        yaw: 0.0,
        size: vec![
            cm(rng.random_range(0.4..0.6)),
            cm(length),
            cm(rng.random_range(0.8..1.8)),
        ],
        elevation: 0.0,
        mass: cm(rng.random_range(40.0..90.0)),
        friction: 0.6,
        fixed: true,
        colour: colour(rng),
        texture: Texture::Checker,
    }
}

/// How far `spec` reaches along y (its footprint's extent across an opening).
fn across_y(spec: &ObjectSpec) -> f64 {
    let t = spec.yaw.to_radians();
    spec.size[0] * t.sin().abs() + spec.size[1] * t.cos().abs()
}
