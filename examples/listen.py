#!/usr/bin/env python3
"""Prints the object lists roadscand publishes over LCM (Python example).

Set up once (the types are generated at build time into build/python):
    python3 -m venv .venv && .venv/bin/pip install lcm
    PYTHONPATH=build/python .venv/bin/python examples/listen.py
Options: --url URL (default: the daemon's), --channel NAME, --count N.
A log recorded with lcm-logger reads with --url 'file:///abs/path.lcmlog?speed=0'.
"""
import argparse
import struct
import sys

import lcm
from roadscan import object_list_t

DEFAULT_URL = "udpm://239.255.76.67:7667?ttl=0"


def well_formed(data):
    """The checks the generated decoder leaves out: the object count is not
    negative and both strings (sensor_id, sensor_model) end with their NUL,
    inside the message (fingerprint, utime, num_objects come first)."""
    if len(data) < 20 or struct.unpack_from(">i", data, 16)[0] < 0:
        return False
    pos = 20
    for _ in range(2):
        if pos + 4 > len(data):
            return False
        n = struct.unpack_from(">i", data, pos)[0]
        pos += 4
        if n < 1 or pos + n > len(data) or data[pos + n - 1] != 0 or 0 in data[pos:pos + n - 1]:
            return False
        pos += n
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--url", default=DEFAULT_URL)
    ap.add_argument("--channel", default="ROADSCAN_OBJECTS")
    ap.add_argument("--count", type=int, default=0, help="exit after N lists")
    args = ap.parse_args()

    lc = lcm.LCM(args.url)
    seen = {"lists": 0, "objects": 0, "gaps": 0, "malformed": 0, "last": {}}

    def on_list(channel, data):
        try:
            if not well_formed(data):
                raise ValueError("malformed")
            m = object_list_t.decode(data)
        except (ValueError, struct.error):
            seen["malformed"] += 1
            print(f"{channel}: a message of {len(data)} bytes is not a roadscan object list; ignored",
                  file=sys.stderr)
            return
        last = seen["last"].get(m.sensor_id)
        if last is not None and m.frame_seq > last + 1:
            seen["gaps"] += m.frame_seq - last - 1
        seen["last"][m.sensor_id] = m.frame_seq
        seen["lists"] += 1
        seen["objects"] += m.num_objects
        print(f"{m.sensor_id} frame {m.frame_seq}: {m.num_objects} objects"
              f"{' (truncated)' if m.truncated else ''}")
        for o in m.objects:
            x, y, z = (o.site_centroid if m.site_valid else o.centroid)
            print(f"  id {o.id:3d} points {o.points:5d} at ({x:7.2f}, {y:7.2f}, {z:5.2f})"
                  f" box {o.obb_length:.2f} x {o.obb_width:.2f} m")
        sys.stdout.flush()
        if args.count and seen["lists"] >= args.count:
            raise SystemExit(0)

    lc.subscribe(args.channel, on_list)
    try:
        while True:
            lc.handle()
    except (KeyboardInterrupt, OSError):  # OSError: end of a log file
        pass
    finally:
        print(f"lists {seen['lists']}, objects {seen['objects']}, gaps {seen['gaps']}, "
              f"malformed {seen['malformed']}", file=sys.stderr)


if __name__ == "__main__":
    main()
