//! The grid's per-cell storage, structure-of-arrays, and the frame-stamped histories the rules read.
//!
//! Nothing here is cleared per frame. Each history is a byte of bits (bit k = "happened at frame
//! `stamp − k`") plus the frame stamp of its latest bit; reading it at frame `f` shifts it by
//! `f − stamp`. So a frame touches only the cells its rays cross and the rules' neighbourhoods.

use crate::prism::ObjectId;

/// Object slot value for "no object".
pub(crate) const NO_OBJECT: u32 = u32::MAX;

/// Per-cell arrays, all of the grid's length, row-major.
#[derive(Clone, Debug)]
pub(crate) struct Layers {
    /// Class code ([`super::CellClass`]).
    pub class: Vec<u8>,
    /// Object id (`NO_OBJECT` for none).
    pub object: Vec<u32>,
    /// Robot-clock stamp of the last observation (NaN: never).
    pub last_seen: Vec<f64>,
    /// Packed evidence (see `evidence.rs`).
    pub evidence: Vec<u32>,
    /// Frames with a return in the cell.
    pub hit_bits: Vec<u8>,
    /// Frames in which the return in the cell was classified temporarily stationary (Tamura 3.3);
    /// shares `hit_frame` as its stamp.
    pub ts_bits: Vec<u8>,
    /// Stamp of `hit_bits`/`ts_bits`.
    pub hit_frame: Vec<u32>,
    /// Frames in which a ray crossed the cell (without ending in it).
    pub free_bits: Vec<u8>,
    /// Frames in which a ray crossed the cell at least the clear margin before its return.
    pub far_bits: Vec<u8>,
    /// Stamp of `free_bits`/`far_bits`.
    pub free_frame: Vec<u32>,
    /// Frame stamp: the cell lies near a cell that was moving in the previous frame.
    pub near_moving: Vec<u32>,
    /// Watch generation stamp: the cell is on the executive's current path.
    pub watch: Vec<u32>,
}

impl Layers {
    pub fn new(n: usize) -> Self {
        Self {
            class: vec![0; n],
            object: vec![NO_OBJECT; n],
            last_seen: vec![f64::NAN; n],
            evidence: vec![0; n],
            hit_bits: vec![0; n],
            ts_bits: vec![0; n],
            hit_frame: vec![0; n],
            free_bits: vec![0; n],
            far_bits: vec![0; n],
            free_frame: vec![0; n],
            near_moving: vec![0; n],
            watch: vec![0; n],
        }
    }

    /// The object in slot `i`.
    #[inline]
    pub fn object_at(&self, i: usize) -> Option<ObjectId> {
        let o = self.object[i];
        (o != NO_OBJECT).then_some(ObjectId(o))
    }

    /// Returns at `i` as seen from frame `f` (bit k = a return at frame f − k).
    #[inline]
    pub fn hits(&self, i: usize, f: u32) -> u8 {
        at(self.hit_bits[i], self.hit_frame[i], f)
    }

    /// Temporarily stationary returns at `i` as seen from frame `f`.
    #[inline]
    pub fn ts(&self, i: usize, f: u32) -> u8 {
        at(self.ts_bits[i], self.hit_frame[i], f)
    }

    /// Frames in which a ray crossed `i` (without ending there) as seen from frame `f`.
    #[inline]
    pub fn crossed(&self, i: usize, f: u32) -> u8 {
        at(self.free_bits[i], self.free_frame[i], f)
    }

    /// Frames in which a ray crossed `i` well before its return, as seen from frame `f`.
    #[inline]
    pub fn crossed_far(&self, i: usize, f: u32) -> u8 {
        at(self.far_bits[i], self.free_frame[i], f)
    }

    /// Records a return at `i` in frame `f`; true the first time in this frame.
    #[inline]
    pub fn record_hit(&mut self, i: usize, f: u32) -> bool {
        let last = self.hit_frame[i];
        if last == f {
            return false;
        }
        self.hit_bits[i] = at(self.hit_bits[i], last, f) | 1;
        self.ts_bits[i] = at(self.ts_bits[i], last, f);
        self.hit_frame[i] = f;
        true
    }

    /// Records a ray crossing `i` in frame `f` (`far`: well before its return); true the first time.
    #[inline]
    pub fn record_crossing(&mut self, i: usize, f: u32, far: bool) -> bool {
        let last = self.free_frame[i];
        if last == f {
            self.far_bits[i] |= far as u8;
            return false;
        }
        self.free_bits[i] = at(self.free_bits[i], last, f) | 1;
        self.far_bits[i] = at(self.far_bits[i], last, f) | far as u8;
        self.free_frame[i] = f;
        true
    }
}

/// History byte `bits` stamped at frame `last`, read at frame `f`.
#[inline]
pub(crate) fn at(bits: u8, last: u32, f: u32) -> u8 {
    match f.checked_sub(last) {
        Some(d) if last != 0 && d < 8 => bits << d,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histories_shift_with_the_frame_counter_and_expire() {
        // Invariant: bit k read at frame f means "recorded at frame f − k", for k < 8, never later.
        let mut l = Layers::new(1);
        assert!(l.record_hit(0, 3));
        assert!(!l.record_hit(0, 3));
        assert!(l.record_hit(0, 5));
        assert_eq!(l.hits(0, 5), 0b101);
        assert_eq!(l.hits(0, 6), 0b1010);
        assert_eq!(l.hits(0, 12), 0b1000_0000);
        assert_eq!(l.hits(0, 13), 0);
        assert_eq!(l.hits(0, 4), 0, "a stamp from the future reads as nothing");
        l.record_crossing(0, 2, false);
        l.record_crossing(0, 2, true);
        assert_eq!((l.crossed(0, 3), l.crossed_far(0, 3)), (0b10, 0b10));
    }
}
