//! Why a perception stage could not produce a result.

/// Errors of the perception stages. Bad input gives one of these (or an empty result), never a panic.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum PerceptionError {
    /// The cloud has no valid (finite) point.
    #[error("the cloud has no valid point")]
    EmptyCloud,
    /// No point fell in the known-floor patch in front of the robot.
    #[error("no point in the known-floor patch centred at ({x:.3}, {y:.3}) m")]
    NoFloorPoints {
        /// Patch centre x in the map frame (m).
        x: f64,
        /// Patch centre y in the map frame (m).
        y: f64,
    },
    /// Too few points fell in the known-floor patch to fit the floor model.
    #[error("only {found} points in the known-floor patch; at least {needed} are needed")]
    TooFewFloorPoints {
        /// Points found in the patch.
        found: usize,
        /// Points required.
        needed: usize,
    },
    /// A pose or parameter is not finite or out of its range.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// ICP needs more valid points than it was given.
    #[error(
        "ICP needs at least {needed} valid points in each cloud; got source {source_count}, target {target_count}"
    )]
    TooFewIcpPoints {
        /// Valid points in the source (before) cloud.
        source_count: usize,
        /// Valid points in the target (after) cloud.
        target_count: usize,
        /// Points required.
        needed: usize,
    },
    /// ICP found too few correspondences to estimate a motion.
    #[error("ICP found only {found} correspondences; at least {needed} are needed")]
    TooFewCorrespondences {
        /// Correspondences found.
        found: usize,
        /// Correspondences required.
        needed: usize,
    },
}
