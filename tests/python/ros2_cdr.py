"""Checks ROS 2 messages' CDR bytes with the `rosbags` package's serializer.

Usage: python3 ros2_cdr.py < messages.jsonl

Each input line is a JSON object {"type": "pkg/msg/Name", "cdr": "<hex>"}: bytes another encoder
wrote (encapsulation header included). For each, rosbags deserializes them as the ROS 2 Humble type,
serializes the result again, and prints one JSON line: the type, whether its bytes equal the input
("same_bytes"), its own bytes in hex when they differ, and the decoded message as plain JSON
("value": dataclasses as objects without their __msgtype__ and constants, arrays as lists). A deserialization
error is reported in "error". Exit code 3 when rosbags is missing.
"""

import dataclasses
import json
import sys

try:
    import numpy
    from rosbags.typesys import Stores, get_typestore
except ImportError:
    print("rosbags not installed", file=sys.stderr)
    sys.exit(3)


def plain(value):
    if dataclasses.is_dataclass(value):
        return {
            f.name: plain(getattr(value, f.name))
            for f in dataclasses.fields(value)
            if f.name != "__msgtype__" and not f.name.isupper()  # constants are no fields
        }
    if isinstance(value, numpy.ndarray):
        return [plain(v) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, numpy.generic):
        return value.item()
    return value


def main():
    store = get_typestore(Stores.ROS2_HUMBLE)
    for line in sys.stdin:
        item = json.loads(line)
        name, ours = item["type"], bytes.fromhex(item["cdr"])
        out = {"type": name}
        try:
            message = store.deserialize_cdr(ours, name)
            again = bytes(store.serialize_cdr(message, name))
            out["same_bytes"] = again == ours
            if again != ours:
                out["rosbags_cdr"] = again.hex()
            out["value"] = plain(message)
        except Exception as error:  # any failure is the answer, not a crash
            out["error"] = f"{type(error).__name__}: {error}"
        print(json.dumps(out))


if __name__ == "__main__":
    main()
