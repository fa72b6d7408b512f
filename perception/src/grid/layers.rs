//! The grid's per-cell storage, structure-of-arrays, and the frame-stamped histories the rules read.
//!
//! Nothing here is cleared per frame. A return history is a byte of bits (bit k = "happened at frame
//! `stamp − k`") plus the frame stamp of its latest bit; reading it at frame `f` shifts it by
//! `f − stamp`. Crossing histories are read the same way from the ring of per-frame bit-planes in
//! [`VisibleArea`]. So a frame touches only the returns and the rules' neighbourhoods per cell.

use super::visible::VisibleArea;
use crate::prism::ObjectId;

/// Object slot value for "no object".
pub(crate) const NO_OBJECT: u32 = u32::MAX;

/// Per-frame bookkeeping of one cell's returns, packed (8 bytes) so that a return and its
/// neighbourhood touch few cache lines. (Crossings live in [`VisibleArea`]; the classes, objects and
/// evidence stay structure-of-arrays.)
#[derive(Clone, Copy, Debug, Default)]
#[repr(C)]
pub(crate) struct Track {
    /// Stamp of `hit_bits`/`ts_bits`.
    pub hit_frame: u32,
    /// Frames with a return in the cell.
    pub hit_bits: u8,
    /// Frames in which the return in the cell was classified temporarily stationary (Tamura 3.3).
    pub ts_bits: u8,
}

/// Per-cell arrays, all of the grid's length, row-major.
#[derive(Clone, Debug)]
pub(crate) struct Layers {
    /// Class code ([`super::CellClass`]).
    pub class: Vec<u8>,
    /// Object id (`NO_OBJECT` for none).
    pub object: Vec<u32>,
    /// Packed evidence (see `evidence.rs`).
    pub evidence: Vec<u32>,
    /// Robot-clock stamp of the latest active verdict on the cell (NaN: none).
    pub marked_at: Vec<f64>,
    /// The rules' per-frame bookkeeping of returns.
    pub track: Vec<Track>,
    /// The last frames' visible areas (crossings).
    pub visible: VisibleArea,
    /// Frame stamp: the cell lies near a cell that was moving in the previous frame.
    pub near_moving: Vec<u32>,
    /// Frame stamp: the cell lies near a cell whose motion was confirmed in the previous frame.
    pub near_confirmed: Vec<u32>,
    /// Frame stamp: the cell was moving in that frame and near motion of the frame before
    /// (confirmed motion).
    pub confirmed: Vec<u32>,
    /// Watch generation stamp: the cell is on the executive's current path.
    pub watch: Vec<u32>,
    /// Robot-clock stamp of every frame, by frame number (entry 0: "never", NaN). 8 bytes per frame:
    /// a cell's last observation is its latest hit or crossing frame, looked up here, so a ray step
    /// writes no timestamp.
    pub stamps: Vec<f64>,
    /// Bit `i % 64` of word `i / 64`: cell `i` is Free. Kept with `class` by [`Self::set_class`],
    /// so that a frame finds the crossed cells that are not free a word at a time.
    pub free: Vec<u64>,
    /// Bit `i % 64` of word `i / 64`: cell `i` was ever observed — crossed by a ray, holding a
    /// return or given a verdict (exactly the cells whose `last_seen` is not NaN). Or-ed in where a
    /// frame's crossed words, its returns and the verdicts are visited anyway, so it costs a word
    /// per crossed word, not a sweep.
    pub observed: Vec<u64>,
}

impl Layers {
    pub fn new(n: usize) -> Self {
        Self {
            free: vec![0; n.div_ceil(64)],
            observed: vec![0; n.div_ceil(64)],
            class: vec![0; n],
            object: vec![NO_OBJECT; n],
            evidence: vec![0; n],
            marked_at: vec![f64::NAN; n],
            track: vec![Track::default(); n],
            visible: VisibleArea::new(n),
            near_moving: vec![0; n],
            near_confirmed: vec![0; n],
            confirmed: vec![0; n],
            watch: vec![0; n],
            stamps: vec![f64::NAN],
        }
    }

    /// Records that cell `i` was observed (see `observed`).
    #[inline]
    pub fn mark_observed(&mut self, i: usize) {
        if let Some(w) = self.observed.get_mut(i / 64) {
            *w |= 1 << (i % 64);
        }
    }

    /// Sets cell `i`'s class code (and its bit in `free`); returns the old code.
    #[inline]
    pub fn set_class(&mut self, i: usize, class: u8) -> u8 {
        let old = std::mem::replace(&mut self.class[i], class);
        let bit = 1u64 << (i % 64);
        if let Some(w) = self.free.get_mut(i / 64) {
            if class == super::CellClass::Free as u8 {
                *w |= bit;
            } else {
                *w &= !bit;
            }
        }
        old
    }

    /// The object in slot `i`.
    #[inline]
    pub fn object_at(&self, i: usize) -> Option<ObjectId> {
        let o = self.object[i];
        (o != NO_OBJECT).then_some(ObjectId(o))
    }

    /// Robot-clock stamp of the cell's latest observation or verdict (NaN: never).
    pub fn last_seen(&self, i: usize) -> f64 {
        let frame = self.track[i].hit_frame.max(self.visible.last_crossed(i)) as usize;
        let seen = self.stamps.get(frame).copied().unwrap_or(f64::NAN);
        let marked = self.marked_at[i];
        if seen.is_nan() || marked > seen {
            marked
        } else {
            seen
        }
    }

    /// Returns at `i` as seen from frame `f` (bit k = a return at frame f − k).
    #[inline]
    pub fn hits(&self, i: usize, f: u32) -> u8 {
        let t = &self.track[i];
        at(t.hit_bits, t.hit_frame, f)
    }

    /// Temporarily stationary returns at `i` as seen from frame `f`.
    #[inline]
    pub fn ts(&self, i: usize, f: u32) -> u8 {
        let t = &self.track[i];
        at(t.ts_bits, t.hit_frame, f)
    }

    /// Frames in which a ray crossed `i` (without ending there) at least the free gap before its return
    /// — the cell was seen free — as seen from frame `f`.
    #[cfg(test)]
    pub fn crossed(&self, i: usize, f: u32) -> u8 {
        self.visible.free(i, f)
    }

    /// Of the frames in `frames` (bit k: frame f − k), those in which a ray crossed `i` at least the
    /// free gap before its return (the cell was seen free), as seen from frame `f`; only those
    /// frames are read.
    #[inline]
    pub fn crossed_in_frames(&self, i: usize, f: u32, frames: u8) -> u8 {
        self.visible.free_in(i, f, frames)
    }

    /// Of the frames in `frames`, those in which a ray crossed `i` well before its return, as seen
    /// from frame `f`; only those frames are read.
    #[inline]
    pub fn crossed_far_in_frames(&self, i: usize, f: u32, frames: u8) -> u8 {
        self.visible.far_in(i, f, frames)
    }

    /// Frames in which a ray crossed `i` well before its return, as seen from frame `f`.
    #[cfg(test)]
    pub fn crossed_far(&self, i: usize, f: u32) -> u8 {
        self.visible.far(i, f)
    }

    /// True when `i` holds a return in frame `f`.
    #[inline]
    pub fn hit_in(&self, i: usize, f: u32) -> bool {
        self.track[i].hit_frame == f
    }

    /// True when a ray crossed `i` in frame `f` (however close to its return).
    #[inline]
    pub fn crossed_in(&self, i: usize, f: u32) -> bool {
        self.visible.crossed_in(i, f)
    }

    /// Marks this frame's return at `i` as temporarily stationary.
    #[inline]
    pub fn mark_ts(&mut self, i: usize) {
        self.track[i].ts_bits |= 1;
    }

    /// Records a return at `i` in frame `f`; true the first time in this frame.
    #[inline]
    pub fn record_hit(&mut self, i: usize, f: u32) -> bool {
        let t = &mut self.track[i];
        let last = t.hit_frame;
        if last == f {
            return false;
        }
        t.hit_bits = at(t.hit_bits, last, f) | 1;
        t.ts_bits = at(t.ts_bits, last, f);
        t.hit_frame = f;
        true
    }

    /// Records a ray crossing `i` in frame `f` (frames must not go back).
    #[cfg(test)]
    pub fn record_crossing(&mut self, i: usize, f: u32, how: Crossing) {
        self.visible.record(i, f, how);
    }
}

/// How far before its return a ray crossed a cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum Crossing {
    /// Within the free gap of the return: inside the return's range noise, possibly the surface
    /// itself. The cell was looked at (its age is renewed) but not seen free.
    Near,
    /// At least the free gap before the return (or along a beam without one): seen free.
    Free,
    /// At least the clear margin before the return: seen free through and through.
    Far,
}

impl Crossing {
    /// The kind as one bit of a cell's level byte (far 1, free 2, near 4): a frame's walks or
    /// these into a byte per cell, and [`super::visible::VisibleArea::fold_levels`] turns the
    /// bytes into bit-planes.
    #[inline]
    pub(crate) fn level(self) -> u8 {
        match self {
            Crossing::Far => 1,
            Crossing::Free => 2,
            Crossing::Near => 4,
        }
    }
}

/// History byte `bits` stamped at frame `last`, read at frame `f`.
#[inline]
pub(crate) fn at(bits: u8, last: u32, f: u32) -> u8 {
    // Branch-free (this runs once per crossed cell): a shift by 8 empties the byte, and a stamp from
    // the future wraps to a huge distance.
    let d = f.wrapping_sub(last);
    let shift = if last == 0 || d >= 8 { 8 } else { d };
    (u32::from(bits) << shift) as u8
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
        l.record_crossing(0, 2, Crossing::Free);
        l.record_crossing(0, 2, Crossing::Far);
        assert_eq!((l.crossed(0, 3), l.crossed_far(0, 3)), (0b10, 0b10));
        l.record_crossing(0, 4, Crossing::Near);
        assert_eq!((l.crossed(0, 4), l.crossed_far(0, 4)), (0b100, 0b100));
        assert_eq!(
            l.visible.last_crossed(0),
            4,
            "a near crossing still renews the age"
        );
    }
}
