//! CDR, as ROS 2 puts a message on the wire: a 4-byte encapsulation header (little-endian plain
//! CDR: `00 01 00 00`), then the message's fields in order, each aligned to its own size from the
//! payload's start.

use cdr_encoding::{from_bytes, to_vec};
use serde::{Serialize, de::DeserializeOwned};

/// The encapsulation header of little-endian plain CDR (`CDR_LE`), what every ROS 2 middleware
/// writes on a little-endian machine.
pub const CDR_LE: [u8; 4] = [0x00, 0x01, 0x00, 0x00];
/// The encapsulation header of big-endian plain CDR (`CDR_BE`).
pub const CDR_BE: [u8; 4] = [0x00, 0x00, 0x00, 0x00];

/// Why bytes are not a message.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum CdrError {
    /// Fewer than the 4 bytes of the encapsulation header.
    #[error("{0} bytes: too short for a CDR encapsulation header")]
    TooShort(usize),
    /// An encapsulation other than plain CDR (XCDR2, parameter lists).
    #[error("encapsulation {0:02x?} is not plain CDR")]
    Encapsulation([u8; 2]),
    /// The payload does not decode as the message type.
    #[error("{0}")]
    Payload(String),
}

/// `message` as a ROS 2 middleware sends it: header and little-endian payload.
pub fn encode<T: Serialize>(message: &T) -> Vec<u8> {
    let payload = to_vec::<T, byteorder::LittleEndian>(message)
        .unwrap_or_else(|e| unreachable!("a message of plain fields always encodes: {e}"));
    let mut out = Vec::with_capacity(4 + payload.len());
    out.extend_from_slice(&CDR_LE);
    out.extend_from_slice(&payload);
    out
}

/// The message in `bytes` (either byte order), or why not.
pub fn decode<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, CdrError> {
    let (header, payload) = bytes
        .split_first_chunk::<4>()
        .ok_or(CdrError::TooShort(bytes.len()))?;
    let decoded = match [header[0], header[1]] {
        [0x00, 0x01] => from_bytes::<T, byteorder::LittleEndian>(payload),
        [0x00, 0x00] => from_bytes::<T, byteorder::BigEndian>(payload),
        other => return Err(CdrError::Encapsulation(other)),
    };
    decoded
        .map(|(message, _)| message)
        .map_err(|e| CdrError::Payload(e.to_string()))
}
