#!/usr/bin/env python3
"""Cross-checks roadscan's decoded points against an independent decoder
(PyPI velodyne-decoder) on the real captures of ../shared/data.

Usage: crosscheck_decoder.py BIN_DIR SHARED_DATA TMP_DIR
Exit 77 (skipped, with a message) when velodyne_decoder, numpy or scipy cannot
be imported or the captures are absent. Every point roadscan decodes must
have a point of the other decoder within 1 cm, and the other way round.

velodyne-decoder's axes are roadscan's turned by 90 degrees (x_vd = y,
y_vd = -x). It refuses the early VLP-16 whose product byte says 0x21 (the
HDL-32E's); that capture is handed to it with the byte set to 0x22 in a
temporary copy (roadscan reads the original and detects the VLP-16)."""
import os
import struct
import subprocess
import sys

try:
    import numpy as np
    import velodyne_decoder as vd
    from scipy.spatial import cKDTree
except ImportError as e:
    print(f"skipped: {e} (scripts/test.sh installs velodyne-decoder and scipy in build/pyvenv)")
    sys.exit(77)

bindir, shared, tmp = sys.argv[1:4]
CAPTURES = [
    ("sample_velodyne_vlp16_gps.pcap", vd.Model.VLP16, None),
    ("vlp-16-test-90deg-1-50-frames.pcap", vd.Model.VLP16, 0x22),
    ("monterey-first-100-packets.pcap", vd.Model.HDL32E, None),
]


def patched(src, product, dst):
    """Copy of a classic pcap (Ethernet/IPv4/UDP) with the data packets' product byte set."""
    b = bytearray(open(src, "rb").read())
    i = 24
    while i + 16 <= len(b):
        incl = struct.unpack_from("<I", b, i + 8)[0]
        i += 16
        if incl == 1248 and b[i + 42] == 0xFF and b[i + 43] == 0xEE:
            b[i + 42 + 1205] = product
        i += incl
    open(dst, "wb").write(b)
    return dst


def theirs(path, model):
    cfg = vd.Config(model=model, min_range=0.0, max_range=1000.0)
    chunks = [pts[:, :3] for _, pts in vd.read_pcap(path, cfg, as_pcl_structs=False)]
    p = np.concatenate(chunks)
    return np.stack([-p[:, 1], p[:, 0], p[:, 2]], 1)  # into roadscan's axes


def ours(path, out):
    subprocess.run([os.path.join(bindir, "roadscan-export"), path, "--frame", "all", "--csv", "-o", out],
                   check=True, stderr=subprocess.DEVNULL)
    return np.loadtxt(out, delimiter=",", skiprows=1, usecols=(0, 1, 2))


failed = False
present = 0
for name, model, product in CAPTURES:
    src = os.path.join(shared, name)
    if not os.path.exists(src):
        continue
    present += 1
    a = ours(src, os.path.join(tmp, name + ".all.csv"))
    path = patched(src, product, os.path.join(tmp, name + ".patched.pcap")) if product else src
    b = theirs(path, model)
    da, _ = cKDTree(b).query(a)
    db, _ = cKDTree(a).query(b)
    share_a = float(np.mean(da < 0.01))
    share_b = float(np.mean(db < 0.01))
    print(f"{name}: roadscan {len(a)} points, velodyne-decoder {len(b)}; within 1 cm: "
          f"{100 * share_a:.3f} % of roadscan's, {100 * share_b:.3f} % of theirs; largest gap {da.max() * 100:.2f} cm")
    if share_a < 0.999 or share_b < 0.999:
        failed = True
if present == 0:
    print(f"skipped: no real captures in {shared}")
    sys.exit(77)
sys.exit(1 if failed else 0)
