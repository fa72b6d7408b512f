//! The run's obstacle-type grid (Tamura, Chen, Lopez-Perez): every frame the camera takes lands in it,
//! the path being walked is watched in it, push-test verdicts and confirmed pushes are written into it,
//! and the planner avoids what it saw moving.

use nalgebra::{Point2, Vector2};
use nudge_perception::grid::{
    CellClass, CellIndex, Evidence, Footprint, GridGeometry, ObstacleGrid, RangeFrame,
    Verdict as GridVerdict,
};
use nudge_perception::{CloudFrame, ColourCloud, ObjectId, Prism};

use super::config::GridSetup;
use super::{Interrupt, Runner};
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
        // A hull's edge runs a few centimetres from the cell centres of the face it was made from: a
        // cell the footprint overlaps at all is the obstacle's own.
        if explained_by_push
            || (centre - robot).norm() < keep_clear
            || prisms.iter().any(|p| overlaps_cell(p, centre, half))
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

/// Stationary cells this many cells or fewer outside a perceived obstacle's footprint are its own
/// returns (a chair's legs under the edge of its seat, the hull a cell or two off the face it was made
/// from), not a second obstacle beside it: a push that moves the obstacle moves them.
const EDGE_CELLS: f64 = 2.0;

/// Obstacles for the planner from cells the passive rules hold Stationary (three frames of returns
/// in place: a wall seen while walking) that no perceived obstacle explains: until a look-around turns
/// them into an obstacle, a path must not run through a wall the walk already saw. Cells within
/// `keep_clear` of `robot` are left out, as for [`moving_obstacles`], and so are cells within the
/// rules' rest radius of any cell ever seen moving (`moved`: per cell, when it was last seen moving,
/// NaN for never): a person who stood still reads as stationary, walks on, and the look-arounds'
/// panning views never cross the cells they left twice in a row, which is what clears a stationary
/// cell. Each row's runs of such cells
/// are joined with the same runs of the rows above into rectangles, so a wall is a few obstacles, not
/// one per cell.
pub(crate) fn stationary_obstacles(
    grid: &ObstacleGrid,
    prisms: &[Prism],
    robot: &Point2<f64>,
    keep_clear: f64,
    moved: &[f64],
) -> Vec<Prism> {
    let geometry = grid.geometry();
    let near_motion = near_motion(geometry, moved, grid.config().rest_radius);
    let moved_near = |x: usize, y: usize| -> bool {
        near_motion
            .as_ref()
            .is_some_and(|m| m.get(y * geometry.width() + x).copied().unwrap_or(false))
    };
    let half = geometry.resolution() / 2.0;
    let (w, h) = (geometry.width(), geometry.height());
    let codes = grid.class_codes();
    let stationary = CellClass::Stationary as u8;
    let unexplained = |x: usize, y: usize| -> bool {
        let i = y * w + x;
        if codes.get(i) != Some(&stationary) {
            return false;
        }
        let cell = CellIndex::new(x as u32, y as u32);
        let centre = geometry.centre(cell);
        let active = grid
            .cell(cell)
            .is_some_and(|c| matches!(c.evidence, Evidence::Active { .. }));
        !active
            && (centre - robot).norm() >= keep_clear
            && !moved_near(x, y)
            && !prisms
                .iter()
                .any(|p| overlaps_cell(p, centre, half + EDGE_CELLS * 2.0 * half))
    };
    // Open rectangles: (x0, x1, first row), keyed by their run.
    let mut open: Vec<(usize, usize, usize)> = Vec::new();
    let mut done: Vec<(usize, usize, usize, usize)> = Vec::new();
    for y in 0..=h {
        let mut runs = Vec::new();
        if y < h {
            let mut x = 0;
            while x < w {
                if unexplained(x, y) {
                    let x0 = x;
                    while x < w && unexplained(x, y) {
                        x += 1;
                    }
                    runs.push((x0, x - 1));
                } else {
                    x += 1;
                }
            }
        }
        let mut still = Vec::new();
        for (x0, x1, y0) in open.drain(..) {
            if runs.contains(&(x0, x1)) {
                still.push((x0, x1, y0));
            } else {
                done.push((x0, x1, y0, y - 1));
            }
        }
        for run in runs {
            if !still.iter().any(|(a, b, _)| (*a, *b) == run) {
                still.push((run.0, run.1, y));
            }
        }
        open = still;
    }
    done.sort_unstable_by_key(|&(x0, _, y0, _)| (y0, x0));
    done.into_iter()
        .map(|(x0, x1, y0, y1)| {
            let lo = geometry.centre(CellIndex::new(x0 as u32, y0 as u32));
            let hi = geometry.centre(CellIndex::new(x1 as u32, y1 as u32));
            let corner = |x: f64, y: f64| Point2::new(x, y);
            Prism {
                id: ObjectId(GRID_OBSTACLE_IDS + (y0 * w + x0) as u32),
                footprint: vec![
                    corner(lo.x - half, lo.y - half),
                    corner(hi.x + half, lo.y - half),
                    corner(hi.x + half, hi.y + half),
                    corner(lo.x - half, hi.y + half),
                ],
                z_min: 0.0,
                // Its height is unknown: it blocks any robot.
                z_max: 2.0,
                points: ColourCloud::empty(CloudFrame::Map, nalgebra::Isometry3::identity(), 0.0),
            }
        })
        .collect()
}

/// Per cell, whether it lies within `radius` of a cell ever seen moving (`moved`: per cell, when it
/// was last seen moving, NaN for never); `None` when nothing ever moved.
pub(crate) fn near_motion(
    geometry: &GridGeometry,
    moved: &[f64],
    radius: f64,
) -> Option<Vec<bool>> {
    let cells: Vec<usize> = moved
        .iter()
        .enumerate()
        .filter(|(_, t)| t.is_finite())
        .map(|(i, _)| i)
        .collect();
    if cells.is_empty() {
        return None;
    }
    let reach = (radius / geometry.resolution()).ceil() as i64;
    let (w, h) = (geometry.width() as i64, geometry.height() as i64);
    let mut near = vec![false; geometry.len()];
    for i in cells {
        let (x, y) = (i as i64 % w, i as i64 / w);
        for v in (y - reach).max(0)..=(y + reach).min(h - 1) {
            for u in (x - reach).max(0)..=(x + reach).min(w - 1) {
                near[(v * w + u) as usize] = true;
            }
        }
    }
    Some(near)
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

/// The cells an obstacle that was pushed away from `before` leaves behind: those its footprint
/// overlaps and those within [`EDGE_CELLS`] of it (its own returns, see [`stationary_obstacles`]),
/// except where another obstacle of `prisms` stands. Left in the grid, the edge cells would be
/// unexplained Stationary cells where the object no longer stands: a wall in front of the robot's
/// next stand pose that the near field under its camera never shows free again.
fn cells_left_behind(geometry: &GridGeometry, before: &Prism, prisms: &[Prism]) -> Vec<CellIndex> {
    let half = geometry.resolution() / 2.0;
    let Some(cells) = footprint_box(geometry, before, EDGE_CELLS + 1.0) else {
        return Vec::new();
    };
    cells
        .filter(|&c| {
            let centre = geometry.centre(c);
            overlaps_cell(before, centre, half + EDGE_CELLS * 2.0 * half)
                && !prisms
                    .iter()
                    .any(|p| p.id != before.id && overlaps_cell(p, centre, half))
        })
        .collect()
}

/// Whether the square cell of side `2 half` around `centre` overlaps `prism`'s convex footprint
/// (separating axes: the square's two and the footprint's edge normals).
pub(crate) fn overlaps_cell(prism: &Prism, centre: Point2<f64>, half: f64) -> bool {
    let f = &prism.footprint;
    if f.len() < 3 {
        return false;
    }
    let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
        .map(|(sx, sy)| Point2::new(centre.x + sx * half, centre.y + sy * half));
    let separated = |axis: Vector2<f64>| {
        let span = |pts: &mut dyn Iterator<Item = &Point2<f64>>| {
            pts.map(|p| axis.dot(&p.coords))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v), hi.max(v))
                })
        };
        let (a, b) = (span(&mut corners.iter()), span(&mut f.iter()));
        a.1 < b.0 || b.1 < a.0
    };
    let edges = (0..f.len()).map(|i| {
        (f[(i + 1) % f.len()] - f[i])
            .yx()
            .component_mul(&Vector2::new(1.0, -1.0))
    });
    let mut axes = [Vector2::x(), Vector2::y()].into_iter().chain(edges);
    !axes.any(separated)
}

/// The share of the obstacle cells the grid holds under `prism`'s footprint (the cells it overlaps) that
/// the passive rules call Movable. Only obstacle cells count: a range sensor returns from the faces
/// turned to it, so the inside of an object stays unknown however movable its faces are.
pub(crate) fn passive_movable_share(grid: &ObstacleGrid, prism: &Prism) -> f64 {
    let geometry = grid.geometry();
    let half = geometry.resolution() / 2.0;
    let Some(cells) = footprint_box(geometry, prism, 1.0) else {
        return 0.0;
    };
    movable_share(
        cells
            .filter(|c| overlaps_cell(prism, geometry.centre(*c), half))
            .filter_map(|c| grid.cell(c))
            .map(|c| (c.class, matches!(c.evidence, Evidence::Passive(_)))),
    )
}

/// Of cells given as (class, passive evidence), the share of the obstacle cells that are Movable by
/// passive evidence; 0 when none is an obstacle.
fn movable_share(cells: impl Iterator<Item = (CellClass, bool)>) -> f64 {
    obstacle_share(cells.map(|(class, passive)| (class, class == CellClass::Movable && passive)))
}

/// Of cells given as (class, whether it counts), the share of the obstacle cells that count; 0 when
/// none is an obstacle.
fn obstacle_share(cells: impl Iterator<Item = (CellClass, bool)>) -> f64 {
    let (obstacles, counted) = cells
        .filter(|(class, _)| class.is_obstacle())
        .fold((0usize, 0usize), |(n, m), (_, counts)| {
            (n + 1, m + usize::from(counts))
        });
    if obstacles == 0 {
        0.0
    } else {
        counted as f64 / obstacles as f64
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
                self.world.look_motion = vec![f64::NAN; grid.class_codes().len()];
                self.world.fresh_motion = vec![f64::NAN; grid.class_codes().len()];
                self.world.memory = super::unseen::SeenMemory::new(grid.class_codes().len());
                // The robot stands on its start: that floor is seen, though no camera sees under it.
                self.world
                    .memory
                    .tread(grid.geometry(), start, self.config.model.body.radius);
                self.world.grid = Some(grid);
            }
            Err(e) => {
                let stamp = self.robot.now();
                self.observer.note(stamp, LogLevel::Warning, &e);
            }
        }
    }

    /// Captures a frame, shows it to the observer and folds it into the grid ([`Self::sense`], with
    /// `motion`).
    pub(crate) fn take_frame(&mut self, motion: bool) -> Result<ColourCloud, Interrupt> {
        let cloud = self.robot.capture()?;
        self.observer.cloud(&cloud);
        self.sense(&cloud, motion);
        Ok(cloud)
    }

    /// Folds one captured frame into the grid, unless the camera looked down too steeply (see
    /// [`GridSetup::max_tilt`]); a frame the grid cannot take is noted, not fatal. With `motion`, the
    /// cells it leaves Moving are remembered as moved lately (not for the robot's own pushes).
    pub(crate) fn sense(&mut self, cloud: &ColourCloud, motion: bool) {
        let Some(grid) = self.world.grid.as_mut() else {
            return;
        };
        // Floor is floor however steeply the camera looked: seen in a cell, nothing stood on that
        // spot (see `WorldModel::floor_seen_since`).
        self.world.memory.saw_floor(
            grid.geometry(),
            cloud,
            self.config.grid.reduction.floor_band,
            self.robot.elapsed(),
        );
        let forward = cloud.sensor_pose().rotation * nalgebra::Vector3::x();
        let tilt = (-forward.z).clamp(-1.0, 1.0).asin();
        if tilt > self.config.grid.max_tilt {
            return;
        }
        let moving = CellClass::Moving as u8;
        // Which cells were Moving before the frame: those it turns Moving are motion seen now.
        let before: Vec<bool> = if motion {
            grid.class_codes().iter().map(|&c| c == moving).collect()
        } else {
            Vec::new()
        };
        let result = RangeFrame::from_cloud(cloud, &self.config.grid.reduction)
            .and_then(|frame| grid.update(&frame, cloud.stamp()));
        if result.is_ok() && motion {
            let now = self.robot.elapsed();
            let (last, fresh) = (&mut self.world.last_motion, &mut self.world.fresh_motion);
            for (i, &code) in grid.class_codes().iter().enumerate() {
                if code != moving {
                    continue;
                }
                if let Some(stamp) = last.get_mut(i) {
                    *stamp = now;
                }
                if !before.get(i).copied().unwrap_or(true)
                    && let Some(stamp) = fresh.get_mut(i)
                {
                    *stamp = now;
                }
            }
        }
        if let Err(e) = result {
            self.observer.note(
                cloud.stamp(),
                LogLevel::Warning,
                &format!("a frame was left out of the obstacle-type grid: {e}"),
            );
        } else if motion {
            self.reconcile();
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
        let radius = self.config.model.body.radius;
        if let Some(grid) = self.world.grid.as_mut() {
            let cells = grid.cells_along_path(waypoints, radius);
            grid.set_watched_path(&cells);
            grid.take_replan_flag();
        }
    }

    /// Why the walk should stop and replan, if a watched cell turned into an obstacle. With people
    /// about, a cell that turned Moving does not: someone crossing the path farther on is the search
    /// space's business when the robot gets there (see `search_space.rs`), and a path planned anew
    /// for every passer-by would never be walked.
    pub(crate) fn replan_reason(&mut self) -> Option<String> {
        let people = self.people_about();
        let grid = self.world.grid.as_mut()?;
        let flag = grid.take_replan_flag()?;
        if people && flag.became == CellClass::Moving {
            return None;
        }
        let at = grid.geometry().centre(flag.cell);
        Some(format!(
            "the obstacle-type grid saw {} cell(s) on the path turn {:?} (first at ({:.2}, {:.2}), was {:?})",
            flag.cells, flag.became, at.x, at.y, flag.was
        ))
    }

    /// Writes a push test's verdict into the grid over the object's footprint.
    pub(crate) fn mark_verdict(&mut self, target: ObjectId, verdict: &Verdict, push_test: u32) {
        let class = match verdict {
            Verdict::Static { .. } => GridVerdict::Static,
            Verdict::Movable => GridVerdict::Movable,
        };
        self.world.objects.judge(target, class, push_test);
        let Some(prism) = self.world.prisms.iter().find(|p| p.id == target) else {
            return;
        };
        let Some(grid) = self.world.grid.as_mut() else {
            return;
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
        self.move_object(
            id,
            &nalgebra::Isometry3::translation(offset.x, offset.y, 0.0),
        );
    }

    /// Moves obstacle `id` by the rigid `motion` (map frame) in the world model and the grid.
    pub(crate) fn move_object(&mut self, id: ObjectId, motion: &nalgebra::Isometry3<f64>) {
        if let Ok(pose) = self.robot.base_pose() {
            let here = nalgebra::Point2::from(pose.value.translation.vector);
            self.world.take_in_faces_of(id, &here, &self.config);
        }
        let before = self.world.prisms.iter().find(|p| p.id == id).cloned();
        if let Some(before) = &before {
            self.world
                .shed_points_of(before, self.config.perception.prism.min_thickness);
        }
        self.world.move_rigidly(id, motion);
        let after = self.world.prisms.iter().find(|p| p.id == id).cloned();
        let (Some(before), Some(after), Some(grid)) = (before, after, self.world.grid.as_mut())
        else {
            return;
        };
        let stamp = self.robot.now();
        if grid.verdict(id).is_none() {
            // Known movable from passive evidence alone and cleared without a test: the push is the
            // first active evidence, under push test 0 (none). Without it the faces the passive rules
            // marked would stay where the object no longer stands.
            let marked = grid.mark_object(
                id,
                Footprint::Polygon(&before.footprint),
                GridVerdict::Movable,
                0,
                stamp,
            );
            if let Err(e) = marked {
                self.observer.note(
                    stamp,
                    LogLevel::Warning,
                    &format!("{id}'s push was not written into the grid: {e}"),
                );
                return;
            }
        }
        let left = cells_left_behind(grid.geometry(), &before, &self.world.prisms);
        let moved = grid.object_moved(
            id,
            Footprint::Cells(&left),
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
    /// [`GridSetup::mover_memory`] of now (in a look or a walk), or a look saw something come or go
    /// there.
    pub(crate) fn moved_lately(&self, prism: &Prism) -> bool {
        // Robot time let pass, not the clock's reading (see `WorldModel::last_motion`).
        let since = self.robot.elapsed() - self.config.grid.mover_memory;
        self.motion_on(prism, &self.world.last_motion, since)
    }

    /// Whether `prism` may be a person by what the looks saw: a look saw it arrive (see
    /// [`super::object::Knowledge::arrived`]), or saw something come or go on its cells, or their
    /// neighbours, within [`GridSetup::mover_memory`] of now (see
    /// [`super::world::WorldModel::look_motion`]).
    pub(crate) fn seen_moving(&self, prism: &Prism) -> bool {
        let since = self.robot.elapsed() - self.config.grid.mover_memory;
        self.world.objects.get(prism.id).arrived
            || self.motion_on(prism, &self.world.look_motion, since)
    }

    /// Whether a look saw `prism` arrive, or saw something come or go on its cells, or their
    /// neighbours, at any time in the run.
    pub(crate) fn seen_moving_ever(&self, prism: &Prism) -> bool {
        self.world.objects.get(prism.id).arrived
            || self.motion_on(prism, &self.world.look_motion, f64::NEG_INFINITY)
    }

    /// Whether `stamps` (per cell, NaN for never) hold motion on `prism`'s cells, or their
    /// neighbours, at `since` (robot time let pass) or later.
    fn motion_on(&self, prism: &Prism, stamps: &[f64], since: f64) -> bool {
        let Some(grid) = self.world.grid.as_ref() else {
            return false;
        };
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
                .and_then(|i| stamps.get(i))
                .is_some_and(|&t| t >= since)
                && near(geometry.centre(cell))
        })
    }

    /// Whether passive evidence alone says `prism` is movable (it was seen moving and came to rest),
    /// unless it is someone keeping their distance from the robot
    /// ([`Self::keeps_its_distance`]): to the passive rules a person standing still reads as a
    /// thing moved and left.
    pub(crate) fn passively_movable(&self, prism: &Prism) -> bool {
        self.world
            .grid
            .as_ref()
            .is_some_and(|g| passive_movable_share(g, prism) >= self.config.grid.passive_share)
            && !self.keeps_its_distance(prism)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: f64, y0: f64, x1: f64, y1: f64) -> Prism {
        super::super::world::tests::box_prism(9, (x0, y0, x1, y1), 1.0)
    }

    #[test]
    fn a_cell_the_footprint_only_grazes_still_overlaps_it() {
        // Invariant: a 5 cm cell overlaps a footprint when any part of it does, even with its centre 1 cm outside (a face's cell next to the hull made from it); a cell wholly outside, or only diagonally near a corner, does not.
        let cart = square(2.73, 1.54, 3.28, 2.06);
        let half = 0.025;
        assert!(overlaps_cell(&cart, Point2::new(2.725, 1.8), half));
        assert!(overlaps_cell(&cart, Point2::new(3.0, 1.525), half));
        assert!(overlaps_cell(&cart, Point2::new(3.0, 1.8), half));
        assert!(!overlaps_cell(&cart, Point2::new(2.675, 1.8), half));
        assert!(!overlaps_cell(&cart, Point2::new(3.0, 2.1), half));
        // A diamond: the square next to its left corner touches its bounding box, not the diamond.
        let diamond = Prism {
            footprint: vec![
                Point2::new(0.0, 0.0),
                Point2::new(1.0, -1.0),
                Point2::new(2.0, 0.0),
                Point2::new(1.0, 1.0),
            ],
            ..cart
        };
        assert!(!overlaps_cell(&diamond, Point2::new(0.3, 0.9), 0.1));
        assert!(overlaps_cell(&diamond, Point2::new(0.3, 0.2), 0.1));
    }

    #[test]
    fn the_movable_share_counts_only_cells_the_grid_holds_as_obstacles() {
        // Invariant: the passive movable share is taken over obstacle cells only (a range sensor never sees inside an object, so unknown and free cells do not dilute it); active Movable cells do not count as passive; no obstacle cell gives 0.
        use CellClass::*;
        // A box seen from two sides: its faces movable by passive evidence, its inside unknown.
        let mut cells = vec![(Movable, true); 20];
        cells.extend(vec![(Unknown, false); 80]);
        assert!((movable_share(cells.iter().copied()) - 1.0).abs() < 1e-12);
        // A wall with two jittering cells.
        let mut wall = vec![(Stationary, true); 18];
        wall.extend([(Movable, true), (Movable, true), (Free, false)]);
        assert!((movable_share(wall.into_iter()) - 0.1).abs() < 1e-12);
        // A pushed chair: Movable by a push test, not by passive evidence.
        assert_eq!(movable_share(vec![(Movable, false); 10].into_iter()), 0.0);
        assert_eq!(
            movable_share(vec![(Unknown, false), (Free, false)].into_iter()),
            0.0
        );
    }

    #[test]
    fn a_pushed_obstacle_leaves_its_edge_cells_behind_but_not_its_neighbours() {
        // Invariant: the cells a pushed obstacle frees are those under its old footprint and its own returns up to two cells outside it (the cells stationary_obstacles credits to it), and never a cell under another obstacle standing beside it.
        let geometry = GridGeometry::new(Point2::new(0.0, 0.0), [4.0, 4.0], 0.05).expect("grid");
        let chair = super::super::world::tests::box_prism(1, (1.0, 1.0, 1.5, 1.5), 0.8);
        let wall = super::super::world::tests::box_prism(2, (1.55, 0.0, 1.65, 4.0), 2.0);
        let left = cells_left_behind(&geometry, &chair, &[chair.clone(), wall.clone()]);
        let has = |x: f64, y: f64| {
            let cell = geometry.cell_of(Point2::new(x, y)).expect("in the grid");
            left.contains(&cell)
        };
        assert!(has(1.25, 1.25), "under the footprint");
        assert!(has(0.93, 1.25), "a leg's return a cell and a half outside");
        assert!(!has(0.8, 1.25), "four cells outside");
        assert!(!has(1.58, 1.25), "under the wall beside it");
    }
}
