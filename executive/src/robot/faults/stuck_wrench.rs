//! A wrist sensor stuck on its last reading.

use super::FaultWindow;
use super::forward::{fault, forward, spoiled_wrist};
use crate::robot::{Robot, Stamped, Wrench};

/// Once its window fires, the wrist sensor repeats the last reading it gave before, forever (the
/// stamps go on): a frozen driver or a sensor whose bus stopped updating while the transport still
/// delivers. Each reading is a chance; the first that fires freezes the value for good, whatever the
/// window says afterwards. Taring does not unfreeze it. The adapter's own guard reads its sensor,
/// not this (see [`super`]). Every other call is forwarded.
#[derive(Debug)]
pub struct StuckWrench<R> {
    inner: R,
    window: FaultWindow,
    last: Option<Wrench>,
    stuck: Option<Wrench>,
}

impl<R: Robot> StuckWrench<R> {
    /// Wraps `inner`; the readings freeze when `window` first fires.
    pub fn new(inner: R, window: FaultWindow) -> Self {
        Self {
            inner,
            window,
            last: None,
            stuck: None,
        }
    }

    fn spoil(&mut self, mut reading: Stamped<Wrench>) -> Stamped<Wrench> {
        if self.stuck.is_none() && self.window.fires(reading.stamp) {
            self.stuck = Some(self.last.unwrap_or(reading.value));
        }
        match self.stuck {
            Some(value) => reading.value = value,
            None => self.last = Some(reading.value),
        }
        reading
    }
}

fault!(StuckWrench);
forward!(StuckWrench: Clock, Base, Head, RangeCamera, Arm);

spoiled_wrist!(StuckWrench);
