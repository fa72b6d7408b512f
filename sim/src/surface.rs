//! What a collider looks like and whom it belongs to: the range sensor colours its returns from this.

use nalgebra::Point3;

use crate::scenario::Texture;

/// Edge of one stripe or checker square (m).
const PATTERN_CELL: f64 = 0.05;
/// Edge of one noise patch (m).
const NOISE_CELL: f64 = 0.02;
/// The darker shade of a pattern is this fraction of the main colour.
const DARK_SHADE: f64 = 0.6;
/// Legs of furniture are this fraction of the main colour, so parts read apart.
const LEG_SHADE: f64 = 0.8;
/// Shifts the pattern grid off the round numbers object faces sit on, so a flat face never lies on a
/// cell boundary where rounding noise would speckle it.
const GRID_OFFSET: f64 = 0.0123;

/// The thing a collider is part of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Owner {
    /// The floor slab.
    Floor,
    /// One of the room's walls.
    Wall,
    /// The scenario object with this index in `Scenario::objects`.
    Object(usize),
    /// The scenario actor with this index in `Scenario::actors`.
    Actor(usize),
    /// Any part of the robot (body, head, hand).
    Robot,
}

/// The appearance and owner of one collider.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Surface {
    /// Main colour, RGB 0–255.
    pub colour: [u8; 3],
    /// How the colour varies over the surface.
    pub texture: Texture,
    /// What the collider belongs to.
    pub owner: Owner,
    /// For a compound collider (furniture): its parts from this index on are legs, seen a shade
    /// darker than the rest. `None`: every part looks alike.
    pub legs_from: Option<usize>,
}

impl Surface {
    /// One plain-looking surface (no legs).
    pub fn new(colour: [u8; 3], texture: Texture, owner: Owner) -> Self {
        Self {
            colour,
            texture,
            owner,
            legs_from: None,
        }
    }

    /// How part `k` of the collider looks: legs take a darker colour.
    pub fn of_part(&self, k: usize) -> Self {
        let leg = self.legs_from.is_some_and(|first| k >= first);
        Self {
            colour: if leg {
                self.colour.map(|c| (f64::from(c) * LEG_SHADE) as u8)
            } else {
                self.colour
            },
            legs_from: None,
            ..*self
        }
    }

    /// The colour seen at `local_point`, a point on the surface in the collider's local frame (m).
    ///
    /// The pattern is fixed to the collider, so it moves with the object — what colour ICP needs.
    /// Stripes: 5 cm diagonal bands in x+y (visible on every vertical face); checker: 5 cm cubes;
    /// noise: each 2 cm cube gets a shade between the dark shade and the full colour, hashed with `seed`.
    /// The dark shade is 60 % of the colour.
    pub fn colour_at(&self, local_point: Point3<f64>, seed: u64) -> [u8; 3] {
        let cell = |v: f64, size: f64| ((v + GRID_OFFSET) / size).floor() as i64;
        let factor = match self.texture {
            Texture::Plain => 1.0,
            Texture::Stripes => {
                let band = cell(local_point.x + local_point.y, PATTERN_CELL);
                if band.rem_euclid(2) == 0 {
                    1.0
                } else {
                    DARK_SHADE
                }
            }
            Texture::Checker => {
                let parity = cell(local_point.x, PATTERN_CELL)
                    + cell(local_point.y, PATTERN_CELL)
                    + cell(local_point.z, PATTERN_CELL);
                if parity.rem_euclid(2) == 0 {
                    1.0
                } else {
                    DARK_SHADE
                }
            }
            Texture::Noise => {
                let h = hash_cell(
                    seed,
                    cell(local_point.x, NOISE_CELL),
                    cell(local_point.y, NOISE_CELL),
                    cell(local_point.z, NOISE_CELL),
                );
                // Top 53 bits → uniform in [0, 1).
                let u = (h >> 11) as f64 / (1u64 << 53) as f64;
                DARK_SHADE + (1.0 - DARK_SHADE) * u
            }
        };
        // The shaded value is never negative, so adding a half and truncating rounds half away from
        // zero as `round` does, and the saturating cast clamps to 255; `round` itself is a libm call
        // on baseline x86-64, a fifth of this function's cost per pixel.
        self.colour.map(|c| (f64::from(c) * factor + 0.5) as u8)
    }
}

/// A well-mixed 64-bit hash of a seed and a cell index (SplitMix64 finaliser over each word).
fn hash_cell(seed: u64, x: i64, y: i64, z: i64) -> u64 {
    let mix = |mut v: u64| {
        v = (v ^ (v >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        v = (v ^ (v >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        v ^ (v >> 31)
    };
    let mut h = mix(seed ^ 0x9e37_79b9_7f4a_7c15);
    for w in [x, y, z] {
        h = mix(h ^ (w as u64).wrapping_add(0x9e37_79b9_7f4a_7c15));
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    fn surface(texture: Texture) -> Surface {
        Surface::new([200, 100, 50], texture, Owner::Object(0))
    }

    #[test]
    fn plain_is_the_colour_everywhere() {
        // A plain surface shows its main colour at every point.
        let s = surface(Texture::Plain);
        for p in [Point3::new(0.0, 0.0, 0.0), Point3::new(0.31, -0.7, 1.2)] {
            assert_eq!(s.colour_at(p, 7), [200, 100, 50]);
        }
    }

    #[test]
    fn stripes_alternate_every_five_centimetres() {
        // Stripes show the colour and the 60 % shade in alternate 5 cm bands along x + y.
        let s = surface(Texture::Stripes);
        let a = s.colour_at(Point3::new(0.0, 0.0, 0.3), 1);
        let b = s.colour_at(Point3::new(0.05, 0.0, 0.3), 1);
        let c = s.colour_at(Point3::new(0.10, 0.0, 0.3), 1);
        assert_ne!(a, b);
        assert_eq!(a, c);
        let shades = [a, b];
        assert!(shades.contains(&[200, 100, 50]));
        assert!(shades.contains(&[120, 60, 30]));
    }

    #[test]
    fn checker_flips_along_each_axis() {
        // A checker flips shade when any one coordinate crosses a 5 cm cell.
        let s = surface(Texture::Checker);
        let o = s.colour_at(Point3::new(0.0, 0.0, 0.0), 1);
        for p in [
            Point3::new(0.05, 0.0, 0.0),
            Point3::new(0.0, 0.05, 0.0),
            Point3::new(0.0, 0.0, 0.05),
        ] {
            assert_ne!(s.colour_at(p, 1), o);
        }
    }

    #[test]
    fn noise_is_fixed_by_seed_and_varies_between_patches() {
        // Noise is the same for the same seed and point, stays within [60 %, 100 %] of the colour,
        // and differs between patches and between seeds.
        let s = surface(Texture::Noise);
        let pts: Vec<Point3<f64>> = (0..50)
            .map(|i| Point3::new(0.02 * f64::from(i), 0.0, 0.0))
            .collect();
        let a: Vec<[u8; 3]> = pts.iter().map(|p| s.colour_at(*p, 3)).collect();
        let again: Vec<[u8; 3]> = pts.iter().map(|p| s.colour_at(*p, 3)).collect();
        let other: Vec<[u8; 3]> = pts.iter().map(|p| s.colour_at(*p, 4)).collect();
        assert_eq!(a, again);
        assert_ne!(a, other);
        let distinct: std::collections::HashSet<[u8; 3]> = a.iter().copied().collect();
        assert!(distinct.len() > 10);
        assert!(a.iter().all(|c| c[0] >= 120 && c[0] <= 200));
    }
}
