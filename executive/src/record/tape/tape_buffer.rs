//! The tape being recorded: encoded entries waiting for the recorder to write them.

use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use nudge_robot_model::CameraModel;

use super::call::{Entry, Reply, Request, Transition};
use super::camera_rays::CameraRays;
use super::codec::encode_entry;
use crate::machine::Edge;
use crate::record::Observer;
use crate::state::State;

#[derive(Debug, Default)]
struct Buffer {
    /// The camera whose clouds are stored as range counts, if known.
    camera: Option<Arc<CameraRays>>,
    /// Entries waiting to be stored, in order.
    waiting: Vec<Entry>,
    /// Robot time when the entries waiting began: the clock's last reading before the first.
    stamp: f64,
    /// The clock's last reading on the tape.
    clock: f64,
    entries: u64,
}

/// A shared tape: the [`super::Taped`] robot and the observer side write entries onto it in the
/// order they happen; [`Tape::take`] hands what is waiting to whoever stores it (the
/// [`crate::record::McapRecorder`] takes the entries and has its writer thread encode them).
///
/// As an [`Observer`] it puts each transition on the tape, between the calls around it.
#[derive(Clone, Debug, Default)]
pub struct Tape(Arc<Mutex<Buffer>>);

impl Tape {
    /// An empty tape; clouds go on it as raw points.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty tape for a robot with `camera`: the clouds whose points lie on the camera's pixel
    /// rays at its range steps go on it as one count a point (any other point as it is).
    pub fn for_camera(camera: &CameraModel) -> Self {
        let tape = Self::default();
        tape.buffer().camera = Some(Arc::new(CameraRays::new(camera)));
        tape
    }

    fn buffer(&self) -> MutexGuard<'_, Buffer> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Puts `entry` on the tape.
    pub fn write(&self, entry: Entry) {
        let mut b = self.buffer();
        if b.waiting.is_empty() {
            b.stamp = b.clock;
        }
        if let Entry::Call(Request::Now, Reply::Time(t)) = entry {
            b.clock = t;
        }
        b.waiting.push(entry);
        b.entries += 1;
    }

    /// The entries waiting, encoded, with the robot time they began at; `None` when none wait.
    pub fn take(&self) -> Option<(f64, Vec<u8>)> {
        let (stamp, entries, camera) = self.take_entries(1)?;
        let mut bytes = Vec::new();
        for entry in &entries {
            encode_entry(entry, &mut bytes, camera.as_deref());
        }
        Some((stamp, bytes))
    }

    /// The entries waiting, once at least `min_entries` wait, with the robot time they began at
    /// and the camera to encode their clouds with ([`encode_entry`]).
    pub fn take_entries(
        &self,
        min_entries: usize,
    ) -> Option<(f64, Vec<Entry>, Option<Arc<CameraRays>>)> {
        let mut b = self.buffer();
        if b.waiting.is_empty() || b.waiting.len() < min_entries {
            return None;
        }
        Some((b.stamp, std::mem::take(&mut b.waiting), b.camera.clone()))
    }

    /// Entries put on the tape so far.
    pub fn entries(&self) -> u64 {
        self.buffer().entries
    }
}

impl Observer for Tape {
    fn transition(&mut self, _stamp: f64, from: Option<&State>, edge: Edge, to: &State) {
        self.write(Entry::Transition(Transition::new(from, edge, to)));
    }
}
