//! A colour cloud on the tape: lossless, without the no-return slots, and a point on its pixel's ray
//! as one range count.
//!
//! Layout: width and height (varints), frame (byte), sensor pose, stamp; the camera (a byte, 1 when
//! its model follows: width, height, fields of view and range limits); a bit per slot (least
//! significant first) that is set where the slot is stored; with a camera, a bit per stored slot
//! that is set where its point is its pixel's ray times a range on the camera's step grid
//! ([`CameraRays`]), and those points' counts of steps, each as the change from the one before
//! (zigzag), low bytes then high bytes; then every other stored point's x, y and z as raw `f32`
//! bits, each column byte-shuffled (all first bytes, then all second bytes, …), which lets the MCAP
//! chunk compression find the sign and exponent bytes that neighbouring points share; then the
//! stored slots' colours as changes from the slot before, reds, then greens, then blues. A slot is
//! left out when it is exactly what a sensor writes for no return: the canonical `f32::NAN` in all
//! three coordinates and black. Any other slot, a NaN of another payload included, is stored, so a
//! decoded cloud equals the original bit for bit.
//!
//! A point as a count costs about one byte after compression where its three floats cost nine: the
//! sensor's noise, not the encoding, is then what a recording's size is made of.

use nudge_perception::{CloudFrame, ColourCloud, Rgb};
use nudge_robot_model::CameraModel;

use super::camera_rays::CameraRays;
use super::codec::{Dec, DecodeError, Enc, isometry3, read_isometry3};

fn is_no_return(x: f32, y: f32, z: f32, rgb: Rgb) -> bool {
    let nan = f32::NAN.to_bits();
    x.to_bits() == nan && y.to_bits() == nan && z.to_bits() == nan && rgb == [0, 0, 0]
}

/// `v` as a signed change, folded so that small changes of either sign are small numbers.
fn zigzag(v: u16) -> u16 {
    let v = v as i16;
    ((v << 1) ^ (v >> 15)) as u16
}

fn unzigzag(z: u16) -> u16 {
    ((z >> 1) as i16 ^ -((z & 1) as i16)) as u16
}

/// Writes `bits` as bytes, least significant bit first.
fn bit_bytes(bits: impl ExactSizeIterator<Item = bool>) -> Vec<u8> {
    let mut bytes = vec![0u8; bits.len().div_ceil(8)];
    for (k, bit) in bits.enumerate() {
        if bit {
            bytes[k / 8] |= 1 << (k % 8);
        }
    }
    bytes
}

/// Reads `n` bits written by [`bit_bytes`], refusing bits set past the last.
fn read_bits(d: &mut Dec<'_>, n: usize, what: &str) -> Result<Vec<bool>, DecodeError> {
    let bytes = d.take(n.div_ceil(8))?;
    if !n.is_multiple_of(8) && bytes.last().is_some_and(|&b| b >> (n % 8) != 0) {
        return Err(d.error(format!("{what} has bits set past its last slot")));
    }
    Ok((0..n).map(|k| bytes[k / 8] & (1 << (k % 8)) != 0).collect())
}

fn camera_model(e: &mut Enc<'_>, c: &CameraModel) {
    e.var(c.width as u64);
    e.var(c.height as u64);
    e.f64(c.h_fov_deg);
    e.f64(c.v_fov_deg);
    e.f64(c.min_range);
    e.f64(c.max_range);
}

fn read_camera_model(d: &mut Dec<'_>) -> Result<CameraModel, DecodeError> {
    let mut size = || usize::try_from(d.var()?).map_err(|_| d.error("camera size too large"));
    let (width, height) = (size()?, size()?);
    Ok(CameraModel {
        width,
        height,
        h_fov_deg: d.f64()?,
        v_fov_deg: d.f64()?,
        min_range: d.f64()?,
        max_range: d.f64()?,
        // The tape keeps what places a cloud's points on their rays, not the colour's noise.
        ..CameraModel::default()
    })
}

pub(super) fn encode(e: &mut Enc<'_>, cloud: &ColourCloud, camera: Option<&CameraRays>) {
    e.var(cloud.width() as u64);
    e.var(cloud.height() as u64);
    e.u8(match cloud.frame() {
        CloudFrame::Sensor => 0,
        CloudFrame::Map => 1,
    });
    isometry3(e, cloud.sensor_pose());
    e.f64(cloud.stamp());
    // Only a camera of the cloud's own image and frame has the cloud's points on its rays.
    let camera = camera.filter(|c| {
        c.camera().width == cloud.width()
            && c.camera().height == cloud.height()
            && c.len() == cloud.len()
            && cloud.frame() == CloudFrame::Sensor
    });
    match camera {
        None => e.u8(0),
        Some(c) => {
            e.u8(1);
            camera_model(e, c.camera());
        }
    }
    let (xs, ys, zs, rgb) = (cloud.xs(), cloud.ys(), cloud.zs(), cloud.colours());
    let stored: Vec<bool> = (0..cloud.len())
        .map(|i| !is_no_return(xs[i], ys[i], zs[i], rgb[i]))
        .collect();
    e.bytes(&bit_bytes(stored.iter().copied()));
    let kept: Vec<usize> = (0..cloud.len()).filter(|&i| stored[i]).collect();

    let counts: Vec<Option<u16>> = match camera {
        Some(c) => kept
            .iter()
            .map(|&i| c.count_of(i, [xs[i], ys[i], zs[i]]))
            .collect(),
        None => vec![None; kept.len()],
    };
    if camera.is_some() {
        e.bytes(&bit_bytes(counts.iter().map(Option::is_some)));
    }
    let mut previous = 0u16;
    let changes: Vec<u16> = counts
        .iter()
        .flatten()
        .map(|&count| {
            let change = zigzag(count.wrapping_sub(previous));
            previous = count;
            change
        })
        .collect();
    e.bytes(&changes.iter().map(|&v| v as u8).collect::<Vec<u8>>());
    e.bytes(&changes.iter().map(|&v| (v >> 8) as u8).collect::<Vec<u8>>());

    let raw: Vec<usize> = kept
        .iter()
        .zip(&counts)
        .filter(|(_, count)| count.is_none())
        .map(|(&i, _)| i)
        .collect();
    let mut column = Vec::with_capacity(raw.len());
    for values in [xs, ys, zs] {
        column.clear();
        column.extend(raw.iter().map(|&i| values[i].to_bits()));
        for byte in 0..4 {
            e.bytes(
                &column
                    .iter()
                    .map(|v| (v >> (8 * byte)) as u8)
                    .collect::<Vec<u8>>(),
            );
        }
    }
    let mut planes = [
        Vec::with_capacity(kept.len()),
        Vec::with_capacity(kept.len()),
        Vec::with_capacity(kept.len()),
    ];
    let mut previous = [0u8; 3];
    for &i in &kept {
        for ((plane, p), v) in planes.iter_mut().zip(&mut previous).zip(rgb[i]) {
            plane.push(v.wrapping_sub(*p));
            *p = v;
        }
    }
    for plane in &planes {
        e.bytes(plane);
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
    let camera = match d.u8()? {
        0 => None,
        1 => Some(read_camera_model(d)?),
        other => return Err(d.error(format!("cloud camera flag {other}, not 0 or 1"))),
    };
    if let Some(c) = &camera
        && (c.width, c.height) != (width, height)
    {
        return Err(d.error(format!(
            "a {} × {} camera for a {width} × {height} cloud",
            c.width, c.height
        )));
    }
    // The mask is taken before anything of size n is allocated: n is bounded by the bytes there are.
    let stored = read_bits(d, n, "cloud mask")?;
    let kept: Vec<usize> = (0..n).filter(|&i| stored[i]).collect();
    let on_ray = match &camera {
        Some(_) => read_bits(d, kept.len(), "cloud ray mask")?,
        None => vec![false; kept.len()],
    };
    let counted = on_ray.iter().filter(|&&b| b).count();
    let low = d.take(counted)?;
    let high = d.take(counted)?;
    // The rays are built only once the counts are there: their size is the cloud's, now bounded.
    let rays = camera.as_ref().map(CameraRays::new);

    let mut columns = [vec![f32::NAN; n], vec![f32::NAN; n], vec![f32::NAN; n]];
    let mut raw = Vec::with_capacity(kept.len() - counted);
    let mut previous = 0u16;
    let mut k = 0;
    for (&i, &counted) in kept.iter().zip(&on_ray) {
        match (&rays, counted) {
            (Some(rays), true) => {
                let count =
                    previous.wrapping_add(unzigzag(u16::from(low[k]) | u16::from(high[k]) << 8));
                previous = count;
                k += 1;
                let p = rays.point(i, count);
                for (column, v) in columns.iter_mut().zip(p) {
                    column[i] = v;
                }
            }
            _ => raw.push(i),
        }
    }
    for column in &mut columns {
        let planes = d.take(4 * raw.len())?;
        for (k, &i) in raw.iter().enumerate() {
            let bits = (0..4).fold(0u32, |v, byte| {
                v | u32::from(planes[byte * raw.len() + k]) << (8 * byte)
            });
            column[i] = f32::from_bits(bits);
        }
    }
    let planes = [
        d.take(kept.len())?,
        d.take(kept.len())?,
        d.take(kept.len())?,
    ];
    let mut rgb = vec![[0u8; 3]; n];
    let mut previous = [0u8; 3];
    for (k, &i) in kept.iter().enumerate() {
        for ((p, plane), out) in previous.iter_mut().zip(&planes).zip(&mut rgb[i]) {
            *p = p.wrapping_add(plane[k]);
            *out = *p;
        }
    }
    let [x, y, z] = columns;
    ColourCloud::organised(width, height, x, y, z, rgb, frame, sensor_pose, stamp)
        .map_err(|e| d.error(e.to_string()))
}
