//! Reading a recording back: its tape, the run's metadata and the scenario attached to it.

use std::collections::BTreeMap;

use mcap::records::Record;

use super::call::Entry;
use super::codec::{DecodeError, decode_batch};
use super::{TAPE_ENCODING, TAPE_TOPIC};
use crate::record::{RUN_METADATA, SUMMARY_METADATA};

/// What a recording holds for a replay.
#[derive(Clone, Debug, Default)]
pub struct Recording {
    /// The tape, in call order.
    pub entries: Vec<Entry>,
    /// Tape messages read.
    pub tape_messages: usize,
    /// The run's settings ([`RUN_METADATA`]: scenario, seed, version, policy); empty when absent.
    pub run: BTreeMap<String, String>,
    /// The run's summary ([`SUMMARY_METADATA`]), when the run ended normally.
    pub summary: Option<BTreeMap<String, String>>,
    /// The attached scenario file (name, text), if any (`application/toml`).
    pub scenario: Option<(String, String)>,
}

/// Why a file holds no replayable recording.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
    /// The file does not start with the MCAP magic.
    #[error("not an MCAP file (no MCAP magic at the start)")]
    NotMcap,
    /// A record could not be read: the file is cut short or damaged.
    #[error("truncated or corrupt recording (read {messages} tape messages before: {reason})")]
    Broken {
        /// Tape messages read before the damage.
        messages: usize,
        /// What the MCAP reader said.
        reason: String,
    },
    /// Every record read, but the footer is missing: the file was cut short at a record boundary.
    #[error("truncated recording: it ends without an MCAP footer")]
    NoFooter,
    /// No tape channel.
    #[error(
        "no replay tape (no {TAPE_TOPIC} channel): a recording made before replay existed, or not by nudge"
    )]
    NoTape,
    /// A tape in another format.
    #[error("the tape is encoded as '{found}'; this build reads '{TAPE_ENCODING}'")]
    Encoding {
        /// The channel's message encoding.
        found: String,
    },
    /// A tape message does not decode.
    #[error("tape message {index} (robot time {stamp:.3} s) does not decode: {error}")]
    Decode {
        /// Which tape message, from 0.
        index: usize,
        /// Its log time (s).
        stamp: f64,
        /// Where and why.
        error: DecodeError,
    },
    /// The scenario attachment is not text.
    #[error("the attached scenario {name} is not UTF-8 text")]
    ScenarioText {
        /// The attachment's name.
        name: String,
    },
}

/// Reads the tape, the run's metadata and the scenario from a whole MCAP file's bytes. Never panics:
/// anything but a complete recording with a readable tape is an error saying what is wrong.
pub fn read_recording(bytes: &[u8]) -> Result<Recording, RecordingError> {
    if !bytes.starts_with(mcap::MAGIC) {
        return Err(RecordingError::NotMcap);
    }
    let records = crate::record::mcap_records(bytes);
    let mut recording = Recording::default();
    // Channel id → its message encoding, for the tape's channels.
    let mut tape_channels: BTreeMap<u16, String> = BTreeMap::new();
    let mut footer = false;
    for record in records {
        let record = record.map_err(|e| RecordingError::Broken {
            messages: recording.tape_messages,
            reason: e.to_string(),
        })?;
        match record {
            Record::Channel(ch) if ch.topic == TAPE_TOPIC => {
                tape_channels.insert(ch.id, ch.message_encoding);
            }
            Record::Message { header, data, .. } => {
                let Some(encoding) = tape_channels.get(&header.channel_id) else {
                    continue;
                };
                if encoding != TAPE_ENCODING {
                    return Err(RecordingError::Encoding {
                        found: encoding.clone(),
                    });
                }
                let entries = decode_batch(&data).map_err(|error| RecordingError::Decode {
                    index: recording.tape_messages,
                    stamp: header.log_time as f64 * 1e-9,
                    error,
                })?;
                recording.entries.extend(entries);
                recording.tape_messages += 1;
            }
            Record::Metadata(m) if m.name == RUN_METADATA => recording.run = m.metadata,
            Record::Metadata(m) if m.name == SUMMARY_METADATA => {
                recording.summary = Some(m.metadata);
            }
            Record::Attachment { header, data, .. }
                if header.media_type == "application/toml" && recording.scenario.is_none() =>
            {
                let text = String::from_utf8(data.into_owned()).map_err(|_| {
                    RecordingError::ScenarioText {
                        name: header.name.clone(),
                    }
                })?;
                recording.scenario = Some((header.name, text));
            }
            Record::Footer(_) => footer = true,
            _ => {}
        }
    }
    if !footer {
        return Err(RecordingError::NoFooter);
    }
    if tape_channels.is_empty() {
        return Err(RecordingError::NoTape);
    }
    Ok(recording)
}
