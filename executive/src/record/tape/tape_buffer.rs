//! The tape being recorded: encoded entries waiting for the recorder to write them.

use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use super::call::{Entry, Reply, Request, Transition};
use super::codec::encode_entry;
use crate::machine::Edge;
use crate::record::Observer;
use crate::state::State;

#[derive(Debug, Default)]
struct Buffer {
    bytes: Vec<u8>,
    /// Robot time when the bytes waiting began: the clock's last reading before their first entry.
    stamp: f64,
    /// The clock's last reading on the tape.
    clock: f64,
    entries: u64,
}

/// A shared tape: the [`super::Taped`] robot and the observer side write entries onto it in the
/// order they happen; [`Tape::take`] hands what is waiting to whoever stores it (the
/// [`crate::record::McapRecorder`] does so at every observer call, about once a tick).
///
/// As an [`Observer`] it puts each transition on the tape, between the calls around it.
#[derive(Clone, Debug, Default)]
pub struct Tape(Arc<Mutex<Buffer>>);

impl Tape {
    /// An empty tape.
    pub fn new() -> Self {
        Self::default()
    }

    fn buffer(&self) -> MutexGuard<'_, Buffer> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Encodes `entry` onto the tape.
    pub fn write(&self, entry: &Entry) {
        let mut b = self.buffer();
        if b.bytes.is_empty() {
            b.stamp = b.clock;
        }
        encode_entry(entry, &mut b.bytes);
        if let Entry::Call(Request::Now, Reply::Time(t)) = entry {
            b.clock = *t;
        }
        b.entries += 1;
    }

    /// The entries waiting, encoded, with the robot time they began at; `None` when none wait.
    pub fn take(&self) -> Option<(f64, Vec<u8>)> {
        let mut b = self.buffer();
        if b.bytes.is_empty() {
            return None;
        }
        Some((b.stamp, std::mem::take(&mut b.bytes)))
    }

    /// Entries put on the tape so far.
    pub fn entries(&self) -> u64 {
        self.buffer().entries
    }
}

impl Observer for Tape {
    fn transition(&mut self, _stamp: f64, from: Option<&State>, edge: Edge, to: &State) {
        self.write(&Entry::Transition(Transition::new(from, edge, to)));
    }
}
