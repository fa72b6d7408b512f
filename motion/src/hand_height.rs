//! How high the hand pushes on a face: low enough that the object slides before it tips, on a
//! part of the face that is solid.
//!
//! An object of depth `d` (along the push) standing on a floor, pushed at height `h`, pivots on its
//! far edge once `F h > m g d / 2` (its weight acts at its centre) and slides once `F > μ m g`. It
//! slides first when `h < d / (2 μ)`. The robot knows neither `m` nor `μ`, but μ of furniture on a
//! floor is bounded ([`PushConfig::max_floor_friction`]), so a push at or below `d / (2 μ_max)`
//! never tips what it could slide. A tipping object reads as static at the limit (it locks against
//! the palm as it pitches), so the push test is pushed there where the face allows.
//!
//! Where the face is not solid that low (a table's legs, a chair's legs under its seat) the hand
//! would meet nothing, or a leg, or catch a thin edge with its rim: it pushes near the top as the
//! paper does.

use nalgebra::{Point2, Unit, Vector2};
use nudge_perception::Prism;

use crate::obstacle::Obstacle;
use crate::push::PushConfig;

/// Share of the face's width (as far as any of its points show it) that the points at a height
/// must cover for the face to count as solid there: most of it, so the hand lands on the surface
/// wherever along the face its contact is planned.
pub const SOLID_COVER: f64 = 0.5;

/// Where the hand pushes on one face (m above the floor).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandHeights {
    /// In the push test: below tipping where the face is solid that low (when
    /// [`PushConfig::test_below_tipping`]), else the paper's height.
    pub test: f64,
    /// In the strokes that clear the way: the paper's height, just below the face's top (clearing
    /// low as well saved none of the runs the option loses: BENCHMARKS.md, "Push test sweep"). An
    /// object that tipped under a test is cleared at the height its retest slid it.
    pub clear: f64,
}

/// The heights the hand pushes at on the face from `a` to `b` (outward normal `outward`) of
/// `object`, whose cluster is `prism`, with the hand's middle at each of `ats` along the face (0 at
/// `a`, 1 at `b`), in that order; `None` where no part of the face is within the hand's reach.
///
/// The paper's height is the top of the surface facing the robot, less a margin; where the face's
/// points on the hand's line (within the hand's width of it) all lie below the hand at that height,
/// the top of those instead. A face's top elsewhere along it is not the hand's: a chair seen from its
/// side shows the end of its back 0.4 m higher than the seat under the hand's line, and a hand at the
/// back's height passes over the seat and meets nothing. Above the tipping-safe height it is lowered
/// to the highest height at or below that one where the face is solid; a face solid only higher up (a
/// chair's seat and back, a table's top) keeps the paper's.
pub fn hand_heights_on(
    a: &Point2<f64>,
    b: &Point2<f64>,
    outward: &Unit<Vector2<f64>>,
    ats: &[f64],
    object: &Obstacle,
    prism: &Prism,
    config: &PushConfig,
) -> Vec<Option<HandHeights>> {
    // The face's points, gathered once for every place along it the hand is asked about.
    let near: Vec<(f64, f64)> = near_face(a, b, outward, prism, config).collect();
    let face_top = highest(near.iter().map(|(_, z)| *z))
        .unwrap_or(object.z_max())
        .min(object.z_max());
    // The hand at the face's height spans down to its lower edge; a surface on its line lower than
    // that, it passes over.
    let hand_bottom = face_top - config.hand_below_top - config.hand_half_height;
    let half = config.hand_half_width / (b - a).norm().max(1e-9);
    let (low, high) = config.reach_z;
    let bottom = object.z_min().max(low);
    let safe = depth_along(object.footprint(), a, outward) / (2.0 * config.max_floor_friction);
    // Only a face that may be pushed lower is cut into slots: planning asks every face of every
    // candidate, and most never need it.
    let mut slotted: Option<FacePoints> = None;
    ats.iter()
        .map(|&at| {
            let line_top = highest(
                near.iter()
                    .filter(|(t, _)| (t - at).abs() <= half)
                    .map(|(_, z)| *z),
            );
            let top = line_top.filter(|z| *z < hand_bottom).unwrap_or(face_top);
            let paper = (top - config.hand_below_top).min(high);
            if paper < bottom {
                return None;
            }
            let heights = |test| HandHeights { test, clear: paper };
            if !config.test_below_tipping || paper <= safe {
                return Some(heights(paper));
            }
            let face = slotted.get_or_insert_with(|| FacePoints::near(a, b, &near, config));
            // The middle half of the hand on the surface: a thin edge (a chair's seat) caught by
            // the hand's rim turns the push into a lift.
            let solid = |h: f64| face.cover(h, config.hand_half_height / 2.0) >= SOLID_COVER;
            let below =
                heights_down(safe.min(paper), bottom, config.hand_half_height).find(|h| solid(*h));
            Some(heights(below.unwrap_or(paper)))
        })
        .collect()
}

/// The largest of `zs`, if any.
fn highest(zs: impl Iterator<Item = f64>) -> Option<f64> {
    zs.fold(None, |m: Option<f64>, z| Some(m.map_or(z, |m| m.max(z))))
}

/// How deep the footprint reaches behind the face through `a` with outward normal `outward` (m).
fn depth_along(footprint: &[Point2<f64>], a: &Point2<f64>, outward: &Unit<Vector2<f64>>) -> f64 {
    footprint
        .iter()
        .map(|v| (a - v).dot(outward))
        .fold(0.0, f64::max)
}

/// Heights from `from` down to `to`, `step` apart.
fn heights_down(from: f64, to: f64, step: f64) -> impl Iterator<Item = f64> {
    (0..)
        .map(move |k| from - f64::from(k) * step)
        .take_while(move |h| *h >= to - 1e-9)
}

/// The object's points near one face: where along it (as a slot of the face's width) and how
/// high.
struct FacePoints {
    /// `(slot, z)` per point.
    points: Vec<(usize, f64)>,
    /// Slots along the face.
    slots: usize,
}

/// The points of `prism` within the face band of the face from `a` to `b`: where along the face
/// (0 at `a`, 1 at `b`) and how high.
fn near_face<'a>(
    a: &'a Point2<f64>,
    b: &'a Point2<f64>,
    outward: &'a Unit<Vector2<f64>>,
    prism: &'a Prism,
    config: &'a PushConfig,
) -> impl Iterator<Item = (f64, f64)> + 'a {
    let edge = b - a;
    let len2 = edge.norm_squared();
    prism.points.iter_valid().filter_map(move |(_, p, _)| {
        let q = Point2::new(f64::from(p.x), f64::from(p.y));
        let depth = -(q - a).dot(outward);
        let t = (q - a).dot(&edge) / len2;
        (depth.abs() <= config.face_band && (-0.05..=1.05).contains(&t))
            .then_some((t, f64::from(p.z)))
    })
}

impl FacePoints {
    /// The face from `a` to `b` cut into slots of the footprint's cell (the finest width perception
    /// resolves), with its points `near` it ([`near_face`]: where along it, how high).
    fn near(a: &Point2<f64>, b: &Point2<f64>, near: &[(f64, f64)], config: &PushConfig) -> Self {
        let slots = (((b - a).norm() / config.footprint_cell).ceil() as usize).max(1);
        let points = near
            .iter()
            .map(|&(t, z)| {
                let slot = (t.clamp(0.0, 1.0) * slots as f64) as usize;
                (slot.min(slots - 1), z)
            })
            .collect();
        Self { points, slots }
    }

    /// Share of the slots any point shows that points within `half` of height `h` cover.
    fn cover(&self, h: f64, half: f64) -> f64 {
        let mut any = vec![false; self.slots];
        let mut at = vec![false; self.slots];
        for (slot, z) in &self.points {
            any[*slot] = true;
            at[*slot] |= (z - h).abs() <= half;
        }
        let shown = any.iter().filter(|s| **s).count();
        if shown == 0 {
            return 0.0;
        }
        at.iter().filter(|s| **s).count() as f64 / shown as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Isometry3;
    use nalgebra::Point3;
    use nudge_perception::{CloudFrame, ColourCloud, ObjectId};

    /// A prism over the footprint `[x0, x1] × [y0, y1]` with points on its near face (x = x0)
    /// wherever `solid(y, z)` holds, on a 2 cm grid up to `top`.
    fn prism_with_face(
        x: (f64, f64),
        y: (f64, f64),
        top: f64,
        solid: impl Fn(f64, f64) -> bool,
    ) -> Prism {
        let mut points = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
        let mut yy = y.0;
        while yy <= y.1 {
            let mut z = 0.0;
            while z <= top {
                if solid(yy, z) {
                    points.push(
                        Point3::new(x.0 as f32, yy as f32, z as f32),
                        [100, 100, 100],
                    );
                }
                z += 0.02;
            }
            yy += 0.02;
        }
        Prism {
            id: ObjectId(1),
            footprint: vec![
                Point2::new(x.0, y.0),
                Point2::new(x.1, y.0),
                Point2::new(x.1, y.1),
                Point2::new(x.0, y.1),
            ],
            z_min: 0.0,
            z_max: top,
            points,
        }
    }

    /// The height on the face at x = x0, pushed along +x.
    fn height(prism: &Prism) -> Option<f64> {
        let object = Obstacle::from_prism(prism).expect("a valid prism");
        let f = &prism.footprint;
        let outward = Unit::new_normalize(Vector2::new(-1.0, 0.0));
        // The face runs from (x0, y1) to (x0, y0) counter-clockwise.
        hand_heights_on(
            &f[3],
            &f[0],
            &outward,
            &[0.5],
            &object,
            prism,
            &PushConfig {
                test_below_tipping: true,
                ..PushConfig::default()
            },
        )[0]
        .map(|h| h.test)
    }

    #[test]
    fn a_tall_solid_box_is_pushed_low_enough_to_slide_before_it_tips() {
        // Invariant: on a face solid all the way down, the hand pushes at or below d / (2 μ_max).
        let prism = prism_with_face((3.0, 3.6), (0.4, 1.0), 0.7, |_, _| true);
        let h = height(&prism).expect("a face within reach");
        let safe = 0.6 / (2.0 * PushConfig::default().max_floor_friction);
        assert!(h <= safe + 1e-6, "pushed at {h} m, tips above {safe} m");
        assert!(
            h >= PushConfig::default().reach_z.0,
            "pushed at {h} m, below the reach"
        );
    }

    #[test]
    fn without_testing_below_tipping_a_tall_box_is_pushed_just_below_its_top() {
        // Invariant: without `test_below_tipping` the push test keeps the paper's height.
        let prism = prism_with_face((3.0, 3.6), (0.4, 1.0), 0.7, |_, _| true);
        let object = Obstacle::from_prism(&prism).expect("a valid prism");
        let f = &prism.footprint;
        let outward = Unit::new_normalize(Vector2::new(-1.0, 0.0));
        let config = PushConfig {
            test_below_tipping: false,
            ..PushConfig::default()
        };
        let h = hand_heights_on(&f[3], &f[0], &outward, &[0.5], &object, &prism, &config)[0]
            .expect("a face within reach");
        assert!((h.test - h.clear).abs() < 1e-12, "{h:?}");
        assert!(
            (h.test - (0.7 - config.hand_below_top)).abs() < 0.021,
            "{h:?}"
        );
    }

    #[test]
    fn a_table_is_pushed_at_its_top_where_only_legs_stand_below() {
        // Invariant: a face solid only near its top (legs below) is pushed near the top.
        let prism = prism_with_face((3.0, 3.8), (0.4, 1.6), 0.72, |y, z| {
            z >= 0.66 || !(0.46..=1.54).contains(&y)
        });
        let h = height(&prism).expect("a face within reach");
        assert!(
            (0.6..=0.72).contains(&h),
            "pushed at {h} m, off the table's top"
        );
    }

    #[test]
    fn a_chair_seen_from_its_side_is_pushed_at_its_seat_not_its_backs_height() {
        // Invariant: the hand's height follows the face's top on the hand's own line; the end of a chair's back elsewhere along the face does not lift it over the seat.
        let seat_top = 0.45;
        // The side of a chair 0.5 m deep: its back's end (2 cm) at y = 0.4 rises to 0.85 m, the
        // seat's edge (4 cm) runs along the whole side, legs at both ends below it.
        let prism = prism_with_face((3.0, 3.5), (0.4, 0.9), 0.85, |y, z| {
            let back = y <= 0.42;
            let seat = (seat_top - 0.04..=seat_top).contains(&z);
            let leg = z < seat_top && !(0.44..=0.86).contains(&y);
            back || seat || leg
        });
        let object = Obstacle::from_prism(&prism).expect("a valid prism");
        let f = &prism.footprint;
        let outward = Unit::new_normalize(Vector2::new(-1.0, 0.0));
        let config = PushConfig::default();
        let at = |t: f64| {
            hand_heights_on(&f[3], &f[0], &outward, &[t], &object, &prism, &config)[0]
                .expect("a face within reach")
                .clear
        };
        let under_seat = seat_top - config.hand_below_top;
        assert!((at(0.5) - under_seat).abs() < 0.021, "middle: {}", at(0.5));
        assert!((at(0.3) - under_seat).abs() < 0.021, "at 0.3: {}", at(0.3));
        // On the back's end the hand meets the back.
        assert!((at(1.0) - (0.85 - config.hand_below_top)).abs() < 0.021);
    }

    #[test]
    fn a_low_box_is_pushed_below_its_top_as_the_paper_does() {
        // Invariant: an object too low to tip is pushed at its top less the margin.
        let prism = prism_with_face((3.0, 3.6), (0.4, 1.0), 0.4, |_, _| true);
        let h = height(&prism).expect("a face within reach");
        assert!(
            (h - (0.4 - PushConfig::default().hand_below_top)).abs() < 0.021,
            "{h}"
        );
    }
}
