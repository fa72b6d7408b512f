//! Sensor models: what the simulated robot perceives (the colour range sensor on the head, the
//! force/torque sensor at the wrist).

pub mod colour_range;
pub mod wrist_ft;
