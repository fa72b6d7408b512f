//! A camera that drops out: no frame.

use nudge_perception::ColourCloud;

use super::FaultWindow;
use super::forward::{fault, forward};
use crate::robot::{RangeCamera, Robot, RobotError};

/// While its window fires, [`RangeCamera::capture`] fails with [`RobotError::Unavailable`], as a
/// camera whose driver lost the device does; the call never reaches the wrapped camera. Every other
/// call is forwarded.
#[derive(Debug)]
pub struct CameraDropout<R> {
    inner: R,
    window: FaultWindow,
}

impl<R: Robot> CameraDropout<R> {
    /// Wraps `inner`; the camera drops out whenever `window` fires (one chance per capture).
    pub fn new(inner: R, window: FaultWindow) -> Self {
        Self { inner, window }
    }
}

fault!(CameraDropout);
forward!(CameraDropout: Clock, Base, Head, WristSensor, Arm);

impl<R: Robot> RangeCamera for CameraDropout<R> {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        if self.window.fires(self.inner.now()) {
            return Err(RobotError::Unavailable {
                capability: "camera",
                reason: "no frame (injected dropout)".into(),
            });
        }
        self.inner.capture()
    }
}
