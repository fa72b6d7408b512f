//! Scoring the obstacle-type grid against the simulation's ground truth, frame by frame (Tamura et
//! al.'s hallway experiment).
//!
//! Two views of the same frame:
//! - **returns** (Tamura's data points): every beam that ends in a hit is one return; its true class is
//!   that of the obstacle it lies on ([`true_class_of_return`]: the hit lies on a surface, where the
//!   truth is ambiguous), its predicted class is the grid's class of the cell holding it after the
//!   update;
//! - **cells**: every cell observed this frame (its `last_seen` is this frame's stamp, i.e. crossed by
//!   a beam or holding a return) whose true class is the same at its centre and near its four corners
//!   (cells straddling a surface have no single true class and are left out).
//!
//! Truth is Tamura's, not the push test's: [`Truth::obstacle_type_at`] calls a resting object Movable
//! when anything in the world moves it — here the suitcase a person pulls — whatever its sliding force.
//! [`Truth::true_class_at`] calls a resting object Movable only when the robot's 20 N guarded push would
//! slide it, so the hallway's suitcase (8 kg, μ 0.3: 23.5 N) is Stationary there although a person
//! pulls it.

use nalgebra::{Point2, Vector2};
use nudge_perception::grid::{
    BeamEnd, CellClass, CellIndex, GridGeometry, ObstacleGrid, RangeFrame,
};
use nudge_sim::truth::{TrueClass, Truth};
use nudge_sim::world::World;

/// Ground truth in Tamura's terms (the obstacle-type grid's classes).
pub struct TamuraTruth<'a> {
    truth: Truth<'a>,
}

impl<'a> TamuraTruth<'a> {
    /// Tamura's ground truth of `world` at its current time.
    pub fn new(world: &'a World) -> Self {
        Self {
            truth: Truth::new(world),
        }
    }

    /// The true obstacle type of the map point `p` now ([`Truth::obstacle_type_at`]).
    pub fn true_class_at(&self, p: Point2<f64>) -> TrueClass {
        self.truth.obstacle_type_at(p)
    }
}

/// How far from a return the obstacle it lies on is looked for (m): more than twice the range noise
/// at the sensor's 5 m limit (σ ≈ 1.5 cm), less than the 35 cm between the person's and the robot's
/// lanes.
pub const PROBE: f64 = 0.06;

/// The four true classes, in the order of [`Confusion`]'s rows.
pub const TRUE_CLASSES: [TrueClass; 4] = [
    TrueClass::Free,
    TrueClass::Stationary,
    TrueClass::Movable,
    TrueClass::Moving,
];

/// Row of a true class in [`Confusion`].
pub fn true_row(c: TrueClass) -> usize {
    match c {
        TrueClass::Free => 0,
        TrueClass::Stationary => 1,
        TrueClass::Movable => 2,
        TrueClass::Moving => 3,
    }
}

/// The grid class that means the same as a true class.
pub fn grid_class_of(c: TrueClass) -> CellClass {
    match c {
        TrueClass::Free => CellClass::Free,
        TrueClass::Stationary => CellClass::Stationary,
        TrueClass::Movable => CellClass::Movable,
        TrueClass::Moving => CellClass::Moving,
    }
}

/// Counts of (true class, grid class) pairs.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Confusion {
    /// `counts[true_row][grid class code]`.
    pub counts: [[u64; 5]; 4],
}

impl Confusion {
    /// Records one scored item.
    pub fn add(&mut self, truth: TrueClass, predicted: CellClass) {
        self.counts[true_row(truth)][usize::from(predicted.code())] += 1;
    }

    /// Adds every count of `other`.
    pub fn merge(&mut self, other: &Confusion) {
        for (row, o) in self.counts.iter_mut().zip(other.counts.iter()) {
            for (c, v) in row.iter_mut().zip(o.iter()) {
                *c += v;
            }
        }
    }

    /// Items whose true class is `c`.
    pub fn truly(&self, c: TrueClass) -> u64 {
        self.counts[true_row(c)].iter().sum()
    }

    /// Items the grid called `c`'s class.
    pub fn called(&self, c: TrueClass) -> u64 {
        let k = usize::from(grid_class_of(c).code());
        self.counts.iter().map(|row| row[k]).sum()
    }

    /// Items of true class `c` that the grid called so.
    pub fn hits(&self, c: TrueClass) -> u64 {
        self.counts[true_row(c)][usize::from(grid_class_of(c).code())]
    }

    /// Fraction of the items called `c` that truly are `c`; `None` if none was called `c`.
    pub fn precision(&self, c: TrueClass) -> Option<f64> {
        let n = self.called(c);
        (n > 0).then(|| self.hits(c) as f64 / n as f64)
    }

    /// Fraction of the items truly `c` that were called `c`; `None` if there were none.
    pub fn recall(&self, c: TrueClass) -> Option<f64> {
        let n = self.truly(c);
        (n > 0).then(|| self.hits(c) as f64 / n as f64)
    }

    /// A table: one line per true class with its counts by grid class, precision and recall.
    pub fn table(&self, title: &str) -> String {
        let pct =
            |v: Option<f64>| v.map_or("   -   ".to_string(), |v| format!("{:6.2}%", 100.0 * v));
        let mut s = format!(
            "{title}\n  true \\ grid  Unknown     Free  Station.  Movable   Moving  precision  recall\n"
        );
        for c in TRUE_CLASSES {
            let row = &self.counts[true_row(c)];
            s.push_str(&format!(
                "  {:<11} {:>8} {:>8} {:>8} {:>8} {:>8}    {}  {}\n",
                format!("{c:?}"),
                row[0],
                row[1],
                row[2],
                row[3],
                row[4],
                pct(self.precision(c)),
                pct(self.recall(c)),
            ));
        }
        s
    }
}

/// The true class of a return at `hit` seen from `sensor`: the first obstacle class met going on
/// along the beam up to [`PROBE`] beyond the hit (a hit lies on a surface; noise puts it either side),
/// else the first met within [`PROBE`] of the hit around it (a beam grazing a wall runs along it),
/// else Free (a return from nothing).
pub fn true_class_of_return(
    truth: &TamuraTruth<'_>,
    sensor: Point2<f64>,
    hit: Point2<f64>,
) -> TrueClass {
    let d: Vector2<f64> = hit - sensor;
    let n = d.norm();
    let along = (0..=8).map(|k| {
        let s = PROBE * f64::from(k) / 8.0;
        if n > 0.0 { hit + d * (s / n) } else { hit }
    });
    let around = (1..=2).flat_map(|r| {
        (0..8).map(move |k| {
            let a = std::f64::consts::FRAC_PI_4 * f64::from(k);
            let s = PROBE * f64::from(r) / 2.0;
            hit + Vector2::new(a.cos(), a.sin()) * s
        })
    });
    along
        .chain(around)
        .map(|p| truth.true_class_at(p))
        .find(|&c| c != TrueClass::Free)
        .unwrap_or(TrueClass::Free)
}

/// The true class of `cell` if it is the same at its centre and 0.45 cells from it towards each
/// corner, `None` for a cell straddling a surface.
pub fn pure_true_class(
    truth: &TamuraTruth<'_>,
    geom: &GridGeometry,
    cell: CellIndex,
) -> Option<TrueClass> {
    let c = geom.centre(cell);
    let h = 0.45 * geom.resolution();
    let centre = truth.true_class_at(c);
    [(-h, -h), (-h, h), (h, -h), (h, h)]
        .iter()
        .all(|&(dx, dy)| truth.true_class_at(Point2::new(c.x + dx, c.y + dy)) == centre)
        .then_some(centre)
}

/// Scores the returns of `frame` against `truth`, after `grid` was updated with it.
pub fn score_returns(
    grid: &ObstacleGrid,
    frame: &RangeFrame,
    truth: &TamuraTruth<'_>,
) -> Confusion {
    let mut conf = Confusion::default();
    for beam in frame.beams().iter().filter(|b| b.kind == BeamEnd::Hit) {
        if let Some(class) = grid.class_at(beam.end) {
            conf.add(true_class_of_return(truth, frame.sensor(), beam.end), class);
        }
    }
    conf
}

/// Scores the cells observed at `now` (last seen at `now`, single true class) against `truth`.
pub fn score_cells(grid: &ObstacleGrid, now: f64, truth: &TamuraTruth<'_>) -> Confusion {
    let geom = grid.geometry();
    let mut conf = Confusion::default();
    for i in 0..geom.len() {
        let Some(cell) = geom.cell_at(i) else {
            continue;
        };
        let Some(info) = grid.cell(cell) else {
            continue;
        };
        if info.last_seen != Some(now) {
            continue;
        }
        if let Some(t) = pure_true_class(truth, geom, cell) {
            conf.add(t, info.class);
        }
    }
    conf
}

#[cfg(test)]
mod tests {
    use super::*;
    use nudge_executive::robot::Clock;
    use nudge_sim::adapter::SimRobot;

    #[test]
    fn a_suitcase_a_person_leaves_is_movable_to_tamura_and_static_to_the_push() {
        // Invariant: once the person has left the suitcase (8 kg, 23.5 N to slide: over the push limit),
        // Tamura's truth calls it Movable and the push-test truth Stationary; the bolted cabinet is
        // Stationary to both, the floor Free, and the carried suitcase Moving.
        let scenario = crate::scenario("tamura-hallway").expect("scenario loads");
        let mut robot = SimRobot::new(&scenario, 1).expect("world builds");
        let suitcase = |r: &SimRobot| {
            let w = r.world();
            let i = w
                .objects()
                .iter()
                .position(|(s, _)| s.name == "suitcase")
                .expect("a suitcase");
            let p = w.object_pose(i).expect("pose").translation;
            (i, Point2::new(p.x, p.y))
        };
        let (i, carried_at) = suitcase(&robot);
        let truth = Truth::new(robot.world());
        assert_eq!(truth.obstacle_type_at(carried_at), TrueClass::Moving);
        assert!(truth.carried_by_an_actor(i));
        while robot.now() < 7.0 {
            robot.advance(0.1).expect("advance");
        }
        let (i, rest) = suitcase(&robot);
        assert!(
            (rest - Point2::new(6.0, 0.55)).norm() < 0.05,
            "left at {rest}"
        );
        let truth = Truth::new(robot.world());
        assert_eq!(truth.object_at(rest), Some(i));
        assert_eq!(truth.obstacle_type_at(rest), TrueClass::Movable);
        assert_eq!(truth.true_class_at(rest), TrueClass::Stationary);
        let cabinet = Point2::new(6.0, 2.2);
        assert_eq!(truth.obstacle_type_at(cabinet), TrueClass::Stationary);
        assert_eq!(truth.true_class_at(cabinet), TrueClass::Stationary);
        assert_eq!(
            truth.obstacle_type_at(Point2::new(3.0, 1.9)),
            TrueClass::Free
        );
    }
}
