#!/usr/bin/env python3
"""Time against foreground returns per frame for FSPC, FSPC-adaptive, DBSCAN and CCL
(the FSPC paper's Figure 19), from `roadscan-bench CAPTURE --model MODEL --csv FILE`.

    python3 scripts/plot-bench.py bench.csv [more.csv ...] -o figure.png

Needs matplotlib (pip install matplotlib). Not part of the pipeline."""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("csv", nargs="+")
ap.add_argument("-o", "--output", default="bench.png")
ap.add_argument("--log", action="store_true", help="logarithmic time axis")
args = ap.parse_args()
series = {"fspc_us": "FSPC", "fspc_adaptive_us": "FSPC-adaptive", "dbscan_us": "DBSCAN", "ccl_us": "CCL"}
pts = {k: ([], []) for k in series}
for path in args.csv:
    for row in csv.DictReader(open(path)):
        for k in series:
            pts[k][0].append(int(row["foreground"]))
            pts[k][1].append(float(row[k]) / 1000.0)
fig, ax = plt.subplots(figsize=(8, 5))
for k, name in series.items():
    ax.scatter(pts[k][0], pts[k][1], s=6, label=name)
ax.set_xlabel("foreground returns per frame")
ax.set_ylabel("clustering time per frame (ms)")
if args.log:
    ax.set_yscale("log")
ax.legend()
ax.grid(True, alpha=0.3)
fig.tight_layout()
fig.savefig(args.output, dpi=100)
print("wrote", args.output)
