//! The tape's binary encoding: little-endian, floats as raw bits, lengths as LEB128 varints.
//!
//! An entry is a tag byte (the request, or [`TRANSITION`]), the request's arguments, then the reply,
//! whose kind the request fixes. A result is a byte (0 ok, 1–4 the [`RobotError`] variant) and
//! then the value or the error's fields.

use std::collections::BTreeSet;
use std::sync::{Mutex, PoisonError};

use nalgebra::{
    Complex, Isometry2, Isometry3, Point2, Point3, Quaternion, Translation2, Translation3,
    UnitComplex, UnitQuaternion, Vector3,
};

use super::call::{Entry, Reply, Request, Transition};
use super::camera_rays::CameraRays;
use super::cloud;
use super::wrench_samples;
use crate::robot::{
    ActionStatus, GuardedMove, HandOutcome, RobotError, Stamped, WalkOutcome, Wrench,
};

/// Tag of a transition entry (requests use 1..=19).
const TRANSITION: u8 = 0x20;

/// Why tape bytes do not decode.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("at byte {at}: {what}")]
pub struct DecodeError {
    /// Offset into the message where decoding failed.
    pub at: usize,
    /// What was wrong there.
    pub what: String,
}

/// Appends to a byte buffer.
pub(super) struct Enc<'a>(pub(super) &'a mut Vec<u8>);

impl Enc<'_> {
    pub(super) fn u8(&mut self, v: u8) {
        self.0.push(v);
    }
    pub(super) fn bytes(&mut self, v: &[u8]) {
        self.0.extend_from_slice(v);
    }
    pub(super) fn var(&mut self, mut v: u64) {
        loop {
            let low = (v & 0x7f) as u8;
            v >>= 7;
            if v == 0 {
                self.0.push(low);
                return;
            }
            self.0.push(low | 0x80);
        }
    }
    pub(super) fn f64(&mut self, v: f64) {
        self.bytes(&v.to_bits().to_le_bytes());
    }
    fn str(&mut self, s: &str) {
        self.var(s.len() as u64);
        self.bytes(s.as_bytes());
    }
}

/// Reads from a byte slice, every read checked.
pub(super) struct Dec<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Dec<'a> {
    pub(super) fn new(bytes: &'a [u8]) -> Self {
        Self { bytes, pos: 0 }
    }
    pub(super) fn error(&self, what: impl Into<String>) -> DecodeError {
        DecodeError {
            at: self.pos,
            what: what.into(),
        }
    }
    fn is_done(&self) -> bool {
        self.pos >= self.bytes.len()
    }
    pub(super) fn take(&mut self, n: usize) -> Result<&'a [u8], DecodeError> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&end| end <= self.bytes.len())
            .ok_or_else(|| {
                self.error(format!(
                    "needs {n} more bytes, {} left",
                    self.bytes.len() - self.pos
                ))
            })?;
        let out = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(out)
    }
    pub(super) fn u8(&mut self) -> Result<u8, DecodeError> {
        Ok(self.take(1)?[0])
    }
    pub(super) fn var(&mut self) -> Result<u64, DecodeError> {
        let mut v: u64 = 0;
        for shift in (0..64).step_by(7) {
            let b = self.u8()?;
            v |= u64::from(b & 0x7f) << shift;
            if b & 0x80 == 0 {
                return Ok(v);
            }
        }
        Err(self.error("a length runs past 64 bits"))
    }
    /// A count of items each at least `min_bytes` long: refused when the bytes left cannot hold them
    /// (no allocation sized by corrupt data).
    pub(super) fn count(&mut self, min_bytes: usize) -> Result<usize, DecodeError> {
        let n = self.var()?;
        let left = (self.bytes.len() - self.pos) as u64;
        if n.saturating_mul(min_bytes.max(1) as u64) > left {
            return Err(self.error(format!(
                "a count of {n} does not fit in the {left} bytes left"
            )));
        }
        usize::try_from(n).map_err(|_| self.error("a count too large for this machine"))
    }
    pub(super) fn f64(&mut self) -> Result<f64, DecodeError> {
        let b = self.take(8)?;
        let mut raw = [0u8; 8];
        raw.copy_from_slice(b);
        Ok(f64::from_bits(u64::from_le_bytes(raw)))
    }
    fn str(&mut self) -> Result<String, DecodeError> {
        let n = self.count(1)?;
        let at = self.pos;
        let b = self.take(n)?;
        String::from_utf8(b.to_vec()).map_err(|_| DecodeError {
            at,
            what: "text that is not UTF-8".into(),
        })
    }
}

/// Encodes one entry onto `out`; a cloud taken by `camera` stores its points as range counts
/// along the camera's rays (see `cloud.rs`).
pub fn encode_entry(entry: &Entry, out: &mut Vec<u8>, camera: Option<&CameraRays>) {
    let mut e = Enc(out);
    match entry {
        Entry::Call(request, reply) => {
            encode_request(&mut e, request);
            encode_reply(&mut e, reply, camera);
        }
        Entry::Transition(t) => {
            e.u8(TRANSITION);
            e.str(&t.from);
            e.str(&t.edge);
            e.str(&t.to);
        }
    }
}

/// The encoding of a request alone: two requests are the same call when these bytes are equal.
pub(super) fn request_bytes(request: &Request) -> Vec<u8> {
    let mut out = Vec::new();
    encode_request(&mut Enc(&mut out), request);
    out
}

/// Decodes every entry of one tape message.
pub fn decode_batch(bytes: &[u8]) -> Result<Vec<Entry>, DecodeError> {
    let mut d = Dec::new(bytes);
    let mut entries = Vec::new();
    while !d.is_done() {
        entries.push(decode_entry(&mut d)?);
    }
    Ok(entries)
}

fn tag(request: &Request) -> u8 {
    match request {
        Request::Now => 1,
        Request::Advance(_) => 2,
        Request::BasePose => 3,
        Request::StartWalk(_) => 4,
        Request::StartTurn(_) => 5,
        Request::WalkStatus => 6,
        Request::StopWalk => 7,
        Request::HeadAngles => 8,
        Request::StartPointHead(..) => 9,
        Request::HeadStatus => 10,
        Request::Capture => 11,
        Request::Tare => 12,
        Request::Wrench => 13,
        Request::DrainWrenches => 14,
        Request::HandPosition => 15,
        Request::StartGuardedMove(_) => 16,
        Request::StartRetract => 17,
        Request::HandStatus => 18,
        Request::StopHand => 19,
        Request::DiscardWrenches => 20,
    }
}

fn encode_request(e: &mut Enc<'_>, request: &Request) {
    e.u8(tag(request));
    match request {
        Request::Advance(dt) => e.f64(*dt),
        Request::StartWalk(points) => {
            e.var(points.len() as u64);
            for p in points {
                e.f64(p.x);
                e.f64(p.y);
            }
        }
        Request::StartTurn(yaw) => e.f64(*yaw),
        Request::StartPointHead(pan, tilt) => {
            e.f64(*pan);
            e.f64(*tilt);
        }
        Request::StartGuardedMove(m) => {
            point3(e, &m.from);
            point3(e, &m.to);
            e.f64(m.speed);
            e.f64(m.force_limit);
            match m.acceleration {
                None => e.u8(0),
                Some(a) => {
                    e.u8(1);
                    e.f64(a);
                }
            }
        }
        _ => {}
    }
}

fn encode_reply(e: &mut Enc<'_>, reply: &Reply, camera: Option<&CameraRays>) {
    match reply {
        Reply::Time(t) => e.f64(*t),
        Reply::Done(r) => result(e, r, |_, ()| {}),
        Reply::Pose(r) => result(e, r, |e, s| stamped(e, s, isometry2)),
        Reply::Walk(r) => result(e, r, |e, s| status(e, s, walk_outcome)),
        Reply::Angles(r) => result(e, r, |e, s| {
            stamped(e, s, |e, (pan, tilt)| {
                e.f64(*pan);
                e.f64(*tilt);
            });
        }),
        Reply::Head(r) => result(e, r, |e, s| status(e, s, |_, ()| {})),
        Reply::Cloud(r) => result(e, r, |e, c| cloud::encode(e, c, camera)),
        Reply::Wrench(r) => result(e, r, |e, s| {
            wrench_samples::samples(e, std::slice::from_ref(s));
        }),
        Reply::Wrenches(r) => result(e, r, |e, v| wrench_samples::samples(e, v)),
        Reply::Hand(r) => result(e, r, |e, s| stamped(e, s, point3)),
        Reply::HandStatus(r) => result(e, r, |e, s| status(e, s, hand_outcome)),
    }
}

fn decode_entry(d: &mut Dec<'_>) -> Result<Entry, DecodeError> {
    let at = d.pos;
    let tag = d.u8()?;
    let entry = match tag {
        TRANSITION => Entry::Transition(Transition {
            from: d.str()?,
            edge: d.str()?,
            to: d.str()?,
        }),
        1 => Entry::Call(Request::Now, Reply::Time(d.f64()?)),
        2 => Entry::Call(Request::Advance(d.f64()?), Reply::Done(done(d)?)),
        3 => Entry::Call(
            Request::BasePose,
            Reply::Pose(read_result(d, |d| read_stamped(d, read_isometry2))?),
        ),
        4 => {
            let n = d.count(16)?;
            let mut points = Vec::with_capacity(n);
            for _ in 0..n {
                points.push(Point2::new(d.f64()?, d.f64()?));
            }
            Entry::Call(Request::StartWalk(points), Reply::Done(done(d)?))
        }
        5 => Entry::Call(Request::StartTurn(d.f64()?), Reply::Done(done(d)?)),
        6 => Entry::Call(
            Request::WalkStatus,
            Reply::Walk(read_result(d, |d| read_status(d, read_walk_outcome))?),
        ),
        7 => Entry::Call(Request::StopWalk, Reply::Done(done(d)?)),
        8 => Entry::Call(
            Request::HeadAngles,
            Reply::Angles(read_result(d, |d| {
                read_stamped(d, |d| Ok((d.f64()?, d.f64()?)))
            })?),
        ),
        9 => Entry::Call(
            Request::StartPointHead(d.f64()?, d.f64()?),
            Reply::Done(done(d)?),
        ),
        10 => Entry::Call(
            Request::HeadStatus,
            Reply::Head(read_result(d, |d| read_status(d, |_| Ok(())))?),
        ),
        11 => Entry::Call(
            Request::Capture,
            Reply::Cloud(read_result(d, cloud::decode)?),
        ),
        12 => Entry::Call(Request::Tare, Reply::Done(done(d)?)),
        13 => Entry::Call(
            Request::Wrench,
            Reply::Wrench(read_result(d, |d| {
                let mut one = wrench_samples::read_samples(d)?;
                match (one.pop(), one.is_empty()) {
                    (Some(s), true) => Ok(s),
                    _ => Err(d.error("a wrench reading that is not one sample")),
                }
            })?),
        ),
        14 => Entry::Call(
            Request::DrainWrenches,
            Reply::Wrenches(read_result(d, wrench_samples::read_samples)?),
        ),
        15 => Entry::Call(
            Request::HandPosition,
            Reply::Hand(read_result(d, |d| read_stamped(d, read_point3))?),
        ),
        16 => {
            let from = read_point3(d)?;
            let to = read_point3(d)?;
            let speed = d.f64()?;
            let force_limit = d.f64()?;
            let acceleration = match d.u8()? {
                0 => None,
                1 => Some(d.f64()?),
                other => return Err(d.error(format!("acceleration flag {other}, not 0 or 1"))),
            };
            let motion = GuardedMove {
                from,
                to,
                speed,
                force_limit,
                acceleration,
            };
            Entry::Call(Request::StartGuardedMove(motion), Reply::Done(done(d)?))
        }
        17 => Entry::Call(Request::StartRetract, Reply::Done(done(d)?)),
        18 => Entry::Call(
            Request::HandStatus,
            Reply::HandStatus(read_result(d, |d| read_status(d, read_hand_outcome))?),
        ),
        19 => Entry::Call(Request::StopHand, Reply::Done(done(d)?)),
        20 => Entry::Call(Request::DiscardWrenches, Reply::Done(done(d)?)),
        other => {
            return Err(DecodeError {
                at,
                what: format!("unknown entry tag {other:#04x}"),
            });
        }
    };
    Ok(entry)
}

fn result<T>(e: &mut Enc<'_>, r: &Result<T, RobotError>, value: impl FnOnce(&mut Enc<'_>, &T)) {
    match r {
        Ok(v) => {
            e.u8(0);
            value(e, v);
        }
        Err(RobotError::Unavailable { capability, reason }) => {
            e.u8(1);
            e.str(capability);
            e.str(reason);
        }
        Err(RobotError::Refused { capability, reason }) => {
            e.u8(2);
            e.str(capability);
            e.str(reason);
        }
        Err(RobotError::Timeout {
            capability,
            seconds,
        }) => {
            e.u8(3);
            e.str(capability);
            e.f64(*seconds);
        }
        Err(RobotError::Fault { capability, reason }) => {
            e.u8(4);
            e.str(capability);
            e.str(reason);
        }
    }
}

fn read_result<T>(
    d: &mut Dec<'_>,
    value: impl FnOnce(&mut Dec<'_>) -> Result<T, DecodeError>,
) -> Result<Result<T, RobotError>, DecodeError> {
    Ok(match d.u8()? {
        0 => Ok(value(d)?),
        1 => Err(RobotError::Unavailable {
            capability: capability(&d.str()?),
            reason: d.str()?,
        }),
        2 => Err(RobotError::Refused {
            capability: capability(&d.str()?),
            reason: d.str()?,
        }),
        3 => Err(RobotError::Timeout {
            capability: capability(&d.str()?),
            seconds: d.f64()?,
        }),
        4 => Err(RobotError::Fault {
            capability: capability(&d.str()?),
            reason: d.str()?,
        }),
        other => return Err(d.error(format!("result tag {other}, not 0 to 4"))),
    })
}

fn done(d: &mut Dec<'_>) -> Result<Result<(), RobotError>, DecodeError> {
    read_result(d, |_| Ok(()))
}

/// The `'static` name of a capability read back: the adapters' own names are known; any other is
/// kept once for the life of the process (a file holds few).
fn capability(name: &str) -> &'static str {
    const KNOWN: [&str; 9] = [
        "arm", "base", "head", "camera", "wrist", "clock", "bound", "replay", "hand",
    ];
    if let Some(known) = KNOWN.iter().find(|k| **k == name) {
        return known;
    }
    static OTHERS: Mutex<BTreeSet<&'static str>> = Mutex::new(BTreeSet::new());
    let mut others = OTHERS.lock().unwrap_or_else(PoisonError::into_inner);
    if let Some(kept) = others.get(name) {
        return kept;
    }
    let kept: &'static str = Box::leak(name.to_owned().into_boxed_str());
    others.insert(kept);
    kept
}

fn stamped<T>(e: &mut Enc<'_>, s: &Stamped<T>, value: impl FnOnce(&mut Enc<'_>, &T)) {
    e.f64(s.stamp);
    value(e, &s.value);
}

fn read_stamped<T>(
    d: &mut Dec<'_>,
    value: impl FnOnce(&mut Dec<'_>) -> Result<T, DecodeError>,
) -> Result<Stamped<T>, DecodeError> {
    let stamp = d.f64()?;
    Ok(Stamped {
        stamp,
        value: value(d)?,
    })
}

fn status<T>(e: &mut Enc<'_>, s: &ActionStatus<T>, outcome: impl FnOnce(&mut Enc<'_>, &T)) {
    match s {
        ActionStatus::Running => e.u8(0),
        ActionStatus::Done(o) => {
            e.u8(1);
            outcome(e, o);
        }
    }
}

fn read_status<T>(
    d: &mut Dec<'_>,
    outcome: impl FnOnce(&mut Dec<'_>) -> Result<T, DecodeError>,
) -> Result<ActionStatus<T>, DecodeError> {
    match d.u8()? {
        0 => Ok(ActionStatus::Running),
        1 => Ok(ActionStatus::Done(outcome(d)?)),
        other => Err(d.error(format!("action status {other}, not 0 or 1"))),
    }
}

fn walk_outcome(e: &mut Enc<'_>, o: &WalkOutcome) {
    match o {
        WalkOutcome::Arrived => e.u8(0),
        WalkOutcome::Blocked { at } => {
            e.u8(1);
            isometry2(e, at);
        }
        WalkOutcome::Stopped => e.u8(2),
    }
}

fn read_walk_outcome(d: &mut Dec<'_>) -> Result<WalkOutcome, DecodeError> {
    match d.u8()? {
        0 => Ok(WalkOutcome::Arrived),
        1 => Ok(WalkOutcome::Blocked {
            at: read_isometry2(d)?,
        }),
        2 => Ok(WalkOutcome::Stopped),
        other => Err(d.error(format!("walk outcome {other}, not 0 to 2"))),
    }
}

fn hand_outcome(e: &mut Enc<'_>, o: &HandOutcome) {
    match o {
        HandOutcome::Reached => e.u8(0),
        HandOutcome::ForceLimit { wrench: w, at } => {
            e.u8(1);
            stamped(e, w, wrench);
            point3(e, at);
        }
        HandOutcome::Stopped => e.u8(2),
    }
}

fn read_hand_outcome(d: &mut Dec<'_>) -> Result<HandOutcome, DecodeError> {
    match d.u8()? {
        0 => Ok(HandOutcome::Reached),
        1 => Ok(HandOutcome::ForceLimit {
            wrench: read_stamped(d, read_wrench)?,
            at: read_point3(d)?,
        }),
        2 => Ok(HandOutcome::Stopped),
        other => Err(d.error(format!("hand outcome {other}, not 0 to 2"))),
    }
}

fn vector3(e: &mut Enc<'_>, v: &Vector3<f64>) {
    e.f64(v.x);
    e.f64(v.y);
    e.f64(v.z);
}

fn read_vector3(d: &mut Dec<'_>) -> Result<Vector3<f64>, DecodeError> {
    Ok(Vector3::new(d.f64()?, d.f64()?, d.f64()?))
}

fn point3(e: &mut Enc<'_>, p: &Point3<f64>) {
    vector3(e, &p.coords);
}

fn read_point3(d: &mut Dec<'_>) -> Result<Point3<f64>, DecodeError> {
    Ok(Point3::from(read_vector3(d)?))
}

fn wrench(e: &mut Enc<'_>, w: &Wrench) {
    vector3(e, &w.force);
    vector3(e, &w.torque);
}

fn read_wrench(d: &mut Dec<'_>) -> Result<Wrench, DecodeError> {
    Ok(Wrench {
        force: read_vector3(d)?,
        torque: read_vector3(d)?,
    })
}

fn isometry2(e: &mut Enc<'_>, iso: &Isometry2<f64>) {
    e.f64(iso.translation.x);
    e.f64(iso.translation.y);
    let c = iso.rotation.complex();
    e.f64(c.re);
    e.f64(c.im);
}

fn read_isometry2(d: &mut Dec<'_>) -> Result<Isometry2<f64>, DecodeError> {
    let translation = Translation2::new(d.f64()?, d.f64()?);
    let rotation = UnitComplex::new_unchecked(Complex::new(d.f64()?, d.f64()?));
    Ok(Isometry2::from_parts(translation, rotation))
}

/// Translation, then the quaternion's coordinates in nalgebra's order (i, j, k, w).
pub(super) fn isometry3(e: &mut Enc<'_>, iso: &Isometry3<f64>) {
    vector3(e, &iso.translation.vector);
    for c in iso.rotation.coords.iter() {
        e.f64(*c);
    }
}

pub(super) fn read_isometry3(d: &mut Dec<'_>) -> Result<Isometry3<f64>, DecodeError> {
    let t = read_vector3(d)?;
    let (i, j, k, w) = (d.f64()?, d.f64()?, d.f64()?, d.f64()?);
    Ok(Isometry3::from_parts(
        Translation3::from(t),
        UnitQuaternion::new_unchecked(Quaternion::new(w, i, j, k)),
    ))
}
