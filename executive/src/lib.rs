//! nudge-executive: the task executive that reaches a goal among obstacles it has never seen.
//!
//! It decides; it talks to the world only through the adapter traits in [`robot`], one small trait per
//! capability in the manner of OpenRR's `arci`. A simulation, a real robot or a log replay plugs in
//! behind the same traits.
#![warn(missing_docs)]

pub mod robot;
