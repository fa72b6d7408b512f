//! A camera that returns frames with no points.

use nudge_perception::ColourCloud;

use super::FaultWindow;
use super::forward::{fault, forward};
use crate::robot::{RangeCamera, Robot, RobotError};

/// While its window fires, [`RangeCamera::capture`] returns a cloud with no points at all, stamped
/// and posed as the frame the wrapped camera took: a sensor that answers but sees nothing (lens
/// covered, all returns below its confidence threshold). Every other call is forwarded.
#[derive(Debug)]
pub struct EmptyCloud<R> {
    inner: R,
    window: FaultWindow,
}

impl<R: Robot> EmptyCloud<R> {
    /// Wraps `inner`; a frame comes back empty whenever `window` fires (one chance per capture).
    pub fn new(inner: R, window: FaultWindow) -> Self {
        Self { inner, window }
    }
}

fault!(EmptyCloud);
forward!(EmptyCloud: Clock, Base, Head, WristSensor, Arm);

impl<R: Robot> RangeCamera for EmptyCloud<R> {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        let cloud = self.inner.capture()?;
        if !self.window.fires(self.inner.now()) {
            return Ok(cloud);
        }
        Ok(ColourCloud::empty(
            cloud.frame(),
            *cloud.sensor_pose(),
            cloud.stamp(),
        ))
    }
}
