//! The colour range sensor.

use nudge_perception::ColourCloud;

use super::RobotError;

/// A colour range sensor (the paper's SR-4000 with stereo colour cameras).
pub trait RangeCamera {
    /// Captures one organised colour cloud in the sensor frame, carrying the sensor pose in the map
    /// frame and the robot-clock stamp.
    fn capture(&mut self) -> Result<ColourCloud, RobotError>;
}
