//! The 6-axis wrist force/torque sensor: true joint reaction + bias + Gaussian noise, sampled at its
//! own rate, with tare.
//!
//! Sign convention: the reading is the wrench the hand exerts ON the wrist, in the wrist frame
//! (x forward, y left, z up for a level wrist). A hand hanging at rest reads `(0, 0, −m g)`; pushing
//! an obstacle straight ahead reads a force along −x.

use std::collections::VecDeque;

use nalgebra::Vector3;
use nudge_executive::robot::{Stamped, Wrench};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use rapier3d::prelude::ImpulseJoint;

/// How many recent raw readings the tare averages.
const TARE_WINDOW: usize = 50;
/// The drain buffer keeps at most this many samples (a minute at 1 kHz); older ones are dropped.
const MAX_BUFFERED: usize = 60_000;

/// Parameters of the wrist sensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WristFtConfig {
    /// Sample rate (Hz).
    pub rate_hz: f64,
    /// Standard deviation of the force noise per axis (N).
    pub force_noise: f64,
    /// Standard deviation of the torque noise per axis (N·m).
    pub torque_noise: f64,
    /// Largest constant force bias per axis (N); the actual bias is drawn from the seed.
    pub max_force_bias: f64,
    /// The step of the force counts the sensor reports (N); 0 for readings on no grid.
    pub force_step: f64,
    /// The step of the torque counts the sensor reports (N·m); 0 for readings on no grid.
    pub torque_step: f64,
}

/// The step of a sensor's counts for an axis with noise `sigma`: the largest power of two no more
/// than a tenth of it, so that rounding (a uniform error of step/√12, under σ/30) adds nothing the
/// noise had not, as in the 16-bit transducers of the class (ATI's Gamma resolves 1/80 N and
/// 1/1333 N·m against 0.2 N and 0.01 N·m here: 1/64 N and 1/1024 N·m). 0 for a noiseless axis.
pub fn count_step(sigma: f64) -> f64 {
    if sigma > 0.0 && sigma.is_finite() {
        2f64.powi((sigma / 10.0).log2().floor() as i32)
    } else {
        0.0
    }
}

/// `v` on the grid of `step` (unchanged for a step of 0): the nearest whole count, half a step
/// away from zero. It runs for six axes a millisecond, so it rounds with a truncating cast, not the
/// library call `f64::round` is on the baseline x86-64 target.
fn on_step(v: f64, step: f64) -> f64 {
    if step > 0.0 {
        let steps = v / step;
        let count = if steps >= 0.0 {
            (steps + 0.5) as i64
        } else {
            -((0.5 - steps) as i64)
        };
        count as f64 * step
    } else {
        v
    }
}

impl Default for WristFtConfig {
    /// The paper's robot's wrist ([`nudge_robot_model::RobotModel::default`]).
    fn default() -> Self {
        Self::for_wrist(&nudge_robot_model::WristModel::default())
    }
}

impl WristFtConfig {
    /// A sensor at `wrist`'s rate with a JR3-like noise: 0.2 N and 0.01 N·m per axis, a bias of up
    /// to 1 N per axis, reported in counts of [`count_step`] of the noise.
    pub fn for_wrist(wrist: &nudge_robot_model::WristModel) -> Self {
        let (force_noise, torque_noise) = (0.2, 0.01);
        Self {
            rate_hz: wrist.rate_hz,
            force_noise,
            torque_noise,
            max_force_bias: 1.0,
            force_step: count_step(force_noise),
            torque_step: count_step(torque_noise),
        }
    }
}

/// Why a sensor could not be made.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum WristFtError {
    /// A parameter is out of range.
    #[error("wrist sensor parameter {name} is invalid: {value}")]
    InvalidParameter {
        /// Which parameter.
        name: &'static str,
        /// Its value.
        value: f64,
    },
}

/// The wrench a joint applied during the last physics step, from its per-substep impulses.
///
/// rapier writes back the impulse of the LAST solver substep (joints are not warm-started), so the
/// force is `impulse × substeps / dt`. Linear rows of the compliant wrist joint are motors (their
/// impulse lives in `motors[i].impulse`); angular rows are locked (`impulses[3..6]`). The stored
/// impulses act on the joint's first body, so the result is the wrench the hand exerts on the wrist,
/// in the wrist frame (pinned by the hanging-hand test: a hand at rest gives `(0, 0, −m g)`).
pub fn wrench_on_wrist(joint: &ImpulseJoint, substeps: usize, dt: f64) -> Wrench {
    if dt <= 0.0 {
        return Wrench::default();
    }
    let scale = substeps as f64 / dt;
    let lin = |i: usize| f64::from(joint.data.motors[i].impulse + joint.impulses[i]) * scale;
    let ang = |i: usize| f64::from(joint.impulses[i]) * scale;
    Wrench {
        force: Vector3::new(lin(0), lin(1), lin(2)),
        torque: Vector3::new(ang(3), ang(4), ang(5)),
    }
}

/// The simulated sensor.
#[derive(Clone, Debug)]
pub struct WristFt {
    config: WristFtConfig,
    period_us: u64,
    rng: ChaCha8Rng,
    force_noise: Normal<f64>,
    torque_noise: Normal<f64>,
    bias: Wrench,
    offset: Wrench,
    recent_raw: VecDeque<Wrench>,
    buffer: VecDeque<Stamped<Wrench>>,
    latest_raw: Option<Stamped<Wrench>>,
}

impl WristFt {
    /// A sensor with its bias and noise drawn from `seed`.
    pub fn new(config: WristFtConfig, seed: u64) -> Result<Self, WristFtError> {
        let check = |name, value: f64, ok: bool| {
            if ok {
                Ok(())
            } else {
                Err(WristFtError::InvalidParameter { name, value })
            }
        };
        check(
            "rate_hz",
            config.rate_hz,
            config.rate_hz.is_finite() && (1.0..=1.0e6).contains(&config.rate_hz),
        )?;
        check(
            "force_noise",
            config.force_noise,
            config.force_noise.is_finite() && config.force_noise >= 0.0,
        )?;
        check(
            "torque_noise",
            config.torque_noise,
            config.torque_noise.is_finite() && config.torque_noise >= 0.0,
        )?;
        for (name, step) in [
            ("force_step", config.force_step),
            ("torque_step", config.torque_step),
        ] {
            check(name, step, step.is_finite() && step >= 0.0)?;
        }
        check(
            "max_force_bias",
            config.max_force_bias,
            config.max_force_bias.is_finite() && config.max_force_bias >= 0.0,
        )?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5752_4953_5446_5431);
        let b = config.max_force_bias;
        let bias = Wrench {
            force: Vector3::from_fn(|_, _| {
                if b > 0.0 {
                    rng.random_range(-b..b)
                } else {
                    0.0
                }
            }),
            torque: Vector3::zeros(),
        };
        let normal = |sd: f64| {
            Normal::new(0.0, sd).map_err(|_| WristFtError::InvalidParameter {
                name: "noise",
                value: sd,
            })
        };
        Ok(Self {
            period_us: ((1.0e6 / config.rate_hz).round() as u64).max(1),
            force_noise: normal(config.force_noise)?,
            torque_noise: normal(config.torque_noise)?,
            config,
            rng,
            bias,
            offset: Wrench::default(),
            recent_raw: VecDeque::with_capacity(TARE_WINDOW),
            buffer: VecDeque::new(),
            latest_raw: None,
        })
    }

    /// The sensor's parameters.
    pub fn config(&self) -> &WristFtConfig {
        &self.config
    }

    /// Records the true wrench on the wrist held during `(t0_us, t1_us]` (µs of simulated time): takes
    /// every sample the sensor's clock falls on in that interval. Returns the tared reading to check
    /// limits against this step: the last sample taken, or a fresh noisy reading when none fell in it.
    pub fn record(&mut self, truth: &Wrench, t0_us: u64, t1_us: u64) -> Stamped<Wrench> {
        let mut tick = (t0_us / self.period_us + 1) * self.period_us;
        let mut last = None;
        while tick <= t1_us {
            let raw = self.raw(truth);
            let sample = Stamped {
                stamp: tick as f64 * 1.0e-6,
                value: self.tared(&raw),
            };
            self.latest_raw = Some(Stamped {
                stamp: sample.stamp,
                value: raw,
            });
            if self.recent_raw.len() == TARE_WINDOW {
                self.recent_raw.pop_front();
            }
            self.recent_raw.push_back(raw);
            if self.buffer.len() == MAX_BUFFERED {
                self.buffer.pop_front();
            }
            self.buffer.push_back(sample);
            last = Some(sample);
            tick += self.period_us;
        }
        match last {
            Some(s) => s,
            None => {
                let raw = self.raw(truth);
                self.latest_raw = Some(Stamped {
                    stamp: t1_us as f64 * 1.0e-6,
                    value: raw,
                });
                Stamped {
                    stamp: t1_us as f64 * 1.0e-6,
                    value: self.tared(&raw),
                }
            }
        }
    }

    /// Zeroes the sensor: later readings subtract the mean of the recent raw readings (or of one
    /// fresh reading of `truth` when none were taken yet).
    pub fn tare(&mut self, truth: &Wrench) {
        if self.recent_raw.is_empty() {
            self.offset = self.raw(truth);
        } else {
            let n = self.recent_raw.len() as f64;
            let sum = self
                .recent_raw
                .iter()
                .fold(Wrench::default(), |acc, w| Wrench {
                    force: acc.force + w.force,
                    torque: acc.torque + w.torque,
                });
            self.offset = self.counted(&Wrench {
                force: sum.force / n,
                torque: sum.torque / n,
            });
        }
    }

    /// `w` in the sensor's counts: a reading, or the offset a tare subtracts from readings (a
    /// sensor's electronics subtract a whole count), so tared readings stay on the grid too.
    fn counted(&self, w: &Wrench) -> Wrench {
        Wrench {
            force: w.force.map(|v| on_step(v, self.config.force_step)),
            torque: w.torque.map(|v| on_step(v, self.config.torque_step)),
        }
    }

    /// The latest tared reading, if any was taken.
    pub fn latest(&self) -> Option<Stamped<Wrench>> {
        self.latest_raw.map(|r| Stamped {
            stamp: r.stamp,
            value: self.tared(&r.value),
        })
    }

    /// Every sample since the previous drain, oldest first.
    pub fn drain(&mut self) -> Vec<Stamped<Wrench>> {
        self.buffer.drain(..).collect()
    }

    /// Forgets the buffered samples.
    pub fn discard(&mut self) {
        self.buffer.clear();
    }

    fn raw(&mut self, truth: &Wrench) -> Wrench {
        let f = Vector3::from_fn(|_, _| self.force_noise.sample(&mut self.rng));
        let t = Vector3::from_fn(|_, _| self.torque_noise.sample(&mut self.rng));
        self.counted(&Wrench {
            force: truth.force + self.bias.force + f,
            torque: truth.torque + self.bias.torque + t,
        })
    }

    fn tared(&self, raw: &Wrench) -> Wrench {
        Wrench {
            force: raw.force - self.offset.force,
            torque: raw.torque - self.offset.torque,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn truth() -> Wrench {
        Wrench {
            force: Vector3::new(1.0, 2.0, -5.0),
            torque: Vector3::zeros(),
        }
    }

    #[test]
    fn samples_fall_on_the_sensor_clock() {
        // At 1 kHz, a 10 ms interval yields exactly ten samples stamped on whole milliseconds.
        let mut s = WristFt::new(WristFtConfig::default(), 1).expect("valid config");
        s.record(&truth(), 0, 10_000);
        let samples = s.drain();
        assert_eq!(samples.len(), 10);
        assert!((samples[0].stamp - 0.001).abs() < 1e-12);
        assert!((samples[9].stamp - 0.010).abs() < 1e-12);
        assert!(s.drain().is_empty());
    }

    #[test]
    fn tare_removes_bias_and_load() {
        // After tare, the mean reading of an unchanged load is near zero (within noise / sqrt(n)).
        let mut s = WristFt::new(WristFtConfig::default(), 2).expect("valid config");
        s.record(&truth(), 0, 100_000);
        s.tare(&truth());
        s.drain();
        s.record(&truth(), 100_000, 1_100_000);
        let samples = s.drain();
        let mean =
            samples.iter().map(|w| w.value.force).sum::<Vector3<f64>>() / samples.len() as f64;
        assert!(mean.norm() < 0.15, "mean after tare {mean:?}");
        let sd = (samples
            .iter()
            .map(|w| (w.value.force.x - mean.x).powi(2))
            .sum::<f64>()
            / samples.len() as f64)
            .sqrt();
        assert!((sd - 0.2).abs() < 0.03, "noise sd {sd}");
    }

    #[test]
    fn readings_are_whole_counts_of_the_sensor_steps_after_tare_too() {
        // Invariant: every sample, before and after a tare, is a whole number of 1/64 N force counts and 1/1024 N·m torque counts (steps a tenth of the noise or less).
        let config = WristFtConfig::default();
        assert_eq!(
            (config.force_step, config.torque_step),
            (1.0 / 64.0, 1.0 / 1024.0)
        );
        let mut s = WristFt::new(config, 3).expect("valid config");
        let load = Wrench {
            force: Vector3::new(1.234_567, -7.654_321, 3.3),
            torque: Vector3::new(0.012_345, 0.2, -0.3),
        };
        s.record(&load, 0, 60_000);
        s.tare(&load);
        s.record(&load, 60_000, 80_000);
        for w in s.drain() {
            for v in w.value.force.iter() {
                assert_eq!((v * 64.0).fract(), 0.0, "force {v}");
            }
            for v in w.value.torque.iter() {
                assert_eq!((v * 1024.0).fract(), 0.0, "torque {v}");
            }
        }
    }

    #[test]
    fn bad_rate_is_an_error() {
        // A non-positive or non-finite rate is refused.
        for rate in [0.0, -5.0, f64::NAN] {
            let c = WristFtConfig {
                rate_hz: rate,
                ..WristFtConfig::default()
            };
            assert!(WristFt::new(c, 1).is_err());
        }
    }
}
