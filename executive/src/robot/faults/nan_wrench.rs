//! Wrist readings of NaN.

use nalgebra::Vector3;

use super::FaultWindow;
use super::forward::{fault, forward, spoiled_wrist};
use crate::robot::{Robot, Stamped, Wrench};

/// While its window fires, wrist readings (from [`crate::robot::WristSensor::wrench`] and every sample
/// of [`crate::robot::WristSensor::drain_wrenches`]) carry NaN force and torque: what a sensor driver that lost its
/// calibration or a division by a zero gain gives. Each reading is a chance. A NaN compares false
/// with every threshold, so an executive that only asks "is the force above the limit?" never sees
/// it. The adapter's own guard reads its sensor, not this (see [`super`]). Every other call is
/// forwarded.
#[derive(Debug)]
pub struct NanWrench<R> {
    inner: R,
    window: FaultWindow,
}

impl<R: Robot> NanWrench<R> {
    /// Wraps `inner`; a reading becomes NaN whenever `window` fires.
    pub fn new(inner: R, window: FaultWindow) -> Self {
        Self { inner, window }
    }

    fn spoil(&self, mut reading: Stamped<Wrench>) -> Stamped<Wrench> {
        if self.window.fires(reading.stamp) {
            reading.value = Wrench {
                force: Vector3::repeat(f64::NAN),
                torque: Vector3::repeat(f64::NAN),
            };
        }
        reading
    }
}

fault!(NanWrench);
forward!(NanWrench: Clock, Base, Head, RangeCamera, Arm);

spoiled_wrist!(NanWrench);
