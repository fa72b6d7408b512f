//! Sensor models: the wrist force/torque sensor (and the colour range sensor).

pub mod wrist_ft;
