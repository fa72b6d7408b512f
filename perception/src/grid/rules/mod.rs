//! The passive classification rules, one file each, and the flowchart that orders them.
//!
//! Every rule is a pure predicate over the grid's stored layers at frame `f` (the frame being
//! processed: its returns are recorded, its classes not yet written), so each can be tested alone.

pub(crate) mod appeared;
pub(crate) mod free_space;
pub mod fsm;
pub(crate) mod movable;
pub(crate) mod moving;
pub(crate) mod stationary;

use super::class::CellClass;
use super::evidence::Rule;
use super::geometry::GridGeometry;
use super::layers::Layers;

/// What the flowchart decides for one return, before the rest test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum HitDecision {
    /// Active evidence holds: no change.
    Keep,
    /// Set this class with this rule.
    Set(CellClass, Rule),
    /// Near last frame's motion and in place for three frames: movable, unless motion is seen near it
    /// this frame (decided once all returns of the frame are known).
    RestCandidate,
    /// Already movable: stays movable (retention) unless motion is seen near it this frame.
    MovableUnlessMotion,
    /// Resting next to a movable cell: joins it (extension) unless motion is seen near it this frame.
    ExtendUnlessMotion,
    /// In place next to last frame's motion that was not confirmed (a blip): moving while motion is
    /// seen near it this frame, else this class and rule (the stationary test's verdict).
    MovingUnlessStill(CellClass, Rule),
}

/// Tamura's Fig. 5 for one return at linear index `i` in frame `f` (see the module docs of `grid`);
/// `quiet` is the moving rule's neighbourhood for this return ([`moving::quiet_radius`]), `sensor`
/// the sensor's continuous grid coordinates, and `appeared` whether a return in the cell appeared
/// inside the previous frame's range ([`appeared::PreviousBeams::appeared`]).
// Called once per return from the update's hot loop: left to itself the compiler stopped inlining
// it when the observed bitset grew the update a little (callgrind: 6 000 instructions a scan more).
#[inline]
pub(crate) fn decide_hit(
    l: &Layers,
    g: &GridGeometry,
    i: usize,
    f: u32,
    (quiet, sensor, appeared): (usize, (f64, f64), bool),
) -> HitDecision {
    if super::evidence::is_active(l.evidence[i]) && l.class[i] != CellClass::Free as u8 {
        return HitDecision::Keep;
    }
    let class = CellClass::from_code(l.class[i]).unwrap_or(CellClass::Unknown);
    if moving::appeared_in_free_space(l, g, i, f, quiet, sensor) {
        return HitDecision::Set(CellClass::Moving, Rule::Moving);
    }
    // The same rule on the ray; walls stay walls (a person brushing past one is seen next to it).
    if appeared && class != CellClass::Stationary {
        return HitDecision::Set(CellClass::Moving, Rule::Appeared);
    }
    if movable::retained(class) {
        return HitDecision::MovableUnlessMotion;
    }
    let place = stationary::in_place(l, g, i, f);
    let (rested, three_frames) = (place.rested, place.three_frames);
    if movable::extended(l, g, i, class, rested) {
        return HitDecision::ExtendUnlessMotion;
    }
    if class != CellClass::Stationary && moving::near_previous_motion(l, i, f) {
        if !rested {
            return HitDecision::Set(CellClass::Moving, Rule::MovingContinued);
        }
        // Only motion seen going on into new cells comes to rest: a blip (a grazed wall's return
        // landing in last frame's free space and staying in its cell) must not make its wall movable.
        if moving::near_confirmed_motion(l, i, f) {
            return HitDecision::RestCandidate;
        }
        return moving_unless_still(passive_rest(l, g, i, class, three_frames));
    }
    // Something has entered a cell last seen free, with no surface beside it before: moving while
    // motion is seen near it (a suitcase pulled out of its puller's shadow), else the stationary test.
    if moving::entered_free_cell(l, g, i, f) {
        return moving_unless_still(passive_rest(l, g, i, class, three_frames));
    }
    passive_rest(l, g, i, class, three_frames)
}

/// `d` (the stationary test's verdict) while no motion is seen near the return in the same frame;
/// moving otherwise.
fn moving_unless_still(d: HitDecision) -> HitDecision {
    match d {
        HitDecision::Set(c, r) => HitDecision::MovingUnlessStill(c, r),
        d => d,
    }
}

/// The stationary test (Tamura 3.3 with Chen's neighbours) for a return no motion rule claimed;
/// `three_frames` is [`stationary::InPlace::three_frames`] of it.
fn passive_rest(
    l: &Layers,
    g: &GridGeometry,
    i: usize,
    class: CellClass,
    three_frames: bool,
) -> HitDecision {
    if three_frames && !movable::touches_movable(l, g, i) {
        HitDecision::Set(CellClass::Stationary, Rule::Stationary)
    } else if class == CellClass::Stationary {
        HitDecision::Keep
    } else {
        HitDecision::Set(CellClass::Unknown, Rule::Tentative)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point2;

    /// A 10 × 10 grid of 5 cm cells with a return at cell 55 in frame 5 that was returned around in
    /// frames 3 and 4 (in place), near last frame's motion.
    fn resting_return_near_motion() -> (GridGeometry, Layers) {
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 0.05).expect("valid");
        let mut l = Layers::new(g.len());
        for f in 3..=5 {
            l.record_hit(55, f);
        }
        l.near_moving[55] = 5;
        (g, l)
    }

    const FAR: (usize, (f64, f64), bool) = (1, (5.0, -1000.0), false);

    #[test]
    fn only_confirmed_motion_comes_to_rest() {
        // Invariant: a return in place next to last frame's motion is a rest candidate (movable by
        // addition) only when that motion was confirmed (went on into new cells); next to a blip it is
        // moving while motion is seen near it, else the stationary test decides (here: tentative).
        let (g, mut l) = resting_return_near_motion();
        assert_eq!(
            decide_hit(&l, &g, 55, 5, FAR),
            HitDecision::MovingUnlessStill(CellClass::Unknown, Rule::Tentative)
        );
        l.near_confirmed[55] = 5;
        assert_eq!(decide_hit(&l, &g, 55, 5, FAR), HitDecision::RestCandidate);
    }

    #[test]
    fn a_return_not_in_place_next_to_motion_continues_it() {
        // Invariant: near last frame's motion, a return not yet in place is the moving obstacle gone on.
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 0.05).expect("valid");
        let mut l = Layers::new(g.len());
        l.record_hit(55, 5);
        l.near_moving[55] = 5;
        assert_eq!(
            decide_hit(&l, &g, 55, 5, FAR),
            HitDecision::Set(CellClass::Moving, Rule::MovingContinued)
        );
        // A stationary cell is never continued: walls next to a passer-by stay walls.
        l.class[55] = CellClass::Stationary as u8;
        assert_eq!(decide_hit(&l, &g, 55, 5, FAR), HitDecision::Keep);
    }

    #[test]
    fn a_return_that_appeared_on_the_ray_is_moving_unless_it_is_a_wall() {
        // Invariant: a return the ray rule found appearing is Moving whatever the cell held (unknown,
        // movable: the movable obstacle is being moved), except in a Stationary cell, which keeps its
        // class; without the ray rule the same return is not Moving.
        let (g, mut l) = resting_return_near_motion();
        l.near_moving[55] = 0;
        let appeared = (1, (5.0, -1000.0), true);
        let moving = HitDecision::Set(CellClass::Moving, Rule::Appeared);
        assert_eq!(decide_hit(&l, &g, 55, 5, appeared), moving);
        assert_ne!(decide_hit(&l, &g, 55, 5, FAR), moving);
        l.class[55] = CellClass::Movable as u8;
        assert_eq!(decide_hit(&l, &g, 55, 5, appeared), moving);
        l.class[55] = CellClass::Stationary as u8;
        assert_eq!(decide_hit(&l, &g, 55, 5, appeared), HitDecision::Keep);
    }

    #[test]
    fn a_return_entering_a_cell_last_seen_free_is_moving_unless_still() {
        // Invariant: a return in a Free cell with nothing returned beside it at t−1 or t−2, far from
        // last frame's motion, is moving while motion is seen near it (else the stationary test's
        // verdict); in a cell not seen free, or next to last frame's returns, it goes to the
        // stationary test at once.
        let g = GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 0.05).expect("valid");
        let mut l = Layers::new(g.len());
        l.class[55] = CellClass::Free as u8;
        l.record_hit(55, 5);
        let tentative = HitDecision::Set(CellClass::Unknown, Rule::Tentative);
        assert_eq!(
            decide_hit(&l, &g, 55, 5, FAR),
            HitDecision::MovingUnlessStill(CellClass::Unknown, Rule::Tentative)
        );
        l.record_hit(56, 4);
        assert_eq!(decide_hit(&l, &g, 55, 5, FAR), tentative);
        let mut l = Layers::new(g.len());
        l.record_hit(55, 5);
        assert_eq!(decide_hit(&l, &g, 55, 5, FAR), tentative);
    }

    #[test]
    fn active_evidence_outranks_every_passive_rule() {
        // Invariant: a cell a push test marked keeps its verdict whatever returns land on it.
        let (g, mut l) = resting_return_near_motion();
        l.class[55] = CellClass::Stationary as u8;
        l.evidence[55] = super::super::evidence::pack_active(3);
        assert_eq!(decide_hit(&l, &g, 55, 5, FAR), HitDecision::Keep);
    }
}
