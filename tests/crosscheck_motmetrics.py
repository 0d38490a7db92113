#!/usr/bin/env python3
"""Cross-checks roadscan-eval's tracking figures against py-motmetrics.

Usage: crosscheck_motmetrics.py BIN_DIR TMP_DIR
Simulates a short VLP-16 rush capture (a site learned first), tracks it with
roadscand (--labels-out: 2 + track id), scores it with roadscan-eval
--tracking --json --mot-dump, and feeds the same per-frame instances and
overlaps to motmetrics (distance 1 - IoU, matchable when IoU > 0.5). MOTA,
MOTP, IDF1, IDTP, switches, fragmentations, mostly tracked / partly / lost,
misses, false positives and instance counts must be equal. Exit 77 (skipped,
with a message) when motmetrics or numpy cannot be imported."""
import collections
import csv
import json
import math
import os
import subprocess
import sys

try:
    import motmetrics as mm
    import numpy as np
except ImportError as e:
    print(f"skipped: {e} (scripts/test.sh installs motmetrics in build/pyvenv)")
    sys.exit(77)

bindir, tmp = sys.argv[1:3]
p = lambda name: os.path.join(tmp, "mm-" + name)


def run(*args):
    r = subprocess.run([os.path.join(bindir, args[0])] + list(args[1:]), capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(args)}: exit {r.returncode}: {r.stderr[-2000:]}")
    return r.stdout


run("roadscan-sim", "--sensor", "VLP-16", "--scenario", "rush", "--seconds", "40", "--seed", "5",
    "-o", p("learn.pcap"), "--labels", p("learn.csv"))
run("roadscan-sim", "--sensor", "VLP-16", "--scenario", "rush", "--seconds", "12", "--seed", "6",
    "-o", p("cap.pcap"), "--labels", p("truth.csv"))
run("roadscan-learn", p("learn.pcap"), "-o", p("model"))
run("roadscand", "--pcap", p("cap.pcap"), "--fast", "--background", p("model"), "--no-publish", "--quiet",
    "--labels-out", p("pred.csv"))
ours = json.loads(run("roadscan-eval", "--tracking", p("cap.pcap"), p("truth.csv"), p("pred.csv"), "--json",
                      "--mot-dump", p("dump.csv")))

frames = collections.defaultdict(lambda: {"g": [], "h": [], "iou": {}})
with open(p("dump.csv")) as f:
    for r in csv.DictReader(f):
        fr, g, h, iou = int(r["frame"]), int(r["truth"]), int(r["pred"]), float(r["iou"])
        if g and not h:
            frames[fr]["g"].append(g)
        elif h and not g:
            frames[fr]["h"].append(h)
        else:
            frames[fr]["iou"][(g, h)] = iou
acc = mm.MOTAccumulator(auto_id=False)
for fr in sorted(frames):
    d = frames[fr]
    dist = np.full((len(d["g"]), len(d["h"])), np.nan)
    for i, g in enumerate(d["g"]):
        for j, h in enumerate(d["h"]):
            v = d["iou"].get((g, h))
            if v is not None and v > 0.5:
                dist[i, j] = 1.0 - v
    acc.update(d["g"], d["h"], dist, frameid=fr)
names = ["num_frames", "mota", "motp", "idf1", "idtp", "num_switches", "num_fragmentations", "mostly_tracked",
         "partially_tracked", "mostly_lost", "num_false_positives", "num_misses", "num_objects", "num_predictions",
         "num_unique_objects"]
theirs = mm.metrics.create().compute(acc, metrics=names, name="roadscan").to_dict("records")[0]

pairs = [("num_frames", "frames"), ("num_objects", "gt"), ("num_predictions", "hyp"), ("num_misses", "misses"),
         ("num_false_positives", "false_positives"), ("num_switches", "id_switches"),
         ("num_fragmentations", "fragmentations"), ("mostly_tracked", "mostly_tracked"),
         ("partially_tracked", "partly_tracked"), ("mostly_lost", "mostly_lost"), ("num_unique_objects", "objects"),
         ("idtp", "idtp")]
bad = []
for m, o in pairs:
    if int(round(theirs[m])) != int(ours[o]):
        bad.append(f"{m}: motmetrics {theirs[m]}, roadscan-eval {ours[o]}")
for m, v in (("mota", ours["mota"]), ("idf1", ours["idf1"]), ("motp", 1.0 - ours["motp_iou"])):
    if not math.isclose(theirs[m], v, abs_tol=2e-6):
        bad.append(f"{m}: motmetrics {theirs[m]:.6f}, roadscan-eval {v:.6f}")
if ours["gt"] < 500 or ours["tracks"] < 5:
    bad.append(f"too little to compare: {ours['gt']} true instances, {ours['tracks']} tracks")
print(f"roadscan-eval --tracking vs py-motmetrics {mm.__version__}: {ours['frames']} frames, {ours['gt']} true "
      f"instances, {ours['tracks']} tracks: MOTA {ours['mota']:.4f}, IDF1 {ours['idf1']:.4f}, "
      f"{ours['id_switches']} switches")
if bad:
    print("DIFFERENT:\n  " + "\n  ".join(bad))
    sys.exit(1)
print("every figure equal")
