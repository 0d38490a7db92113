#!/usr/bin/env python3
"""examples/listen.py survives hostile object lists: a negative string length,
a string without its NUL and a forged object count are each refused with a
message, the good lists around them are printed.

Usage: python_hostile.py EXAMPLE PYTHON_TYPES_DIR TMP_DIR
Exit 77 (skipped, with a message) without PyPI's lcm."""
import os
import struct
import subprocess
import sys

try:
    import lcm
except ImportError as e:
    print(f"skipped: {e} (scripts/test.sh installs lcm in build/pyvenv)")
    sys.exit(77)

example, types, tmp = sys.argv[1:4]
sys.path.insert(0, types)
from roadscan import object_list_t  # noqa: E402

m = object_list_t()
m.sensor_id = "north"
m.sensor_model = "VLP-16"
m.objects = []
m.num_objects = 0
good = m.encode()
negative = good[:20] + struct.pack(">i", -16) + good[24:]  # sensor_id's length
no_nul = bytearray(good)
no_nul[24 + 5] = ord("x")  # "north" + NUL: the NUL overwritten
forged = good[:16] + struct.pack(">i", 1000000) + good[20:]  # num_objects
path = os.path.join(tmp, "hostile.lcmlog")
log = lcm.EventLog(path, "w", overwrite=True)
for i, b in enumerate([good, negative, bytes(no_nul), forged, good]):
    log.write_event(1700000000000000 + i, "ROADSCAN_OBJECTS", bytes(b))
log.close()
r = subprocess.run([sys.executable, example, "--url", f"file://{os.path.abspath(path)}?speed=0"],
                   capture_output=True, text=True, env=dict(os.environ, PYTHONPATH=types), timeout=120)
print(r.stdout + r.stderr)
if r.returncode != 0 or "lists 2, objects 0, gaps 0, malformed 3" not in r.stderr + r.stdout:
    sys.exit(f"examples/listen.py: exit {r.returncode}, not the expected tally")
if (r.stderr + r.stdout).count("is not a roadscan object list; ignored") != 3:
    sys.exit("three refusals expected")
print("the Python example refused the 3 hostile lists and printed the 2 good ones")
