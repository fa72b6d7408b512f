//! A synthetic 2D replication of Tamura et al.'s hallway experiment (Sect. 4, Figs. 7–12).
//!
//! A robot walks straight down a 2.4 m hallway at 0.2 m/s with a 180° laser scanner (361 beams at 0.5°,
//! 5 m range limit, 1 cm range noise, 10 Hz). A person (a 0.2 m disc) walks past it pulling a suitcase
//! (a 0.4 × 0.3 m box), leaves the suitcase ahead of the robot, walks on out of the measurement field,
//! waits, comes back, takes the suitcase and walks past the robot with it (Fig. 8's periods i–iii).
//!
//! Every frame goes through `ObstacleGrid::update`, the call the lead makes with real frames. Each
//! return's cell is scored against the object the simulated beam hit: wall → Stationary, person →
//! Moving, suitcase → Moving while it moves and Movable while it rests.

use nalgebra::{Point2, Vector2};
use nudge_perception::grid::{
    CellClass, CellIndex, GridConfig, GridGeometry, LaserScan, ObstacleGrid, RangeFrame,
};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::{HashMap, HashSet};

const DT: f64 = 0.1;
const FRAMES: usize = 200;
const RANGE_MAX: f64 = 5.0;
const HALL_Y: (f64, f64) = (0.01, 2.41);
const PERSON_R: f64 = 0.2;
const SUITCASE_HALF: (f64, f64) = (0.2, 0.15);
const LANE_Y: f64 = 1.7;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Thing {
    Wall,
    Person,
    Suitcase,
}

fn robot_at(t: f64) -> Point2<f64> {
    Point2::new(0.3 + 0.2 * t, 0.7)
}

/// Piecewise-linear person x: overtakes the robot (i), leaves the suitcase at t = 7, walks out of the
/// field to x = 8.5, waits, returns at 1.2 m/s to the suitcase (t = 13.5), walks back past the robot.
fn person_at(t: f64) -> Point2<f64> {
    let x = if t < 10.0 {
        -1.5 + t
    } else if t < 11.0 {
        8.5
    } else if t < 13.5 {
        8.5 - 1.2 * (t - 11.0)
    } else {
        5.5 - (t - 13.5)
    };
    Point2::new(x, LANE_Y)
}

/// The suitcase trails 0.6 m behind the person until t = 7, rests, and is carried off from t = 13.5.
fn suitcase_at(t: f64) -> Point2<f64> {
    let x = if t < 7.0 {
        -1.5 + t - 0.6
    } else if t < 13.5 {
        4.9
    } else {
        4.9 - (t - 13.5)
    };
    Point2::new(x, LANE_Y)
}

/// Nearest intersection parameter of the ray o + s·d (|d| = 1) with segment a–b.
fn ray_segment(o: Point2<f64>, d: Vector2<f64>, a: Point2<f64>, b: Point2<f64>) -> Option<f64> {
    let e = b - a;
    let den = d.x * e.y - d.y * e.x;
    if den.abs() < 1e-12 {
        return None;
    }
    let w = a - o;
    let s = (w.x * e.y - w.y * e.x) / den;
    let u = (w.x * d.y - w.y * d.x) / den;
    (s > 0.0 && (0.0..=1.0).contains(&u)).then_some(s)
}

fn ray_disc(o: Point2<f64>, d: Vector2<f64>, c: Point2<f64>, r: f64) -> Option<f64> {
    let oc = o - c;
    let b = oc.dot(&d);
    let disc = b * b - (oc.norm_squared() - r * r);
    if disc < 0.0 {
        return None;
    }
    let s = -b - disc.sqrt();
    (s > 0.0).then_some(s)
}

fn ray_box(o: Point2<f64>, d: Vector2<f64>, c: Point2<f64>) -> Option<f64> {
    let (hx, hy) = SUITCASE_HALF;
    let p = [
        Point2::new(c.x - hx, c.y - hy),
        Point2::new(c.x + hx, c.y - hy),
        Point2::new(c.x + hx, c.y + hy),
        Point2::new(c.x - hx, c.y + hy),
    ];
    (0..4)
        .filter_map(|k| ray_segment(o, d, p[k], p[(k + 1) % 4]))
        .min_by(f64::total_cmp)
}

/// One simulated scan at time `t`: ranges plus which thing each beam hit.
fn scan(t: f64, rng: &mut ChaCha8Rng) -> (Vec<f32>, Vec<Option<Thing>>) {
    let o = robot_at(t);
    let person = person_at(t);
    let suitcase = suitcase_at(t);
    let mut ranges = Vec::with_capacity(361);
    let mut things = Vec::with_capacity(361);
    for i in 0..361 {
        let a = (-90.0 + 0.5 * i as f64).to_radians();
        let d = Vector2::new(a.cos(), a.sin());
        let mut best: Option<(f64, Thing)> = None;
        let mut offer = |s: Option<f64>, th: Thing| {
            if let Some(s) = s
                && best.is_none_or(|(b, _)| s < b)
            {
                best = Some((s, th));
            }
        };
        for y in [HALL_Y.0, HALL_Y.1] {
            offer(
                ray_segment(o, d, Point2::new(-10.0, y), Point2::new(30.0, y)),
                Thing::Wall,
            );
        }
        offer(ray_disc(o, d, person, PERSON_R), Thing::Person);
        offer(ray_box(o, d, suitcase), Thing::Suitcase);
        // Box–Muller, σ = 1 cm (Chen Table 1, static σ for d ≤ 5 m); a noisy range at or past the
        // limit is no return, as the scanner would report it.
        let (u1, u2): (f64, f64) = (rng.random(), rng.random());
        let noise = 0.01 * (-2.0 * (1.0 - u1).ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
        match best {
            Some((s, th)) if s + noise < RANGE_MAX => {
                ranges.push((s + noise) as f32);
                things.push(Some(th));
            }
            _ => {
                ranges.push(f32::INFINITY);
                things.push(None);
            }
        }
    }
    (ranges, things)
}

#[derive(Default, Debug)]
struct Confusion {
    /// (truth, predicted) → count over scored (frame, cell) pairs.
    counts: HashMap<(CellClass, CellClass), usize>,
}

impl Confusion {
    fn add(&mut self, truth: CellClass, pred: CellClass) {
        *self.counts.entry((truth, pred)).or_default() += 1;
    }
    fn recall(&self, c: CellClass) -> f64 {
        let tp = self.counts.get(&(c, c)).copied().unwrap_or(0);
        let all: usize = self
            .counts
            .iter()
            .filter(|((t, _), _)| *t == c)
            .map(|(_, n)| n)
            .sum();
        tp as f64 / all.max(1) as f64
    }
    fn precision(&self, c: CellClass) -> f64 {
        let tp = self.counts.get(&(c, c)).copied().unwrap_or(0);
        let all: usize = self
            .counts
            .iter()
            .filter(|((_, p), _)| *p == c)
            .map(|(_, n)| n)
            .sum();
        tp as f64 / all.max(1) as f64
    }
}

struct Outcome {
    confusion: Confusion,
    wall_cells: usize,
    wall_cells_misclassified: usize,
    wall_cells_ever_free_after_stationary: usize,
    suitcase_cells_ever_stationary: usize,
    suitcase_rest_cells_left_movable: usize,
    movable_cells_at_end: usize,
}

fn run_hallway(seed: u64) -> Outcome {
    let geom = GridGeometry::from_rect(Point2::new(-2.0, 0.0), Point2::new(12.0, 2.42), 0.5, 0.05)
        .expect("valid hallway");
    let mut grid = ObstacleGrid::new(geom, GridConfig::default());
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut confusion = Confusion::default();
    let mut wall: HashSet<CellIndex> = HashSet::new();
    let mut wall_bad: HashSet<CellIndex> = HashSet::new();
    let mut wall_free: HashSet<CellIndex> = HashSet::new();
    let mut suitcase_cells: HashSet<CellIndex> = HashSet::new();
    let mut suitcase_stationary: HashSet<CellIndex> = HashSet::new();
    let mut rest_movable: HashSet<CellIndex> = HashSet::new();
    let mut stationary_seen: HashSet<CellIndex> = HashSet::new();
    let mut prev_suitcase = suitcase_at(-DT);
    for k in 0..FRAMES {
        let t = k as f64 * DT;
        let (ranges, things) = scan(t, &mut rng);
        let frame = RangeFrame::from_laser_scan(&LaserScan {
            position: robot_at(t),
            yaw: 0.0,
            angle_min: -std::f64::consts::FRAC_PI_2,
            angle_increment: 0.5_f64.to_radians(),
            range_max: RANGE_MAX,
            ranges: &ranges,
        })
        .expect("finite scan");
        grid.update(&frame, t).expect("frames in clock order");
        let s = suitcase_at(t);
        let suitcase_moving = (s - prev_suitcase).norm() > 1e-9;
        prev_suitcase = s;
        // Truth per returned cell; a cell hit by several things counts as the most dynamic.
        let mut truth: HashMap<CellIndex, (Thing, CellClass)> = HashMap::new();
        for (beam, th) in frame.beams().iter().zip(&things) {
            let Some(th) = *th else { continue };
            let Some(cell) = geom.cell_of(beam.end) else {
                continue;
            };
            let class = match th {
                Thing::Wall => CellClass::Stationary,
                Thing::Person => CellClass::Moving,
                Thing::Suitcase if suitcase_moving => CellClass::Moving,
                Thing::Suitcase => CellClass::Movable,
            };
            let rank = |t: Thing| match t {
                Thing::Wall => 0,
                Thing::Suitcase => 1,
                Thing::Person => 2,
            };
            if truth.get(&cell).is_none_or(|(o, _)| rank(th) > rank(*o)) {
                truth.insert(cell, (th, class));
            }
        }
        for (&cell, &(th, class)) in &truth {
            let pred = grid.class(cell).expect("returned cells are in the grid");
            confusion.add(class, pred);

            match th {
                Thing::Wall => {
                    wall.insert(cell);
                }
                Thing::Suitcase => {
                    suitcase_cells.insert(cell);
                    if class == CellClass::Movable && pred == CellClass::Movable {
                        rest_movable.insert(cell);
                    }
                }
                Thing::Person => {}
            }
        }
        // "Ever" checks look at every wall and suitcase cell known so far, every frame.
        for &cell in &wall {
            match grid.class(cell) {
                Some(CellClass::Moving | CellClass::Movable) => {
                    wall_bad.insert(cell);
                }
                Some(CellClass::Stationary) => {
                    stationary_seen.insert(cell);
                }
                Some(CellClass::Free) if stationary_seen.contains(&cell) => {
                    wall_free.insert(cell);
                }
                _ => {}
            }
        }
        for &cell in &suitcase_cells {
            if grid.class(cell) == Some(CellClass::Stationary) {
                suitcase_stationary.insert(cell);
            }
        }
    }
    if std::env::var_os("NUDGE_GRID_PNG").is_some() {
        let _ = grid.write_png(std::env::temp_dir().join("nudge-grid-hallway.png"));
    }
    let suitcase_rest_cells_left_movable = rest_movable
        .iter()
        .filter(|&&c| grid.class(c) == Some(CellClass::Movable))
        .count();
    Outcome {
        confusion,
        wall_cells: wall.len(),
        wall_cells_misclassified: wall_bad.len(),
        wall_cells_ever_free_after_stationary: wall_free.len(),
        suitcase_cells_ever_stationary: suitcase_stationary.len(),
        suitcase_rest_cells_left_movable,
        movable_cells_at_end: grid.class_counts()[CellClass::Movable.code() as usize],
    }
}

#[test]
fn tamura_hallway_goals_hold_on_the_synthetic_replication() {
    // Invariant: ≥ 98 % of moving returns are Moving, < 1 % of wall cells are ever Moving/Movable, the
    // suitcase is Movable at rest and never Stationary, and its resting cells are deleted once taken.
    for seed in 1_u64..=8 {
        let o = run_hallway(seed);
        let c = &o.confusion;
        println!("seed {seed}");
        for class in [CellClass::Stationary, CellClass::Movable, CellClass::Moving] {
            println!(
                "  {class:?}: precision {:.4} recall {:.4}",
                c.precision(class),
                c.recall(class)
            );
        }
        let mut counts: Vec<_> = c.counts.iter().collect();
        counts.sort_by_key(|((t, p), _)| (*t as u8, *p as u8));
        println!("  confusion (truth, predicted) → n: {counts:?}");
        println!(
            "  wall cells {} misclassified {} free-after-stationary {}; suitcase cells ever stationary {}; \
             rest cells left movable {}; movable cells at end {}",
            o.wall_cells,
            o.wall_cells_misclassified,
            o.wall_cells_ever_free_after_stationary,
            o.suitcase_cells_ever_stationary,
            o.suitcase_rest_cells_left_movable,
            o.movable_cells_at_end
        );
        assert!(
            c.recall(CellClass::Moving) >= 0.98,
            "moving recall {}",
            c.recall(CellClass::Moving)
        );
        assert!(
            (o.wall_cells_misclassified as f64) < 0.01 * o.wall_cells as f64,
            "{} of {} wall cells misclassified",
            o.wall_cells_misclassified,
            o.wall_cells
        );
        assert_eq!(
            o.suitcase_cells_ever_stationary, 0,
            "suitcase never stationary"
        );
        assert!(
            c.recall(CellClass::Movable) > 0.85,
            "suitcase movable at rest: {}",
            c.recall(CellClass::Movable)
        );
        assert!(c.precision(CellClass::Moving) > 0.95, "moving precision");
        assert!(c.precision(CellClass::Movable) > 0.95, "movable precision");
        assert!(
            c.precision(CellClass::Stationary) > 0.99,
            "stationary precision"
        );
        assert_eq!(
            o.suitcase_rest_cells_left_movable, 0,
            "deleted once taken away"
        );
    }
}
