//! The families: what each varies and what it guarantees. Each is one drawing function; the
//! guarantee is checked on the true world afterwards (`super::Guarantee::holds`).
//!
//! | family | varies | guarantees |
//! | --- | --- | --- |
//! | `open-clutter` | a 6–9 × 5–7 m room, 3–8 pieces, half light | a way once movable things are moved |
//! | `large-room` | a 12–16 × 6–9 m room (beyond the camera's 5 m), goal ≥ 8 m away, 5–10 pieces | the same |
//! | `flat` | 2–4 rooms in a row, doors 1.0–1.4 m at random places, 1–3 pieces per room | the same |
//! | `corridor` | a 10–14 m corridor 1.5–2 m wide, things along its walls, half the time a light box across it | a way (or a way only once the box is moved) |
//! | `blocked-door` | two rooms, a door with a box in it, light or bolted | a way only once the box is moved, or none: the box shuts the goal off |
//! | `force-limit` | the same door, the box's μ m g 10–16 N or 20–30 N (0.5–0.8 or 1.0–1.5 × the 20 N limit; the band between is not scored) | as `blocked-door`, movable below 16 N |
//! | `overhang` | a shelf across the whole room above the robot's head (1.6–1.9 m), a low bench under part of it | a way, under the shelf |
//! | `wanderers` | an open room with 0–10 people walking 0.3–1.0 m/s between free places, 2–4 light pieces | a way once movable things are moved |
//! | `touching` | one opening between two rooms (or across a hall) shut by things standing as people leave them: flush against a wall, two abreast, against a bolted cabinet, turned in a doorway, low against a partition; a quarter bolted | a way only once they are pushed (each push checked: a reachable stand pose, a sweep that fits), or none: the bolted one shuts it |

mod doors;
mod rooms;
mod touching;
mod wanderers;

use std::fmt;

use rand_chacha::ChaCha8Rng;

use super::Guarantee;
use super::pushable::NeededPush;
use crate::scenario::Scenario;

/// A family of generated scenarios.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, clap::ValueEnum)]
pub enum Family {
    /// An open room with clutter.
    OpenClutter,
    /// A room larger than the camera's range.
    LargeRoom,
    /// A flat of 2–4 rooms joined by doors.
    Flat,
    /// A corridor.
    Corridor,
    /// A door blocked by a movable or a static object.
    BlockedDoor,
    /// A door blocked by an object near the push force limit.
    ForceLimit,
    /// Overhangs the robot passes under, and one it does not.
    Overhang,
    /// People walking about.
    Wanderers,
    /// Things standing against walls, each other and bolted furniture in the one opening.
    Touching,
}

impl Family {
    /// Every family, in order.
    pub const ALL: [Family; 9] = [
        Family::OpenClutter,
        Family::LargeRoom,
        Family::Flat,
        Family::Corridor,
        Family::BlockedDoor,
        Family::ForceLimit,
        Family::Overhang,
        Family::Wanderers,
        Family::Touching,
    ];

    /// The family's name in files and tables.
    pub fn name(self) -> &'static str {
        match self {
            Family::OpenClutter => "open-clutter",
            Family::LargeRoom => "large-room",
            Family::Flat => "flat",
            Family::Corridor => "corridor",
            Family::BlockedDoor => "blocked-door",
            Family::ForceLimit => "force-limit",
            Family::Overhang => "overhang",
            Family::Wanderers => "wanderers",
            Family::Touching => "touching",
        }
    }

    /// One line on what the family is.
    pub fn summary(self) -> &'static str {
        match self {
            Family::OpenClutter => "An open room with clutter, light and heavy",
            Family::LargeRoom => "A room larger than the camera's range, the goal far away",
            Family::Flat => "A flat of rooms in a row joined by doors",
            Family::Corridor => "A corridor with things along its walls",
            Family::BlockedDoor => "Two rooms, a box in the door",
            Family::ForceLimit => "Two rooms, a box in the door near the push force limit",
            Family::Overhang => "A shelf across the room above the robot's head",
            Family::Wanderers => "An open room with people walking about",
            Family::Touching => {
                "Two rooms or a hall, the one opening shut by things standing against walls and each other"
            }
        }
    }

    /// One draw: a scenario (name, family, expectation filled in by the caller), its guarantee and
    /// the pushes it needs the robot to make (checked on the true world by the caller).
    pub(super) fn draw(self, rng: &mut ChaCha8Rng) -> (Scenario, Guarantee, Vec<NeededPush>) {
        let none = |(s, g): (Scenario, Guarantee)| (s, g, Vec::new());
        none(match self {
            Family::OpenClutter => rooms::open_clutter(rng),
            Family::LargeRoom => rooms::large_room(rng),
            Family::Flat => doors::flat(rng),
            Family::Corridor => rooms::corridor(rng),
            Family::BlockedDoor => doors::blocked_door(rng, doors::Blocker::LightOrBolted),
            Family::ForceLimit => doors::blocked_door(rng, doors::Blocker::NearTheLimit),
            Family::Overhang => rooms::overhang(rng),
            Family::Wanderers => wanderers::wanderers(rng),
            Family::Touching => return touching::touching(rng),
        })
    }
}

impl fmt::Display for Family {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A bare scenario: `size` room, the robot at `start` (x, y, yaw in degrees), the goal at `goal`.
fn bare(size: [f64; 2], start: [f64; 3], goal: [f64; 2]) -> Scenario {
    Scenario::bare("g", size, start, goal)
}

/// Rounds to centimetres, so files read well and round-trip exactly.
fn cm(v: f64) -> f64 {
    (v * 100.0).round() / 100.0
}
