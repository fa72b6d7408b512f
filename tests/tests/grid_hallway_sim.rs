//! Tamura et al.'s hallway experiment (section 4) in the simulation: the robot walks straight down a
//! 12 m hallway at 0.2 m/s with its head fixed (pan 0, tilt 20°), a person pulls a suitcase ahead of it,
//! leaves it, walks off, comes back and takes it away. Every 0.1 s a range frame is reduced to beams
//! and fed to the obstacle-type grid (5 cm cells), and the grid is scored against ground truth.
//!
//! Scoring (see `nudge_tests::hallway`): per frame, the returns (Tamura's data points: true class
//! of the obstacle within 6 cm of the hit, predicted class = the grid's class of its cell after the update) and
//! the observed cells (last seen this frame, one true class over the whole cell). The goals (Tamura
//! and Chen): ≥ 98 % of the returns on moving things called Moving; under 1 % of the wall cells ever
//! called anything but Stationary or Unknown; the resting suitcase becomes Movable and never
//! Stationary; once it is taken away its cells are no longer Movable. `HALLWAY_MISSES=1` prints
//! every return whose Moving call disagrees with the truth; `HALLWAY_SEED=N` walks another noise seed
//! in the first test. The second test walks noise seeds 2–10: the goals must not hang on a lucky seed
//! (held out while the rules were fixed, seeds 11–20 met them too, at 98.25–98.50 %).

use std::collections::HashSet;

use nalgebra::Point2;
use nudge_executive::robot::{ActionStatus, Base, Clock, Head, RangeCamera};
use nudge_perception::grid::{
    BeamEnd, CellClass, ColumnReduction, GridGeometry, ObstacleGrid, RangeFrame,
};
use nudge_sim::adapter::SimRobot;
use nudge_sim::truth::{MOVING_SPEED, TrueClass};
use nudge_tests::hallway::{
    Confusion, TamuraTruth, score_cells, score_returns, true_class_of_return,
};

/// Frame period (s): Tamura's 10 Hz.
const DT: f64 = 0.1;
/// Head tilt (rad, down positive): floor seen from about 1.8 m to the 5 m range limit.
const TILT_DEG: f64 = 20.0;
/// Longest the walk may take (s): 54 s planned.
const TIME_LIMIT: f64 = 90.0;
/// Cells closer than this to the suitcase's resting centre belong to its resting place (m).
const REST_PLACE: f64 = 0.35;

/// What one run measured.
#[derive(Default)]
struct Run {
    returns: Confusion,
    /// Returns in frames where every person walks (none stands still).
    returns_walking: Confusion,
    /// Wall cells ever misclassified, by the first wrong class (Free, Movable, Moving).
    walls_wrong_by: [usize; 3],
    cells: Confusion,
    /// Returns on moving things, over the frames with at least one such return.
    moving_frames: u64,
    /// Wall cells (outside the room, whole cell) ever classified, and those ever misclassified.
    walls_seen: HashSet<usize>,
    walls_wrong: HashSet<usize>,
    /// Frames in which a cell whose centre lies inside the resting suitcase was Movable / Stationary.
    suitcase_movable_frames: u64,
    suitcase_stationary_frames: u64,
    /// Cells of the resting place the grid ever called Movable while the suitcase rested there.
    rest_cells: HashSet<usize>,
    /// Stamps: the suitcase first rests in the grid as Movable; it is taken; its place has no Movable.
    first_movable: Option<f64>,
    taken_at: Option<f64>,
    deleted_at: Option<f64>,
    /// Whether the resting place still holds Movable cells at the end.
    movable_left_at_end: usize,
    end_time: f64,
    /// Stamps: the suitcase left at rest; first and last frame with a return on it at rest.
    dropped_at: Option<f64>,
    rest_seen: Option<(f64, f64)>,
    reached_goal: bool,
}

fn suitcase_index(robot: &SimRobot) -> usize {
    robot
        .world()
        .objects()
        .iter()
        .position(|(spec, _)| spec.name == "suitcase")
        .expect("the scenario has a suitcase")
}

/// Whether the suitcase rests now (nobody pulls it and it is not sliding), and where.
fn suitcase_rest(robot: &SimRobot, i: usize) -> Option<Point2<f64>> {
    let world = robot.world();
    let carried = world.actors().iter().any(|a| a.carrying() == Some(i));
    let sliding = world.object_speed(i).is_some_and(|s| s > MOVING_SPEED);
    let pose = world.object_pose(i)?;
    (!carried && !sliding).then(|| Point2::new(pose.translation.x, pose.translation.y))
}

fn run_hallway(seed: u64) -> Run {
    let scenario = nudge_tests::scenario("tamura-hallway").expect("scenario loads");
    let mut robot = SimRobot::new(&scenario, seed).expect("world builds");
    let room = robot.world().room_size();
    let geom = GridGeometry::from_rect(
        Point2::origin(),
        Point2::new(room[0], room[1]),
        0.5,
        nudge_perception::grid::DEFAULT_RESOLUTION,
    )
    .expect("grid geometry");
    let mut grid = ObstacleGrid::new(geom, Default::default());
    let reduction = ColumnReduction::default();
    let suitcase = suitcase_index(&robot);

    // Wall cells: wholly outside the room (the walls are the room's boundary).
    let wall_cells: Vec<usize> = (0..geom.len())
        .filter(|&i| {
            let Some(cell) = geom.cell_at(i) else {
                return false;
            };
            let c = geom.centre(cell);
            let h = geom.resolution() / 2.0;
            let inside_x = c.x + h > 0.0 && c.x - h < room[0];
            let inside_y = c.y + h > 0.0 && c.y - h < room[1];
            !(inside_x && inside_y)
        })
        .collect();

    robot
        .start_point_head(0.0, TILT_DEG.to_radians())
        .expect("head");
    while robot.head_status().expect("head status") == ActionStatus::Running {
        robot.advance(DT).expect("advance");
    }
    let goal = Point2::new(scenario.goal.position[0], scenario.goal.position[1]);
    robot.start_walk(&[goal]).expect("walk starts");

    let mut run = Run::default();
    let mut was_resting = false;
    loop {
        robot.advance(DT).expect("advance");
        let now = robot.now();
        let cloud = robot.capture().expect("capture");
        let frame = RangeFrame::from_cloud(&cloud, &reduction).expect("frame");
        grid.update(&frame, now).expect("update");

        let truth = TamuraTruth::new(robot.world());
        let returns = score_returns(&grid, &frame, &truth);
        if std::env::var_os("HALLWAY_MISSES").is_some() {
            print_misses(&grid, &frame, &truth, now);
        }
        if returns.truly(TrueClass::Moving) > 0 {
            run.moving_frames += 1;
        }
        if robot.world().actors().iter().all(|a| a.is_moving()) {
            run.returns_walking.merge(&returns);
        }
        run.returns.merge(&returns);
        if returns.truly(TrueClass::Movable) > 0 {
            let first = run.rest_seen.map_or(now, |(f, _)| f);
            run.rest_seen = Some((first, now));
        }
        run.cells.merge(&score_cells(&grid, now, &truth));

        for &i in &wall_cells {
            match grid.class_codes()[i] {
                c if c == CellClass::Unknown.code() => {}
                c => {
                    run.walls_seen.insert(i);
                    if c != CellClass::Stationary.code() && run.walls_wrong.insert(i) {
                        let k = match c {
                            c if c == CellClass::Free.code() => 0,
                            c if c == CellClass::Movable.code() => 1,
                            _ => 2,
                        };
                        run.walls_wrong_by[k] += 1;
                        if let Some(cell) = geom.cell_at(i) {
                            let p = geom.centre(cell);
                            println!(
                                "t {now:.1}: wall cell ({:.3}, {:.3}) class {c} {:?}",
                                p.x,
                                p.y,
                                grid.cell(cell).expect("c").evidence
                            );
                        }
                    }
                }
            }
        }

        // The suitcase: after the person lets it go (it is pulled from the start).
        let rest = suitcase_rest(&robot, suitcase);
        if let Some(centre) = rest {
            let (mut movable, mut stationary) = (false, false);
            for i in 0..geom.len() {
                let Some(cell) = geom.cell_at(i) else {
                    continue;
                };
                if (geom.centre(cell) - centre).norm() > REST_PLACE {
                    continue;
                }
                let class = grid.class_codes()[i];
                if class == CellClass::Movable.code() {
                    run.rest_cells.insert(i);
                }
                if truth.true_class_at(geom.centre(cell)) == TrueClass::Movable {
                    movable |= class == CellClass::Movable.code();
                    stationary |= class == CellClass::Stationary.code();
                }
            }
            run.suitcase_movable_frames += u64::from(movable);
            run.suitcase_stationary_frames += u64::from(stationary);
            if movable && run.first_movable.is_none() {
                run.first_movable = Some(now);
            }
            if !was_resting && run.dropped_at.is_none() {
                run.dropped_at = Some(now);
            }
        } else if was_resting && run.taken_at.is_none() {
            run.taken_at = Some(now);
        }
        was_resting = rest.is_some();
        let left = run
            .rest_cells
            .iter()
            .filter(|&&i| grid.class_codes()[i] == CellClass::Movable.code())
            .count();
        if run.taken_at.is_some() && run.deleted_at.is_none() && left == 0 {
            run.deleted_at = Some(now);
        }
        run.movable_left_at_end = left;

        run.end_time = now;
        match robot.walk_status().expect("walk status") {
            ActionStatus::Running if now < TIME_LIMIT => {}
            ActionStatus::Running => break,
            ActionStatus::Done(outcome) => {
                println!("walk ended: {outcome:?}");
                let pose = robot.base_pose().expect("pose").value;
                run.reached_goal = (Point2::from(pose.translation.vector) - goal).norm()
                    <= scenario.goal.tolerance;
                break;
            }
        }
    }
    run
}

/// Diagnostics (`HALLWAY_MISSES=1`): every return whose Moving call disagrees with the truth, with
/// the rule behind its cell's class.
fn print_misses(grid: &ObstacleGrid, frame: &RangeFrame, truth: &TamuraTruth<'_>, now: f64) {
    for b in frame.beams().iter().filter(|b| b.kind == BeamEnd::Hit) {
        let t = true_class_of_return(truth, frame.sensor(), b.end);
        let Some(info) = grid.geometry().cell_of(b.end).and_then(|c| grid.cell(c)) else {
            continue;
        };
        if (t == TrueClass::Moving) != (info.class == CellClass::Moving) {
            println!(
                "miss t {now:.1}: truly {t:?}, grid {:?} ({:?}) at ({:.3}, {:.3}), {:.2} m away",
                info.class,
                info.evidence,
                b.end.x,
                b.end.y,
                (b.end - frame.sensor()).norm()
            );
        }
    }
}

fn pct(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{:.2} %", 100.0 * v))
}

/// Tamura's and Chen's goals: ≥ 98 % of the returns on moving things called Moving, under 1 % of
/// the wall cells ever misclassified. On seed 1 the grid reaches 98.34 % (41 of 2467 returns
/// missed: 28 in the person's first three frames back inside the 5 m range, beyond the 4.8 m to
/// which the camera's clear columns saw the floor the frame before; 5 on the suitcase as it is taken,
/// behind the person; 8 on the suitcase at the edge of the view once the person pulling it has left
/// the view, read as resting), and 98.10–98.50 % on seeds 2–10.
const MOVING_RECALL_GOAL: f64 = 0.98;
const WALLS_WRONG_GOAL: f64 = 0.01;

impl Run {
    fn moving_recall(&self) -> Option<f64> {
        self.returns.recall(TrueClass::Moving)
    }

    /// Share of the wall cells ever classified that were ever misclassified.
    fn walls_wrong_share(&self) -> f64 {
        self.walls_wrong.len() as f64 / self.walls_seen.len().max(1) as f64
    }

    /// The goals this run misses, in words (none when all are met).
    fn missed_goals(&self) -> Vec<String> {
        let recall = self.moving_recall();
        let checks = [
            (
                self.reached_goal,
                "the robot must walk to the goal".to_string(),
            ),
            (
                self.moving_frames > 0,
                "the person must come into view".into(),
            ),
            (
                recall.is_some_and(|r| r >= MOVING_RECALL_GOAL),
                format!(
                    "Moving recall {} is under the {:.0} % goal",
                    pct(recall),
                    100.0 * MOVING_RECALL_GOAL
                ),
            ),
            (
                self.walls_wrong_share() < WALLS_WRONG_GOAL,
                format!(
                    "{:.2} % of wall cells misclassified",
                    100.0 * self.walls_wrong_share()
                ),
            ),
            (
                self.suitcase_movable_frames > 0,
                "the resting suitcase never became Movable".into(),
            ),
            (
                self.suitcase_stationary_frames == 0,
                format!(
                    "the resting suitcase was Stationary in {} frames",
                    self.suitcase_stationary_frames
                ),
            ),
            (self.taken_at.is_some(), "the suitcase must be taken".into()),
            (
                self.movable_left_at_end == 0,
                format!(
                    "{} Movable cells left where the suitcase rested",
                    self.movable_left_at_end
                ),
            ),
        ];
        checks
            .into_iter()
            .filter(|(met, _)| !met)
            .map(|(_, what)| what)
            .collect()
    }
}

#[test]
fn the_hallway_grid_meets_tamuras_goals_against_ground_truth() {
    // Invariant: walking Tamura's hallway, at least 98 % of the returns on moving things are called Moving, under 1 % of wall cells are ever misclassified, the resting suitcase becomes Movable and is never Stationary, and its cells are deleted once it is taken.
    // `HALLWAY_SEED=N` walks another noise seed, for diagnosis (the goals hold for the scenario's).
    let seed = std::env::var("HALLWAY_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let run = run_hallway(seed);
    println!("{}", run.returns.table("returns (Tamura's data points):"));
    println!(
        "{}",
        run.cells.table("observed cells (one true class per cell):")
    );
    let moving_recall = run.moving_recall();
    let wall_wrong = run.walls_wrong_share();
    println!(
        "end t = {:.1} s, goal reached: {}; frames with moving returns: {}; Moving recall (returns) {}, (cells) {}",
        run.end_time,
        run.reached_goal,
        run.moving_frames,
        pct(moving_recall),
        pct(run.cells.recall(TrueClass::Moving)),
    );
    println!(
        "Moving recall while every person walks (returns): {}",
        pct(run.returns_walking.recall(TrueClass::Moving))
    );
    println!(
        "wall cells seen {}, ever misclassified {} ({:.2} %): Free {}, Movable {}, Moving {}",
        run.walls_seen.len(),
        run.walls_wrong.len(),
        100.0 * wall_wrong,
        run.walls_wrong_by[0],
        run.walls_wrong_by[1],
        run.walls_wrong_by[2],
    );
    println!(
        "suitcase dropped at {:?}, returns on it at rest from/to {:?}\nsuitcase at rest: Movable in {} frames (first at {:?}), Stationary in {} frames; taken at {:?}; resting place without Movable at {:?}; Movable cells left at end {} of {}",
        run.dropped_at,
        run.rest_seen,
        run.suitcase_movable_frames,
        run.first_movable,
        run.suitcase_stationary_frames,
        run.taken_at,
        run.deleted_at,
        run.movable_left_at_end,
        run.rest_cells.len(),
    );
    println!(
        "goals: Moving recall >= {:.0} %: {}; wall cells misclassified < {:.0} %: {}",
        100.0 * MOVING_RECALL_GOAL,
        if moving_recall.is_some_and(|r| r >= MOVING_RECALL_GOAL) {
            "met"
        } else {
            "NOT met"
        },
        100.0 * WALLS_WRONG_GOAL,
        if wall_wrong < WALLS_WRONG_GOAL {
            "met"
        } else {
            "NOT met"
        },
    );
    let missed = run.missed_goals();
    assert!(missed.is_empty(), "seed {seed}: {}", missed.join("; "));
}

/// The sensor-noise seeds besides the scenario's on which the goals must hold too (a walk takes
/// about 2 s; two run at once).
const OTHER_SEEDS: std::ops::RangeInclusive<u64> = 2..=10;

#[test]
fn the_hallway_goals_hold_on_other_noise_seeds() {
    // Invariant: the goals of the test above (Moving recall ≥ 98 %, under 1 % of wall cells ever misclassified, the resting suitcase Movable and never Stationary, its cells deleted once taken) hold on every noise seed 2–10, not on a lucky one.
    let seeds: Vec<u64> = OTHER_SEEDS.collect();
    let (first, second) = seeds.split_at(seeds.len() / 2);
    let walk =
        |seeds: &[u64]| -> Vec<(u64, Run)> { seeds.iter().map(|&s| (s, run_hallway(s))).collect() };
    let mut runs = std::thread::scope(|scope| {
        let other = scope.spawn(|| walk(second));
        let mut runs = walk(first);
        runs.extend(other.join().expect("the other half of the seeds ran"));
        runs
    });
    runs.sort_by_key(|(seed, _)| *seed);
    let mut failed = Vec::new();
    for (seed, run) in &runs {
        println!(
            "seed {seed}: Moving recall {}; wall cells ever misclassified {} of {}; resting suitcase Movable in {} frames, Stationary in {}",
            pct(run.moving_recall()),
            run.walls_wrong.len(),
            run.walls_seen.len(),
            run.suitcase_movable_frames,
            run.suitcase_stationary_frames,
        );
        let missed = run.missed_goals();
        if !missed.is_empty() {
            failed.push(format!("seed {seed}: {}", missed.join("; ")));
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}
