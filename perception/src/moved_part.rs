//! Which part of an obstacle a push moved: interactive segmentation (Katz & Brock 2008; Bohg et
//! al., "Interactive Perception", 2017). Perception cannot always tell two touching things apart
//! (a box flush against a cabinet of its colour and height); a push that moves one of them can.
//!
//! Each point of the obstacle before the push is asked two questions of the cloud after it: is
//! there a surface where the point was (it *stayed*), and is there one where the push's motion
//! would have carried it (it *moved*)? A face across the push answers one of them only: the
//! pushed object's near face has left its old place and lies where the motion takes it; the
//! cabinet's face beside it is where it was and not a push's length on. Points inside a surface
//! that slides along itself (a top, a side along the push) answer both, and points hidden after
//! the push answer neither; they go with the nearer of the points that answered one. The motion
//! is first the hand's travel, then the colour ICP of the part that moved (the object may turn).

use nalgebra::{Isometry3, Point3};

use crate::icp::PointTree;
use crate::{ColourCloud, IcpConfig, colour_icp};

/// How the points of an obstacle are told apart after a push.
#[derive(Clone, Debug, PartialEq)]
pub struct MovedPartConfig {
    /// A point lies on a surface of the cloud after the push when that cloud has a point within
    /// this distance of it (m). Default 0.012: colour ICP's finest correspondence distance (the
    /// last of [`IcpConfig::max_correspondence`]), a few widths of the range noise at the arm's
    /// reach, above the point spacing there (the paper's camera, 43.6° over 176 pixels: 4.3 mrad,
    /// 6.5 mm at 1.5 m).
    pub on_surface: f64,
    /// Fewest points that must answer each way (moved only, stayed only) for the obstacle to be
    /// two. Default 20: the fewest points colour ICP reads a motion from
    /// ([`IcpConfig::min_points`]), so that the part that moved gets a reading of its own.
    pub min_points: usize,
    /// A point's answer counts only when at least half of its this many nearest neighbours in the
    /// obstacle gave the same one: a face is a patch of the sensor's samples, which answer
    /// together, where a lone point of range noise or of an edge's mixed pixel answers alone.
    /// Default 6, a sample's ring of neighbours on the sensor's grid.
    pub neighbours: usize,
}

impl Default for MovedPartConfig {
    fn default() -> Self {
        Self {
            on_surface: *IcpConfig::default()
                .max_correspondence
                .last()
                .unwrap_or(&0.012),
            min_points: IcpConfig::default().min_points,
            neighbours: 6,
        }
    }
}

/// What a point of the obstacle answered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Answer {
    /// Only where the motion carried it is there a surface now.
    Moved,
    /// Only where it was is there a surface now.
    Stayed,
    /// Both, or neither: it says nothing.
    Silent,
}

/// The split of an obstacle's points into the part a push moved and the part that stayed.
pub struct MovedPart {
    /// The points of the obstacle before the push that answered, and whether each moved.
    labelled: PointTree,
    moved: Vec<bool>,
    /// The motion of the part that moved (map frame).
    pub motion: Isometry3<f64>,
    /// How many of the points before the push went with the part that moved.
    pub moved_points: usize,
    /// How many stayed.
    pub stayed_points: usize,
}

impl std::fmt::Debug for MovedPart {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MovedPart")
            .field("motion", &self.motion)
            .field("moved_points", &self.moved_points)
            .field("stayed_points", &self.stayed_points)
            .finish_non_exhaustive()
    }
}

impl MovedPart {
    /// Whether point `p` (map frame, where the obstacle stood before the push) belongs to the part
    /// that moved: the nearest of the points the split was made from went with it.
    pub fn moved_at(&self, p: &Point3<f32>) -> bool {
        self.labelled
            .nearest(&[p.x, p.y, p.z])
            .is_some_and(|(i, _)| self.moved[i])
    }
}

/// Splits the obstacle whose points before a push are `before` by the cloud `after` it (both map
/// frame, cropped to where the obstacle stood and where it went), starting from the motion `guess`
/// (the hand's travel). `None` when the points do not say the obstacle is two: fewer than
/// [`MovedPartConfig::min_points`] of them answer "moved" or fewer answer "stayed" (the whole
/// moved, or nothing did), or the part that moved does not stay two after its own motion is
/// measured.
pub fn moved_part(
    before: &ColourCloud,
    after: &ColourCloud,
    guess: &Isometry3<f64>,
    config: &MovedPartConfig,
) -> Option<MovedPart> {
    let points: Vec<[f32; 3]> = before.iter_valid().map(|(_, p, _)| p.into()).collect();
    let targets: Vec<[f32; 3]> = after.iter_valid().map(|(_, p, _)| p.into()).collect();
    if points.len() < 2 * config.min_points || targets.len() < config.min_points {
        return None;
    }
    let after_tree = PointTree::new(&targets);
    let before_tree = PointTree::new(&points);
    let first = split(&points, &before_tree, &after_tree, guess, guess, config)?;
    // The part that moved, measured on its own: the hand's travel is along the push, the object
    // may have turned or slid aside.
    let mut part = ColourCloud::empty(before.frame(), *before.sensor_pose(), before.stamp());
    for ((_, p, c), moved) in before.iter_valid().zip(&first.0) {
        if *moved {
            part.push(p, c);
        }
    }
    // The measured motion is kept where it explains at least as many points as the guess: along a
    // face that slides on itself (a box's front and top, no texture across the push) ICP has
    // nothing to hold it and may drift a centimetre or two, which the guess does not.
    let (moved, motion) = match colour_icp(&part, after, guess, &IcpConfig::default()) {
        Ok(r) => match split(
            &points,
            &before_tree,
            &after_tree,
            &r.transform,
            guess,
            config,
        ) {
            Some(refined) if refined.1 >= first.1 => (refined.0, r.transform),
            _ => (first.0, *guess),
        },
        Err(_) => (first.0, *guess),
    };
    let moved_points = moved.iter().filter(|m| **m).count();
    Some(MovedPart {
        labelled: before_tree,
        stayed_points: moved.len() - moved_points,
        moved,
        motion,
        moved_points,
    })
}

/// Which of `points` moved by `motion`, part of a `push` (the hand's travel): each answers on its own, answers its neighbours do not
/// share are dropped, and every point goes with the nearer of the points that kept an answer; with
/// how many kept the answer "moved". `None` unless at least `min_points` kept each answer.
fn split(
    points: &[[f32; 3]],
    before: &PointTree,
    after: &PointTree,
    motion: &Isometry3<f64>,
    push: &Isometry3<f64>,
    config: &MovedPartConfig,
) -> Option<(Vec<bool>, usize)> {
    let on = (config.on_surface * config.on_surface) as f32;
    let near = |q: [f32; 3]| after.nearest(&q).is_some_and(|(_, d)| d <= on);
    let answers: Vec<Answer> = points
        .iter()
        .map(|p| {
            let here = Point3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]));
            let there = motion * here;
            let carried = [there.x as f32, there.y as f32, there.z as f32];
            match (near(carried), near(*p)) {
                (true, false) => Answer::Moved,
                (false, true) => Answer::Stayed,
                _ => Answer::Silent,
            }
        })
        .collect();
    // Answers the neighbourhood shares (the point itself is its own nearest neighbour).
    let k = config.neighbours + 1;
    let kept: Vec<Answer> = points
        .iter()
        .zip(&answers)
        .map(|(p, a)| {
            if *a == Answer::Silent {
                return Answer::Silent;
            }
            let same = before
                .nearest_k(p, k)
                .iter()
                .filter(|(i, _)| answers[*i] == *a)
                .count();
            if 2 * (same - 1) >= config.neighbours {
                *a
            } else {
                Answer::Silent
            }
        })
        .collect();
    let seeds = |answer: Answer| -> Vec<[f32; 3]> {
        points
            .iter()
            .zip(&kept)
            .filter(|(_, a)| **a == answer)
            .map(|(p, _)| *p)
            .collect()
    };
    let (moved, stayed) = (seeds(Answer::Moved), seeds(Answer::Stayed));
    if moved.len() < config.min_points || stayed.len() < config.min_points {
        return None;
    }
    // A silent point lies on a surface that slid along itself (or was hidden): along the push it
    // may be the whole slide from the answers of its own face, across it no farther than the
    // samples' spacing. So the nearest answer is sought with distances along the push (the hand's
    // line: ICP's measure of the motion may drift along a face) shrunk by the slide's length over
    // the on-surface distance: a slide's length along counts as one on-surface distance across.
    let shift = push.translation.vector.xy();
    let along = shift.try_normalize(1e-9);
    let shrink = (config.on_surface / shift.norm().max(config.on_surface)) as f32;
    let squeeze = |p: &[f32; 3]| -> [f32; 3] {
        let Some(u) = along else { return *p };
        let (ux, uy) = (u.x as f32, u.y as f32);
        let a = p[0] * ux + p[1] * uy;
        let c = -p[0] * uy + p[1] * ux;
        [a * shrink, c, p[2]]
    };
    let squeezed = |v: &[[f32; 3]]| v.iter().map(squeeze).collect::<Vec<_>>();
    let (moved_tree, stayed_tree) = (
        PointTree::new(&squeezed(&moved)),
        PointTree::new(&squeezed(&stayed)),
    );
    let distance =
        |tree: &PointTree, p: &[f32; 3]| tree.nearest(&squeeze(p)).map_or(f32::INFINITY, |h| h.1);
    let labels = points
        .iter()
        .zip(&kept)
        .map(|(p, a)| match a {
            Answer::Moved => true,
            Answer::Stayed => false,
            Answer::Silent => distance(&moved_tree, p) < distance(&stayed_tree, p),
        })
        .collect();
    Some((labels, moved.len()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::CloudFrame;
    use nalgebra::{Translation3, UnitQuaternion};

    /// Samples of an axis-aligned box's faces that a camera at the -x side sees: the near face (x
    /// = `x0`) and the top (1 cm grid), striped so that colour ICP has texture to hold on to.
    fn box_faces(
        cloud: &mut ColourCloud,
        (x0, y0): (f32, f32),
        (dx, dy, h): (f32, f32, f32),
        colour: u8,
    ) {
        let step = 0.01;
        let mut put = |p: Point3<f32>| {
            let stripe = (((p.x + p.y + p.z) / 0.05).floor() as i32).rem_euclid(2) as u8;
            cloud.push(p, [colour, colour / 2 + 60 * stripe, 40]);
        };
        let n = |len: f32| (len / step).round() as usize;
        for i in 0..=n(dy) {
            for j in 0..=n(h) {
                put(Point3::new(
                    x0,
                    y0 + i as f32 * step,
                    0.03 + j as f32 * step,
                ));
            }
        }
        for i in 1..=n(dx) {
            for j in 0..=n(dy) {
                put(Point3::new(
                    x0 + i as f32 * step,
                    y0 + j as f32 * step,
                    h + 0.03,
                ));
            }
        }
    }

    fn cloud() -> ColourCloud {
        ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0)
    }

    fn shove(x: f64) -> Isometry3<f64> {
        Isometry3::from_parts(Translation3::new(x, 0.0, 0.0), UnitQuaternion::identity())
    }

    /// A light box (y 0–0.4) flush beside a cabinet of its height (y 0.4–1.0), seen as one: before
    /// and after the box alone slid `slide` m away along +x.
    fn pair(slide: f32) -> (ColourCloud, ColourCloud) {
        let (mut before, mut after) = (cloud(), cloud());
        box_faces(&mut before, (1.0, 0.0), (0.4, 0.4, 0.6), 200);
        box_faces(&mut before, (1.0, 0.4), (0.4, 0.6, 0.6), 200);
        box_faces(&mut after, (1.0 + slide, 0.0), (0.4, 0.4, 0.6), 200);
        box_faces(&mut after, (1.0, 0.4), (0.4, 0.6, 0.6), 200);
        (before, after)
    }

    #[test]
    fn a_box_pushed_away_from_the_cabinet_it_stood_flush_beside_is_split_off() {
        // Invariant: of one obstacle made of two touching things, the points of the one the push
        // moved go with the part that moved, and those of the one that stayed do not.
        let (before, after) = pair(0.12);
        let part = moved_part(&before, &after, &shove(0.12), &MovedPartConfig::default())
            .expect("two parts");
        for (_, p, _) in before.iter_valid() {
            // A centimetre's band either side of the seam may go either way.
            if (p.y - 0.4).abs() > 0.015 {
                assert_eq!(part.moved_at(&p), p.y < 0.4, "point {p:?}");
            }
        }
        assert!((part.motion.translation.vector.x - 0.12).abs() < 0.01);
    }

    #[test]
    fn an_obstacle_that_moved_whole_or_not_at_all_is_not_split() {
        // Invariant: a split needs points that moved and points that stayed; one rigid body, moved
        // or still, is one.
        let (mut before, mut after) = (cloud(), cloud());
        box_faces(&mut before, (1.0, 0.0), (0.4, 1.0, 0.6), 200);
        box_faces(&mut after, (1.12, 0.0), (0.4, 1.0, 0.6), 200);
        let config = MovedPartConfig::default();
        assert!(moved_part(&before, &after, &shove(0.12), &config).is_none());
        assert!(moved_part(&before, &before, &shove(0.12), &config).is_none());
    }
}
