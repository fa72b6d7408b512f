//! Moving to see: which unseen floor matters to the question asked, and where to look from.

use nalgebra::Point2;

use nudge_motion::view::{Targets, ViewConfig, ViewScene, plan_view};
use nudge_motion::{WayHypothesis, unseen_way};

use super::unseen::{regions, unseen_along, unseen_around, unseen_around_goal};
use super::{Interrupt, Runner};
use crate::event::Event;
use crate::record::Observer;
use crate::robot::Robot;
use crate::view::{Question, UnseenRegion, UnseenWhy, Viewpoint};

/// What the view planner answered.
pub(crate) enum Choice {
    /// Look from here.
    View(Viewpoint, Vec<usize>),
    /// No viewpoint shows enough; why.
    None(String),
}

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Chooses where to look from to answer `question`.
    pub(crate) fn plan_view(&mut self, question: &Question) -> Event {
        let here = match self.robot.base_pose() {
            Ok(p) => Point2::from(p.value.translation.vector),
            Err(e) => return Interrupt::Robot(e).into(),
        };
        let targets = self.targets(question, here);
        if *question == Question::Way && targets.is_empty() {
            return self.way_closed();
        }
        let Some(grid) = self.world.grid.as_ref() else {
            return Event::NoView {
                reason: "no obstacle-type grid: nothing is known of what was not seen".into(),
                unseen: Vec::new(),
            };
        };
        let geometry = grid.geometry();
        let cell_area = geometry.resolution() * geometry.resolution();
        let min_gain = self.min_gain();
        let area = targets.len() as f64 * cell_area;
        if area < min_gain {
            return Event::NoView {
                reason: format!(
                    "{area:.3} m² of unseen floor matters to {}, less than the {min_gain:.3} m² worth a look",
                    question.name()
                ),
                unseen: self.unseen_regions(&targets),
            };
        }
        match self.choose_view(here, &targets) {
            Choice::View(view, cells) => {
                let stamp = self.robot.now();
                self.observer.note(
                    stamp,
                    crate::record::LogLevel::Info,
                    &format!(
                        "to see {} ({area:.2} m² unseen): look from ({:.2}, {:.2}) facing {:.0}°, {:.2} m² predicted, {:.1} m away",
                        question.name(),
                        view.position.x,
                        view.position.y,
                        view.yaw.to_degrees(),
                        view.gain,
                        view.walk
                    ),
                );
                self.world.view_cells = Some(cells);
                Event::ViewPlanned(view)
            }
            Choice::None(reason) => Event::NoView {
                reason,
                unseen: self.unseen_regions(&targets),
            },
        }
    }

    /// No unseen floor could open a way: the answer lists the goal region's floor nobody has seen
    /// (where the robot would stand at the goal), behind the obstacles that close every way to it.
    fn way_closed(&self) -> Event {
        let unseen = self.world.grid.as_ref().map_or_else(Vec::new, |grid| {
            let cells = unseen_around_goal(
                grid,
                &self.world.memory,
                &self.world.prisms,
                self.config.goal,
                self.config.goal_tolerance + self.config.model.body.radius,
            );
            regions(grid.geometry(), &cells, |_| UnseenWhy::BehindObstacles)
        });
        Event::NoView {
            reason: "obstacles seen close every way to the goal: no unseen floor could open one"
                .into(),
            unseen,
        }
    }

    /// Least unseen area worth a walk and a look (m²): a strip one grid cell deep across the robot's
    /// width, the least a way the robot fits through can cross.
    pub(crate) fn min_gain(&self) -> f64 {
        let res = self
            .world
            .grid
            .as_ref()
            .map_or(0.05, |g| g.geometry().resolution());
        2.0 * self.config.model.body.radius * res
    }

    /// The open unseen cells that matter to `question`, sorted grid indices.
    fn targets(&self, question: &Question, here: Point2<f64>) -> Vec<usize> {
        let Some(grid) = self.world.grid.as_ref() else {
            return Vec::new();
        };
        let memory = &self.world.memory;
        let prisms = &self.world.prisms;
        match question {
            Question::PathAhead => {
                let Some(path) = &self.world.path else {
                    return Vec::new();
                };
                let rest = super::unseen::rest_of_path(path.waypoints(), here);
                unseen_along(
                    grid,
                    memory,
                    prisms,
                    &rest,
                    self.config.model.body.radius,
                    self.config.model.camera.max_range,
                )
            }
            Question::Push { target, .. } => {
                let Some(prism) = prisms.iter().find(|p| p.id == *target) else {
                    return Vec::new();
                };
                unseen_around(grid, memory, prism, prisms, self.push_ring())
            }
            Question::Way => self.way_targets(here),
        }
    }

    /// Whether enough floor around `prism` (where the robot would stand, where it would go) is still
    /// unseen to be worth a look: the object is seen only in part.
    pub(crate) fn seen_in_part(&self, prism: &nudge_perception::Prism) -> bool {
        let Some(grid) = self.world.grid.as_ref() else {
            return false;
        };
        let cells = unseen_around(
            grid,
            &self.world.memory,
            prism,
            &self.world.prisms,
            self.push_ring(),
        );
        let res = grid.geometry().resolution();
        cells.len() as f64 * res * res >= self.min_gain()
    }

    /// How far around an object the floor matters to pushing it (m): where the robot stands (up to
    /// the hand's reach plus its body's radius from the face) and where the object goes (the longest
    /// of the short pushes a test is planned among, and its margin: a long clearing push is planned
    /// once the object is known to move, from where its test left the robot).
    fn push_ring(&self) -> f64 {
        let push = &self.config.push;
        let longest = push
            .distances
            .iter()
            .copied()
            .filter(|d| *d <= nudge_motion::push::SHORT_PUSHES + 1e-9)
            .fold(0.0, f64::max)
            + push.distance_margin;
        (push.reach_x.1 + self.config.model.body.radius).max(longest)
    }

    /// The regions of `cells`, each with why it stays unseen.
    fn unseen_regions(&self, cells: &[usize]) -> Vec<UnseenRegion> {
        let Some(grid) = self.world.grid.as_ref() else {
            return Vec::new();
        };
        let memory = &self.world.memory;
        regions(grid.geometry(), cells, |i| memory.why(i))
    }

    /// Unseen floor that could open a way: the unseen cells inside obstacle outlines under the way
    /// the robot could take if they were free ([`nudge_motion::unseen_way`]); none when obstacles
    /// seen close every way.
    fn way_targets(&self, here: Point2<f64>) -> Vec<usize> {
        let Some(grid) = self.world.grid.as_ref() else {
            return Vec::new();
        };
        let memory = &self.world.memory;
        let seen = |i: usize| memory.seen(grid, i);
        let open = |i: usize| memory.open(grid, i);
        match unseen_way(
            grid,
            &self.world.prisms,
            self.config.cylinder(),
            self.config.validity.step_height,
            (here, self.config.goal, self.config.goal_tolerance),
            &seen,
            &open,
        ) {
            WayHypothesis::Closed => Vec::new(),
            WayHypothesis::Through(cells) => cells,
        }
    }

    /// The view planner's choice for `targets`.
    fn choose_view(&mut self, here: Point2<f64>, targets: &[usize]) -> Choice {
        let Some(grid) = self.world.grid.as_ref() else {
            return Choice::None("no obstacle-type grid".into());
        };
        let validity = match self.world.validity(&here, &self.config) {
            Ok(v) => v,
            Err(e) => return Choice::None(e),
        };
        let geometry = grid.geometry();
        let targets = Targets::uniform(targets.iter().filter_map(|&i| geometry.cell_at(i)));
        let scene = ViewScene {
            grid,
            prisms: &self.world.prisms,
            validity: &validity,
            robot: here,
            targets: &targets,
            seen_floor: Some(&self.world.memory.seen),
        };
        let config = ViewConfig {
            coverage: self.config.look_coverage(),
            walk_speed: self.config.model.body.walk_speed,
            look_time: self.world.look_time.max(1e-3),
            lattice_factor: 2,
            spacing: self.config.view.spacing,
            min_gain: self.min_gain(),
            clearance: 0.5 * self.config.clearance,
        };
        match plan_view(&scene, &config) {
            Ok(v) => {
                let cells = v.seen.iter().filter_map(|&c| geometry.index(c)).collect();
                Choice::View(
                    Viewpoint {
                        position: v.position,
                        yaw: v.yaw,
                        gain: v.gain,
                        walk: v.walk,
                        path: v.path,
                    },
                    cells,
                )
            }
            Err(e) => Choice::None(e.to_string()),
        }
    }
}
