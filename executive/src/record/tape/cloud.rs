//! A colour cloud on the tape: lossless, without the no-return slots.
//!
//! Layout: width and height (varints), frame (byte), sensor pose, stamp; then a bit per slot (least
//! significant first) that is set where the slot is stored; then the stored slots' x, y and z as
//! raw `f32` bits, each column byte-shuffled (all first bytes, then all second bytes, …), which
//! lets the MCAP chunk compression find the sign and exponent bytes that neighbouring points share;
//! then their colours. A slot is left out when it is exactly what a sensor writes for no return:
//! the canonical `f32::NAN` in all three coordinates and black. Any other slot, a NaN of another
//! payload included, is stored as it is, so a decoded cloud equals the original bit for bit.

use nudge_perception::{CloudFrame, ColourCloud, Rgb};

use super::codec::{Dec, DecodeError, Enc, isometry3, read_isometry3};

fn is_no_return(x: f32, y: f32, z: f32, rgb: Rgb) -> bool {
    let nan = f32::NAN.to_bits();
    x.to_bits() == nan && y.to_bits() == nan && z.to_bits() == nan && rgb == [0, 0, 0]
}

pub(super) fn encode(e: &mut Enc<'_>, cloud: &ColourCloud) {
    e.var(cloud.width() as u64);
    e.var(cloud.height() as u64);
    e.u8(match cloud.frame() {
        CloudFrame::Sensor => 0,
        CloudFrame::Map => 1,
    });
    isometry3(e, cloud.sensor_pose());
    e.f64(cloud.stamp());
    let (xs, ys, zs, rgb) = (cloud.xs(), cloud.ys(), cloud.zs(), cloud.colours());
    let mut mask = vec![0u8; cloud.len().div_ceil(8)];
    let mut kept = Vec::with_capacity(cloud.len());
    for i in 0..cloud.len() {
        if !is_no_return(xs[i], ys[i], zs[i], rgb[i]) {
            mask[i / 8] |= 1 << (i % 8);
            kept.push(i);
        }
    }
    e.bytes(&mask);
    let mut column = Vec::with_capacity(kept.len());
    for values in [xs, ys, zs] {
        column.clear();
        column.extend(kept.iter().map(|&i| values[i].to_bits()));
        for byte in 0..4 {
            e.bytes(
                &column
                    .iter()
                    .map(|v| (v >> (8 * byte)) as u8)
                    .collect::<Vec<u8>>(),
            );
        }
    }
    for &i in &kept {
        e.bytes(&rgb[i]);
    }
}

pub(super) fn decode(d: &mut Dec<'_>) -> Result<ColourCloud, DecodeError> {
    let width = usize::try_from(d.var()?).map_err(|_| d.error("cloud width too large"))?;
    let height = usize::try_from(d.var()?).map_err(|_| d.error("cloud height too large"))?;
    let frame = match d.u8()? {
        0 => CloudFrame::Sensor,
        1 => CloudFrame::Map,
        other => return Err(d.error(format!("cloud frame {other}, not 0 or 1"))),
    };
    let sensor_pose = read_isometry3(d)?;
    let stamp = d.f64()?;
    let n = width
        .checked_mul(height)
        .ok_or_else(|| d.error(format!("a {width} × {height} cloud is too large")))?;
    // The mask is taken before anything of size n is allocated: n is bounded by the bytes there are.
    let mask = d.take(n.div_ceil(8))?;
    let kept: Vec<usize> = (0..n)
        .filter(|&i| mask[i / 8] & (1 << (i % 8)) != 0)
        .collect();
    if n % 8 != 0 && mask.last().is_some_and(|&b| b >> (n % 8) != 0) {
        return Err(d.error("cloud mask has bits set past its last slot"));
    }
    let mut columns = [vec![f32::NAN; n], vec![f32::NAN; n], vec![f32::NAN; n]];
    for column in &mut columns {
        let planes = d.take(4 * kept.len())?;
        for (k, &i) in kept.iter().enumerate() {
            let bits = (0..4).fold(0u32, |v, byte| {
                v | u32::from(planes[byte * kept.len() + k]) << (8 * byte)
            });
            column[i] = f32::from_bits(bits);
        }
    }
    let colours = d.take(3 * kept.len())?;
    let mut rgb = vec![[0u8; 3]; n];
    for (k, &i) in kept.iter().enumerate() {
        rgb[i] = [colours[3 * k], colours[3 * k + 1], colours[3 * k + 2]];
    }
    let [x, y, z] = columns;
    ColourCloud::organised(width, height, x, y, z, rgb, frame, sensor_pose, stamp)
        .map_err(|e| d.error(e.to_string()))
}
