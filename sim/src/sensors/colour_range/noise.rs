//! The sensor's noise: a counter-based random stream per ray, so a capture is the same whatever the
//! thread count.

use std::convert::Infallible;

use rand::TryRng;
use rand_distr::{Distribution, StandardNormal};

/// A standard normal draw.
pub(super) fn gaussian(rng: &mut RayRng) -> f64 {
    StandardNormal.sample(rng)
}

/// SplitMix64 keyed by (frame seed, ray index): a counter-based stream per ray, so a ray's noise never
/// depends on which thread traced it or on what the other rays hit.
pub(super) struct RayRng {
    pub(super) state: u64,
}

/// SplitMix64's increment (2^64 / φ).
const GOLDEN_GAMMA: u64 = 0x9e37_79b9_7f4a_7c15;

/// SplitMix64's output finaliser: a bijective, well-mixed hash of one word.
pub(super) fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl RayRng {
    pub(super) fn new(frame_seed: u64, ray: usize) -> Self {
        let key = mix64(frame_seed.wrapping_add(GOLDEN_GAMMA));
        Self {
            state: mix64(key ^ mix64((ray as u64).wrapping_mul(GOLDEN_GAMMA))),
        }
    }
}

impl TryRng for RayRng {
    type Error = Infallible;

    fn try_next_u32(&mut self) -> Result<u32, Infallible> {
        self.try_next_u64().map(|v| (v >> 32) as u32)
    }

    fn try_next_u64(&mut self) -> Result<u64, Infallible> {
        self.state = self.state.wrapping_add(GOLDEN_GAMMA);
        Ok(mix64(self.state))
    }

    fn try_fill_bytes(&mut self, dst: &mut [u8]) -> Result<(), Infallible> {
        for chunk in dst.chunks_mut(8) {
            let bytes = self.try_next_u64()?.to_le_bytes();
            chunk.copy_from_slice(&bytes[..chunk.len()]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_noise_streams_depend_only_on_seed_and_ray() {
        // A ray's stream is fixed by (seed, ray) and differs between rays and between seeds.
        let draw = |seed, ray| {
            let mut r = RayRng::new(seed, ray);
            [gaussian(&mut r), gaussian(&mut r)]
        };
        assert_eq!(draw(7, 100), draw(7, 100));
        assert_ne!(draw(7, 100), draw(7, 101));
        assert_ne!(draw(7, 100), draw(8, 100));
    }

    #[test]
    fn ray_noise_is_standard_normal() {
        // Draws across many rays have mean ≈ 0 and variance ≈ 1.
        let n = 200_000;
        let draws: Vec<f64> = (0..n).map(|i| gaussian(&mut RayRng::new(3, i))).collect();
        let mean = draws.iter().sum::<f64>() / n as f64;
        let var = draws.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.01, "mean {mean}");
        assert!((var - 1.0).abs() < 0.02, "variance {var}");
    }
}
