//! A camera whose frames carry NaN coordinates.

use nudge_perception::ColourCloud;

use super::FaultWindow;
use super::forward::{fault, forward};
use crate::robot::{RangeCamera, Robot, RobotError};

/// While its window fires, [`RangeCamera::capture`] returns the wrapped camera's frame with one
/// coordinate of every `every`-th slot set to NaN (x, y and z in turn, slot by slot), the other
/// coordinates left as they were. An organised cloud marks a ray with no return by NaN in all three;
/// a NaN in only one is what a driver's bad conversion leaves, and a consumer that reads the raw
/// arrays instead of the valid points meets NaN beside finite values. The layout (width × height)
/// is kept. Every other call is forwarded.
#[derive(Debug)]
pub struct NanCloud<R> {
    inner: R,
    window: FaultWindow,
    every: usize,
}

impl<R: Robot> NanCloud<R> {
    /// Wraps `inner`; whenever `window` fires (one chance per capture), every `every`-th slot of the
    /// frame gets a NaN (`every` 1: all of them; 0 counts as 1).
    pub fn new(inner: R, window: FaultWindow, every: usize) -> Self {
        Self {
            inner,
            window,
            every: every.max(1),
        }
    }
}

fault!(NanCloud);
forward!(NanCloud: Clock, Base, Head, WristSensor, Arm);

impl<R: Robot> RangeCamera for NanCloud<R> {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        let cloud = self.inner.capture()?;
        if !self.window.fires(self.inner.now()) {
            return Ok(cloud);
        }
        let (mut x, mut y, mut z) = (
            cloud.xs().to_vec(),
            cloud.ys().to_vec(),
            cloud.zs().to_vec(),
        );
        for i in (0..x.len()).step_by(self.every) {
            let axis = match (i / self.every) % 3 {
                0 => &mut x,
                1 => &mut y,
                _ => &mut z,
            };
            axis[i] = f32::NAN;
        }
        ColourCloud::organised(
            cloud.width(),
            cloud.height(),
            x,
            y,
            z,
            cloud.colours().to_vec(),
            cloud.frame(),
            *cloud.sensor_pose(),
            cloud.stamp(),
        )
        .map_err(|e| RobotError::Fault {
            capability: "camera",
            reason: e.to_string(),
        })
    }
}
