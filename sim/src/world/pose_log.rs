//! Where each object stood over the run, so ground truth can be asked about any moment: a verdict
//! is scored against where things stood when the robot reached it, not where later pushes left them.
//!
//! An object's pose is written when it has moved on from its last entry by more than
//! [`LOG_STEP`] or turned by more than [`LOG_TURN`]; objects move only while something pushes them,
//! so a run's log holds a few entries per push.

use nalgebra::Isometry3;

/// Travel after which an object's pose is written again (m): a fifth of the obstacle grid's 5 cm
/// cell, well under anything scoring compares.
pub(super) const LOG_STEP: f64 = 0.01;

/// Turn after which an object's pose is written again (rad): 1°, under a centimetre at the ends of
/// a 1 m object.
pub(super) const LOG_TURN: f64 = std::f64::consts::PI / 180.0;

/// Every object's poses over time, by object index.
#[derive(Debug, Default)]
pub(super) struct PoseLog {
    /// Per object, (time µs, pose) in time order; the first entry is the pose the run started with.
    entries: Vec<Vec<(u64, Isometry3<f64>)>>,
}

impl PoseLog {
    /// A log starting at time 0 with the objects' poses in object order.
    pub(super) fn new(start: impl IntoIterator<Item = Isometry3<f64>>) -> Self {
        let entries = start.into_iter().map(|pose| vec![(0, pose)]).collect();
        Self { entries }
    }

    /// Notes that object `i` stands at `pose` at `time_us`; written when it moved on enough.
    pub(super) fn note(&mut self, i: usize, time_us: u64, pose: Isometry3<f64>) {
        let Some(log) = self.entries.get_mut(i) else {
            return;
        };
        let moved_on = log.last().is_none_or(|(_, last)| {
            (pose.translation.vector - last.translation.vector).norm() > LOG_STEP
                || pose.rotation.angle_to(&last.rotation) > LOG_TURN
        });
        if moved_on {
            log.push((time_us, pose));
        }
    }

    /// Where object `i` stood at `time_us` (its last entry at or before then).
    pub(super) fn at(&self, i: usize, time_us: u64) -> Option<Isometry3<f64>> {
        let log = self.entries.get(i)?;
        let after = log.partition_point(|(t, _)| *t <= time_us);
        log.get(after.saturating_sub(1)).map(|(_, pose)| *pose)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn a_pose_is_found_at_any_moment_and_small_moves_are_not_written() {
        // Invariant: the log answers the pose an object had at a time (the start pose before its
        // first move); moves under a centimetre and a degree add no entry.
        let at = |x: f64| {
            Isometry3::from_parts(Translation3::new(x, 0.0, 0.0), UnitQuaternion::identity())
        };
        let mut log = PoseLog::new([at(1.0)]);
        log.note(0, 1_000, at(1.005));
        log.note(0, 2_000, at(1.5));
        log.note(0, 3_000, at(2.0));
        assert_eq!(log.entries[0].len(), 3);
        assert_eq!(log.at(0, 0), Some(at(1.0)));
        assert_eq!(log.at(0, 1_999), Some(at(1.0)));
        assert_eq!(log.at(0, 2_000), Some(at(1.5)));
        assert_eq!(log.at(0, 10_000), Some(at(2.0)));
        assert_eq!(log.at(1, 0), None);
    }
}
