//! The visible areas V_t of the last few frames, as bit-planes: which cells rays crossed, and how far
//! before their returns.
//!
//! Each frame owns one slot of a ring of [`SLOTS`] frames. A slot holds three bit-planes over the
//! whole grid (bit `i % 64` of word `i / 64` is cell `i`), one per [`Crossing`] kind: the cells whose
//! best crossing this frame was far, free or near. A ray sets a run of bits per grid row it crosses,
//! so a walk writes one word per row instead of a history per cell, and cells seen free again cost
//! nothing beyond their bits: the ring (four slots of 180 kB for 800 × 600 cells) stays in cache
//! where per-cell histories would not. The rules read at most frames t, t−1 and t−2.
//!
//! A cell's last crossing older than the ring is kept per cell: when a slot is reused, the cells it
//! saw that no newer slot saw get its frame number (`older`), so [`VisibleArea::last_crossed`] is
//! exact however long ago.

use super::geometry::{GridGeometry, floor};
#[cfg(any(test, doc))]
use super::layers::Crossing;
use wide::{bytemuck, u8x16, u16x8};

/// Frames kept: t and the three before (the rules read t, t−1 and t−2).
pub(crate) const SLOTS: usize = 4;

/// Plane index of each crossing kind within a word group, and of their union (filled in by
/// [`VisibleArea::for_each_crossed_word`] at the end of the frame, read when the slot is reused).
const FAR: usize = 0;
const FREE: usize = 1;
const NEAR: usize = 2;
const ANY: usize = 3;

/// One word of each plane.
type Group = [u64; 4];

/// The last [`SLOTS`] frames' crossings of every cell of a grid.
#[derive(Clone, Debug)]
pub(crate) struct VisibleArea {
    /// Cells in the grid.
    n: usize,
    /// Words per plane (`n / 64` rounded up).
    words: usize,
    /// Slot `s`'s words at `s * words .. (s + 1) * words`, each `[far, free, near, any]`.
    planes: Vec<Group>,
    /// The frame each slot holds (0: none).
    frame: [u32; SLOTS],
    /// The cells each slot may have set.
    span: [CellBox; SLOTS],
    /// Per cell: the latest frame it was crossed in that has left the ring (0: none).
    older: Vec<u32>,
    /// The latest frame retired so far (0: none), so at least every `older` entry.
    retired: u32,
}

impl VisibleArea {
    /// An empty ring for `n` cells.
    pub fn new(n: usize) -> Self {
        let words = n.div_ceil(64);
        Self {
            n,
            words,
            planes: vec![[0; 4]; words * SLOTS],
            frame: [0; SLOTS],
            span: [CellBox::EMPTY; SLOTS],
            older: vec![0; n],
            retired: 0,
        }
    }

    /// Makes frame `f` the ring's current frame, reusing the slot of frame `f − SLOTS` (or whatever
    /// older frame it holds). Returns false, and does nothing, when the slot already holds a newer
    /// frame (frames must not go back) or `f` is 0.
    pub fn begin(&mut self, f: u32) -> bool {
        let s = f as usize % SLOTS;
        let held = self.frame[s];
        if f == 0 || held > f {
            return false;
        }
        if held == f {
            return true;
        }
        if held != 0 {
            self.retire(s);
        }
        self.frame[s] = f;
        self.span[s] = CellBox::EMPTY;
        true
    }

    /// Folds slot `s`'s cells that no newer slot saw into `older`, and clears the slot.
    fn retire(&mut self, s: usize) {
        let held = self.frame[s];
        // The newer slots, oldest first: the frame after `held` saw most of what it saw, so one
        // slot's union usually leaves nothing gone and the others need not be read.
        let mut newer = [0; SLOTS];
        let mut count = 0;
        for t in (0..SLOTS).filter(|&t| t != s && self.frame[t] > held) {
            newer[count] = t;
            count += 1;
        }
        newer[..count].sort_unstable_by_key(|&t| self.frame[t]);
        let newer = newer.map(|t| t * self.words);
        let newer = &newer[..count];
        let in_order = held >= self.retired;
        let base = s * self.words;
        for k in self.span[s].words(self.words) {
            let w = self.planes[base + k];
            let mut gone = w[FAR] | w[FREE] | w[NEAR];
            if gone | w[ANY] == 0 {
                continue;
            }
            self.planes[base + k] = [0; 4];
            for &t in newer {
                if gone == 0 {
                    break;
                }
                gone &= !self.planes[t + k][ANY];
            }
            while gone != 0 {
                let i = k * 64 + gone.trailing_zeros() as usize;
                gone &= gone - 1;
                if let Some(o) = self.older.get_mut(i) {
                    // Frames retire in order unless some were skipped: then no entry is newer, and
                    // a plain store (which waits on no cache miss, as reading the entry would) is
                    // the max.
                    *o = if in_order { held } else { (*o).max(held) };
                }
            }
        }
        self.retired = self.retired.max(held);
    }

    /// The writer of frame `f`'s slot, if `f` is the current frame (after [`Self::begin`]`(f)`).
    pub fn writer(&mut self, f: u32) -> Option<SlotWriter<'_>> {
        let s = f as usize % SLOTS;
        if f == 0 || self.frame[s] != f {
            return None;
        }
        let words = &mut self.planes[s * self.words..(s + 1) * self.words];
        Some(SlotWriter {
            words,
            span: &mut self.span[s],
        })
    }

    /// Records one crossing of cell `i` in frame `f` (frames must not go back).
    #[cfg(test)]
    pub fn record(&mut self, i: usize, f: u32, how: Crossing) {
        if self.begin(f)
            && let Some(mut w) = self.writer(f)
        {
            w.or_word(i / 64, how, 1 << (i % 64));
            w.cover(CellBox::cell(i));
        }
    }

    /// The `[far, free, near, any]` words holding cell `i`'s bits for frame `g`, if the ring holds `g`.
    #[inline]
    fn word(&self, i: usize, g: u32) -> Option<Group> {
        let s = g as usize % SLOTS;
        if g == 0 || self.frame[s] != g || i >= self.n {
            return None;
        }
        Some(self.planes[s * self.words + i / 64])
    }

    /// History byte of cell `i` as seen from frame `f` (bit k: frame f − k), from `pick` applied to
    /// the frame's `[far, free, near]` words, of the frames set in `frames` (the others' bits 0 and
    /// their slots not read: a rule asking about one or two frames reads one or two words).
    #[inline]
    fn history(&self, i: usize, f: u32, frames: u8, pick: impl Fn(Group) -> u64) -> u8 {
        let mut bits = 0u8;
        for k in 0..SLOTS as u32 {
            if frames >> k & 1 == 0 {
                continue;
            }
            let Some(g) = f.checked_sub(k) else { break };
            if let Some(w) = self.word(i, g) {
                bits |= ((pick(w) >> (i % 64) & 1) as u8) << k;
            }
        }
        bits
    }

    /// Frames in which `i` was crossed at least the free gap before the return (seen free), as seen
    /// from frame `f`: bit k = frame f − k, k < [`SLOTS`].
    #[cfg(test)]
    pub fn free(&self, i: usize, f: u32) -> u8 {
        self.free_in(i, f, 0b1111)
    }

    /// Of the frames in `frames` (bit k: frame f − k), those in which `i` was crossed at least the
    /// free gap before the return, as seen from frame `f`; only those frames are read.
    #[inline]
    pub fn free_in(&self, i: usize, f: u32, frames: u8) -> u8 {
        self.history(i, f, frames, |w| w[FAR] | w[FREE])
    }

    /// Frames in which `i` was crossed at least the clear margin before the return, as seen from `f`.
    #[cfg(test)]
    pub fn far(&self, i: usize, f: u32) -> u8 {
        self.far_in(i, f, 0b1111)
    }

    /// Of the frames in `frames`, those in which `i` was crossed at least the clear margin before
    /// the return, as seen from frame `f`; only those frames are read.
    #[inline]
    pub fn far_in(&self, i: usize, f: u32, frames: u8) -> u8 {
        self.history(i, f, frames, |w| w[FAR])
    }

    /// True when a ray crossed `i` in frame `f`, however near its return.
    #[inline]
    pub fn crossed_in(&self, i: usize, f: u32) -> bool {
        self.word(i, f)
            .is_some_and(|w| (w[FAR] | w[FREE] | w[NEAR]) >> (i % 64) & 1 != 0)
    }

    /// The latest frame in which a ray crossed `i` (0: never).
    pub fn last_crossed(&self, i: usize) -> u32 {
        let ring = (0..SLOTS)
            .filter(|&s| self.frame[s] != 0 && self.crossed_in(i, self.frame[s]))
            .map(|s| self.frame[s])
            .max()
            .unwrap_or(0);
        ring.max(self.older.get(i).copied().unwrap_or(0))
    }

    /// Folds a frame's level bytes (one per cell, or-ed [`Crossing::level`]s; see
    /// `Traversal::for_each_cell`) of the cells in `cells` (and any others of their grid words)
    /// into frame `f`'s planes, and zeroes them; then calls `crossed(k, bits)` for every word `k` of
    /// them with cells crossed this frame (however near their returns), in increasing `k`. Other
    /// bytes are left alone; `level` is as long as the grid. Call it once the frame's walks are
    /// done (it records the union for [`Self::begin`]).
    pub fn fold_levels(
        &mut self,
        f: u32,
        level: &mut [u8],
        cells: CellBox,
        mut crossed: impl FnMut(usize, u64),
    ) {
        let n = self.n;
        let Some(mut out) = self.writer(f) else {
            return;
        };
        for k in cells.words(out.words.len()) {
            let lo = k * 64;
            let planes = if let Some(bytes) = level
                .get_mut(lo..lo + 64)
                .and_then(|b| <&mut [u8; 64]>::try_from(b).ok())
            {
                fold_word(bytes)
            } else if let Some(bytes) = level.get_mut(lo..n) {
                // The grid's last, partial word.
                let mut word = [0u8; 64];
                let Some(head) = word.get_mut(..bytes.len()) else {
                    continue;
                };
                head.copy_from_slice(bytes);
                bytes.fill(0);
                fold_word(&mut word)
            } else {
                continue;
            };
            let w = &mut out.words[k];
            for (p, plane) in planes.into_iter().enumerate() {
                w[p] |= plane;
            }
            w[ANY] = w[FAR] | w[FREE] | w[NEAR];
            if w[ANY] != 0 {
                crossed(k, w[ANY]);
            }
        }
        out.cover(cells);
    }

    /// Calls `f(k, crossed)` for every word `k` frame `f` may have set, with the bits of the cells
    /// crossed in it (however near their returns), in increasing `k`; call it once the frame's walks
    /// are done (it records the union for [`Self::begin`]).
    #[cfg(test)]
    pub fn for_each_crossed_word(&mut self, f: u32, mut each: impl FnMut(usize, u64)) {
        let s = f as usize % SLOTS;
        if f == 0 || self.frame[s] != f {
            return;
        }
        let base = s * self.words;
        for k in self.span[s].words(self.words) {
            let w = &mut self.planes[base + k];
            w[ANY] = w[FAR] | w[FREE] | w[NEAR];
            if w[ANY] != 0 {
                each(k, w[ANY]);
            }
        }
    }
}

/// The far, free and near planes (bits 0, 1 and 2 of each byte) of one word's 64 level bytes, which
/// it zeroes. Four 16-byte vectors: shifting a bit to the top of its byte lets one `pmovmskb`
/// gather it from 16 cells at once (the 8-byte multiply trick gathered 8 per multiply). Inlined into
/// the fold, its planes stay in registers, and the whole word's zero test skips the chunks of words
/// the near field left empty.
#[inline(always)]
fn fold_word(bytes: &mut [u8; 64]) -> [u64; 3] {
    let v: [u8x16; 4] = bytemuck::cast(*bytes);
    let any = v[0] | v[1] | v[2] | v[3];
    if any.simd_eq(u8x16::ZERO).all() {
        return [0; 3];
    }
    *bytes = [0; 64];
    // Bit `b` of every byte, shifted to the byte's top bit (a 16-bit lane shift moves each byte's
    // own bits up; what crosses from the lower byte lands below the top bit).
    let plane = |b: u32| {
        v.iter().enumerate().fold(0u64, |acc, (q, &x)| {
            let lanes: u16x8 = bytemuck::cast(x);
            let top: u8x16 = bytemuck::cast(lanes << (7 - b));
            acc | u64::from(top.to_bitmask()) << (16 * q)
        })
    };
    let mut planes = [plane(0), 0, 0];
    // Most walked cells are crossed far only (all but the last few before a return).
    if !(any & u8x16::splat(!1)).simd_eq(u8x16::ZERO).all() {
        planes[FREE] = plane(1);
        planes[NEAR] = plane(2);
    }
    planes
}

/// Sets one frame's bits.
pub(crate) struct SlotWriter<'a> {
    words: &'a mut [Group],
    span: &'a mut CellBox,
}

impl SlotWriter<'_> {
    /// Marks cells `lo..=hi` (linear indices, `lo <= hi`) as crossed far; the caller reports them
    /// with [`Self::cover`]. Cells outside the grid are ignored.
    pub fn or_far_run(&mut self, lo: usize, hi: usize) {
        let (k0, k1) = (lo / 64, hi / 64);
        let Some(words) = self
            .words
            .get_mut(k0..=k1.min(self.words.len().saturating_sub(1)))
        else {
            return;
        };
        let last = k1 - k0;
        for (n, w) in words.iter_mut().enumerate() {
            let head = if n == 0 { !0u64 << (lo % 64) } else { !0 };
            let tail = if n == last {
                !0u64 >> (63 - hi % 64)
            } else {
                !0
            };
            w[FAR] |= head & tail;
        }
    }

    /// Marks the cells of word `k` set in `bits` as crossed `how` (an out-of-grid word is ignored);
    /// the caller reports the words it marks with [`Self::cover`].
    #[cfg(test)]
    pub fn or_word(&mut self, k: usize, how: Crossing, bits: u64) {
        if let Some(w) = self.words.get_mut(k) {
            match how {
                Crossing::Far => w[FAR] |= bits,
                Crossing::Free => w[FREE] |= bits,
                Crossing::Near => w[NEAR] |= bits,
            }
        }
    }

    /// Widens the cells the frame may have set by `cells`.
    #[inline]
    pub fn cover(&mut self, cells: CellBox) {
        *self.span = self.span.union(cells);
    }
}

/// A box of cells, columns `x0..=x1` and rows `y0..=y1` of a grid `width` cells wide (empty when
/// a range is).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct CellBox {
    pub width: usize,
    pub x0: usize,
    pub x1: usize,
    pub y0: usize,
    pub y1: usize,
}

impl CellBox {
    /// No cell.
    pub const EMPTY: CellBox = CellBox {
        width: 1,
        x0: 1,
        x1: 0,
        y0: 1,
        y1: 0,
    };

    /// The box spanned by two cells (linear indices) of a grid `width` cells wide.
    pub fn spanned(width: usize, a: usize, b: usize) -> Self {
        let width = width.max(1);
        let ((ax, ay), (bx, by)) = ((a % width, a / width), (b % width, b / width));
        CellBox {
            width,
            x0: ax.min(bx),
            x1: ax.max(bx),
            y0: ay.min(by),
            y1: ay.max(by),
        }
    }

    /// The cells of `geom` within a cell of the box with corners `lo` and `hi` (grid
    /// coordinates, [`GridGeometry::grid_coords`]); empty when the box misses the grid or a
    /// corner is NaN.
    pub fn around(geom: &GridGeometry, lo: (f64, f64), hi: (f64, f64)) -> Self {
        let (w, h) = (geom.width() as f64, geom.height() as f64);
        // Clamped in floating point first: a far or infinite corner converts exactly.
        let cell = |c: f64, n: f64| floor(c).clamp(-1.0, n) as i64;
        let (x0, x1) = (cell(lo.0, w) - 1, cell(hi.0, w) + 1);
        let (y0, y1) = (cell(lo.1, h) - 1, cell(hi.1, h) + 1);
        let (w, h) = (geom.width() as i64, geom.height() as i64);
        if !(lo.0 <= hi.0 && lo.1 <= hi.1) || x1 < 0 || y1 < 0 || x0 >= w || y0 >= h {
            return Self::EMPTY;
        }
        CellBox {
            width: geom.width(),
            x0: x0.max(0) as usize,
            x1: x1.min(w - 1) as usize,
            y0: y0.max(0) as usize,
            y1: y1.min(h - 1) as usize,
        }
    }

    /// The one cell `i` (of a grid of any width).
    #[cfg(test)]
    pub fn cell(i: usize) -> Self {
        Self::spanned(1, i, i)
    }

    fn is_empty(&self) -> bool {
        self.x0 > self.x1 || self.y0 > self.y1
    }

    /// The smallest box holding both; of grids of different widths, every cell up to the larger
    /// one's last (as one column).
    pub fn union(self, o: CellBox) -> CellBox {
        if self.is_empty() {
            o
        } else if o.is_empty() {
            self
        } else if self.width == o.width {
            CellBox {
                width: self.width,
                x0: self.x0.min(o.x0),
                x1: self.x1.max(o.x1),
                y0: self.y0.min(o.y0),
                y1: self.y1.max(o.y1),
            }
        } else {
            let last = |b: &CellBox| b.y1 * b.width + b.x1;
            Self::spanned(1, 0, last(&self).max(last(&o)))
        }
    }

    /// The grid words (of `words`) holding the box's cells, each once, in increasing order.
    fn words(&self, words: usize) -> impl Iterator<Item = usize> {
        let b = *self;
        let mut next = 0;
        (b.y0..=b.y1).flat_map(move |y| {
            let (k0, k1) = ((y * b.width + b.x0) / 64, (y * b.width + b.x1) / 64 + 1);
            let from = k0.max(next);
            let to = k1.min(words);
            next = next.max(to);
            from..to.max(from)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn words_set_their_bits_and_the_kinds_nest() {
        // Invariant: a word marks exactly its cells; far counts as free, and every kind as crossed.
        let mut v = VisibleArea::new(300);
        assert!(v.begin(1));
        let mut w = v.writer(1).expect("current frame");
        w.or_word(0, Crossing::Far, !0 << 60);
        w.or_word(1, Crossing::Far, !0);
        w.or_word(2, Crossing::Far, 0b111);
        w.or_word(2, Crossing::Near, 0b1000);
        w.cover(CellBox::spanned(300, 60, 131));
        for i in 0..300 {
            let inside = (60..=130).contains(&i);
            assert_eq!(v.far(i, 1), u8::from(inside), "{i}");
            assert_eq!(v.free(i, 1), u8::from(inside), "{i}");
            assert_eq!(v.crossed_in(i, 1), inside || i == 131, "{i}");
        }
        let mut words = Vec::new();
        v.for_each_crossed_word(1, |k, bits| words.push((k, bits.count_ones())));
        assert_eq!(words, vec![(0, 4), (1, 64), (2, 4)]);
        let mut w = v.writer(1).expect("current frame");
        w.or_word(99, Crossing::Far, 1);
        w.cover(CellBox::spanned(300, 6000, 7000));
        assert_eq!(v.last_crossed(299), 0, "out-of-grid words are ignored");
    }

    #[test]
    fn the_last_crossing_survives_the_ring() {
        // Invariant: last_crossed is the latest crossing frame, also after its slot was reused.
        let mut v = VisibleArea::new(100);
        v.record(7, 1, Crossing::Free);
        v.record(8, 1, Crossing::Near);
        v.record(8, 2, Crossing::Far);
        for f in 3..=9 {
            assert!(v.begin(f));
        }
        assert_eq!((v.last_crossed(7), v.last_crossed(8)), (1, 2));
        assert_eq!(v.last_crossed(9), 0);
        v.record(7, 10, Crossing::Near);
        assert_eq!(v.last_crossed(7), 10);
        assert!(!v.begin(6), "frames do not go back");
    }

    #[test]
    fn the_last_crossing_survives_frames_retired_out_of_order() {
        // Invariant: when skipped frames make the ring retire an older frame after a newer one,
        // last_crossed still keeps the newer frame for a cell both crossed (and the older one for a
        // cell only it crossed).
        let mut v = VisibleArea::new(100);
        v.record(7, 1, Crossing::Far); // slot 1
        v.record(8, 1, Crossing::Far);
        v.record(7, 6, Crossing::Far); // slot 2
        assert!(v.begin(10)); // slot 2 retires frame 6
        assert!(v.begin(13)); // slot 1 retires frame 1, after frame 6
        assert_eq!((v.last_crossed(7), v.last_crossed(8)), (6, 1));
        for f in 14..=20 {
            assert!(v.begin(f));
        }
        assert_eq!((v.last_crossed(7), v.last_crossed(8)), (6, 1));
    }

    #[test]
    fn a_history_of_some_frames_is_those_bits_of_the_whole() {
        // Invariant: free_in and far_in for any frame mask are free and far masked, over random
        // crossings of every kind in frames around and beyond the ring (also right after frame 0).
        let mut next = super::super::test_rng::xorshift(0x3c6e_f372_fe94_f82b_u64);
        let mut r = move |m: u64| next() % m;
        let mut v = VisibleArea::new(200);
        let kinds = [Crossing::Far, Crossing::Free, Crossing::Near];
        for f in 1..=12 {
            for _ in 0..60 {
                v.record(r(200) as usize, f, kinds[r(3) as usize]);
            }
            assert!(v.begin(f));
            for i in 0..200 {
                for g in f.saturating_sub(1)..=f + 1 {
                    for frames in 0..16 {
                        assert_eq!(v.free_in(i, g, frames), v.free(i, g) & frames, "{i} {g}");
                        assert_eq!(v.far_in(i, g, frames), v.far(i, g) & frames, "{i} {g}");
                    }
                }
            }
        }
    }

    #[test]
    fn level_bytes_fold_into_the_planes_and_are_cleared() {
        // Invariant: fold_levels gives each cell in range the kinds or-ed into its level byte (far
        // also free, any also crossed), zeroes those bytes, and leaves cells out of range alone.
        let n = 150; // two whole words and a partial one
        let mut v = VisibleArea::new(n);
        assert!(v.begin(3));
        let mut level = vec![0u8; n];
        let far = Crossing::Far.level();
        let (free, near) = (Crossing::Free.level(), Crossing::Near.level());
        for (i, b) in [
            (0, far),
            (7, near),
            (8, free | near),
            (63, far | near),
            (64, free),
        ] {
            level[i] = b;
        }
        for (i, b) in [(100, near), (149, far), (20, far)] {
            level[i] = b;
        }
        let mut before = level.clone();
        let mut listed = 0;
        v.fold_levels(3, &mut level, CellBox::spanned(n, 0, n - 1), |_, bits| {
            listed += bits.count_ones()
        });
        assert_eq!(listed, 8, "every crossed cell listed once");
        for (i, &b) in before.iter().enumerate() {
            assert_eq!(v.far(i, 3), u8::from(b & far != 0), "{i}");
            assert_eq!(v.free(i, 3), u8::from(b & (far | free) != 0), "{i}");
            assert_eq!(v.crossed_in(i, 3), b != 0, "{i}");
        }
        assert!(level.iter().all(|&b| b == 0));
        // Out of range: the bytes stay for a later fold.
        level[5] = near;
        level[140] = far;
        before = level.clone();
        v.fold_levels(3, &mut level, CellBox::spanned(n, 64, 127), |_, _| {});
        assert_eq!(level, before);
        assert!(!v.crossed_in(5, 3) && v.far(140, 3) == 0);
    }

    /// The fold as it was before `fold_word` (one chunk of eight bytes at a time): the oracle.
    fn fold_levels_before(
        v: &mut VisibleArea,
        f: u32,
        level: &mut [u8],
        cells: CellBox,
        mut crossed: impl FnMut(usize, u64),
    ) {
        const ONES: u64 = 0x0101_0101_0101_0101;
        // Gathers bit 0 of each of the eight bytes into one byte (byte j to bit j).
        let gather = |v: u64| (v & ONES).wrapping_mul(0x0102_0408_1020_4080) >> 56;
        let n = v.n;
        let Some(mut out) = v.writer(f) else {
            return;
        };
        for k in cells.words(out.words.len()) {
            let Some(bytes) = level.get_mut(k * 64..((k + 1) * 64).min(n)) else {
                continue;
            };
            let bytes_len = bytes.len();
            let mut planes = [0u64; 3];
            let mut fold = |q: usize, v: u64| {
                for (p, plane) in planes.iter_mut().enumerate() {
                    *plane |= gather(v >> p) << (8 * q);
                }
            };
            let mut chunks = bytes.chunks_exact_mut(8);
            for (q, chunk) in chunks.by_ref().enumerate() {
                let Ok(c) = <&mut [u8; 8]>::try_from(chunk) else {
                    continue;
                };
                let v = u64::from_le_bytes(*c);
                if v != 0 {
                    *c = [0; 8];
                    fold(q, v);
                }
            }
            // The grid's last, partial word.
            let tail = chunks.into_remainder();
            if !tail.is_empty() {
                let mut b = [0u8; 8];
                b[..tail.len()].copy_from_slice(tail);
                tail.fill(0);
                fold(bytes_len / 8, u64::from_le_bytes(b));
            }
            let w = &mut out.words[k];
            for (p, plane) in planes.into_iter().enumerate() {
                w[p] |= plane;
            }
            w[ANY] = w[FAR] | w[FREE] | w[NEAR];
            if w[ANY] != 0 {
                crossed(k, w[ANY]);
            }
        }
        out.cover(cells);
    }

    #[test]
    fn the_word_fold_matches_the_chunk_fold_it_replaced() {
        // Invariant: fold_levels (a whole word at a time) leaves the same planes, the same bytes
        // and the same crossed words as the chunk-at-a-time fold it replaced, for any bytes (high
        // bits too), boxes and grid sizes (with and without a partial last word), over frames.
        let mut next = super::super::test_rng::xorshift(0x9e37_79b9_7f4a_7c15_u64);
        let mut r = move |m: usize| (next() % m as u64) as usize;
        for case in 0..40 {
            let width = 1 + r(150);
            let height = 1 + r(40);
            let n = width * height;
            let (mut a, mut b) = (VisibleArea::new(n), VisibleArea::new(n));
            let mut level = vec![0u8; n];
            for f in 1..=6 {
                assert!(a.begin(f) && b.begin(f));
                // Sparse, dense and empty stretches, and a few far runs already in the planes.
                let density = [0, 2, 30, 100][r(4)];
                for byte in level.iter_mut() {
                    if r(100) < density {
                        *byte = if r(8) == 0 { r(256) as u8 } else { 1 << r(3) };
                    }
                }
                let lo = r(n);
                let hi = (lo + r(200)).min(n - 1);
                for w in [&mut a, &mut b] {
                    w.writer(f).expect("current frame").or_far_run(lo, hi);
                }
                let cells = CellBox::spanned(width, r(n), r(n));
                let mut level_b = level.clone();
                let (mut got, mut want) = (Vec::new(), Vec::new());
                a.fold_levels(f, &mut level, cells, |k, bits| got.push((k, bits)));
                fold_levels_before(&mut b, f, &mut level_b, cells, |k, bits| {
                    want.push((k, bits))
                });
                assert_eq!(got, want, "case {case} frame {f}");
                assert_eq!(level, level_b, "case {case} frame {f}");
                assert_eq!(a.planes, b.planes, "case {case} frame {f}");
                assert_eq!(a.span, b.span, "case {case} frame {f}");
                if f % 3 == 0 {
                    level.fill(0);
                }
            }
        }
    }

    #[test]
    fn a_box_lists_the_words_of_its_cells_once_each() {
        // Invariant: words() yields exactly the words holding the box's cells, ascending, once each.
        for (width, x0, x1, y0, y1) in [(100, 30, 70, 0, 3), (100, 0, 99, 2, 9), (800, 5, 5, 0, 40)]
        {
            let b = CellBox {
                width,
                x0,
                x1,
                y0,
                y1,
            };
            let mut want: Vec<usize> = (y0..=y1)
                .flat_map(|y| (x0..=x1).map(move |x| (y * width + x) / 64))
                .collect();
            want.dedup();
            assert_eq!(b.words(usize::MAX).collect::<Vec<_>>(), want, "{b:?}");
        }
        assert_eq!(CellBox::EMPTY.words(10).count(), 0);
        let u = CellBox::spanned(10, 3, 12).union(CellBox::spanned(10, 25, 25));
        assert_eq!((u.x0, u.x1, u.y0, u.y1), (2, 5, 0, 2));
    }
}
