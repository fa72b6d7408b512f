"""Reads a nudge recording with the official Python `mcap` package and prints what it holds as JSON.

Usage: python3 read_mcap.py FILE.mcap

Prints one JSON object: message counts and schema names per topic, how many of each topic's
messages the protobuf decoders decoded, the wrist wrench's largest force norm (decoded), first and
last log time (ns), metadata records by name, and attachment names. Exit code 3 when the `mcap`
package or its protobuf support is missing (the Rust test runs it with a virtual environment that
has them, and fails on any other exit).
"""

import json
import sys

try:
    from mcap.reader import make_reader
    from mcap_protobuf.decoder import DecoderFactory
except ImportError:
    print("python mcap not installed", file=sys.stderr)
    sys.exit(3)


def main(path):
    counts, schemas, decoded = {}, {}, {}
    start, end = None, None
    wrench_peak = None
    factory = DecoderFactory()
    decoders = {}
    with open(path, "rb") as f:
        reader = make_reader(f)
        for schema, channel, message in reader.iter_messages():
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            schemas[channel.topic] = schema.name if schema is not None else ""
            if channel.id not in decoders:
                decoders[channel.id] = factory.decoder_for(channel.message_encoding, schema)
            decoder = decoders[channel.id]
            if decoder is not None:
                value = decoder(message.data)
                decoded[channel.topic] = decoded.get(channel.topic, 0) + 1
                if channel.topic == "/wrist/wrench":
                    norm = max(value.force_norm, value.peak_force_norm)
                    wrench_peak = norm if wrench_peak is None else max(wrench_peak, norm)
            t = message.log_time
            start = t if start is None else min(start, t)
            end = t if end is None else max(end, t)
        metadata = {m.name: dict(m.metadata) for m in reader.iter_metadata()}
        attachments = [a.name for a in reader.iter_attachments()]
    print(
        json.dumps(
            {
                "counts": counts,
                "schemas": schemas,
                "decoded": decoded,
                "wrench_peak": wrench_peak,
                "start": start,
                "end": end,
                "metadata": metadata,
                "attachments": attachments,
            },
            sort_keys=True,
        )
    )


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    main(sys.argv[1])
