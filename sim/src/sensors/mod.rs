//! Sensor models: the colour range sensor and the wrist force/torque sensor.

pub mod colour_range;
pub mod wrist_ft;
