//! The run's obstacle-type grid (Tamura, Chen, Lopez-Perez): every frame the camera takes lands in it,
//! the path being walked is watched in it, push-test verdicts and confirmed pushes are written into it,
//! and the planner avoids what it saw moving.

use nalgebra::{Point2, Vector2};
use nudge_perception::grid::{
    CellClass, CellIndex, Evidence, Footprint, GridGeometry, ObstacleGrid, RangeFrame,
    Verdict as GridVerdict,
};
use nudge_perception::{CloudFrame, ColourCloud, ObjectId, Prism};

use super::Runner;
use super::config::GridSetup;
use crate::push_test::Verdict;
use crate::record::{GridView, LogLevel, Observer};
use crate::robot::Robot;

/// Ids of the obstacles made from grid cells start here, far above any id perception hands out.
const GRID_OBSTACLE_IDS: u32 = 1 << 30;

/// The grid for a run starting at `start`: over the configured area, or around the start and the goal.
pub(crate) fn new_grid(
    setup: &GridSetup,
    start: Point2<f64>,
    goal: Point2<f64>,
) -> Result<ObstacleGrid, String> {
    let (lo, hi) = setup.area.unwrap_or_else(|| {
        let m = Vector2::repeat(setup.margin);
        (start.inf(&goal) - m, start.sup(&goal) + m)
    });
    let extent = hi - lo;
    let geometry = GridGeometry::new(lo, [extent.x, extent.y], setup.resolution)
        .map_err(|e| format!("the obstacle-type grid: {e}"))?;
    Ok(ObstacleGrid::new(geometry, setup.rules))
}

/// Obstacles for the planner from cells the grid saw moving, or resting where something moved (a person
/// who stopped), that no perceived obstacle explains. Cells within `keep_clear` of `robot` are left out:
/// the robot stands there, so whatever the grid saw there has gone.
pub(crate) fn moving_obstacles(
    grid: &ObstacleGrid,
    prisms: &[Prism],
    robot: &Point2<f64>,
    keep_clear: f64,
) -> Vec<Prism> {
    let geometry = grid.geometry();
    let half = geometry.resolution() / 2.0;
    let mut out = Vec::new();
    for (i, &code) in grid.class_codes().iter().enumerate() {
        let passive_motion = code == CellClass::Moving as u8 || code == CellClass::Movable as u8;
        if !passive_motion {
            continue;
        }
        let Some(cell) = geometry.cell_at(i) else {
            continue;
        };
        let explained_by_push = grid
            .cell(cell)
            .is_some_and(|c| matches!(c.evidence, Evidence::Active { .. }));
        let centre = geometry.centre(cell);
        if explained_by_push
            || (centre - robot).norm() < keep_clear
            || prisms.iter().any(|p| p.contains_xy(&centre))
        {
            continue;
        }
        let corner = |dx: f64, dy: f64| Point2::new(centre.x + dx, centre.y + dy);
        out.push(Prism {
            id: ObjectId(GRID_OBSTACLE_IDS + i as u32),
            footprint: vec![
                corner(-half, -half),
                corner(half, -half),
                corner(half, half),
                corner(-half, half),
            ],
            z_min: 0.0,
            // As tall as a person: it blocks any robot.
            z_max: 2.0,
            points: ColourCloud::empty(CloudFrame::Map, nalgebra::Isometry3::identity(), 0.0),
        });
    }
    out
}

/// The cells of the box around `prism`'s footprint grown by `grow` cells, clamped into the grid, row
/// by row; `None` for an empty footprint.
fn footprint_box(
    geometry: &GridGeometry,
    prism: &Prism,
    grow: f64,
) -> Option<impl Iterator<Item = CellIndex>> {
    let (lo, hi) = prism.footprint.iter().fold(None, |acc, p| match acc {
        None => Some((*p, *p)),
        Some((lo, hi)) => Some((p.inf(&lo), p.sup(&hi))),
    })?;
    let r = geometry.resolution();
    let o = geometry.origin();
    let far = Point2::new(
        o.x + (geometry.width() as f64 - 0.5) * r,
        o.y + (geometry.height() as f64 - 0.5) * r,
    );
    let clamp = |p: Point2<f64>| geometry.cell_of(p.sup(&o).inf(&far));
    let grow = nalgebra::Vector2::repeat(grow * r);
    let (a, b) = (clamp(lo - grow)?, clamp(hi + grow)?);
    Some((a.y..=b.y).flat_map(move |y| (a.x..=b.x).map(move |x| CellIndex::new(x, y))))
}

/// Share of the cells under `prism`'s footprint that the passive rules call Movable.
pub(crate) fn passive_movable_share(grid: &ObstacleGrid, prism: &Prism) -> f64 {
    let geometry = grid.geometry();
    let Some(cells) = footprint_box(geometry, prism, 0.0) else {
        return 0.0;
    };
    let (mut inside, mut movable) = (0usize, 0usize);
    for cell in cells.filter(|c| prism.contains_xy(&geometry.centre(*c))) {
        inside += 1;
        if grid.cell(cell).is_some_and(|c| {
            c.class == CellClass::Movable && matches!(c.evidence, Evidence::Passive(_))
        }) {
            movable += 1;
        }
    }
    if inside == 0 {
        0.0
    } else {
        movable as f64 / inside as f64
    }
}

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Makes the run's grid; without one the run goes on with perception's obstacles alone.
    pub(crate) fn start_grid(&mut self) {
        let start = match self.robot.base_pose() {
            Ok(p) => Point2::from(p.value.translation.vector),
            // The first command meets the same error and ends the run with it.
            Err(_) => return,
        };
        match new_grid(&self.config.grid, start, self.config.goal) {
            Ok(grid) => {
                self.world.last_motion = vec![f64::NAN; grid.class_codes().len()];
                self.world.grid = Some(grid);
            }
            Err(e) => {
                let stamp = self.robot.now();
                self.observer.note(stamp, LogLevel::Warning, &e);
            }
        }
    }

    /// Folds one captured frame into the grid, unless the camera looked down too steeply (see
    /// [`GridSetup::max_tilt`]); a frame the grid cannot take is noted, not fatal. With `motion`, the
    /// cells it leaves Moving are remembered as moved lately (not for the robot's own pushes).
    pub(crate) fn sense(&mut self, cloud: &ColourCloud, motion: bool) {
        let Some(grid) = self.world.grid.as_mut() else {
            return;
        };
        let forward = cloud.sensor_pose().rotation * nalgebra::Vector3::x();
        let tilt = (-forward.z).clamp(-1.0, 1.0).asin();
        if tilt > self.config.grid.max_tilt {
            return;
        }
        let result = RangeFrame::from_cloud(cloud, &self.config.grid.reduction)
            .and_then(|frame| grid.update(&frame, cloud.stamp()));
        if result.is_ok() && motion {
            let moving = CellClass::Moving as u8;
            for (stamp, &code) in self.world.last_motion.iter_mut().zip(grid.class_codes()) {
                if code == moving {
                    *stamp = cloud.stamp();
                }
            }
        }
        if let Err(e) = result {
            self.observer.note(
                cloud.stamp(),
                LogLevel::Warning,
                &format!("a frame was left out of the obstacle-type grid: {e}"),
            );
        }
    }

    /// Shows the grid to the observer.
    pub(crate) fn publish_grid(&mut self) {
        let Some(grid) = self.world.grid.as_ref() else {
            return;
        };
        let geometry = grid.geometry();
        let view = GridView {
            origin: geometry.origin(),
            resolution: geometry.resolution(),
            width: geometry.width(),
            height: geometry.height(),
            classes: grid.class_codes(),
        };
        let stamp = self.robot.now();
        self.observer.grid(stamp, &view);
    }

    /// Watches the cells a walk along `waypoints` sweeps; a flag raised before is dropped.
    pub(crate) fn watch_path(&mut self, waypoints: &[Point2<f64>]) {
        let radius = self.config.robot.radius;
        if let Some(grid) = self.world.grid.as_mut() {
            let cells = grid.cells_along_path(waypoints, radius);
            grid.set_watched_path(&cells);
            grid.take_replan_flag();
        }
    }

    /// Why the walk should stop and replan, if a watched cell turned into an obstacle.
    pub(crate) fn replan_reason(&mut self) -> Option<String> {
        let grid = self.world.grid.as_mut()?;
        let flag = grid.take_replan_flag()?;
        let at = grid.geometry().centre(flag.cell);
        Some(format!(
            "the obstacle-type grid saw {} cell(s) on the path turn {:?} (first at ({:.2}, {:.2}), was {:?})",
            flag.cells, flag.became, at.x, at.y, flag.was
        ))
    }

    /// Writes a push test's verdict into the grid over the object's footprint.
    pub(crate) fn mark_verdict(&mut self, target: ObjectId, verdict: &Verdict, push_test: u32) {
        match verdict {
            Verdict::Static { .. } => self.world.settled.insert(target),
            Verdict::Movable => self.world.settled.remove(&target),
        };
        let Some(prism) = self.world.prisms.iter().find(|p| p.id == target) else {
            return;
        };
        let Some(grid) = self.world.grid.as_mut() else {
            return;
        };
        let class = match verdict {
            Verdict::Static { .. } => GridVerdict::Static,
            Verdict::Movable => GridVerdict::Movable,
        };
        let stamp = self.robot.now();
        let marked = grid.mark_object(
            target,
            Footprint::Polygon(&prism.footprint),
            class,
            push_test,
            stamp,
        );
        if let Err(e) = marked {
            self.observer.note(
                stamp,
                LogLevel::Warning,
                &format!("{target}'s verdict was not written into the grid: {e}"),
            );
        }
        self.publish_grid();
    }

    /// Moves `id`'s obstacle by a measured displacement; when a push test already judged it, the grid
    /// frees its old footprint and marks the new one.
    pub(crate) fn displace(&mut self, id: ObjectId, offset: Vector2<f64>) {
        let before = self.world.prisms.iter().find(|p| p.id == id).cloned();
        self.world.displace(id, offset);
        let after = self.world.prisms.iter().find(|p| p.id == id).cloned();
        let (Some(before), Some(after), Some(grid)) = (before, after, self.world.grid.as_mut())
        else {
            return;
        };
        if grid.verdict(id).is_none() {
            return;
        }
        let stamp = self.robot.now();
        let moved = grid.object_moved(
            id,
            Footprint::Polygon(&before.footprint),
            Footprint::Polygon(&after.footprint),
            stamp,
        );
        if let Err(e) = moved {
            self.observer.note(
                stamp,
                LogLevel::Warning,
                &format!("{id}'s push was not written into the grid: {e}"),
            );
        }
    }

    /// Whether the grid saw `prism`'s cells, or their neighbours, Moving within
    /// [`GridSetup::mover_memory`] of now (in a look or a walk).
    pub(crate) fn moved_lately(&self, prism: &Prism) -> bool {
        let Some(grid) = self.world.grid.as_ref() else {
            return false;
        };
        let since = self.robot.now() - self.config.grid.mover_memory;
        let geometry = grid.geometry();
        let r = geometry.resolution();
        let Some(mut cells) = footprint_box(geometry, prism, 1.0) else {
            return false;
        };
        // A cell is near when its centre, or the centre of a neighbour, lies in the footprint.
        let near = |c: Point2<f64>| {
            [-r, 0.0, r].iter().any(|&dx| {
                [-r, 0.0, r]
                    .iter()
                    .any(|&dy| prism.contains_xy(&Point2::new(c.x + dx, c.y + dy)))
            })
        };
        cells.any(|cell| {
            geometry
                .index(cell)
                .and_then(|i| self.world.last_motion.get(i))
                .is_some_and(|&t| t >= since)
                && near(geometry.centre(cell))
        })
    }

    /// Whether passive evidence alone says `prism` is movable (it was seen moving and came to rest).
    pub(crate) fn passively_movable(&self, prism: &Prism) -> bool {
        self.world
            .grid
            .as_ref()
            .is_some_and(|g| passive_movable_share(g, prism) >= self.config.grid.passive_share)
    }
}
