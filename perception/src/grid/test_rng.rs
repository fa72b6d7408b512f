//! A seeded xorshift generator for the grid's randomised tests: every test draws the same
//! sequence from the same seed, with no dependency.

/// The xorshift64 sequence from `seed` (not zero).
pub(crate) fn xorshift(mut seed: u64) -> impl FnMut() -> u64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    }
}

/// Numbers uniform in `[0, 1)` from `seed` (the top 53 bits of [`xorshift`]).
pub(crate) fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut next = xorshift(seed);
    move || (next() >> 11) as f64 / (1u64 << 53) as f64
}
