//! Wrist samples on the tape: a sensor's counts as small integers, losslessly.
//!
//! A force/torque sensor reports counts of a fixed step, and a step that is a power of two makes
//! each axis an integer times 2⁻ᵏ. A batch of samples is stored in columns ([`samples`]): each
//! stamp's kind and each vector's k; the stamps, one on a whole microsecond (`µs × 10⁻⁶`, as the
//! simulated sensor's clock writes it) as the change in microseconds from the one before, any
//! other as its raw bits; each axis's integers as changes from the sample before (zigzag varints)
//! where its vector is integers times one 2⁻ᵏ (k ≤ 52, read back to the bit); then the vectors that
//! are not, as raw bits. With the simulated wrist's 1/64 N and 1/1024 N·m steps the noise is most
//! of what is left.

use nalgebra::Vector3;

use super::codec::{Dec, DecodeError, Enc};
use crate::robot::{Stamped, Wrench};

/// The scale byte of a vector stored as raw bits.
const RAW: u8 = 0xff;
/// The largest k of 2⁻ᵏ tried: beyond 52 an integer no longer has the float's precision.
const MAX_SCALE: u8 = 52;

fn zigzag(v: i64) -> u64 {
    ((v << 1) ^ (v >> 63)) as u64
}

fn unzigzag(z: u64) -> i64 {
    (z >> 1) as i64 ^ -((z & 1) as i64)
}

/// `v` as integers times 2⁻ᵏ for the least k that reads back to the bit, if any. The k an axis
/// needs is read off its bits (the exponent less the mantissa's trailing zeros), not searched for:
/// it runs for every 1 kHz sample.
fn scaled(v: &Vector3<f64>) -> Option<(u8, [i64; 3])> {
    let mut k = 0i32;
    for a in [v.x, v.y, v.z] {
        k = k.max(scale_needed(a)?);
    }
    let k = u8::try_from(k).ok().filter(|&k| k <= MAX_SCALE)?;
    let scale = 2f64.powi(i32::from(k));
    let ints = [v.x, v.y, v.z].map(|a| (a * scale) as i64);
    let reads_back = ints
        .iter()
        .zip([v.x, v.y, v.z])
        .all(|(&i, a)| i.unsigned_abs() <= 1 << 53 && (i as f64 / scale).to_bits() == a.to_bits());
    reads_back.then_some((k, ints))
}

/// The least k for which `a` × 2ᵏ is an integer: `None` for what is not a finite number or is −0
/// (an integer reads back as +0).
fn scale_needed(a: f64) -> Option<i32> {
    let bits = a.to_bits();
    if bits == 0 {
        return Some(0);
    }
    if !a.is_finite() || bits == (-0.0f64).to_bits() {
        return None;
    }
    let field = ((bits >> 52) & 0x7ff) as i32;
    let fraction = bits & ((1 << 52) - 1);
    // a = mantissa × 2^exponent, with the implicit leading one of a normal number.
    let (mantissa, exponent) = if field == 0 {
        (fraction, -1074)
    } else {
        (fraction | 1 << 52, field - 1075)
    };
    Some((-(exponent + mantissa.trailing_zeros() as i32)).max(0))
}

/// Puts a batch of samples on the tape, column by column: the stamps' kinds and the vectors'
/// scales (nearly constant, so they cost nearly nothing compressed), the stamps, then each axis's
/// changes, then the vectors stored raw. Columns put like values together, which is what the
/// chunk compression finds.
pub(super) fn samples(e: &mut Enc<'_>, samples: &[Stamped<Wrench>]) {
    e.var(samples.len() as u64);
    let micros: Vec<Option<u64>> = samples.iter().map(|s| on_micros(s.stamp)).collect();
    let forces: Vec<Option<(u8, [i64; 3])>> =
        samples.iter().map(|s| scaled(&s.value.force)).collect();
    let torques: Vec<Option<(u8, [i64; 3])>> =
        samples.iter().map(|s| scaled(&s.value.torque)).collect();
    e.bytes(
        &micros
            .iter()
            .map(|m| u8::from(m.is_none()))
            .collect::<Vec<u8>>(),
    );
    for column in [&forces, &torques] {
        e.bytes(
            &column
                .iter()
                .map(|v| v.map_or(RAW, |(k, _)| k))
                .collect::<Vec<u8>>(),
        );
    }
    let mut previous = 0u64;
    for (s, m) in samples.iter().zip(&micros) {
        match m {
            Some(m) => {
                e.var(zigzag(m.wrapping_sub(previous) as i64));
                previous = *m;
            }
            None => e.f64(s.stamp),
        }
    }
    for column in [&forces, &torques] {
        for axis in 0..3 {
            let mut previous = 0i64;
            for (_, ints) in column.iter().flatten() {
                e.var(zigzag(ints[axis].wrapping_sub(previous)));
                previous = ints[axis];
            }
        }
    }
    for (s, (f, t)) in samples.iter().zip(forces.iter().zip(&torques)) {
        for (v, stored) in [(&s.value.force, f), (&s.value.torque, t)] {
            if stored.is_none() {
                for a in [v.x, v.y, v.z] {
                    e.f64(a);
                }
            }
        }
    }
}

/// Reads a batch written by [`samples`].
pub(super) fn read_samples(d: &mut Dec<'_>) -> Result<Vec<Stamped<Wrench>>, DecodeError> {
    let n = d.count(MIN_SAMPLE_BYTES)?;
    let stamp_kinds = d.take(n)?.to_vec();
    let force_scales = d.take(n)?.to_vec();
    let torque_scales = d.take(n)?.to_vec();
    for &k in force_scales.iter().chain(&torque_scales) {
        if k != RAW && k > MAX_SCALE {
            return Err(d.error(format!("wrench scale {k}, not 0 to {MAX_SCALE} or {RAW}")));
        }
    }
    let mut out: Vec<Stamped<Wrench>> = Vec::with_capacity(n);
    let mut previous = 0u64;
    for &kind in &stamp_kinds {
        let stamp = match kind {
            0 => {
                previous = previous.wrapping_add(unzigzag(d.var()?) as u64);
                previous as f64 * 1.0e-6
            }
            1 => d.f64()?,
            other => return Err(d.error(format!("wrench stamp tag {other}, not 0 or 1"))),
        };
        out.push(Stamped {
            stamp,
            value: Wrench::default(),
        });
    }
    for (scales, torque) in [(&force_scales, false), (&torque_scales, true)] {
        for axis in 0..3 {
            let mut previous = 0i64;
            for (s, &k) in out.iter_mut().zip(scales.iter()) {
                if k == RAW {
                    continue;
                }
                previous = previous.wrapping_add(unzigzag(d.var()?));
                let v = previous as f64 / 2f64.powi(i32::from(k));
                let vector = if torque {
                    &mut s.value.torque
                } else {
                    &mut s.value.force
                };
                vector[axis] = v;
            }
        }
    }
    for (s, (&f, &t)) in out.iter_mut().zip(force_scales.iter().zip(&torque_scales)) {
        for (vector, k) in [(&mut s.value.force, f), (&mut s.value.torque, t)] {
            if k == RAW {
                *vector = Vector3::new(d.f64()?, d.f64()?, d.f64()?);
            }
        }
    }
    Ok(out)
}

/// The whole microseconds `stamp` is, to the bit, as the simulated sensor's clock writes them.
fn on_micros(stamp: f64) -> Option<u64> {
    let micros = (stamp * 1.0e6).round();
    ((0.0..=2f64.powi(53)).contains(&micros)
        && ((micros as u64) as f64 * 1.0e-6).to_bits() == stamp.to_bits())
    .then_some(micros as u64)
}

/// The fewest bytes a sample takes: its stamp's kind and two scales, a stamp change and six
/// changes.
pub(super) const MIN_SAMPLE_BYTES: usize = 10;
