//! Moving to see: which unseen floor matters to the question asked, and where to look from.

use nalgebra::Point2;

use super::unseen::{regions, unseen_along, unseen_around};
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

    /// Least unseen area worth a walk and a look (m²): a strip one grid cell deep across the robot's
    /// width, the least a way the robot fits through can cross.
    pub(crate) fn min_gain(&self) -> f64 {
        let res = self
            .world
            .grid
            .as_ref()
            .map_or(0.05, |g| g.geometry().resolution());
        2.0 * self.config.robot.radius * res
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
                    self.config.robot.radius,
                    self.config.view.camera.max_range,
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

    /// How far around an object the floor matters to pushing it (m): where the robot stands (up to
    /// the hand's reach plus its body's radius from the face) and where the object goes (the longest
    /// push tried, and its margin).
    fn push_ring(&self) -> f64 {
        let push = &self.config.push;
        let longest = push.distances.iter().copied().fold(0.0, f64::max) + push.distance_margin;
        (push.reach_x.1 + self.config.robot.radius).max(longest)
    }

    /// The regions of `cells`, each with why it stays unseen.
    fn unseen_regions(&self, cells: &[usize]) -> Vec<UnseenRegion> {
        let Some(grid) = self.world.grid.as_ref() else {
            return Vec::new();
        };
        let memory = &self.world.memory;
        regions(grid.geometry(), cells, |i| memory.why(i))
    }

    /// Unseen floor that could open a way: see [`super::hypothesis`].
    fn way_targets(&self, here: Point2<f64>) -> Vec<usize> {
        let _ = here;
        Vec::new()
    }

    /// The view planner's choice for `targets`.
    fn choose_view(&mut self, here: Point2<f64>, targets: &[usize]) -> Choice {
        let _ = (here, targets, UnseenWhy::ViewLimit);
        Choice::None("the view planner is not built yet".into())
    }
}
