//! nudge-executive: the task executive that reaches a goal among obstacles it has never seen.
//!
//! It decides; it talks to the world only through the adapter traits in [`robot`], one small trait per
//! capability in the manner of OpenRR's `arci`. A simulation, a real robot or a log replay plugs in
//! behind the same traits.
//!
//! The decision logic is a pure transition function ([`machine::transition`]) over [`State`]s and
//! [`Event`]s that emits [`Command`]s; the push test's fused decision is [`push_test::classify`].
#![warn(missing_docs)]

pub mod command;
pub mod config;
pub mod event;
pub mod explain;
pub mod machine;
pub mod push_test;
pub mod record;
pub mod robot;
pub mod runner;
pub mod state;
pub mod view;

pub use command::Command;
pub use config::{CandidatePolicy, ExecutiveConfig};
pub use event::{Candidate, Event, SetAside, SetAsideWhy};
pub use explain::{Explanation, TestRecord};
pub use machine::{Edge, Knowledge, Step, start, transition};
/// What the robot is (its description, read by every crate): re-exported so an adapter needs one
/// dependency.
pub use nudge_robot_model::{self as robot_model, RobotModel};
pub use push_test::{Finding, PushEvidence, PushIntent, Verdict};
pub use runner::{RunConfig, RunReport, Runner};
pub use state::{AbortReason, Approach, Purpose, State};
pub use view::{Question, UnseenRegion, UnseenWhy, ViewRecord, Viewpoint};
