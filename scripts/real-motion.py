#!/usr/bin/env python3
"""Does the sensor of a capture move? Aligns every frame of a capture with
its first complete frame (point-to-point ICP on the decoded points, those
beyond MIN_RANGE only, so a person near the sensor does not count) and prints
the translation, the yaw and the share of points that find a partner within
5 cm. Off the real-time path; needs numpy and scipy (build/pyvenv after
scripts/test.sh).

Usage: real-motion.py CAPTURE [--bin build/bin] [--min-range 2.5] [--every 5]"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy.spatial import cKDTree

ap = argparse.ArgumentParser()
ap.add_argument("capture")
ap.add_argument("--bin", default="build/bin")
ap.add_argument("--min-range", type=float, default=2.5)
ap.add_argument("--every", type=int, default=5)
a = ap.parse_args()

with tempfile.TemporaryDirectory() as d:
    csv = os.path.join(d, "all.csv")
    subprocess.run([os.path.join(a.bin, "roadscan-export"), a.capture, "--frame", "all", "--csv", "-o", csv],
                   check=True, stderr=subprocess.DEVNULL)
    p = np.loadtxt(csv, delimiter=",", skiprows=1, usecols=(0, 1, 2, 6, 11))
frames = sorted(set(p[:, 4].astype(int)))[1:-1]  # complete frames only


def cloud(f):
    q = p[(p[:, 4] == f) & (p[:, 3] > a.min_range)]
    return q[:, :3]


def icp(src, dst, iters=30):
    tree = cKDTree(dst)
    R, t, cur = np.eye(3), np.zeros(3), src.copy()
    for _ in range(iters):
        dist, j = tree.query(cur)
        k = dist < 0.3
        x, y = cur[k], dst[j[k]]
        cx, cy = x.mean(0), y.mean(0)
        u, _, vt = np.linalg.svd((x - cx).T @ (y - cy))
        r = vt.T @ u.T
        if np.linalg.det(r) < 0:
            vt[-1] *= -1
            r = vt.T @ u.T
        cur = cur @ r.T + (cy - r @ cx)
        R, t = r @ R, r @ t + (cy - r @ cx)
    dist, _ = tree.query(cur)
    return R, t, float(np.mean(dist < 0.05))


ref = cloud(frames[0])
print(f"{a.capture}: frames {frames[0]}-{frames[-1]}, points beyond {a.min_range} m, against frame {frames[0]}")
print("| frame | translation (cm) | yaw (deg) | points within 5 cm |")
print("|---|---|---|---|")
for f in frames[:: a.every] + ([frames[-1]] if frames[-1] not in frames[:: a.every] else []):
    R, t, fit = icp(cloud(f), ref)
    yaw = np.degrees(np.arctan2(R[1, 0], R[0, 0]))
    print(f"| {f} | {100 * np.linalg.norm(t):.1f} | {yaw:.2f} | {100 * fit:.1f} % |")
