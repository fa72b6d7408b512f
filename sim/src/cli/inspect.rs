//! `nudge inspect`: what a recording holds — topics, message counts, schemas, the robot-time span,
//! metadata, attachments and the run's summary. Reads truncated files up to where they break.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, bail};
use mcap::records::Record;
use nudge_executive::record::{RUN_METADATA, SUMMARY_METADATA};

use super::InspectArgs;

/// Everything `inspect` prints, read from one file.
#[derive(Debug, Default)]
pub struct Contents {
    /// Schema id → (name, encoding).
    pub schemas: BTreeMap<u16, (String, String)>,
    /// Channel id → (topic, schema id, message encoding).
    pub channels: BTreeMap<u16, (String, u16, String)>,
    /// Channel id → message count.
    pub counts: BTreeMap<u16, u64>,
    /// First and last message log time (ns).
    pub span: Option<(u64, u64)>,
    /// Metadata records by name.
    pub metadata: BTreeMap<String, BTreeMap<String, String>>,
    /// Attachments: name, media type, size in bytes.
    pub attachments: Vec<(String, String, usize)>,
    /// True when the file ends with a summary section and footer.
    pub complete: bool,
    /// Why reading stopped early, if it did.
    pub broken: Option<String>,
}

/// Reads an MCAP file's records in order.
pub fn read(bytes: &[u8]) -> anyhow::Result<Contents> {
    if !bytes.starts_with(mcap::MAGIC) {
        bail!("not an MCAP file (no MCAP magic at the start)");
    }
    // Read with a record length limit and chunk CRCs checked: a damaged length field is where the
    // file breaks, not an allocation of what it claims.
    let records = nudge_executive::record::mcap_records(bytes);
    let mut c = Contents::default();
    for record in records {
        let record = match record {
            Ok(r) => r,
            Err(e) => {
                c.broken = Some(e.to_string());
                break;
            }
        };
        match record {
            Record::Schema { header, .. } => {
                c.schemas.insert(header.id, (header.name, header.encoding));
            }
            Record::Channel(ch) => {
                c.channels
                    .insert(ch.id, (ch.topic, ch.schema_id, ch.message_encoding));
            }
            Record::Message { header, .. } => {
                *c.counts.entry(header.channel_id).or_default() += 1;
                let t = header.log_time;
                c.span = Some(c.span.map_or((t, t), |(a, b)| (a.min(t), b.max(t))));
            }
            Record::Metadata(m) => {
                c.metadata.insert(m.name, m.metadata);
            }
            Record::Attachment { header, data, .. } => {
                c.attachments
                    .push((header.name, header.media_type, data.len()));
            }
            Record::Footer(_) => c.complete = true,
            _ => {}
        }
    }
    Ok(c)
}

pub(super) fn inspect(args: InspectArgs) -> anyhow::Result<ExitCode> {
    let bytes = std::fs::read(&args.file)
        .with_context(|| format!("cannot read {}", args.file.display()))?;
    let c = read(&bytes).with_context(|| format!("{}", args.file.display()))?;
    print(&args.file, bytes.len(), &c);
    if let Some(e) = &c.broken {
        bail!(
            "{}: truncated or corrupt recording (read {} messages before: {e})",
            args.file.display(),
            c.counts.values().sum::<u64>()
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn print(path: &Path, size: usize, c: &Contents) {
    let state = match (&c.broken, c.complete) {
        (Some(e), _) => format!("BROKEN, read up to: {e}"),
        (None, true) => "complete".to_string(),
        (None, false) => "no footer".to_string(),
    };
    println!("file         {} ({size} bytes, {state})", path.display());
    let total: u64 = c.counts.values().sum();
    println!("messages     {total} on {} topics", c.channels.len());
    if let Some((a, b)) = c.span {
        let (a, b) = (a as f64 * 1e-9, b as f64 * 1e-9);
        println!("robot time   {a:.3} s .. {b:.3} s ({:.3} s)", b - a);
    }
    let width = c
        .channels
        .values()
        .map(|(t, _, _)| t.len())
        .max()
        .unwrap_or(5)
        .max(5);
    println!(
        "\n{:<width$}  {:>8}  schema (encoding)",
        "topic", "messages"
    );
    let mut rows: Vec<_> = c.channels.iter().collect();
    rows.sort_by(|a, b| a.1.0.cmp(&b.1.0));
    for (id, (topic, schema, encoding)) in rows {
        let (name, schema_encoding) = c
            .schemas
            .get(schema)
            .map_or(("-", "-"), |(n, e)| (n.as_str(), e.as_str()));
        let encodings = if schema_encoding == encoding {
            encoding.clone()
        } else {
            format!("{encoding} messages, {schema_encoding} schema")
        };
        println!(
            "{topic:<width$}  {:>8}  {name} ({encodings})",
            c.counts.get(id).copied().unwrap_or(0)
        );
    }
    for (name, map) in &c.metadata {
        if name == SUMMARY_METADATA {
            continue;
        }
        println!("\nmetadata     {name}");
        for (k, v) in map {
            println!("  {k:<12} {v}");
        }
    }
    for (name, media, size) in &c.attachments {
        println!("\nattachment   {name} ({media}, {size} bytes)");
    }
    match c.metadata.get(SUMMARY_METADATA) {
        Some(summary) => {
            println!("\nrun summary");
            for (k, v) in summary.iter().filter(|(_, v)| !v.is_empty()) {
                println!("  {k:<14} {v}");
            }
        }
        None if c.metadata.contains_key(RUN_METADATA) => {
            println!("\nrun summary  none (the run did not end normally)");
        }
        None => println!("\nrun summary  none (not a nudge recording)"),
    }
}
