//! How often the force guard of a guarded line must read the wrist: at every sample, except during a
//! steady push far below its limit, which may be read every [`STEADY_STEP_US`]. The simulation steps
//! its physics at this pace; the ROS 2 adapter lock-steps its simulator at it.

/// How long the hand must have pressed, without a break, before a push counts as steady (µs): the
/// impact has rung out (the wrist is critically damped, its period 31 ms) and a movable object slides.
pub const STEADY_PRESS_US: u64 = 200_000;
/// The least distance (N) between the tared force and the guard's limit for a steady push to be
/// read coarsely. A jam raises the force by at most stiffness × speed × step, 4 N in a 10 ms step at
/// the executive's 2 cm/s, so the read that follows is at the full rate again before the limit can
/// be reached; a chair's push test (15–19 N against 20 N) never qualifies, a clearing push (15 N
/// against 30 N) does.
pub const STEADY_MARGIN: f64 = 10.0;
/// How often a steady push is read (µs).
pub const STEADY_STEP_US: u64 = 10_000;

/// Whether a push may be read only every [`STEADY_STEP_US`]: it has pressed steadily (`held`), the
/// base stands, and its tared `force` lies below `limit` by [`STEADY_MARGIN`] and by twice what a
/// wrist of `stiffness` (N/m) can add at `speed` (m/s) in that time.
pub fn steady_push(
    force: f64,
    limit: f64,
    speed: f64,
    stiffness: f64,
    held: bool,
    standing: bool,
) -> bool {
    let rise = stiffness * speed * STEADY_STEP_US as f64 * 1.0e-6;
    let margin = STEADY_MARGIN.max(2.0 * rise);
    held && standing && force + margin <= limit
}
