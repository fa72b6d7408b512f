//! One huge wrist reading.

use nalgebra::Vector3;

use super::FaultWindow;
use super::forward::{fault, forward};
use crate::robot::{Robot, RobotError, Stamped, Wrench, WristSensor};

/// While its window fires, one wrist reading (from [`WristSensor::wrench`] or one sample of
/// [`WristSensor::drain_wrenches`]) carries `force` instead of what the sensor measured: the spike a
/// loose connector or an electrical transient puts into one sample. Each reading taken after the
/// latest [`WristSensor::tare`] is a chance (older samples, drained after a tare, are what an
/// executive throws away: a spike there would be lost); the window says how many spikes there are. The adapter's own guard reads its sensor, not this (see
/// [`super`]); the executive must not take the spike for the object's answer. Every other call is
/// forwarded.
#[derive(Debug)]
pub struct WrenchSpike<R> {
    inner: R,
    window: FaultWindow,
    force: Vector3<f64>,
    /// Robot time of the latest tare (s).
    tared_at: f64,
}

impl<R: Robot> WrenchSpike<R> {
    /// Wraps `inner`; a reading becomes `force` (N, wrist frame) whenever `window` fires.
    pub fn new(inner: R, window: FaultWindow, force: Vector3<f64>) -> Self {
        Self {
            inner,
            window,
            force,
            tared_at: f64::NEG_INFINITY,
        }
    }

    fn spoil(&self, mut reading: Stamped<Wrench>) -> Stamped<Wrench> {
        if reading.stamp > self.tared_at && self.window.fires(reading.stamp) {
            reading.value.force = self.force;
        }
        reading
    }
}

fault!(WrenchSpike);
forward!(WrenchSpike: Clock, Base, Head, RangeCamera, Arm);

impl<R: Robot> WristSensor for WrenchSpike<R> {
    fn tare(&mut self) -> Result<(), RobotError> {
        self.inner.tare()?;
        self.tared_at = self.inner.now();
        Ok(())
    }

    fn wrench(&mut self) -> Result<Stamped<Wrench>, RobotError> {
        let reading = self.inner.wrench()?;
        Ok(self.spoil(reading))
    }

    fn drain_wrenches(&mut self) -> Result<Vec<Stamped<Wrench>>, RobotError> {
        let samples = self.inner.drain_wrenches()?;
        Ok(samples.into_iter().map(|s| self.spoil(s)).collect())
    }
}
