//! Reading an MCAP file's records safely: a damaged or hostile file is an error, never an
//! allocation the size its length fields claim. `nudge replay` and `nudge inspect` read through it.

use mcap::records::Record;

/// The largest record (a chunk decompressed included) read (bytes): a damaged length field must
/// be an error, not an allocation of exabytes. Chunks of a nudge recording are a few MiB at most.
pub const RECORD_LENGTH_LIMIT: usize = 256 << 20;

/// Every record of an MCAP file in file order, chunks unpacked and their CRCs checked, no record
/// longer than [`RECORD_LENGTH_LIMIT`]. (`mcap::read::ChunkFlattener` sets no length limit: a
/// damaged chunk header made it try to allocate 3.9 EB and abort the process.)
pub struct Records<'a> {
    buf: &'a [u8],
    reader: mcap::sans_io::LinearReader,
}

impl<'a> Records<'a> {
    /// The records of the MCAP file whose whole bytes are `buf`.
    pub fn new(buf: &'a [u8]) -> Self {
        let options = mcap::sans_io::LinearReaderOptions::default()
            .with_record_length_limit(RECORD_LENGTH_LIMIT)
            .with_validate_chunk_crcs(true);
        Self {
            buf,
            reader: mcap::sans_io::LinearReader::new_with_options(options),
        }
    }
}

impl Iterator for Records<'_> {
    type Item = Result<Record<'static>, mcap::McapError>;

    fn next(&mut self) -> Option<Self::Item> {
        while let Some(event) = self.reader.next_event() {
            match event {
                Ok(mcap::sans_io::LinearReadEvent::ReadRequest(need)) => {
                    let len = need.min(self.buf.len());
                    self.reader.insert(len).copy_from_slice(&self.buf[..len]);
                    self.reader.notify_read(len);
                    self.buf = &self.buf[len..];
                }
                Ok(mcap::sans_io::LinearReadEvent::Record { data, opcode }) => {
                    return Some(mcap::parse_record(opcode, data).map(Record::into_owned));
                }
                Err(e) => return Some(Err(e)),
            }
        }
        None
    }
}

/// The records of the MCAP file whose whole bytes are `bytes`, in file order (see [`Records`]).
pub fn mcap_records(bytes: &[u8]) -> Records<'_> {
    Records::new(bytes)
}
