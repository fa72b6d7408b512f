//! A push test that moved part of an obstacle: the obstacle becomes two (issue #58 item 4;
//! interactive segmentation, Katz & Brock 2008).
//!
//! Perception may take two touching things for one obstacle (a box flush beside a cabinet of its
//! colour and height). The push test's hand then moves the box, and colour ICP over the whole
//! obstacle sees little motion where most of its points stayed, or follows the box and carries the
//! cabinet's points with it where few did. After every stroke the hand travelled on, the points before and after the push are asked which of them moved
//! ([`nudge_perception::moved_part`]); when some did and some stayed, the part that moved keeps the
//! obstacle's id and this test's reading (of its own points), and the rest becomes an obstacle of
//! its own with no verdict (see [`super::world::WorldModel::split`]).

use nalgebra::{Isometry3, Point2, Translation3, UnitQuaternion, Vector2};
use nudge_perception::prism::convex_intersection_area;
use nudge_perception::{ColourCloud, MovedPartConfig, Prism, moved_part};

use super::Runner;
use super::push::{crop as crop_around, icp_reading};
use crate::push_test::{IcpReading, PushIntent};
use crate::record::{LogLevel, Observer};
use crate::robot::Robot;

/// What the push test saw of the obstacle before and after its stroke.
pub(super) struct TestClouds<'a> {
    /// The obstacle as perception gave it, where it stood before the test's stroke.
    pub prism: &'a Prism,
    /// Its points before the stroke (cropped with a margin around where it stood, map frame).
    pub before: &'a ColourCloud,
    /// The whole view taken after the stroke (map frame).
    pub view: &'a ColourCloud,
    /// How far a test before this one slid it from where the prism stands (map frame).
    pub slid_by: Vector2<f64>,
    /// The hand's travel after contact, along the push (map frame).
    pub shift: Vector2<f64>,
    /// Where the hand met its face before the stroke moved it (map frame).
    pub face: Point2<f64>,
}

/// A split the push test made.
pub(super) struct Split {
    /// Colour ICP over the moved part's own points, with its planar displacement.
    pub reading: Option<(IcpReading, Vector2<f64>)>,
}

impl<R: Robot, O: Observer> Runner<R, O> {
    /// Splits the test's obstacle in two where the hand moved part of it (see the module's doc).
    /// Asked whatever ICP read of the whole: a block a quarter of the obstacle's points does not
    /// keep ICP from following the rest, and the block would go with the box. `None` (nothing
    /// changed) when the hand travelled too little for a face to leave its place ([`MovedPartConfig::on_surface`] twice: once for each cloud's noise), or
    /// when the points do not say the obstacle is two, or the part that moved is not where the
    /// hand met the obstacle.
    pub(super) fn split_what_moved(
        &mut self,
        intent: &PushIntent,
        seen: &TestClouds<'_>,
    ) -> Option<Split> {
        let config = MovedPartConfig::default();
        if seen.shift.norm() <= 2.0 * config.on_surface {
            return None;
        }
        let margin = self.config.push_motion.crop_margin;
        let prism = seen.prism;
        let min_thickness = self.config.perception.prism.min_thickness;
        // Where the obstacle stood and where the part that moved went.
        let swept = prism.merged_with(&prism.transformed(&planar(seen.shift)));
        let after = crop_around(seen.view, &swept, seen.slid_by, margin);
        // Only the obstacle's own points answer: what stood beside it within the crop's margin is
        // something else, whatever it did.
        let own = |p: &nalgebra::Point3<f32>| {
            let q = Point2::new(f64::from(p.x), f64::from(p.y)) - seen.slid_by;
            prism.distance_xy(&q) <= config.on_surface
        };
        let before = keep_points(seen.before, own);
        let part = moved_part(&before, &after, &planar(seen.shift), &config)?;
        let at_before = |p: &nalgebra::Point3<f32>| {
            let mut q = *p;
            q.x += seen.slid_by.x as f32;
            q.y += seen.slid_by.y as f32;
            part.moved_at(&q)
        };
        let moved = prism.with_points_where(at_before, min_thickness)?;
        let rest = prism.with_points_where(|p| !at_before(p), min_thickness)?;
        // Two solid things cannot stand in one place: what stayed lies where it stood, the part
        // that moved where the motion took it, and a rest more than half inside that is the moved
        // part's own (a face that turned with it, read against a motion that did not turn).
        let went = moved.transformed(&part.motion).footprint;
        let inside = convex_intersection_area(&rest.footprint, &went);
        if inside > 0.5 * super::fragments::area(&rest.footprint) {
            return None;
        }
        // The hand pushed what moved: a split whose moving part lies off the hand's face is
        // something else moving (a person's leg in the crop), not what the test asked about.
        let reach = self.config.push.hand_half_width + config.on_surface;
        if moved.distance_xy(&(seen.face - seen.slid_by)) > reach {
            return None;
        }
        let moved_before = keep_points(&before, |p| part.moved_at(p));
        let moved_after = crop_around(seen.view, &moved, seen.slid_by + seen.shift, margin);
        let reading = icp_reading(&moved_before, &moved_after, seen.shift);
        let stayed = match self.world.split(intent.target, moved, rest) {
            Some(id) => format!("what stayed is {id}, untested"),
            None => "what stayed was a strip of the obstacle beside it, dropped".into(),
        };
        let stamp = self.robot.now();
        self.observer.note(
            stamp,
            LogLevel::Info,
            &format!(
                "push test split {}: {} of its points moved with the hand and {} stayed; {stayed}",
                intent.target, part.moved_points, part.stayed_points
            ),
        );
        Some(Split { reading })
    }
}

/// The planar motion by `shift` (map frame).
fn planar(shift: Vector2<f64>) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(shift.x, shift.y, 0.0),
        UnitQuaternion::identity(),
    )
}

/// The points of `cloud` that `keep` accepts.
fn keep_points(cloud: &ColourCloud, keep: impl Fn(&nalgebra::Point3<f32>) -> bool) -> ColourCloud {
    let mut out = ColourCloud::empty(cloud.frame(), *cloud.sensor_pose(), cloud.stamp());
    for (_, p, c) in cloud.iter_valid().filter(|(_, p, _)| keep(p)) {
        out.push(p, c);
    }
    out
}
