//! Which floor has been seen: a push keeps the robot's stand pose on seen floor, and the object's sweep
//! on seen floor or in the object's own shadow.
//!
//! The robot walks only where it knows it can stand; the floor right behind an object it is about to
//! push is usually hidden by that object itself (a chair's back hides the floor behind it from any
//! camera in front), and pushing it there is what the guarded stroke is for: whatever stands in that
//! shadow stops the stroke at its force limit. Floor hidden by something else, or never in view at
//! all, is not pushed into until a look has shown it.

use nalgebra::Point2;

/// Whether the floor at a map point has been observed (crossed by a ray, or trodden by the robot).
pub trait SeenFloor {
    /// Whether the floor at `p` (map frame) has been seen.
    fn seen(&self, p: &Point2<f64>) -> bool;
}

/// Every point counts as seen: no floor check (the push planner before moving to see).
#[derive(Clone, Copy, Debug, Default)]
pub struct AllSeen;

impl SeenFloor for AllSeen {
    fn seen(&self, _: &Point2<f64>) -> bool {
        true
    }
}

/// How a push is checked against the floor seen so far.
#[derive(Clone, Copy)]
pub struct FloorCheck<'a> {
    /// What has been seen.
    pub seen: &'a dyn SeenFloor,
    /// How far behind the pushed object's footprint its own shadow reaches (m): unseen floor within
    /// this distance of the footprint, and behind it, may be swept (see the module's doc).
    pub own_shadow: f64,
    /// Where the shadow was cast from (map frame): the place of the look it was measured from.
    /// Floor counts as the object's own shadow only where the line of sight from here to it
    /// crosses the object; floor beside it, or hidden by a neighbour it touches, does not.
    pub eye: Point2<f64>,
}

impl FloorCheck<'_> {
    /// Whether the robot's disc of `radius` at `centre` stands on seen floor: its centre and two rings
    /// of sample points (half the radius, and just inside the rim).
    pub fn stands(&self, centre: &Point2<f64>, radius: f64) -> bool {
        const RING: usize = 8;
        let ring = |r: f64, k: usize, phase: f64| {
            let a = std::f64::consts::TAU * (k as f64 + phase) / RING as f64;
            centre + nalgebra::Vector2::new(a.cos(), a.sin()) * r
        };
        self.seen.seen(centre)
            && (0..RING).all(|k| {
                self.seen.seen(&ring(0.5 * radius, k, 0.0))
                    && self.seen.seen(&ring(0.9 * radius, k, 0.5))
            })
    }
}

/// The shadow an object of height `height` casts on the floor behind it, seen from an eye at
/// `eye_height` whose nearest view of its far side was `distance` away (m): the floor between the
/// object and `distance · eye / (eye − height)` is hidden by it. Infinite for an object as tall as the
/// eye or taller.
pub fn shadow_length(distance: f64, height: f64, eye_height: f64) -> f64 {
    if height >= eye_height {
        f64::INFINITY
    } else {
        (distance * height / (eye_height - height)).max(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct HalfPlane;
    impl SeenFloor for HalfPlane {
        fn seen(&self, p: &Point2<f64>) -> bool {
            p.x < 1.0
        }
    }

    #[test]
    fn a_disc_stands_on_seen_floor_only_when_all_of_it_is_seen() {
        // Invariant: a disc wholly on seen floor stands; one whose rim crosses into unseen floor does not.
        let check = FloorCheck {
            seen: &HalfPlane,
            own_shadow: 0.0,
            eye: Point2::origin(),
        };
        assert!(check.stands(&Point2::new(0.5, 0.0), 0.35));
        assert!(!check.stands(&Point2::new(0.8, 0.0), 0.35));
    }

    #[test]
    fn a_shadow_grows_with_distance_and_height() {
        // Invariant: the floor hidden behind an object is distance · h / (H − h), infinite for an object at or above the eye.
        assert!((shadow_length(2.0, 0.7, 1.4) - 2.0).abs() < 1e-12);
        assert!(shadow_length(2.0, 1.4, 1.4).is_infinite());
        assert_eq!(shadow_length(2.0, 0.0, 1.4), 0.0);
    }
}
