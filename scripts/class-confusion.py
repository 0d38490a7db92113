#!/usr/bin/env python3
"""How the tracker's classes compare with the simulator's, per capture.

Every confirmed row of a track file (roadscand --tracks-out) is paired with the
true road user (roadscan-sim --truth-states of the same run) whose centre,
interpolated to the row's time, lies nearest to the track's position and
within 2.5 m; the rows of each true class are then counted by the class the
track gave them. The simulator's van and truck count as van/truck.

    scripts/class-confusion.py out/tracking/VLP-16-rush-tracks.csv out/results/VLP-16-rush-states.csv [...]

Arguments come in pairs (tracks, states); one table per pair, then (more than one pair) the rows of
all of them together, to a tenth of a percent. Off the real-time
path: plain Python, no third-party module.
"""
import bisect
import csv
import math
import sys
from collections import defaultdict

CLASSES = ["pedestrian", "cyclist", "car", "van/truck", "bus", "unknown"]
TRUE_AS = {"van": "van/truck", "truck": "van/truck"}
RADIUS = 2.5


def load_states(path):
    """id -> (times, rows of x, y), and id -> class"""
    times, pos, cls = defaultdict(list), defaultdict(list), {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            k = int(r["id"])
            times[k].append(float(r["t"]))
            pos[k].append((float(r["x"]), float(r["y"])))
            cls[k] = TRUE_AS.get(r["class"], r["class"])
    return times, pos, cls


def at(times, pos, t):
    """the position at time t (linear between the steps), None outside the object's life"""
    if t < times[0] - 0.15 or t > times[-1] + 0.15:
        return None
    i = bisect.bisect_left(times, t)
    if i <= 0:
        return pos[0]
    if i >= len(times):
        return pos[-1]
    t0, t1 = times[i - 1], times[i]
    w = 0.0 if t1 <= t0 else (t - t0) / (t1 - t0)
    (x0, y0), (x1, y1) = pos[i - 1], pos[i]
    return (x0 + w * (x1 - x0), y0 + w * (y1 - y0))


def confusion(tracks_path, states_path):
    times, pos, cls = load_states(states_path)
    table = defaultdict(lambda: defaultdict(int))
    with open(tracks_path, newline="") as f:
        for r in csv.DictReader(f):
            if r["state"] != "confirmed":
                continue
            t, x, y = float(r["t"]), float(r["x"]), float(r["y"])
            best, best_d = None, RADIUS
            for k in times:
                p = at(times[k], pos[k], t)
                if p is None:
                    continue
                d = math.hypot(p[0] - x, p[1] - y)
                if d <= best_d:
                    best, best_d = k, d
            if best is not None:
                table[cls[best]][r["class"]] += 1
    return table


def print_table(title, table, digits=0):
    print(f"\n{title}: confirmed track rows by true class (rows within {RADIUS} m of a road user), share classed as")
    print("| true class | rows | " + " | ".join(CLASSES) + " |")
    print("|---|---" + "|---" * len(CLASSES) + "|")
    for true in CLASSES:
        row = table.get(true)
        if not row:
            continue
        n = sum(row.values())
        print(f"| {true} | {n} | " + " | ".join(f"{100.0 * row.get(c, 0) / n:.{digits}f} %" for c in CLASSES) + " |")


def main(argv):
    if len(argv) < 2 or len(argv) % 2:
        sys.exit(__doc__.strip().splitlines()[0] + "\nusage: class-confusion.py TRACKS STATES [TRACKS STATES ...]")
    pooled = defaultdict(lambda: defaultdict(int))
    for tracks_path, states_path in zip(argv[0::2], argv[1::2]):
        table = confusion(tracks_path, states_path)
        print_table(tracks_path, table)
        for true, row in table.items():
            for c, n in row.items():
                pooled[true][c] += n
    if len(argv) > 2:
        print_table(f"all {len(argv) // 2} pairs", pooled, digits=1)


if __name__ == "__main__":
    main(sys.argv[1:])
