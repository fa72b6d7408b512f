//! Forwarding the capability traits a decorator leaves alone, so each decorator writes out only the
//! trait its fault changes.

/// Implements the named capability traits for `$ty<R>` (a struct with an `inner: R` field) by
/// forwarding every method to `inner`: `forward!(CameraDropout: Clock, Base, Head, WristSensor, Arm);`.
macro_rules! forward {
    ($ty:ident: $($cap:ident),+ $(,)?) => { $(forward!(@ $ty, $cap);)+ };
    (@ $ty:ident, Clock) => {
        impl<R: $crate::robot::Robot> $crate::robot::Clock for $ty<R> {
            fn now(&self) -> f64 {
                $crate::robot::Clock::now(&self.inner)
            }
            fn advance(&mut self, dt: f64) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::Clock::advance(&mut self.inner, dt)
            }
        }
    };
    (@ $ty:ident, Base) => {
        impl<R: $crate::robot::Robot> $crate::robot::Base for $ty<R> {
            fn base_pose(
                &mut self,
            ) -> Result<$crate::robot::Stamped<nalgebra::Isometry2<f64>>, $crate::robot::RobotError>
            {
                $crate::robot::Base::base_pose(&mut self.inner)
            }
            fn start_walk(
                &mut self,
                waypoints: &[nalgebra::Point2<f64>],
            ) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::Base::start_walk(&mut self.inner, waypoints)
            }
            fn start_turn(&mut self, yaw: f64) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::Base::start_turn(&mut self.inner, yaw)
            }
            fn walk_status(
                &mut self,
            ) -> Result<
                $crate::robot::ActionStatus<$crate::robot::WalkOutcome>,
                $crate::robot::RobotError,
            > {
                $crate::robot::Base::walk_status(&mut self.inner)
            }
            fn stop_walk(&mut self) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::Base::stop_walk(&mut self.inner)
            }
        }
    };
    (@ $ty:ident, Head) => {
        impl<R: $crate::robot::Robot> $crate::robot::Head for $ty<R> {
            fn head_angles(
                &mut self,
            ) -> Result<$crate::robot::Stamped<(f64, f64)>, $crate::robot::RobotError> {
                $crate::robot::Head::head_angles(&mut self.inner)
            }
            fn start_point_head(
                &mut self,
                pan: f64,
                tilt: f64,
            ) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::Head::start_point_head(&mut self.inner, pan, tilt)
            }
            fn head_status(
                &mut self,
            ) -> Result<$crate::robot::ActionStatus<()>, $crate::robot::RobotError> {
                $crate::robot::Head::head_status(&mut self.inner)
            }
        }
    };
    (@ $ty:ident, RangeCamera) => {
        impl<R: $crate::robot::Robot> $crate::robot::RangeCamera for $ty<R> {
            fn capture(
                &mut self,
            ) -> Result<nudge_perception::ColourCloud, $crate::robot::RobotError> {
                $crate::robot::RangeCamera::capture(&mut self.inner)
            }
        }
    };
    (@ $ty:ident, WristSensor) => {
        impl<R: $crate::robot::Robot> $crate::robot::WristSensor for $ty<R> {
            fn tare(&mut self) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::WristSensor::tare(&mut self.inner)
            }
            fn wrench(
                &mut self,
            ) -> Result<$crate::robot::Stamped<$crate::robot::Wrench>, $crate::robot::RobotError>
            {
                $crate::robot::WristSensor::wrench(&mut self.inner)
            }
            fn drain_wrenches(
                &mut self,
            ) -> Result<
                Vec<$crate::robot::Stamped<$crate::robot::Wrench>>,
                $crate::robot::RobotError,
            > {
                $crate::robot::WristSensor::drain_wrenches(&mut self.inner)
            }
            fn discard_wrenches(&mut self) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::WristSensor::discard_wrenches(&mut self.inner)
            }
        }
    };
    (@ $ty:ident, Arm) => {
        impl<R: $crate::robot::Robot> $crate::robot::Arm for $ty<R> {
            fn hand_position(
                &mut self,
            ) -> Result<$crate::robot::Stamped<nalgebra::Point3<f64>>, $crate::robot::RobotError>
            {
                $crate::robot::Arm::hand_position(&mut self.inner)
            }
            fn start_guarded_move(
                &mut self,
                motion: $crate::robot::GuardedMove,
            ) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::Arm::start_guarded_move(&mut self.inner, motion)
            }
            fn start_retract(&mut self) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::Arm::start_retract(&mut self.inner)
            }
            fn hand_status(
                &mut self,
            ) -> Result<
                $crate::robot::ActionStatus<$crate::robot::HandOutcome>,
                $crate::robot::RobotError,
            > {
                $crate::robot::Arm::hand_status(&mut self.inner)
            }
            fn stop_hand(&mut self) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::Arm::stop_hand(&mut self.inner)
            }
        }
    };
}

/// Implements [`super::Fault`] for `$ty<R>`, a struct with `inner: R` and `window: FaultWindow`
/// fields.
macro_rules! fault {
    ($ty:ident) => {
        impl<R: $crate::robot::Robot> $crate::robot::faults::Fault for $ty<R> {
            type Inner = R;
            fn window(&self) -> &$crate::robot::faults::FaultWindow {
                &self.window
            }
            fn inner(&self) -> &R {
                &self.inner
            }
            fn into_inner(self) -> R {
                self.inner
            }
        }
    };
}

/// Implements [`crate::robot::WristSensor`] for `$ty<R>` by passing every reading through its
/// `spoil(&mut self, Stamped<Wrench>) -> Stamped<Wrench>` (a `&self` one does too); tare forwards.
macro_rules! spoiled_wrist {
    ($ty:ident) => {
        impl<R: $crate::robot::Robot> $crate::robot::WristSensor for $ty<R> {
            fn tare(&mut self) -> Result<(), $crate::robot::RobotError> {
                $crate::robot::WristSensor::tare(&mut self.inner)
            }
            fn wrench(
                &mut self,
            ) -> Result<$crate::robot::Stamped<$crate::robot::Wrench>, $crate::robot::RobotError>
            {
                let reading = $crate::robot::WristSensor::wrench(&mut self.inner)?;
                Ok(self.spoil(reading))
            }
            fn drain_wrenches(
                &mut self,
            ) -> Result<
                Vec<$crate::robot::Stamped<$crate::robot::Wrench>>,
                $crate::robot::RobotError,
            > {
                let samples = $crate::robot::WristSensor::drain_wrenches(&mut self.inner)?;
                Ok(samples.into_iter().map(|s| self.spoil(s)).collect())
            }
        }
    };
}

pub(crate) use {fault, forward, spoiled_wrist};
