//! Sensor models: what the simulated robot perceives.

pub mod colour_range;
