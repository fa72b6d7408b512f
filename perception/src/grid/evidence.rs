//! Why a cell has its class: which passive rule fired, or which push test decided.
//!
//! Stored packed in one `u32` per cell so that the grid stays structure-of-arrays and small:
//! `0` = no evidence, `1 + rule` = a passive rule, `ACTIVE_BIT | push_test` = an active verdict (the
//! object is kept in the cell's object slot).

use crate::prism::ObjectId;

/// A passive classification rule (from range frames alone).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum Rule {
    /// A ray passed through the cell (Tamura 3.1 visible area; Lopez-Perez f₂ = 1).
    SeenFree = 0,
    /// A return where the previous frame saw free space, with no return around it then (Tamura 3.1,
    /// guarded by Chen's 8-neighbourhood).
    Moving = 1,
    /// A return near last frame's moving returns that is not at rest yet: the moving obstacle went on.
    MovingContinued = 2,
    /// Something rests where something moving was (Tamura 3.2.1, addition).
    MovableAddition = 3,
    /// A return at or next to a movable cell stays movable (Tamura 3.2.2, retention).
    MovableRetention = 4,
    /// A movable cell seen free: the movable obstacle has gone (Tamura 3.2.3, deletion).
    MovableDeletion = 5,
    /// A return seen at t, t−1 and t−2 within the 8-neighbourhood (Tamura 3.3 with Chen 2.4).
    Stationary = 6,
    /// A return not yet seen often enough to be called anything (Tamura's temporarily stationary point).
    Tentative = 7,
    /// A moving cell that is no longer returned and was not seen free: whatever moved is elsewhere.
    MovingExpired = 8,
    /// A stationary (or actively marked) cell seen free through and through in consecutive frames.
    StationaryCleared = 9,
    /// A resting return next to a movable cell found by addition or retention: a new face of the same
    /// movable obstacle coming into view (Tamura 3.2.2's ε-neighbourhood, one ring deep).
    MovableExtension = 10,
    /// A return inside what the previous frame saw empty along its bearing: the previous beams around
    /// it went on past it with nothing returned (Tamura 3.1 on the ray, as range-image differencing).
    Appeared = 11,
}

impl Rule {
    const ALL: [Rule; 12] = [
        Rule::SeenFree,
        Rule::Moving,
        Rule::MovingContinued,
        Rule::MovableAddition,
        Rule::MovableRetention,
        Rule::MovableDeletion,
        Rule::Stationary,
        Rule::Tentative,
        Rule::MovingExpired,
        Rule::StationaryCleared,
        Rule::MovableExtension,
        Rule::Appeared,
    ];
}

/// The evidence behind a cell's class.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Evidence {
    /// Never classified.
    None,
    /// A passive rule on range frames.
    Passive(Rule),
    /// A push test: the executive marked the cell as `object`'s (static or movable), or a confirmed push
    /// moved `object` off it.
    Active {
        /// The object the push test was about.
        object: ObjectId,
        /// The executive's push-test number.
        push_test: u32,
    },
}

/// Highest push-test number the grid can store (31 bits).
pub const MAX_PUSH_TEST: u32 = ACTIVE_BIT - 1;

pub(crate) const ACTIVE_BIT: u32 = 1 << 31;

/// Packs a passive rule.
#[inline]
pub(crate) const fn pack_rule(rule: Rule) -> u32 {
    1 + rule as u32
}

/// Packs an active verdict's push test (must be ≤ [`MAX_PUSH_TEST`], checked by the caller).
#[inline]
pub(crate) const fn pack_active(push_test: u32) -> u32 {
    ACTIVE_BIT | push_test
}

/// True when the packed evidence is active.
#[inline]
pub(crate) const fn is_active(packed: u32) -> bool {
    packed & ACTIVE_BIT != 0
}

/// Unpacks; `object` is the cell's object slot (needed for active evidence).
pub(crate) fn unpack(packed: u32, object: Option<ObjectId>) -> Evidence {
    if is_active(packed) {
        match object {
            Some(object) => Evidence::Active {
                object,
                push_test: packed & !ACTIVE_BIT,
            },
            None => Evidence::None,
        }
    } else if packed == 0 {
        Evidence::None
    } else {
        Rule::ALL
            .get(packed as usize - 1)
            .map_or(Evidence::None, |r| Evidence::Passive(*r))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evidence_round_trips_through_its_packing() {
        // Invariant: every rule and any push test up to 31 bits unpack to what was packed.
        for r in Rule::ALL {
            assert_eq!(unpack(pack_rule(r), None), Evidence::Passive(r));
        }
        let o = ObjectId(7);
        for t in [0, 1, 12345, MAX_PUSH_TEST] {
            assert_eq!(
                unpack(pack_active(t), Some(o)),
                Evidence::Active {
                    object: o,
                    push_test: t
                }
            );
        }
        assert_eq!(unpack(0, None), Evidence::None);
    }
}
