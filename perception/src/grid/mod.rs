//! The obstacle-type grid: what every part of nudge knows about each patch of floor.
//!
//! A 2D grid (default 50 mm cells) over the room. Each cell holds a [`CellClass`] (Unknown, Free,
//! Stationary, Movable, Moving), the [`ObjectId`] it belongs to if the executive said so, when it was
//! last observed (robot clock), and the [`Evidence`] behind its class. Perception writes it from range
//! frames ([`ObstacleGrid::update`]), motion reads it, and the executive writes push-test verdicts into
//! it ([`ObstacleGrid::mark_object`], [`ObstacleGrid::object_moved`]).
//!
//! # Passive rules (one file each under `rules/`)
//! Per frame, every beam is traversed from the sensor (Amanatides–Woo, `traversal.rs`); crossed cells
//! are the visible area V_t, end cells hold returns (Tamura 3.1). The last `clear_tail` of a beam
//! without a return is not counted (a wall entering the range limit, or grazed beyond the incidence
//! limit behind the floor seen up to its foot, must not look like something appearing in free
//! space). Where a scan's beams lie closer together than a cell subtends, every cell between them
//! is crossed by one: that annulus (`near_field.rs`) is filled a row at a time and
//! each walk jumps over it, with the same result as walking it (tested against whole walks). A
//! return is classified by the first rule that fires (Tamura's Fig. 5
//! flowchart, extended; "motion nearby" = a return classified moving this frame within `rest_radius`):
//! 1. **Moving** (Tamura 3.1, `rules/moving.rs`): the cell was seen free beyond doubt (crossed at
//!    least `clear_margin` before the ray's return, farther than a grazing ray runs inside a surface's
//!    cells) in one of V_{t−1}, V_{t−2}, V_{t−3}, and
//!    nothing was returned in its 8-neighbourhood at t−1 or t−2 (Chen 2.4's neighbourhood, here
//!    against rays grazing a surface: they cross its cells just before their return), nor nearer the
//!    sensor within half the along-surface beam spacing at the grazing limit (`quiet_radius`).
//!    **On the ray** (`rules/appeared.rs`, range-image differencing), for any return not in a
//!    Stationary cell: seen from the previous frame's sensor position, the two previous beams
//!    straddling its bearing and the next one out on each side all went on at least `appear_gap`
//!    past it with nothing returned — it appeared inside what the previous frame saw empty. This
//!    needs no cell seen free, so a person walking in from a laser's range limit is moving from
//!    its second frame (from its third for a camera, whose clear beams end at the farthest floor
//!    point, short of the limit); a static surface cannot lie beyond itself on both sides of a bearing, and a wall
//!    entering the range limit was beyond every previous beam. One binary search per return.
//! 2. **Movable retention** (Tamura 3.2.2, `rules/movable.rs`): a movable cell stays movable — unless
//!    motion is nearby (the movable obstacle is being moved: moving).
//! 3. **Movable extension** (Tamura 3.2.2's ε-neighbourhood): a return in place (returned around in
//!    two of the last three frames) within 3 cells of a cell found by addition or retention joins it,
//!    unless motion is nearby. One ring only: an extension cell does not extend further, so the label
//!    cannot creep along a wall the object touches.
//! 4. **Moving continued / movable addition** (Tamura 3.2.1): within `moving_step` of a cell that was
//!    moving at t−1, a return not yet in place is the moving obstacle gone on (moving); one in place
//!    rests and is *movable* — unless motion is nearby (the person still pulling the suitcase; the
//!    leading corner of a face that slides along itself and so looks static in a grid). Only
//!    *confirmed* motion comes to rest: motion that went on into new cells (or cells something has
//!    just left, seen through with nothing around). A return that appears and stays in its cell is a
//!    blip (a grazed wall looks just so): moving while motion is nearby, else the stationary test.
//! 5. **Entered** (`rules/moving.rs`, `entered_free_cell`): a return in a cell last seen free (class
//!    Free) with nothing returned in its 8-neighbourhood at t−1 or t−2 has arrived there — a static
//!    surface cannot — though perhaps unseen for longer than the moving rule remembers (a suitcase
//!    pulled out of the shadow of the person pulling it): moving while motion is nearby, else the
//!    stationary test.
//! 6. **Stationary** (Tamura 3.3 with Chen 2.3–2.4, `rules/stationary.rs`): a temporarily stationary
//!    return (none of the above) with temporarily stationary returns in its 8-neighbourhood at t−1 and
//!    at t−2, and no movable cell within 3 cells (a movable object's fringe never becomes a wall).
//!    Otherwise it stays *tentative* (class Unknown, evidence `Tentative`) or keeps its Stationary class.
//!
//! A cell is *seen free* when a ray crosses it at least `free_gap` before its return (or along a beam
//! without one); nearer, the ray may run inside the returned surface (range noise, grazing beams), and
//! the crossing only renews the cell's age. Crossed cells without a return this frame (a return in a
//! cell wins over rays crossing it): unknown and moving cells seen free become free; a movable cell crossed at least `clear_margin` before the ray's return,
//! with no return around it, is deleted (Tamura 3.2.3); a stationary cell is cleared only when crossed
//! that far in two consecutive frames with nothing returned around it (`rules/free_space.rs`). A moving
//! cell neither returned nor crossed, with no return around it, expires to Unknown (moving things are
//! not remembered out of view). All other cells out of view keep their class (Tamura 3.2.3);
//! [`ObstacleGrid::age`] says how old their evidence is.
//!
//! Known limits: a surface that slides along itself (a box carried past the robot broadside, a person
//! at the closest point of passing) returns the same cells frame after frame and can read as resting
//! (movable) when no other motion is within `rest_radius`; a person walking slower than about one cell
//! per frame reads as resting too (Tamura's ε has the same trade-off); the first frame of anything
//! entering the field of view is tentative (nothing was seen free there before), and so is the first
//! frame of anything entering the range limit (a camera column records how far it saw the floor,
//! not how far its rays above the floor reached).
//!
//! # Active evidence and precedence
//! A push test outranks any passive rule: cells marked by [`ObstacleGrid::mark_object`] keep their
//! class and object whatever returns land on them; only being crossed well before the return in two
//! consecutive frames with no return around them (the object is provably gone) hands them back to the
//! passive rules. [`ObstacleGrid::object_moved`] clears the old footprint to Free (even where no
//! background has been seen behind it: the push is the evidence) and writes the new footprint Movable.
//!
//! # Replanning (Lopez-Perez 2.2)
//! The executive names its path's cells with [`ObstacleGrid::set_watched_path`]; a watched cell that
//! turns Stationary or Moving (or Movable) raises a flag read and cleared by [`ObstacleGrid::take_replan_flag`]
//! (the transition table itself is `rules::fsm`).
//!
//! # Speed
//! Classes, objects and evidence are structure-of-arrays (the class codes are the raw recording
//! slice). A ray step writes one byte: it ors its crossing kind into a per-cell level byte. Once all
//! rays are in, the bytes of the box of cells the walks spanned are folded, eight cells at a time,
//! into the frame's bit-planes (`visible.rs`: a ring of the last four frames' far / free / near
//! crossings, which is all the rules read of crossings), and the crossed cells that are not free are
//! listed by masking each 64-cell word with its 64 class bytes at once: free space seen free again
//! costs its bits and nothing per cell. Returns keep an 8-byte frame-stamped record per cell (hit and
//! temporarily stationary bit bytes); a cell's last observation is its latest frame number (looked
//! up in a per-frame stamp table), with crossings older than the ring kept per cell when a slot is
//! reused. So an update costs O(ray steps + cells in the walks' box / 8 + returns × neighbourhood),
//! plus O(beams · log beams) for the ray rule's previous frame ordered by bearing. Which cells were
//! ever observed is one more bitset ([`ObstacleGrid::observed_words`]), or-ed from each crossed word
//! as those words are listed, and set by returns and verdicts: a word per crossed word, no sweep.

mod active;
mod class;
mod departed;
mod evidence;
mod frame;
mod geometry;
mod image;
mod layers;
mod near_field;
mod queries;
mod raster;
pub mod rules;
#[cfg(test)]
mod test_rng;
mod traversal;
mod update;
mod visible;
mod watch;

use std::collections::HashMap;

pub use active::{Footprint, Verdict};
pub use class::CellClass;
pub use evidence::{Evidence, MAX_PUSH_TEST, Rule};
pub use frame::{Beam, BeamEnd, ColumnReduction, LaserScan, RangeFrame};
pub use geometry::{CellIndex, DEFAULT_RESOLUTION, GridGeometry, MAX_CELLS};
pub use queries::CellInfo;
pub use traversal::{RayCell, Traversal};
pub use watch::ReplanReason;

use crate::prism::ObjectId;
use layers::Layers;

/// Why a grid operation was refused.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum GridError {
    /// The cell size is not a positive finite number.
    #[error("grid resolution must be positive and finite, got {0}")]
    BadResolution(f64),
    /// The extent or origin is not positive and finite.
    #[error("grid extent must be positive and finite")]
    BadExtent,
    /// The grid would exceed [`MAX_CELLS`].
    #[error("grid would have more than {MAX_CELLS} cells")]
    TooLarge,
    /// A position, time or scan parameter is not finite.
    #[error("non-finite position, time or scan parameter")]
    NonFinite,
    /// Time went backwards: updates must come in robot-clock order.
    #[error("frame stamp {now} is earlier than the previous frame's {previous}")]
    TimeWentBack {
        /// The refused stamp.
        now: f64,
        /// The previous frame's stamp.
        previous: f64,
    },
    /// The cloud is not organised (the column reduction needs image columns).
    #[error("the cloud is not organised (width × height)")]
    NotOrganised,
    /// The object has never been marked.
    #[error("object {0} has never been marked in the grid")]
    UnknownObject(ObjectId),
    /// `ObjectId(u32::MAX)` is reserved for "no object".
    #[error("object id {0} is reserved")]
    ReservedObjectId(ObjectId),
    /// The push test number does not fit the evidence field.
    #[error("push test {0} exceeds {MAX_PUSH_TEST}")]
    PushTestTooLarge(u32),
    /// The grid has processed 2³² − 1 frames (over 13 years at 10 Hz): build a new one.
    #[error("the grid's frame counter is exhausted")]
    TooManyFrames,
    /// Writing the snapshot failed.
    #[error("could not write the grid snapshot: {0}")]
    Image(String),
}

/// Tuning of the passive rules. Distances in metres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridConfig {
    /// How far a moving obstacle's returns may move between two frames and still be the same moving
    /// obstacle (Tamura's ε for the moving → movable test). Default 0.15 m: 1.5 m/s at 10 Hz.
    pub moving_step: f64,
    /// A return that rests where something was moving stays moving while other motion is seen this
    /// close in the same frame (the person still pulling the suitcase; the leading corner of a face
    /// that slides along itself and so looks static in a grid). About an object's size. Default 0.7 m.
    pub rest_radius: f64,
    /// A crossing counts as "well before the return" when the ray goes on at least this far past the
    /// cell: at least a cell over the sine of the grazing limit (0.05 / sin 10° = 0.29 m), the
    /// stretch a ray grazing a surface runs inside that surface's row of cells. The moving rule,
    /// deletion of movable and clearing of stationary cells need it. Default 0.3 m.
    pub clear_margin: f64,
    /// The last stretch of a beam without a return that is not counted as seen: a wall entering the
    /// range limit next frame must not look like something appearing in free space, and a wall
    /// grazed beyond the sensor's incidence limit returns nothing while the floor in front of it is
    /// seen up to its foot, so the beam's last `cell / sin(grazing limit)` may run inside the wall's
    /// own row of cells, where its returns of the frame before landed. Default 0.3 m (as
    /// `clear_margin`, for the same reason).
    pub clear_tail: f64,
    /// A cell counts as seen free only when the ray goes on at least this far past it to its return:
    /// nearer, the ray may be crossing the returned surface itself (range noise along the beam; a
    /// beam grazing a wall runs inside the wall's cells for several centimetres before its return).
    /// Default 0.05 m, a cell: rays this far from their return free unknown and moving cells, while
    /// the rules that must not fire on a grazed surface (moving, deletion, clearing) ask for the
    /// clear margin. Cells crossed nearer still count as observed (age).
    pub free_gap: f64,
    /// A return has appeared inside the previous frame's range (moving) when the previous frame's
    /// beams around its bearing went on at least this far past it with nothing returned: about three
    /// standard deviations of the difference of two ranges at 5 m (√2 · 1.5 cm for an SR4000-like
    /// camera), under what a person walking towards the robot covers in a frame (0.1 m at 1 m/s and
    /// 10 Hz). Default 0.06 m.
    pub appear_gap: f64,
}

impl Default for GridConfig {
    fn default() -> Self {
        Self {
            moving_step: 0.15,
            rest_radius: 0.7,
            clear_margin: 0.3,
            clear_tail: 0.3,
            free_gap: 0.05,
            appear_gap: 0.06,
        }
    }
}

/// What the executive recorded about an object it pushed.
#[derive(Clone, Debug)]
pub(crate) struct ObjectRecord {
    pub verdict: Verdict,
    pub push_test: u32,
    /// Linear indices marked for this object (a superset of its current cells).
    pub cells: Vec<u32>,
}

/// The obstacle-type grid.
#[derive(Clone, Debug)]
pub struct ObstacleGrid {
    geom: GridGeometry,
    cfg: GridConfig,
    layers: Layers,
    /// Frames processed so far (frame numbers start at 1; 0 means never).
    frame: u32,
    /// Stamp of the latest frame.
    last_stamp: Option<f64>,
    /// Cells that were classified moving by the latest frame.
    moving: Vec<u32>,
    objects: HashMap<ObjectId, ObjectRecord>,
    watch_gen: u32,
    replan: Option<ReplanReason>,
    /// The previous frame's beams by bearing and this frame's returns that appeared inside them.
    appearances: rules::appeared::Appearances,
    scratch: update::Scratch,
}

impl ObstacleGrid {
    /// An all-Unknown grid with the given geometry and rule tuning.
    pub fn new(geom: GridGeometry, cfg: GridConfig) -> Self {
        Self {
            layers: Layers::new(geom.len()),
            geom,
            cfg,
            frame: 0,
            last_stamp: None,
            moving: Vec::new(),
            objects: HashMap::new(),
            watch_gen: 0,
            replan: None,
            appearances: Default::default(),
            scratch: update::Scratch::default(),
        }
    }

    /// An all-Unknown grid with default rules, lower-left corner `origin`, covering `extent` (m) with
    /// `resolution` cells.
    pub fn from_extent(
        origin: nalgebra::Point2<f64>,
        extent: [f64; 2],
        resolution: f64,
    ) -> Result<Self, GridError> {
        Ok(Self::new(
            GridGeometry::new(origin, extent, resolution)?,
            GridConfig::default(),
        ))
    }

    /// The grid's placement and size.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geom
    }

    /// The rule tuning.
    pub fn config(&self) -> &GridConfig {
        &self.cfg
    }

    /// Number of frames processed.
    pub fn frames(&self) -> u32 {
        self.frame
    }

    /// Row-major class codes ([`CellClass::code`]), one byte per cell: raw access for recording.
    pub fn class_codes(&self) -> &[u8] {
        &self.layers.class
    }

    /// Linear index of an in-grid cell.
    fn idx(&self, cell: CellIndex) -> Option<usize> {
        self.geom.index(cell)
    }
}
