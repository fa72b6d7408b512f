//! `nudge sim-bridge`: a scenario's simulated robot served over ROS 2.

use std::path::Path;
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::Context;
use nudge_ros2::config::Ros2Config;

use super::SimBridgeArgs;
use super::source::Source;
use crate::adapter::SimRobot;
use crate::bridge::{Pace, SimBridge};

/// The ROS 2 graph from `path`, or the defaults; a bad file is an error placed at its line.
pub(super) fn ros2_config(path: Option<&Path>) -> anyhow::Result<Ros2Config> {
    let Some(path) = path else {
        return Ok(Ros2Config::default());
    };
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    Ok(Ros2Config::from_toml_str(
        &text,
        &path.display().to_string(),
    )?)
}

pub(super) fn sim_bridge(args: SimBridgeArgs) -> anyhow::Result<ExitCode> {
    if !(args.idle.is_finite() && args.idle > 0.0) {
        anyhow::bail!(
            "--idle must be a positive number of seconds, got {}",
            args.idle
        );
    }
    let pace = match args.real_time_factor {
        None => Pace::LockStep {
            idle: Duration::from_secs_f64(args.idle),
        },
        Some(factor) if factor.is_finite() && factor > 0.0 => Pace::Free {
            factor,
            until: args.until,
        },
        Some(factor) => anyhow::bail!("--real-time-factor must be positive, got {factor}"),
    };
    if let Some(until) = args.until
        && !(until.is_finite() && until >= 0.0)
    {
        anyhow::bail!("--until must be a non-negative number of seconds, got {until}");
    }
    let Source {
        file: file_name,
        scenario,
        ..
    } = match &args.scenario {
        Some(path) => Source::load(path)?,
        None => Source::default_room()?,
    };
    let seed = args.seed.unwrap_or(scenario.seed);
    let mut config = ros2_config(args.ros2.as_deref())?;
    // The bridge is a simulator: its clients take its time.
    config.use_sim_time = true;
    let robot = SimRobot::new(&scenario, seed)?;
    let mut bridge = SimBridge::new(robot, config)?.with_faults(args.fault);
    println!(
        "sim-bridge: {} ({file_name}), seed {seed}: serving over ROS 2, {}",
        scenario.name,
        match pace {
            Pace::LockStep { .. } => "lock-stepped".to_string(),
            Pace::Free { factor, .. } => format!("free-running at {factor}× real time"),
        }
    );
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    let started = Instant::now();
    let report = bridge.serve(&stop, pace)?;
    println!(
        "sim-bridge: ended at {:.1} s robot time after {:.1} s wall: {} steps, {} frames, {} command(s) refused, hand {:.1} mm from rest",
        report.robot_time,
        started.elapsed().as_secs_f64(),
        report.steps,
        report.frames,
        report.refused,
        report.hand_from_rest * 1e3
    );
    Ok(ExitCode::SUCCESS)
}
