//! The next-best view: where to walk and which way to face for a look-around that shows the most
//! target area per second of robot time.

use nalgebra::Point2;
use nudge_perception::Prism;
use nudge_perception::grid::{CellIndex, ObstacleGrid};

use crate::validity::Validity;
use crate::view::coverage::LookCoverage;
use crate::view::lattice::{Lattice, LatticeError};
use crate::view::search::Search;
use crate::view::sight::SightMap;
use crate::view::targets::Targets;

/// What the planner looks at: the grid, the obstacles, where the robot is and what it wants seen.
#[derive(Clone, Copy, Debug)]
pub struct ViewScene<'a> {
    /// The obstacle-type grid (its Free cells are the floor the robot may walk on; its obstacle
    /// classes occlude).
    pub grid: &'a ObstacleGrid,
    /// The prisms perceived so far (their points occlude up to their heights).
    pub prisms: &'a [Prism],
    /// What blocks the robot (obstacles already filtered by height) and the walls.
    pub validity: &'a Validity,
    /// The robot's position (map frame, m).
    pub robot: Point2<f64>,
    /// The grid cells the decision needs seen.
    pub targets: &'a Targets,
    /// Grid cells to count as seen floor besides the grid's Free cells (bit `i % 64` of word
    /// `i / 64`), e.g. floor a look-around's steep views saw: candidates may stand there.
    pub seen_floor: Option<&'a [u64]>,
}

/// How the planner weighs walking against seeing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewConfig {
    /// The floor one look-around shows.
    pub coverage: LookCoverage,
    /// Walking speed (m/s); default 0.15, the paper robot's.
    pub walk_speed: f64,
    /// How long one look-around takes (s); default 10 (the simulated 15 views).
    pub look_time: f64,
    /// Grid cells per lattice cell edge; default 2 (10 cm on the 5 cm grid).
    pub lattice_factor: usize,
    /// Distance between candidate positions (m), rounded to whole lattice cells; default 0.3.
    pub spacing: f64,
    /// Least weighted area a look must be predicted to show (m²); default 0.05 (20 cells).
    pub min_gain: f64,
    /// Clearance kept between the robot's disc and obstacles or walls (m); default 0.05.
    pub clearance: f64,
}

impl Default for ViewConfig {
    fn default() -> Self {
        Self {
            coverage: LookCoverage::default(),
            walk_speed: 0.15,
            look_time: 10.0,
            lattice_factor: 2,
            spacing: 0.3,
            min_gain: 0.05,
            clearance: 0.05,
        }
    }
}

/// The chosen look-around.
#[derive(Clone, Debug, PartialEq)]
pub struct Viewpoint {
    /// Where to stand (map frame, m).
    pub position: Point2<f64>,
    /// Which way to face for the look-around (rad, map frame, in `(−π, π]`).
    pub yaw: f64,
    /// Weighted target area predicted visible (m²).
    pub gain: f64,
    /// Geodesic walking distance from the robot (m); 0 where it stands.
    pub walk: f64,
    /// Predicted area per second of robot time: `gain / (walk / walk_speed + look_time)` (m²/s).
    pub score: f64,
    /// The waypoints of the walk, from the robot's position to `position`.
    pub path: Vec<Point2<f64>>,
    /// The target cells predicted seen, row-major, deduplicated.
    pub seen: Vec<CellIndex>,
}

/// Why no viewpoint was chosen.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum NoView {
    /// There is no target (or none inside the grid).
    #[error("no target cell to see")]
    NoTargets,
    /// No reachable position on observed floor is predicted to see any target cell.
    #[error("no reachable position sees any of the {targets} target cells")]
    Unreachable {
        /// Target cells inside the grid.
        targets: usize,
    },
    /// The best look is predicted to show less than asked for.
    #[error("the best look shows {best_gain} m², less than the {min_gain} m² asked for")]
    TooLittle {
        /// The largest predicted gain of any reachable position (m²).
        best_gain: f64,
        /// The least gain asked for (m²).
        min_gain: f64,
    },
    /// A setting is out of range (named).
    #[error("view planner setting {0} must be finite and positive")]
    BadConfig(&'static str),
    /// The lattice could not be built or searched (the robot outside the grid, a bad clearance).
    #[error(transparent)]
    Lattice(#[from] LatticeError),
}

/// Chooses the look-around that shows the most target area per second of robot time.
///
/// Candidates are the reachable cells of the planning lattice ([`Lattice::observed_floor`]: free
/// of obstacles, on observed floor) on a fixed sub-lattice every `spacing` (so the same cells
/// whatever the robot's position), within `coverage.far` of a target block, plus the robot's own
/// position. Each is scored `gain / (walk / walk_speed + look_time)`: its best heading's target
/// area over the robot time of walking there and looking ([`SightMap`]); candidates showing less
/// than `min_gain` are refused. The search is best first and coarse to fine, so that a decision
/// on an 800 × 600 grid takes a few milliseconds (`search.rs` says how): walking distances are
/// searched only as far as they can matter, positions are ranked by an estimate on a coarse
/// raster, bounded beforehand by what they have in sight through walls, and only the best few
/// are predicted on the grid's own cells. Ties go to the earlier candidate (the robot's position
/// first, then row-major), so the answer is the same, bit for bit, for the same inputs.
pub fn plan_view(scene: &ViewScene<'_>, config: &ViewConfig) -> Result<Viewpoint, NoView> {
    check(config)?;
    if scene.targets.is_empty() {
        return Err(NoView::NoTargets);
    }
    let radius = scene.validity.robot().radius;
    let sight = SightMap::new(
        scene.grid,
        scene.prisms,
        scene.targets,
        &config.coverage,
        radius,
    )
    .ok_or(NoView::NoTargets)?;
    let lattice = Lattice::seen_floor(
        scene.grid,
        scene.seen_floor,
        scene.validity,
        config.lattice_factor,
        config.clearance,
        scene.robot,
    )?;
    let mut search = Search::new(&sight, &lattice, config, scene.robot);
    let field = search.best_first()?;
    search.refine(&field);
    let (chosen, mut rays) = search.choose()?;
    let look = sight.predict_with(&mut rays, chosen.position);
    let path = match chosen.cell {
        Some(c) => field
            .path_to(c)
            .unwrap_or_else(|| vec![scene.robot, chosen.position]),
        None => vec![scene.robot],
    };
    Ok(Viewpoint {
        position: chosen.position,
        yaw: look.heading,
        gain: look.gain,
        walk: chosen.walk,
        score: look.gain / (chosen.walk / config.walk_speed + config.look_time),
        path,
        seen: look.seen,
    })
}

/// The settings' ranges.
fn check(c: &ViewConfig) -> Result<(), NoView> {
    let positive = |v: f64| v.is_finite() && v > 0.0;
    let cov = &c.coverage;
    let ranges = cov.near >= 0.0 && positive(cov.far) && cov.near < cov.far;
    let angle = positive(cov.half_angle) && cov.half_angle <= std::f64::consts::PI;
    if !(positive(cov.eye_height) && ranges && angle) {
        return Err(NoView::BadConfig("coverage"));
    }
    if !positive(c.walk_speed) {
        return Err(NoView::BadConfig("walk_speed"));
    }
    if !positive(c.look_time) {
        return Err(NoView::BadConfig("look_time"));
    }
    if !positive(c.spacing) {
        return Err(NoView::BadConfig("spacing"));
    }
    if !(c.min_gain.is_finite() && c.min_gain >= 0.0) {
        return Err(NoView::BadConfig("min_gain"));
    }
    if c.lattice_factor == 0 {
        return Err(NoView::BadConfig("lattice_factor"));
    }
    Ok(())
}
