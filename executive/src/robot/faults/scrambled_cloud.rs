//! A frame after a push that colour ICP cannot register.

use nalgebra::{Point3, Vector3};
use nudge_perception::ColourCloud;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::FaultWindow;
use super::forward::{fault, forward};
use crate::robot::{Arm, GuardedMove, RangeCamera, Robot, RobotError};

/// Makes the push test's colour ICP fail to converge. While its window fires, the first frame
/// captured after a guarded move has started is replaced by seeded noise: every valid point is
/// moved to a uniformly random place inside the frame's bounding box and given a random colour
/// (rays with no return stay so). The frame before the push is untouched, so ICP has to register the
/// object's points against points that no rigid motion matches — what a frame torn by a driver, a
/// camera bumped by the push, or a scene changed beyond recognition give it. ICP then fails, stops
/// unconverged, or converges to a fit the push test must not trust. A capture with no guarded move
/// before it (a look-around) is not a chance. Every other call is forwarded.
#[derive(Debug)]
pub struct ScrambledCloud<R> {
    inner: R,
    window: FaultWindow,
    rng: ChaCha8Rng,
    after_push: bool,
}

impl<R: Robot> ScrambledCloud<R> {
    /// Wraps `inner`; the first frame after a guarded move is noise whenever `window` fires, the
    /// noise drawn from `seed` (the same seed gives the same noise).
    pub fn new(inner: R, window: FaultWindow, seed: u64) -> Self {
        Self {
            inner,
            window,
            rng: ChaCha8Rng::seed_from_u64(seed),
            after_push: false,
        }
    }

    fn scramble(&mut self, cloud: &ColourCloud) -> Result<ColourCloud, RobotError> {
        let (lo, hi) = cloud.iter_valid().fold(
            (
                Vector3::repeat(f32::INFINITY),
                Vector3::repeat(f32::NEG_INFINITY),
            ),
            |(lo, hi), (_, p, _)| (lo.inf(&p.coords), hi.sup(&p.coords)),
        );
        let (mut x, mut y, mut z) = (
            cloud.xs().to_vec(),
            cloud.ys().to_vec(),
            cloud.zs().to_vec(),
        );
        let mut rgb = cloud.colours().to_vec();
        for (i, _, _) in cloud.iter_valid() {
            let u: Vector3<f32> = Vector3::from_fn(|_, _| self.rng.random::<f32>());
            let p = Point3::from(lo + (hi - lo).component_mul(&u));
            (x[i], y[i], z[i]) = (p.x, p.y, p.z);
            rgb[i] = [self.rng.random(), self.rng.random(), self.rng.random()];
        }
        ColourCloud::organised(
            cloud.width(),
            cloud.height(),
            x,
            y,
            z,
            rgb,
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

fault!(ScrambledCloud);
forward!(ScrambledCloud: Clock, Base, Head, WristSensor);

impl<R: Robot> RangeCamera for ScrambledCloud<R> {
    fn capture(&mut self) -> Result<ColourCloud, RobotError> {
        let cloud = self.inner.capture()?;
        if !std::mem::take(&mut self.after_push) || !self.window.fires(self.inner.now()) {
            return Ok(cloud);
        }
        self.scramble(&cloud)
    }
}

impl<R: Robot> Arm for ScrambledCloud<R> {
    fn hand_position(
        &mut self,
    ) -> Result<crate::robot::Stamped<nalgebra::Point3<f64>>, RobotError> {
        self.inner.hand_position()
    }

    fn start_guarded_move(&mut self, motion: GuardedMove) -> Result<(), RobotError> {
        self.inner.start_guarded_move(motion)?;
        self.after_push = true;
        Ok(())
    }

    fn start_retract(&mut self) -> Result<(), RobotError> {
        self.inner.start_retract()
    }

    fn hand_status(
        &mut self,
    ) -> Result<crate::robot::ActionStatus<crate::robot::HandOutcome>, RobotError> {
        self.inner.hand_status()
    }

    fn stop_hand(&mut self) -> Result<(), RobotError> {
        self.inner.stop_hand()
    }
}
