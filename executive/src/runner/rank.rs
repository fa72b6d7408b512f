//! Ordering push candidates by the run's policy.

use nalgebra::Point2;
use nudge_motion::blocking_obstacles;
use nudge_perception::ObjectId;

use super::world::WorldModel;
use super::{Interrupt, Runner};
use crate::config::CandidatePolicy;
use crate::event::{Candidate, Event, SetAside, SetAsideWhy};
use crate::record::Observer;
use crate::robot::Robot;

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Ranks the pushable obstacles: nearest first, or those whose removal opens the cheapest path first.
    pub(crate) fn rank(&mut self, policy: CandidatePolicy, exclude: &[ObjectId]) -> Event {
        let here = match self.robot.base_pose() {
            Ok(p) => Point2::from(p.value.translation.vector),
            Err(e) => return Interrupt::Robot(e).into(),
        };
        let validity = match self.world.validity(&here, &self.config) {
            Ok(v) => v,
            Err(e) => return Event::PerceptionFailed(e),
        };
        // Candidates: obstacles that block the robot (not stepped over, not passed under), not
        // settled, not room structure, small enough to push; the others are set aside, saying why.
        // A low box flush against a wall is a candidate: only a top out of view makes structure.
        let limit = self.config.max_candidate_extent;
        let mut set_aside = Vec::new();
        let mut by_distance: Vec<(f64, ObjectId)> = Vec::new();
        for p in self
            .world
            .prisms
            .iter()
            .filter(|p| !exclude.contains(&p.id))
        {
            let Some(obstacle) = validity.obstacle(p.id) else {
                continue;
            };
            let extent = p.extent();
            // A push test's finding outweighs how the object looks: one found movable (or moved by
            // a push) that came to rest clear of everything else is pushed again while it is small
            // enough, its top seen or not. Resting against something, its outline may have taken
            // that in.
            let known = self.world.objects.get(p.id);
            let moves =
                (known.movable() || known.ever_moved()) && !self.world.rests_against_another(p);
            let why = if !moves && self.world.is_structure(p, &self.config) {
                SetAsideWhy::Structure
            } else if extent > limit {
                SetAsideWhy::TooLarge { extent, limit }
            } else {
                by_distance.push((obstacle.distance_to_point(&here), p.id));
                continue;
            };
            set_aside.push(SetAside { id: p.id, why });
        }
        by_distance.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let nearest: Vec<ObjectId> = by_distance.iter().map(|(_, id)| *id).collect();
        let ordered = match policy {
            CandidatePolicy::Nearest => nearest,
            CandidatePolicy::Blocking => {
                let problem = match WorldModel::problem(&here, &self.config) {
                    Ok(p) => p,
                    Err(e) => return Event::PerceptionFailed(e),
                };
                let reports = blocking_obstacles(
                    &problem,
                    &validity,
                    &nearest,
                    &self.config.blocking,
                    &mut self.rng,
                );
                // Openers first, cheapest path first (the report's order); then the rest, nearest first.
                let mut ordered: Vec<ObjectId> = reports
                    .iter()
                    .filter(|r| r.opens_path())
                    .map(|r| r.object)
                    .collect();
                let rest: Vec<ObjectId> = nearest
                    .iter()
                    .copied()
                    .filter(|id| !ordered.contains(id))
                    .collect();
                ordered.extend(rest);
                ordered
            }
        };
        let mut ranked: Vec<Candidate> = ordered
            .into_iter()
            .map(|id| {
                let prism = self.world.prisms.iter().find(|p| p.id == id);
                Candidate {
                    id,
                    passively_movable: prism.is_some_and(|p| self.passively_movable(p)),
                    moved_lately: prism.is_some_and(|p| self.moved_lately(p)),
                    seen_moving: prism.is_some_and(|p| self.seen_moving(p)),
                }
            })
            .collect();
        // Excluded obstacles that moved lately go last: the machine will not push them, but when
        // nothing else is left it waits for them to walk on rather than give up.
        ranked.extend(
            self.world
                .prisms
                .iter()
                .filter(|p| exclude.contains(&p.id) && self.moved_lately(p))
                .map(|p| Candidate {
                    id: p.id,
                    passively_movable: false,
                    moved_lately: true,
                    seen_moving: true,
                }),
        );
        Event::CandidatesRanked { ranked, set_aside }
    }
}
