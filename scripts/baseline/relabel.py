#!/usr/bin/env python3
"""relabel.py LABELS FRAMES ASSOC OUT [confirmed]

Turns roadscand's cluster labels (--no-tracking --labels-out) into another tracker's track labels:
a return of object k in frame f gets 2 + the track ASSOC gives (f, k) (a harness's --assoc output,
scripts/baseline/run.sh), 2 when none (or, with "confirmed", when that track was not confirmed
then). The label file holds, frame by frame, as many returns as --frames-out's foreground column
says (docs/objects-and-lcm.md)."""
import csv
import sys

lab, frm, asc, out = sys.argv[1:5]
conf_only = len(sys.argv) > 5 and sys.argv[5] == 'confirmed'
frames = list(csv.DictReader(open(frm)))
fg = [int(r['foreground']) for r in frames]
fn = [int(r['frame']) for r in frames]
track = {}
for r in csv.DictReader(open(asc)):
    if conf_only and r['state'] != 'confirmed':
        continue
    track[(int(r['frame']), int(r['object']))] = int(r['track'])
fi, left = 0, fg[0] if fg else 0
with open(lab) as f, open(out, 'w') as o:
    for line in f:
        if not line[0].isdigit():
            o.write(line)
            continue
        while left == 0:
            fi += 1
            if fi == len(fg):
                sys.exit(f"relabel.py: {lab} does not hold the returns {frm} counts (more returns than its "
                         f"{len(fg)} frames' {sum(fg)})")
            left = fg[fi]
        left -= 1
        p, b, c, l = line.rstrip('\n').split(',')
        l = int(l)
        if l >= 3:
            t = track.get((fn[fi], l - 2))
            l = 2 + t if t else 2
        o.write(f"{p},{b},{c},{l}\n")
if not (fi == len(fg) - 1 and left == 0):
    sys.exit(f"relabel.py: {lab} does not hold the returns {frm} counts (frame {fi} of {len(fg)}, {left} left)")
