//! Watching a run: the [`Observer`] trait the runner reports to, and the MCAP recorder behind it.

mod mcap_recorder;
mod mcap_records;
mod messages;
mod observer;
mod summary;
pub mod tape;
mod wrench_message;
mod writer_thread;

pub use mcap_recorder::{
    McapRecorder, RecordError, RunInfo, TAPE_BATCH, topics, view_cloud_stride,
};
pub use mcap_records::{RECORD_LENGTH_LIMIT, Records, mcap_records};
pub use observer::{GridView, LogLevel, NullObserver, Observer, RobotFrames};
pub use summary::{RUN_METADATA, RUN_SUMMARY_LOG, RunSummary, SUMMARY_METADATA};
pub use tape::TAPE_TOPIC;
pub use wrench_message::{
    VIEW_WINDOW, Vector3, WRIST_WRENCH_SCHEMA, WrenchWindows, WristWrench, wrist_wrench_schema,
};
