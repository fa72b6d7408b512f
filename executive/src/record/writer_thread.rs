//! The recorder's writer thread: it owns the MCAP writer, so compressing chunks and writing them
//! to disk happen beside the run, not in it. The run hands over finished messages in order; the
//! thread registers each topic's schema and channel on its first message and writes the rest as
//! they come, so the file is the same byte for byte as one written in the run's own thread.

use std::collections::BTreeMap;
use std::io::{Seek, Write};
use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
use std::thread::JoinHandle;

use mcap::records::{MessageHeader, Metadata};

use super::mcap_recorder::RecordError;

/// Jobs handed over at once: waking the writer costs the run a system call, and the wrench alone
/// brings a thousand messages a second, so they go in batches (a quarter of a second of wrench).
const BATCH: usize = 256;

/// Batches that may wait for the writer before the run waits for it: a few seconds of the busiest
/// topic (the wrench, a thousand samples a second). It counts messages, not bytes; clouds, a few
/// hundred kB each, come a few a second at most.
const QUEUE: usize = 4096 / BATCH;

/// A topic's schema and message encoding, sent with its first message.
pub(super) struct Channel {
    /// Schema name; empty for a channel without a schema (id 0).
    pub schema_name: String,
    /// Schema encoding.
    pub schema_encoding: String,
    /// Schema data.
    pub schema: Vec<u8>,
    /// Message encoding.
    pub message_encoding: String,
}

/// A message's bytes: ready, or encoded by the writer thread when it comes to them (the replay
/// tape's entries, whose encoding would otherwise cost the run's own thread).
pub(super) enum Payload {
    /// Encoded already.
    Bytes(Vec<u8>),
    /// Encoded by the writer thread.
    Deferred(Box<dyn FnOnce() -> Vec<u8> + Send>),
}

impl From<Vec<u8>> for Payload {
    fn from(bytes: Vec<u8>) -> Self {
        Self::Bytes(bytes)
    }
}

/// What the writer is asked to write, in order.
enum Job {
    Message {
        topic: &'static str,
        channel: Option<Channel>,
        header: MessageHeader,
        data: Payload,
    },
    Metadata(Metadata),
}

/// The writer thread and the queue to it.
pub(super) struct WriterThread<W: Write + Seek + Send + 'static> {
    jobs: Option<SyncSender<Vec<Job>>>,
    /// Jobs not yet handed over.
    batch: Vec<Job>,
    thread: Option<JoinHandle<Result<W, RecordError>>>,
}

impl<W: Write + Seek + Send + 'static> WriterThread<W> {
    /// Starts a thread writing into `writer`.
    pub fn spawn(writer: mcap::Writer<W>) -> Result<Self, RecordError> {
        let (jobs, queue) = sync_channel(QUEUE);
        let thread = std::thread::Builder::new()
            .name("mcap-writer".into())
            .spawn(move || write_all(writer, queue))
            .map_err(|e| RecordError::Writer(e.to_string()))?;
        Ok(Self {
            jobs: Some(jobs),
            batch: Vec::with_capacity(BATCH),
            thread: Some(thread),
        })
    }

    /// Queues a message; `channel` must come with a topic's first message. Nothing happens once
    /// the writer has stopped: its error comes from [`Self::finish`].
    pub fn message(
        &mut self,
        topic: &'static str,
        channel: Option<Channel>,
        header: MessageHeader,
        data: Payload,
    ) {
        self.send(Job::Message {
            topic,
            channel,
            header,
            data,
        });
    }

    /// Queues a metadata record (nothing once the writer has stopped).
    pub fn metadata(&mut self, metadata: Metadata) {
        self.send(Job::Metadata(metadata));
    }

    /// Adds `job` to the batch and hands the batch over when it is full.
    fn send(&mut self, job: Job) {
        self.batch.push(job);
        if self.batch.len() >= BATCH {
            self.hand_over();
        }
    }

    /// Hands the batch to the writer. A closed queue means the writer stopped at an error, which
    /// `finish` returns.
    fn hand_over(&mut self) {
        let batch = std::mem::replace(&mut self.batch, Vec::with_capacity(BATCH));
        if let Some(jobs) = &self.jobs
            && !batch.is_empty()
        {
            let _ = jobs.send(batch);
        }
    }

    /// Closes the queue, waits for the writer to write what it holds and finish the file (summary
    /// and footer), and returns the sink or the first error the writer met.
    pub fn finish(&mut self) -> Result<W, RecordError> {
        self.hand_over();
        self.jobs = None;
        let thread = self
            .thread
            .take()
            .ok_or_else(|| RecordError::Writer("already finished".into()))?;
        thread
            .join()
            .map_err(|_| RecordError::Writer("the writer thread panicked".into()))?
    }
}

/// A recorder dropped unfinished still leaves a complete file: the thread is told to finish it and
/// waited for.
impl<W: Write + Seek + Send + 'static> Drop for WriterThread<W> {
    fn drop(&mut self) {
        if self.thread.is_some() {
            let _ = self.finish();
        }
    }
}

/// Writes every job until the queue closes, then finishes the file. At the first error it finishes
/// what was written so far and drops the rest.
fn write_all<W: Write + Seek>(
    mut writer: mcap::Writer<W>,
    queue: Receiver<Vec<Job>>,
) -> Result<W, RecordError> {
    let mut channels: BTreeMap<&'static str, u16> = BTreeMap::new();
    for job in queue.into_iter().flatten() {
        let written = match job {
            Job::Message {
                topic,
                channel,
                mut header,
                data,
            } => (|| {
                let id = match (channels.get(topic), channel) {
                    (Some(&id), _) => id,
                    (None, Some(c)) => {
                        let schema_id = if c.schema_name.is_empty() {
                            0
                        } else {
                            writer.add_schema(&c.schema_name, &c.schema_encoding, &c.schema)?
                        };
                        let id = writer.add_channel(
                            schema_id,
                            topic,
                            &c.message_encoding,
                            &BTreeMap::new(),
                        )?;
                        channels.insert(topic, id);
                        id
                    }
                    (None, None) => {
                        return Err(RecordError::Writer(format!(
                            "a {topic} message came before its channel"
                        )));
                    }
                };
                header.channel_id = id;
                let data = match data {
                    Payload::Bytes(bytes) => bytes,
                    Payload::Deferred(encode) => encode(),
                };
                writer.write_to_known_channel(&header, &data)?;
                Ok(())
            })(),
            Job::Metadata(m) => writer.write_metadata(&m).map_err(RecordError::from),
        };
        if let Err(e) = written {
            let _ = writer.finish();
            return Err(e);
        }
    }
    writer.finish()?;
    Ok(writer.into_inner())
}
