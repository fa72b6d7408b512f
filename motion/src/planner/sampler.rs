//! Where RRT-Connect looks next: uniform samples, plus bridge-test samples where a tree was blocked.
//!
//! The bridge test (Hsu et al. 2003, "The bridge test for sampling narrow passages") draws a point in
//! collision, a second one a Gaussian step away, and keeps their midpoint only when both ends are in
//! collision and the midpoint is free: a short "bridge" across a gap. Such midpoints crowd into narrow
//! passages, which uniform samples almost never hit. Drawn uniformly over the whole space, the first
//! end is rarely near a passage and each bridge costs about a hundred point checks (more than the
//! iterations it saves, measured on the narrow passages A and Z). So the bridges are centred where a
//! tree's extension was just blocked: a tree stuck against a wall is blocked near the wall's gaps
//! as often as anywhere else along it. A bridge found becomes the next sample, for the tree that was
//! blocked. Every other sample is uniform, so the sampler's support is still the whole space and the
//! planner stays probabilistically complete; every draw comes from the seeded generator.

use nalgebra::{Point2, Vector2};
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

use super::Metered;

/// How RRT-Connect draws its samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    /// Bridge attempts after each blocked extension (0: uniform sampling only).
    pub bridge_attempts: usize,
    /// Standard deviation (m) of the Gaussian steps: from the blocked end to a bridge's first end,
    /// and from there to its second end. About the thickness of the obstacles grown by the robot's
    /// radius works best: bridges must reach across a passage from obstacle to obstacle.
    pub bridge_spread: f64,
}

impl Default for Sampling {
    fn default() -> Self {
        // Tuned on the narrow passages A and Z (200 seeds): 4 attempts cut the p90 iterations of Z
        // from 3 582 to 1 348 for about two point checks per iteration; more attempts save few more
        // iterations than the point checks they cost.
        Self {
            bridge_attempts: 4,
            bridge_spread: 0.5,
        }
    }
}

impl Sampling {
    /// A uniform sample of the space.
    pub(crate) fn uniform(&self, v: &Metered, rng: &mut ChaCha8Rng) -> Point2<f64> {
        v.bounds().sample(rng)
    }

    /// A bridge midpoint near `blocked` (where an extension was just blocked), if one of
    /// `bridge_attempts` attempts finds one.
    pub(crate) fn bridge_near(
        &self,
        blocked: &Point2<f64>,
        v: &Metered,
        rng: &mut ChaCha8Rng,
    ) -> Option<Point2<f64>> {
        let spread = self.bridge_spread;
        if !(spread.is_finite() && spread > 0.0) {
            return None;
        }
        for _ in 0..self.bridge_attempts {
            let a = blocked + gaussian(rng) * spread;
            if v.is_free(&a) {
                continue;
            }
            let b = a + gaussian(rng) * spread;
            if v.is_free(&b) {
                continue;
            }
            let mid = nalgebra::center(&a, &b);
            if v.is_free(&mid) {
                return Some(mid);
            }
        }
        None
    }
}

/// A standard normal 2D vector (Box–Muller).
fn gaussian(rng: &mut ChaCha8Rng) -> Vector2<f64> {
    // 1 - u lies in (0, 1], so the logarithm is finite.
    let u: f64 = 1.0 - rng.random::<f64>();
    let t: f64 = rng.random::<f64>() * std::f64::consts::TAU;
    let r = (-2.0 * u.ln()).sqrt();
    Vector2::new(r * t.cos(), r * t.sin())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::Budget;
    use crate::space::Bounds;
    use crate::validity::StateValidity;
    use rand::SeedableRng;

    /// Free everywhere except a wall at 4 ≤ y ≤ 6 with a gap 4.95 < x < 5.05.
    struct Slit(Bounds);

    impl StateValidity for Slit {
        fn is_free(&self, p: &Point2<f64>) -> bool {
            self.0.contains(p) && !((4.0..=6.0).contains(&p.y) && (p.x - 5.0).abs() >= 0.05)
        }
        fn motion_free(&self, a: &Point2<f64>, b: &Point2<f64>) -> bool {
            (0..=1000).all(|k| {
                let t = f64::from(k) / 1000.0;
                self.is_free(&Point2::from(a.coords.lerp(&b.coords, t)))
            })
        }
        fn sampling_bounds(&self) -> &Bounds {
            &self.0
        }
    }

    #[test]
    fn bridges_land_in_the_gap() {
        // Invariant: every bridge midpoint is free, and near a wall they land in its gap, not beside it.
        let slit =
            Slit(Bounds::new(Point2::new(0.0, 0.0), Point2::new(10.0, 10.0)).expect("bounds"));
        let v = Metered::new(&slit, &Budget::iterations(1));
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let sampling = Sampling::default();
        let bridges: Vec<_> = (0..2_000)
            .filter_map(|_| sampling.bridge_near(&Point2::new(5.2, 3.9), &v, &mut rng))
            .collect();
        assert!(bridges.len() > 20, "only {} bridges", bridges.len());
        assert!(bridges.iter().all(|p| slit.is_free(p)));
        assert!(
            bridges
                .iter()
                .all(|p| (4.0..=6.0).contains(&p.y) && (p.x - 5.0).abs() < 0.05)
        );
    }

    #[test]
    fn no_spread_means_no_bridges() {
        // Invariant: a zero or non-finite spread disables bridges instead of sampling nonsense.
        let slit =
            Slit(Bounds::new(Point2::new(0.0, 0.0), Point2::new(10.0, 10.0)).expect("bounds"));
        let v = Metered::new(&slit, &Budget::iterations(1));
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        for spread in [0.0, f64::NAN, -1.0] {
            let sampling = Sampling {
                bridge_attempts: 64,
                bridge_spread: spread,
            };
            assert_eq!(
                sampling.bridge_near(&Point2::new(5.2, 3.9), &v, &mut rng),
                None
            );
        }
    }
}
