#!/usr/bin/env python3
"""Where the tracker's speed error and identity losses come from, per capture.

    scripts/track-errors.py speed TRACKS STATES
        Every confirmed row of a track file (roadscand --tracks-out) is paired with the
        true road user (roadscan-sim --truth-states of the same run) nearest to it within
        2.5 m at the row's time; rows of vehicles within 80 m are kept. Prints the speed
        RMSE and, per kind of row, its share of the rows and of the squared error:
        vehicles turning (their velocity's direction changing faster than 5 deg/s over
        +-0.3 s), speeding up or braking harder than 0.5 m/s^2 (over +-0.3 s), tracks
        younger than 1 s, rows of one vehicle followed by two tracks at once, and the
        steady rest; and the heading RMSE (the track's heading against the true velocity's
        direction, rows of vehicles moving faster than 1 m/s) of each. Then the rows of
        standing vehicles (true speed under 0.05 m/s) and how many of them report a speed; the
        mean (signed) error of the rows speeding up and of those braking, and the RMSE by range
        (0-20, 20-40, 40-60, 60-80 m from the sensor).
    scripts/track-errors.py ids MOTDUMP STATES
        From roadscan-eval --tracking ... --mot-dump MOTDUMP: per true class, the frames of
        each true object not matched (IoU > 0.5) by its most frequent track, and each
        switch by kind (back to a track it had, to a new track, or taken from another
        road user walking or driving the other way, the same way, or crossing/standing,
        within 3 m or farther); and how many of the walkers' and cyclists' switches came
        within 1.5 s after (or 0.5 s before) their centre passed within 0.45 m of another
        walker's or cyclist's: the simulator's walkers are 0.5 m wide and walk through
        each other, which real ones do not. Then the same frames for the vehicles and
        cyclists whose velocity's direction turned by over 60 deg (turn_share) and for the rest.
    scripts/track-errors.py traffic STATES...
        Per true-states file, how the simulator's traffic moved (turn_share, docs/simulator.md):
        vehicles, those whose heading turned by over 60 deg (left, right; trucks and buses
        among them), those that passed within 8 m of the intersection's centre (the default
        pole: 11.5 m east and north of the sensor), pairs of boxes that overlapped (vehicle with
        vehicle or walker, in how many states), and the longest any vehicle stood (s).
    scripts/track-errors.py unmatched MOTDUMP TRACKS
        The confirmed rows of a track file that no true instance matches (IoU > 0.5), and
        how many of them have fewer than 10 returns (never a true instance's).
    scripts/track-errors.py matched MOTDUMP TRACKS STATES [MOTDUMP TRACKS STATES ...]
        Per capture, then over all given: the speed error as roadscan-eval --tracking scores it (the confirmed rows matched to a
        true vehicle within 80 m, IoU > 0.5, from its --mot-dump), split: tracks younger than
        1 s past the capture's first 3 s (moving vehicles), those in its first 3 s, and the
        older tracks' rows by how long the track has had this vehicle: under 2 s after having
        had another one (it took this one over), under 2 s as its first, or longer; per kind
        its rows, its share of the squared error and its RMSE. (The truth is taken between
        its states, not extrapolated: a few rows fewer than roadscan-eval's.)
    scripts/track-errors.py born MOTDUMP TRACKS STATES [MOTDUMP TRACKS STATES ...]
        Over all given: the rows of matched, split by whether their track was born within 15 m
        of the sensor (its first row) and is younger than 2.5 s (a vehicle pulling away from
        beside the pole, out of the circle below the lowest beam: circle_whole,
        docs/tracking.md) or not; per kind its rows, share of the squared error and RMSE.
    scripts/track-errors.py common STATES MOTDUMP_A TRACKS_A MOTDUMP_B TRACKS_B [STATES MOTDUMP_A ...]
        Two trackers' vehicle speed error on the same rows: per capture (five files each: the true
        states, then each tracker's --mot-dump and track file), the frames where both have a
        confirmed track matched (IoU > 0.5) to the same true vehicle within 80 m; the speed RMSE of
        each on those rows, and of each on all of its own such rows (as roadscan-eval scores it).
    scripts/track-errors.py spot REPORT...
        Pooled over roadscan-eval --tracking --json reports made with --counts and --crossings (as
        scripts/tracking.sh leaves them in out/tracking/*.json): the vehicles' spot speed RMSE at the
        counting lines, by how each crossing was found (seen, hidden, unseen) and in all, and on the
        crossings where the track was listed confirmed, the spot speed's against the track's own.
    scripts/track-errors.py crossings CROSSINGS TRACKS STATES [CROSSINGS TRACKS STATES ...]
        Over all given (roadscand --crossings-out, --tracks-out, roadscan-sim --truth-states of
        one run each; the five lines of scripts/tracking.sh): the true crossings (each segment of a
        road user's path between two true states that crosses a line, the crossing interpolated:
        a few more or fewer than roadscan-eval's, which takes the first state past the line),
        each counted crossing matched to a true one of its line and way within 1.5 s and 2.5 m
        along it (greedy, in time order, as roadscan-eval --crossings); the counted ones that match
        none, by kind: a second count of a true crossing already matched, one near a true crossing
        of the line left unmatched (within 4 s), or none; how many of those and of the matched
        ones were counted by slivers (a track's box under 0.25 m tall or wide at the crossing);
        the true crossings missed, vehicles among them; and the pairs of counted crossings of one
        line and way within 2.5 s whose tracks' boxes overlapped at the second one (a rule that
        would not count the second: how many of those are second counts, how many true).
    scripts/track-errors.py visible MOTDUMP CROSSINGS TRACKS STATES [MOTDUMP CROSSINGS TRACKS STATES ...]
        Over all given (roadscan-eval --tracking ... --mot-dump, roadscand --crossings-out and
        --tracks-out, roadscan-sim --truth-states of one run each; the tracks give the frames'
        times): the true crossings the counts missed (as crossings matches them), road lines and
        the walk line apart, by how near in time to its crossing the road user was a true
        instance (>= 10 returns in a frame: what the sensor could show of it): within 1 s, 1-3 s,
        over 3 s, never in the capture.
    scripts/track-errors.py late MOTDUMP TRACKS STATES [MOTDUMP TRACKS STATES ...]
        Over all given: the true objects not matched (IoU > 0.5) by a confirmed track within 0.3 s
        (3 frames) of their first frame as an instance (>= 10 returns), as roadscan-eval's
        confirmed_within_0_3s counts them, walkers (pedestrians, cyclists) and vehicles apart, by
        why: hidden most of the wait (an instance in under half its frames), seen and matched by a
        tentative track in at least half of them (the confirmation rules held it), or seen and not
        matched; then the objects confirmed in time.
    scripts/track-errors.py reacquired MOTDUMP TRACKS STATES [MOTDUMP TRACKS STATES ...]
        Over all given: each true vehicle's change of matched track (IoU > 0.5, as roadscan-eval
        --tracking matches) to a track it never had before, by how long the old track had been
        unseen (from its last row with no miss to the new one's first row with this vehicle:
        under 0.15 s, under 1 s, 1-3 s, 3-6 s, longer), whether the old track was still listed
        then, and whether the new one lay within 6 m along and 2.5 m across the old one's
        heading from where it was predicted (straight on from its last row seen): the vehicles
        that came back out of their track's gate (kin_accel, docs/tracking.md); then each of those
        unseen 1-3 s, no longer listed and out: the old track's last reported speed, the true
        speeds then and when it came back, and where it came back.
    scripts/track-errors.py budget MOTDUMP TRACKS STATES [MOTDUMP TRACKS STATES ...]
        Over all given: where the vehicle speed error of roadscan-eval --tracking comes from (its
        rows: confirmed, matched IoU > 0.5 to a true vehicle within 80 m; the truth between its
        states). Each row is put in the first kind it fits: the capture's first 3 s; a track that
        took this vehicle over from another road user under 2 s ago; a track under 1 s old that
        is the vehicle's first, or was born after the vehicle's earlier track last had it (under
        0.5 s, 0.5-1.5 s, 1.5 s or more before); a track seen again under 1 s after 1 s or more
        unseen; a track that has had this vehicle 1-2 s; the rest (2 s or more). Per kind: its
        rows, its share of the rows and of the squared error, its RMSE and mean signed error
        (m/s), and over its rows of vehicles moving at 0.5 m/s or more the RMSE of the reported
        velocity (vx, vy) along the true velocity and across it. Then, across the kinds, the rows
        reported 0 while the vehicle moved at 1 m/s or more, those reported moving while it moved
        slower than 1 m/s, and those reported under half the speed of a vehicle moving at 2 m/s or
        more (and in how many pairs of a track and a vehicle; the largest pair: its triple's number
        from 1, track, vehicle, and share of the squared error). Last, by the size of the error
        (under 0.3, 0.3-1, 1-2, 2-3, 3-5, 5 m/s or more): the rows and their share of the squared
        error; and of the rows 3 m/s or more off, the share of all the squared error reported too
        fast and too slow, and per kind.
    scripts/track-errors.py gaps MOTDUMP TRACKS STATES [MOTDUMP TRACKS STATES ...]
        Over all given, pedestrians and vehicles apart: where a road user's frames as a true instance
        (>= 10 returns) are away from its own track (the one matching it, IoU > 0.5, in most of its
        frames): on another track, or on none; for pedestrians by range (0-15, 15-30, 30-45, 45 m or
        more) and by how near the nearest other pedestrian is (under 1, 1-2, 2-4, 4 m or more). Then
        each time it comes back matched after over 1 s with no match (hidden, or too few returns), by
        how long (1-2, 2-4, 4-6, 6-10, 10-20 s, longer): on the track it had before the gap, on one
        it had earlier, on a new track, or on a track that had another road user; and, when not on the
        one it had before, whether that one was still listed (TRACKS) then.
    scripts/track-errors.py young MOTDUMP TRACKS STATES OBJECTS [MOTDUMP TRACKS STATES OBJECTS ...]
        Over all given (OBJECTS: roadscand --objects-out of the same run): the speed error of young
        tracks as roadscan-eval scores it (the confirmed rows matched to a true vehicle within 80 m),
        rows of tracks younger than 1 s past the capture's first 3 s with the vehicle moving at 1 m/s or
        more: by the track's hits (3, 4, ... 10 or more), by whether it reports too little (over 0.5
        m/s under), too much, or within 0.5 m/s, by the range, and by whether the object it took (the
        frame's object with the row's return count nearest its position) was marked hidden at an end
        (something nearer beside it, rs_object_t.occluded): per kind its rows, mean (signed) error,
        RMSE and share of the squared error.
    scripts/track-errors.py close STATES...
        Per true-states file: how many pairs of walkers came within 0.45 m of each other (centres;
        bodies are 0.5 m wide), the states within 0.6 m, and the nearest two ever came (m): how
        well the simulator's walkers keep apart (walker_space, docs/simulator.md).

The files are those scripts/tracking.sh leaves in out/tracking/ and out/results/.
Off the real-time path: plain Python, no third-party module.
"""
import bisect
import csv
import json
import math
import sys
from collections import Counter, defaultdict

VEHICLES = {"car", "van", "truck", "bus"}
BORN_NEAR_M = 15.0  # born: a track's first row this near the sensor
BORN_YOUNG_S = 2.5  # ... and younger than this
STANDING = 0.05  # speed: a vehicle slower than this (m/s) stands


def load_states(path):
    """id -> sorted rows (t, x, y, vx, vy), id -> class"""
    rows, cls = defaultdict(list), {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            k = int(r["id"])
            rows[k].append((float(r["t"]), float(r["x"]), float(r["y"]), float(r["vx"]), float(r["vy"])))
            cls[k] = r["class"]
    return rows, cls


def at(rows, t):
    """the state (x, y, vx, vy) at time t, linear between steps; None outside the object's life"""
    if t < rows[0][0] - 0.15 or t > rows[-1][0] + 0.15:
        return None
    i = bisect.bisect_left(rows, (t,))
    if i <= 0:
        return rows[0][1:]
    if i >= len(rows):
        return rows[-1][1:]
    a, b = rows[i - 1], rows[i]
    w = 0.0 if b[0] <= a[0] else (t - a[0]) / (b[0] - a[0])
    return tuple(a[j] + w * (b[j] - a[j]) for j in range(1, 5))


def wrap(deg):
    return (deg + 180.0) % 360.0 - 180.0


def heading_rmse(samples):
    """the heading RMSE of the rows of a moving vehicle (deg), as text"""
    h = [s[7] for s in samples if s[7] is not None]
    return f"  heading RMSE {math.sqrt(sum(e * e for e in h) / len(h)):.1f} deg" if h else ""


def speed(tracks_path, states_path):
    states, cls = load_states(states_path)
    samples = []  # (track, truth, t, speed error, accel, age, turn rate deg/s, heading error deg or None)
    with open(tracks_path, newline="") as f:
        for r in csv.DictReader(f):
            if r["state"] != "confirmed":
                continue
            t, x, y = float(r["t"]), float(r["x"]), float(r["y"])
            best, best_d = None, 2.5
            for k, rows in states.items():
                s = at(rows, t)
                if s is not None and math.hypot(s[0] - x, s[1] - y) <= best_d:
                    best, best_d = k, math.hypot(s[0] - x, s[1] - y)
            if best is None or cls[best] not in VEHICLES:
                continue
            s = at(states[best], t)
            if math.hypot(s[0], s[1]) > 80.0:
                continue
            s0, s1 = at(states[best], t - 0.3), at(states[best], t + 0.3)
            accel = 0.0 if s0 is None or s1 is None else (math.hypot(s1[2], s1[3]) - math.hypot(s0[2], s0[3])) / 0.6
            turn = 0.0  # deg/s, from the true velocity's direction over +-0.3 s
            if s0 is not None and s1 is not None and min(math.hypot(s0[2], s0[3]), math.hypot(s1[2], s1[3])) > 1.0:
                turn = abs(wrap(math.degrees(math.atan2(s1[3], s1[2]) - math.atan2(s0[3], s0[2])))) / 0.6
            herr = None  # the track's heading against the true velocity's direction (deg), when moving
            if math.hypot(s[2], s[3]) > 1.0 and r.get("heading", "") not in ("", "nan"):
                herr = wrap(math.degrees(float(r["heading"]) - math.atan2(s[3], s[2])))
            samples.append((int(r["track"]), best, round(t, 2), float(r["speed"]) - math.hypot(s[2], s[3]), accel,
                            float(r["age"]), turn, herr, math.hypot(s[2], s[3]), math.hypot(s[0], s[1])))
    if not samples:
        print(f"{tracks_path}: no confirmed vehicle rows within 80 m")
        return
    per_truth_time = Counter((s[1], s[2]) for s in samples)
    total = sum(s[3] ** 2 for s in samples)
    kinds = {
        "turning (> 5 deg/s)": lambda s: s[6] > 5.0,
        "speeding up or braking (> 0.5 m/s^2)": lambda s: abs(s[4]) > 0.5,
        "tracks younger than 1 s": lambda s: s[5] < 1.0,
        "one vehicle, two tracks": lambda s: per_truth_time[(s[1], s[2])] > 1,
    }
    n = len(samples)
    print(f"{tracks_path}: {n} rows, speed RMSE {math.sqrt(total / n):.3f} m/s" + heading_rmse(samples))
    steady = [True] * n
    for name, test in kinds.items():
        sel = [i for i, s in enumerate(samples) if test(s)]
        for i in sel:
            steady[i] = False
        sq = sum(samples[i][3] ** 2 for i in sel)
        rmse = math.sqrt(sq / len(sel)) if sel else 0.0
        print(f"  {name:38s} rows {100.0 * len(sel) / n:5.1f} %  squared error {100.0 * sq / total:5.1f} %  "
              f"RMSE {rmse:.3f}" + heading_rmse([samples[i] for i in sel]))
    rest = [samples[i][3] for i in range(n) if steady[i]]
    if rest:
        print(f"  {'the rest (steady, older, one track)':38s} rows {100.0 * len(rest) / n:5.1f} %  "
              f"RMSE {math.sqrt(sum(e * e for e in rest) / len(rest)):.3f}")
    standing = [s for s in samples if s[8] < STANDING]
    if standing:
        moving = [s[3] + s[8] for s in standing if s[3] + s[8] > 0.0]
        print(f"  {'standing (true speed < 0.05 m/s)':38s} rows {len(standing):6d}  reported moving {len(moving)} "
              f"({100.0 * len(moving) / len(standing):.1f} %, the most {max(moving, default=0.0):.2f} m/s)")
    for name, sel in (("speeding up (> 0.5 m/s^2)", [s for s in samples if s[4] > 0.5]),
                      ("braking (< -0.5 m/s^2)", [s for s in samples if s[4] < -0.5])):
        if sel:
            print(f"  {name:38s} rows {len(sel):6d}  mean error {sum(s[3] for s in sel) / len(sel):+.3f} m/s")
    bands = [(lo, [s[3] for s in samples if lo <= s[9] < lo + 20.0]) for lo in (0.0, 20.0, 40.0, 60.0)]
    print("  by range: " + ", ".join(f"{lo:.0f}-{lo + 20:.0f} m {math.sqrt(sum(e * e for e in es) / len(es)):.3f} ({len(es)})"
                                     for lo, es in bands if es))


def read_mot(mot_path):
    """(frames, match, had) of a --mot-dump: frames[truth] the frames a true instance is in, match[truth][frame]
    the track it is matched to (IoU > 0.5), had[track][frame] the true instance matched to it. A track's label
    is 2 + its id; the dump's pred is 0 (a truth row) or a label of 3 or more."""
    frames, match, had = defaultdict(set), defaultdict(dict), defaultdict(dict)
    with open(mot_path, newline="") as f:
        for r in csv.DictReader(f):
            fr, t, p, iou = int(r["frame"]), int(r["truth"]), int(r["pred"]), float(r["iou"])
            if t == 0:
                continue
            frames[t].add(fr)
            if p >= 3 and iou > 0.5:
                match[t][fr] = p - 2
                had[p - 2][fr] = t
    return frames, match, had


def ids(mot_path, states_path):
    states, cls = load_states(states_path)
    frames, match, pred_truth = read_mot(mot_path)
    t0 = min(rows[0][0] for rows in states.values())
    state_at = lambda k, fr: at(states[k], t0 + 0.1 * fr) if k in states else None
    lost, total, switches, objects = Counter(), Counter(), Counter(), Counter()
    kinds, through = Counter(), Counter()
    small = [k for k in states if cls.get(k) in ("pedestrian", "cyclist")]

    def passed_through(t, fr):
        """walker t's centre within 0.45 m of another walker's or cyclist's in frames fr-15 .. fr+5"""
        for g in range(fr - 15, fr + 6):
            s = state_at(t, g)
            if s is None:
                continue
            for k in small:
                if k == t:
                    continue
                so = state_at(k, g)
                if so is not None and math.hypot(s[0] - so[0], s[1] - so[1]) < 0.45:
                    return True
        return False

    for t, fs in frames.items():
        c = cls.get(t, "?")
        m = match[t]
        keep = Counter(m.values()).most_common(1)[0][1] if m else 0
        lost[c] += len(fs) - keep
        total[c] += len(fs)
        objects[c] += 1
        seq = sorted(m)
        for a, b in zip(seq, seq[1:]):
            if m[a] == m[b]:
                continue
            switches[c] += 1
            if c in ("pedestrian", "cyclist") and passed_through(t, b):
                through[c] += 1
            before = [pred_truth[m[b]][g] for g in sorted(pred_truth[m[b]]) if g < b]
            if not before:
                kinds[(c, "to a new track")] += 1
            elif before[-1] == t:
                kinds[(c, "back to a track it had")] += 1
            else:
                o, s, so = before[-1], state_at(t, b), state_at(before[-1], b)
                if s is None or so is None:
                    continue
                cos = (s[2] * so[2] + s[3] * so[3]) / (math.hypot(s[2], s[3]) * math.hypot(so[2], so[3]) + 1e-9)
                way = "the other way" if cos < -0.5 else "the same way" if cos > 0.5 else "crossing/standing"
                near = "within 3 m" if math.hypot(s[0] - so[0], s[1] - so[1]) < 3.0 else "farther"
                kinds[(c, f"taken from a {cls.get(o, '?')} going {way}, {near}")] += 1
    all_frames = sum(total.values())
    print(f"{mot_path}: true frames {all_frames}")
    for c in sorted(total, key=lambda c: -lost[c]):
        print(f"  {c:12s} objects {objects[c]:4d} frames {total[c]:6d} not with their track {lost[c]:5d} "
              f"({100.0 * lost[c] / all_frames:.2f} % of all) switches {switches[c]}")
    for (c, k), v in kinds.most_common(15):
        print(f"  {v:4d} {c}: {k}")
    for c in sorted(through):
        print(f"  {c}: {through[c]} of {switches[c]} switches within 1.5 s of passing through another walker "
              f"or cyclist (centres within 0.45 m)")
    way = Counter()  # vehicles that turned (docs/simulator.md, turn_share) and those that went straight
    for t, fs in frames.items():
        if cls.get(t) not in VEHICLES | {"cyclist"}:
            continue
        moving = [r for r in states.get(t, []) if math.hypot(r[3], r[4]) > 1.0]
        turn = wrap(math.degrees(math.atan2(moving[-1][4], moving[-1][3]) - math.atan2(moving[0][4], moving[0][3]))) \
            if moving else 0.0
        m = match[t]
        key = "left" if turn > 60.0 else "right" if turn < -60.0 else "straight"  # counter-clockwise is left
        way[key, "objects"] += 1
        way[key, "frames"] += len(fs)
        way[key, "lost"] += len(fs) - (Counter(m.values()).most_common(1)[0][1] if m else 0)
    for key in ("left", "right", "straight"):
        if way[key, "objects"]:
            what = "went straight" if key == "straight" else f"turned {key} (over 60 deg)"
            print(f"  vehicles and cyclists that {what}: "
                  f"objects {way[key, 'objects']} frames {way[key, 'frames']} not with their track "
                  f"{way[key, 'lost']} ({100.0 * way[key, 'lost'] / way[key, 'frames']:.1f} %)")


def boxes_overlap(a, b):
    """do two boxes (x, y, heading, length, width) overlap (separating axes)"""
    def corners(x, y, h, ln, wd):
        c, s = math.cos(h), math.sin(h)
        return [(x + u * ln / 2 * c - v * wd / 2 * s, y + u * ln / 2 * s + v * wd / 2 * c)
                for u, v in ((1, 1), (1, -1), (-1, -1), (-1, 1))]
    pa, pb = corners(*a), corners(*b)
    for p in (pa, pb):
        for k in range(2):
            nx, ny = p[k + 1][1] - p[k][1], p[k][0] - p[k + 1][0]
            ia = [q[0] * nx + q[1] * ny for q in pa]
            ib = [q[0] * nx + q[1] * ny for q in pb]
            if max(ia) < min(ib) or max(ib) < min(ia):
                return False
    return True


def traffic(*paths):
    for path in paths:
        rows, by_t = defaultdict(list), defaultdict(list)
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                d = (int(r["id"]), r["class"], float(r["t"]), float(r["x"]), float(r["y"]), float(r["vx"]),
                     float(r["vy"]), float(r["heading"]), float(r["length"]), float(r["width"]))
                rows[d[0]].append(d)
                by_t[d[2]].append(d)
        turns, through, longest = Counter(), 0, 0.0
        for k, tr in rows.items():
            if tr[0][1] == "pedestrian":
                continue
            turns["vehicles"] += 1
            turned = wrap(math.degrees(tr[-1][7] - tr[0][7]))
            if abs(turned) > 60.0:
                turns["left" if turned > 0 else "right"] += 1
                turns["trucks and buses"] += tr[0][1] in ("truck", "bus")
            through += any(math.hypot(d[3] - 11.5, d[4] - 11.5) < 8.0 for d in tr)
            run = t_start = None
            for d in tr:
                if math.hypot(d[5], d[6]) < 0.1:
                    t_start = d[2] if t_start is None else t_start
                    run = d[2] - t_start
                    longest = max(longest, run)
                else:
                    t_start = None
        pairs, states = set(), 0
        for ds in by_t.values():
            for i, a in enumerate(ds):
                for b in ds[i + 1:]:
                    if (a[1] == "pedestrian" and b[1] == "pedestrian") or math.hypot(a[3] - b[3], a[4] - b[4]) > 15.0:
                        continue
                    if boxes_overlap((a[3], a[4], a[7], a[8], a[9]), (b[3], b[4], b[7], b[8], b[9])):
                        pairs.add((min(a[0], b[0]), max(a[0], b[0])))
                        states += 1
        print(f"{path}: {turns['vehicles']} vehicles, turned {turns['left'] + turns['right']} ({turns['left']} left, "
              f"{turns['right']} right; {turns['trucks and buses']} trucks or buses), {through} through the centre, "
              f"{len(pairs)} pairs of boxes overlapping in {states} states, longest stand {longest:.1f} s")


def unmatched(mot_path, tracks_path):
    """confirmed track rows no true instance matches (IoU > 0.5), and how many have fewer than 10 returns"""
    _, _, had = read_mot(mot_path)
    matched = {(fr, track) for track, frames in had.items() for fr in frames}
    rows = few = 0
    with open(tracks_path, newline="") as f:
        for r in csv.DictReader(f):
            if r["state"] == "confirmed" and (int(r["frame"]), int(r["track"])) not in matched:
                rows += 1
                few += int(r["points"]) < 10
    print(f"{tracks_path}: {rows} confirmed rows unmatched, {few} ({100.0 * few / max(rows, 1):.0f} %) "
          f"with fewer than 10 returns")


def close(*paths):
    for path in paths:
        frames = defaultdict(list)
        with open(path, newline="") as f:
            for r in csv.DictReader(f):
                if r["class"] == "pedestrian":
                    frames[r["t"]].append((int(r["id"]), float(r["x"]), float(r["y"])))
        pairs, near, nearest = set(), 0, math.inf
        for walkers in frames.values():
            for i, a in enumerate(walkers):
                for b in walkers[i + 1:]:
                    d = math.hypot(a[1] - b[1], a[2] - b[2])
                    nearest = min(nearest, d)
                    near += d < 0.6
                    if d < 0.45:
                        pairs.add((min(a[0], b[0]), max(a[0], b[0])))
        print(f"{path}: {len(pairs)} pairs of walkers within 0.45 m, {near} states within 0.6 m, "
              f"nearest {nearest:.2f} m")


def matched(*paths):
    if len(paths) % 3:
        sys.exit(__doc__.strip())
    sq_all, n_all = Counter(), Counter()
    for k in range(0, len(paths), 3):
        sq, n = matched_one(*paths[k:k + 3])
        sq_all.update(sq)
        n_all.update(n)
    if len(paths) > 3:
        print_split("all", sq_all, n_all)


def print_split(name, sq, n):
    total = sum(sq.values())
    if not total:
        print(f"{name}: no confirmed vehicle rows matched within 80 m")
        return
    print(f"{name}: {sum(n.values())} rows, speed RMSE {math.sqrt(total / sum(n.values())):.3f} m/s")
    for kind in sorted(n):
        print(f"  {kind:34s} rows {n[kind]:6d}  squared error {100.0 * sq[kind] / total:5.1f} %  "
              f"RMSE {math.sqrt(sq[kind] / n[kind]):.2f}")


def match_pairs(mot_path):
    """(frame, track, truth) of each match (IoU > 0.5) of a --mot-dump, in order (a track's label is 2 + its id)"""
    with open(mot_path, newline="") as f:
        return sorted((int(r["frame"]), int(r["pred"]) - 2, int(r["truth"])) for r in csv.DictReader(f)
                      if int(r["pred"]) >= 3 and float(r["iou"]) > 0.5)


def matched_rows(mot_path, tracks_path, states_path):
    """The confirmed rows of a track file matched (IoU > 0.5, --mot-dump) to a true vehicle within
    80 m: (frame, track, track row, true speed, whether the track had another road user before,
    the frame it first had this one, the capture's first time)"""
    states, cls = load_states(states_path)
    rows = track_rows(tracks_path)
    pairs = match_pairs(mot_path)
    t0 = min(rows[0][0] for rows in states.values())
    first_with, had = {}, {}  # (track, truth) -> first frame matched; track -> the truths it matched
    for frame, track, truth in pairs:
        first_with.setdefault((track, truth), frame)
        took = bool(had.setdefault(track, set()) - {truth})
        had[track].add(truth)
        rs = scored_row(rows, frame, track, truth, states, cls)
        if rs is not None:
            yield frame, track, rs[0], math.hypot(rs[1][2], rs[1][3]), took, first_with[(track, truth)], t0


def track_rows(tracks_path):
    """(frame, track) -> the track file's row"""
    with open(tracks_path, newline="") as f:
        return {(int(r["frame"]), int(r["track"])): r for r in csv.DictReader(f)}


def scored_row(rows, frame, track, truth, states, cls):
    """(track row, true state) when the match is one roadscan-eval scores for vehicle speed (a
    confirmed row, a true vehicle within 80 m), else None"""
    r = rows.get((frame, track))
    if r is None or r["state"] != "confirmed" or cls.get(truth) not in VEHICLES:
        return None
    s = at(states[truth], float(r["t"]))
    if s is None or math.hypot(s[0], s[1]) > 80.0:
        return None
    return r, s


def matched_one(mot_path, tracks_path, states_path):
    sq, n = Counter(), Counter()
    for frame, track, r, v, took, first, t0 in matched_rows(mot_path, tracks_path, states_path):
        t = float(r["t"])
        if float(r["age"]) < 1.0:
            kind = "younger than 1 s, first 3 s" if t - t0 < 3.0 else \
                   "younger than 1 s, moving" if v >= 1.0 else "younger than 1 s, still"
        else:
            on = (frame - first) * 0.1  # frames of 0.1 s
            kind = "older, took it over < 2 s ago" if on < 2.0 and took else \
                   "older, first had it < 2 s ago" if on < 2.0 else "older, had it >= 2 s"
        e = float(r["speed"]) - v
        sq[kind] += e * e
        n[kind] += 1
    print_split(mot_path, sq, n)
    return sq, n


def born(*paths):
    if not paths or len(paths) % 3:
        sys.exit(__doc__.strip())
    sq, n = Counter(), Counter()
    for k in range(0, len(paths), 3):
        birth = {}  # track -> where its first row is
        with open(paths[k + 1], newline="") as f:
            for r in csv.DictReader(f):
                birth.setdefault(int(r["track"]), (float(r["x"]), float(r["y"])))
        for frame, track, r, v, took, first, t0 in matched_rows(*paths[k:k + 3]):
            near = math.hypot(*birth[track]) < BORN_NEAR_M and float(r["age"]) < BORN_YOUNG_S
            kind = f"born within {BORN_NEAR_M:.0f} m, younger than {BORN_YOUNG_S} s" if near else "the rest"
            e = float(r["speed"]) - v
            sq[kind] += e * e
            n[kind] += 1
    print_split("all", sq, n)


def spot(*paths):
    """spot speeds at the lines pooled over roadscan-eval --json reports made with --crossings"""
    def pooled(key, nkey):
        n = sum(j[nkey] for j in reports)
        se = sum((j[key] or 0.0) ** 2 * j[nkey] for j in reports)
        return f"{math.sqrt(se / n):.3f} ({n})" if n else "n/a (0)"
    reports = [json.load(open(p)) for p in paths]
    for j, p in zip(reports, paths):
        if "spot_speed_samples_vehicles" not in j:
            sys.exit(f"{p}: not a roadscan-eval --json report made with --crossings")
    print(f"{len(reports)} reports: {sum(j['crossing_events'] for j in reports)} crossings counted, "
          f"{sum(j['crossing_events_matched'] for j in reports)} matched; vehicles' spot speed RMSE (crossings):")
    print(f"  seen {pooled('spot_speed_rmse_vehicles_seen', 'spot_speed_samples_vehicles_seen')}, "
          f"hidden {pooled('spot_speed_rmse_vehicles_hidden', 'spot_speed_samples_vehicles_hidden')}, "
          f"unseen {pooled('spot_speed_rmse_vehicles_unseen', 'spot_speed_samples_vehicles_unseen')}, "
          f"all {pooled('spot_speed_rmse_vehicles', 'spot_speed_samples_vehicles')}")
    print(f"  listed at the crossing: spot {pooled('spot_speed_rmse_vehicles_listed', 'track_speed_at_crossing_samples_vehicles')}"
          f", the track's own {pooled('track_speed_at_crossing_rmse_vehicles', 'track_speed_at_crossing_samples_vehicles')}")


def late(*paths):
    if not paths or len(paths) % 3:
        sys.exit(__doc__.strip())
    n = Counter()
    for k in range(0, len(paths), 3):
        _, cls = load_states(paths[k + 2])
        state = {}
        with open(paths[k + 1], newline="") as f:
            for r in csv.DictReader(f):
                state[(int(r["frame"]), int(r["track"]))] = r["state"]
        inst, match, _ = read_mot(paths[k])
        for t, frames in inst.items():
            f0 = min(frames)
            fc = next((fr for fr in sorted(frames) if state.get((fr, match[t].get(fr))) == "confirmed"), None)
            who = "walkers" if cls.get(t) in ("pedestrian", "cyclist") else "vehicles"
            if fc is not None and fc - f0 <= 3:
                n[f"{who}: confirmed within 0.3 s"] += 1
                continue
            end = fc if fc is not None else max(frames) + 1
            seen = [fr for fr in frames if f0 <= fr < end]
            tentative = sum(1 for fr in seen if fr in match[t])
            why = "hidden most of the wait" if len(seen) < 0.5 * (end - f0) else \
                  "seen, tracked by a tentative track" if tentative >= 0.5 * len(seen) else "seen, not matched"
            n[f"{who}: late, {why}"] += 1
    for kind in sorted(n):
        print(f"  {kind:56s} {n[kind]:6d}")


# the counting lines of scripts/tracking.sh (sensor frame, m)
TRACKING_LINES = {"east": (41.5, 4.5, 41.5, 18.5), "west": (-18.5, 4.5, -18.5, 18.5), "north": (4.5, 41.5, 18.5, 41.5),
                  "south": (4.5, -18.5, 18.5, -18.5), "walk": (31.5, 19.5, 31.5, 23.5)}
SLIVER_M = 0.25  # a box under this tall or wide: one row's arc, a face seen edge-on
MATCH_S, MATCH_M, NEAR_S, PAIR_S = 1.5, 2.5, 4.0, 2.5
FRAME_S = 0.1  # s: a frame at 10 Hz


def true_crossings(states_path):
    """[t, line, way, along, class, id, matched] for each segment of a road user's path that crosses a line;
    forward: from the right of the line's first end -> second end to its left, as roadscand"""
    paths, cls = defaultdict(list), {}
    with open(states_path, newline="") as f:
        for r in csv.DictReader(f):
            paths[int(r["id"])].append((float(r["t"]), float(r["x"]), float(r["y"])))
            cls[int(r["id"])] = r["class"]
    out = []
    for name, (ax, ay, bx, by) in TRACKING_LINES.items():
        length = math.hypot(bx - ax, by - ay)
        for k, rows in paths.items():
            for a, b in zip(rows, rows[1:]):
                sa = (bx - ax) * (a[2] - ay) - (by - ay) * (a[1] - ax)
                sb = (bx - ax) * (b[2] - ay) - (by - ay) * (b[1] - ax)
                if sa * sb >= 0:
                    continue
                w = sa / (sa - sb)
                x, y = a[1] + w * (b[1] - a[1]), a[2] + w * (b[2] - a[2])
                along = ((x - ax) * (bx - ax) + (y - ay) * (by - ay)) / length
                if 0.0 <= along <= length:
                    out.append([a[0] + w * (b[0] - a[0]), name, "backward" if sa > 0 else "forward", along, cls[k], k, False])
    return out


def match_crossings(crossings_path, states_path):
    """(true crossings, their last field set when a counted one matches; the counted crossings in time order)"""
    truth = true_crossings(states_path)
    with open(crossings_path, newline="") as f:
        counted = sorted(csv.DictReader(f), key=lambda r: float(r["t"]))
    for c in counted:
        t, at = float(c["t"]), float(c["at"])
        best = None
        for x in truth:
            if not x[6] and x[1] == c["line"] and x[2] == c["direction"] and abs(x[0] - t) <= MATCH_S and \
                    abs(x[3] - at) <= MATCH_M and (best is None or abs(x[0] - t) < abs(best[0] - t)):
                best = x
        if best:
            best[6] = True
        c["matched"] = best is not None
    return truth, counted


VISIBLE_KINDS = ("within 1 s", "1-3 s", "over 3 s", "never")


def visible_counts(*paths):
    """Counter of (road or walk, kind) over the missed true crossings of the quadruples (MOTDUMP, CROSSINGS, TRACKS,
    STATES)"""
    n = Counter()
    for k in range(0, len(paths), 4):
        truth, _ = match_crossings(paths[k + 1], paths[k + 3])
        seen = defaultdict(list)  # true id -> frames as an instance
        with open(paths[k], newline="") as f:
            for r in csv.DictReader(f):
                if r["pred"] == "0" and r["truth"] != "0":
                    seen[int(r["truth"])].append(int(r["frame"]))
        times = {}  # frame -> time
        with open(paths[k + 2], newline="") as f:
            for r in csv.DictReader(f):
                times[int(r["frame"])] = float(r["t"])
        if not times:
            sys.exit(f"{paths[k + 2]}: no frame listed: the frames' times are not known")
        known = sorted(times)

        def frame_time(fr):
            """the frame's time, or that of the nearest frame listed, 0.1 s per frame from it"""
            if fr in times:
                return times[fr]
            i = bisect.bisect_left(known, fr)
            near = min(known[max(i - 1, 0):i + 1], key=lambda g: abs(g - fr))
            return times[near] + FRAME_S * (fr - near)

        for x in truth:
            if x[6]:
                continue
            where = "walk" if x[1] == "walk" else "road"
            gaps = [abs(frame_time(fr) - x[0]) for fr in seen.get(x[5], [])]
            g = min(gaps) if gaps else None
            kind = VISIBLE_KINDS[3] if g is None else VISIBLE_KINDS[0] if g <= 1.0 else VISIBLE_KINDS[1] if g <= 3.0 \
                else VISIBLE_KINDS[2]
            n[where, kind] += 1
            n[where, "missed"] += 1
    return n


def visible(*paths):
    if not paths or len(paths) % 4:
        sys.exit(__doc__.strip())
    n = visible_counts(*paths)
    for where in ("road", "walk"):
        print(f"  {where} lines: {n[where, 'missed']} true crossings missed; the road user a true instance "
              + ", ".join(f"{kind} {n[where, kind]}" for kind in VISIBLE_KINDS) + " of its crossing")


GAP_BINS = (2.0, 4.0, 6.0, 10.0, 20.0)  # s: the upper ends of gaps' bins, the last open
RANGE_BINS = (15.0, 30.0, 45.0)  # m
NEAR_BINS = (1.0, 2.0, 4.0)  # m


def bin_labels(ends, unit, lo=None):
    """the bins' labels in order (bin_of)"""
    return [bin_of(e - 1e-9, ends, unit, lo) for e in ends] + [bin_of(ends[-1], ends, unit, lo)]


def bin_of(v, ends, unit, lo=None):
    """the label of v's bin: ends' upper bounds, the last one open; lo, when given, the first one's lower"""
    for e in ends:
        if v < e:
            return f"under {e:g} {unit}" if lo is None else f"{lo:g}-{e:g} {unit}"
        lo = e
    return f"{lo:g} {unit} or more"


def gaps_counts(*paths):
    """(away, back): Counters over the triples (MOTDUMP, TRACKS, STATES). away: (group, where, 'on another
    track' | 'on none' | 'frames') -> frames, where 'all', a range bin or a nearest-walker bin (pedestrians); back:
    (group, gap bin, outcome) -> times a road user came back matched after over 1 s unmatched"""
    away, back = Counter(), Counter()
    for k in range(0, len(paths), 3):
        states, cls = load_states(paths[k + 2])
        listed = set()  # (frame, track) rows of the track file
        with open(paths[k + 1], newline="") as f:
            for r in csv.DictReader(f):
                listed.add((int(r["frame"]), int(r["track"])))
        frames, match, had = read_mot(paths[k])
        t0 = min(rows[0][0] for rows in states.values())
        state_at = lambda i, fr: at(states[i], t0 + 0.1 * fr) if i in states else None
        walkers = defaultdict(dict)  # frame -> pedestrian -> (x, y)
        for t, fs in frames.items():
            if cls.get(t) == "pedestrian":
                for fr in fs:
                    s = state_at(t, fr)
                    if s is not None:
                        walkers[fr][t] = s[:2]
        for t, fs in frames.items():
            group = "pedestrian" if cls.get(t) == "pedestrian" else "vehicle" if cls.get(t) in VEHICLES else None
            if group is None:
                continue
            m = match[t]
            own = Counter(m.values()).most_common(1)[0][0] if m else None
            for fr in fs:
                where = ["all"]
                if group == "pedestrian" and fr in walkers and t in walkers[fr]:
                    x, y = walkers[fr][t]
                    near = min((math.hypot(x - a, y - b) for o, (a, b) in walkers[fr].items() if o != t), default=1e9)
                    where += ["range " + bin_of(math.hypot(x, y), RANGE_BINS, "m"),
                              "nearest pedestrian " + bin_of(near, NEAR_BINS, "m")]
                kind = None if m.get(fr) == own and own is not None else "on another track" if fr in m else "on none"
                for w in where:
                    away[group, w, "frames"] += 1
                    if kind:
                        away[group, w, kind] += 1
            seq = sorted(m)
            for a, b in zip(seq, seq[1:]):
                if b - a <= 10:
                    continue
                g = bin_of(0.1 * (b - a), GAP_BINS, "s", 1.0)
                old, new = m[a], m[b]
                earlier = [had[new][f] for f in sorted(had[new]) if f < b]
                if new == old:
                    what = "its track"
                elif not earlier:
                    what = "a new track"
                elif earlier[-1] == t:
                    what = "a track it had earlier"
                else:
                    what = "another road user's track"
                back[group, g, what] += 1
                if new != old:
                    back[group, g, "its track still listed" if (b, old) in listed else "its track ended"] += 1
    return away, back


GAP_OUTCOMES = ("its track", "a track it had earlier", "a new track", "another road user's track")


def gaps(*paths):
    if not paths or len(paths) % 3:
        sys.exit(__doc__.strip())
    away, back = gaps_counts(*paths)
    for group in ("pedestrian", "vehicle"):
        for w in ["all"] + ["range " + b for b in bin_labels(RANGE_BINS, "m")] + \
                ["nearest pedestrian " + b for b in bin_labels(NEAR_BINS, "m")]:
            n = away[group, w, "frames"]
            if not n:
                continue
            other, none = away[group, w, "on another track"], away[group, w, "on none"]
            print(f"  {group}s, {w}: frames {n}, away from their own track {other + none} "
                  f"({100.0 * (other + none) / n:.1f} %: on another track {other}, on none {none})")
        for g in bin_labels(GAP_BINS, "s", 1.0):
            n = sum(back[group, g, w] for w in GAP_OUTCOMES)
            if not n:
                continue
            print(f"  {group}s back after {g} unmatched: {n}; " +
                  ", ".join(f"on {w} {back[group, g, w]}" for w in GAP_OUTCOMES) +
                  f" (the one it had before still listed {back[group, g, 'its track still listed']}, "
                  f"ended {back[group, g, 'its track ended']})")


def crossings(*paths):
    if not paths or len(paths) % 3:
        sys.exit(__doc__.strip())
    n = Counter()
    for k in range(0, len(paths), 3):
        truth, counted = match_crossings(paths[k], paths[k + 2])
        frames = defaultdict(dict)  # frame -> track -> row
        with open(paths[k + 1], newline="") as f:
            for r in csv.DictReader(f):
                frames[int(r["frame"])][r["track"]] = r
        times = sorted((float(next(iter(rs.values()))["t"]), fr) for fr, rs in frames.items())

        def row_at(track, t):
            """the track's row of the first frame at or after t (within a frame) that lists it"""
            i = bisect.bisect_left(times, (t - 0.06,))
            for _, fr in times[i:i + 12]:
                if track in frames[fr]:
                    return fr, frames[fr][track]
            return None, None

        for c in counted:
            _, r = row_at(c["track"], float(c["t"]))
            c["sliver"] = r is not None and (float(r["height"]) < SLIVER_M or float(r["width"]) < SLIVER_M)
            n["matched, by slivers" if c["matched"] and c["sliver"] else "matched" if c["matched"] else "unmatched"] += 1
        for c in counted:
            if c["matched"]:
                continue
            t, at = float(c["t"]), float(c["at"])
            if any(x[6] and x[1] == c["line"] and x[2] == c["direction"] and abs(x[0] - t) <= MATCH_S and
                   abs(x[3] - at) <= MATCH_M for x in truth):
                kind = "a second count of a matched true crossing"
            elif any(not x[6] and x[1] == c["line"] and abs(x[0] - t) <= NEAR_S for x in truth):
                kind = "near an unmatched true crossing of its line"
            else:
                kind = "no true crossing near"
            n["unmatched: " + kind + (", by slivers" if c["sliver"] else "")] += 1
        for i, c in enumerate(counted):  # pairs of one line and way, the tracks' boxes overlapping at the second
            fr, b = row_at(c["track"], float(c["t"]))
            if b is None:
                continue
            for p in counted[:i]:
                if p["line"] != c["line"] or p["direction"] != c["direction"] or p["track"] == c["track"] or \
                        float(c["t"]) - float(p["t"]) > PAIR_S:
                    continue
                a = frames[fr].get(p["track"])
                if a is None:
                    continue
                h = float(b["heading"])
                dx, dy = float(a["x"]) - float(b["x"]), float(a["y"]) - float(b["y"])
                u, v = abs(dx * math.cos(h) + dy * math.sin(h)), abs(-dx * math.sin(h) + dy * math.cos(h))
                if u < 0.5 * (float(a["length"]) + float(b["length"])) and v < 0.5 * (float(a["width"]) + float(b["width"])):
                    n["overlapping pairs: the second " + ("true" if c["matched"] else "unmatched")] += 1
        n["true"] += len(truth)
        n["true, missed"] += sum(1 for x in truth if not x[6])
        n["true, missed vehicles"] += sum(1 for x in truth if not x[6] and x[4] in VEHICLES)
    for kind in sorted(n):
        print(f"  {kind:66s} {n[kind]:6d}")


def reacquired(*paths):
    if len(paths) % 3:
        sys.exit("reacquired: MOTDUMP TRACKS STATES triples")
    kinds, events = Counter(), []
    for m in range(0, len(paths), 3):
        mot_path, tracks_path, states_path = paths[m:m + 3]
        states, cls = load_states(states_path)
        best = {}  # (frame, truth) -> (track, iou): the match
        with open(mot_path, newline="") as f:
            for r in csv.DictReader(f):
                iou = float(r["iou"])
                key = (int(r["frame"]), r["truth"])
                if iou > 0.5 and (key not in best or iou > best[key][1]):
                    best[key] = (str(int(r["pred"]) - 2), iou)  # a track's label is 2 + its id
        rows = defaultdict(dict)  # track -> frame -> row
        with open(tracks_path, newline="") as f:
            for r in csv.DictReader(f):
                rows[r["track"]][int(r["frame"])] = r
        seq = defaultdict(list)
        for (frame, truth), (track, _) in sorted(best.items()):
            seq[truth].append((frame, track))
        for truth, s in seq.items():
            if cls.get(int(truth)) not in VEHICLES:
                continue
            had = set()
            for j in range(1, len(s)):
                had.add(s[j - 1][1])
                (fa, a), (fb, b) = s[j - 1], s[j]
                if b == a or b in had or fb not in rows[b] or fa not in rows[a]:
                    continue
                seen = [fr for fr in rows[a] if fr < fb and rows[a][fr]["misses"] == "0"]
                ra, rb = rows[a][max(seen)], rows[b][fb]
                dt = float(rb["t"]) - float(ra["t"])
                h = float(ra["heading"])
                dx = float(rb["x"]) - (float(ra["x"]) + float(ra["vx"]) * dt)
                dy = float(rb["y"]) - (float(ra["y"]) + float(ra["vy"]) * dt)
                along, across = dx * math.cos(h) + dy * math.sin(h), -dx * math.sin(h) + dy * math.cos(h)
                when = next(name for lim, name in ((0.15, "under 0.15 s"), (1.0, "under 1 s"), (3.0, "1-3 s"),
                                                    (6.0, "3-6 s"), (math.inf, "longer")) if dt < lim)
                listed = "listed" if fb in rows[a] else "not listed"
                near = "near" if abs(along) < 6.0 and abs(across) < 2.5 else "out"
                kinds[(when, listed, near)] += 1
                if when == "1-3 s" and listed == "not listed" and near == "out":
                    t0, t1 = at(states[int(truth)], float(ra["t"])), at(states[int(truth)], float(rb["t"]))
                    v0 = math.hypot(t0[2], t0[3]) if t0 else math.nan
                    v1 = math.hypot(t1[2], t1[3]) if t1 else math.nan
                    events.append(f"    {tracks_path}: {cls[int(truth)]} {truth}, track {a} -> {b}: unseen {dt:.2f} s, "
                                  f"last reported {math.hypot(float(ra['vx']), float(ra['vy'])):.1f} m/s (true {v0:.1f}), "
                                  f"back {along:+.1f} m along, {across:+.1f} m across the prediction at {v1:.1f} m/s")
    print(f"{len(paths) // 3} captures: vehicles' changes to a track they never had, by how long the old one was unseen")
    for when in ("under 0.15 s", "under 1 s", "1-3 s", "3-6 s", "longer"):
        n = sum(v for k, v in kinds.items() if k[0] == when)
        lost = sum(v for k, v in kinds.items() if k[0] == when and k[1] == "not listed")
        out = sum(v for k, v in kinds.items() if k[0] == when and k[1] == "not listed" and k[2] == "out")
        out_listed = sum(v for k, v in kinds.items() if k[0] == when and k[1] == "listed" and k[2] == "out")
        print(f"  {when:12s} {n:4d}; the old track not listed {lost:4d}, of them out of 6 m along or 2.5 m across its "
              f"prediction {out:4d}; listed and out {out_listed:4d}")
    print("  1-3 s, not listed, out:")
    print("\n".join(events))


BUDGET_KINDS = ("capture's first 3 s", "took it over < 2 s ago", "< 1 s old, its first track",
                "< 1 s old, old track had it < 0.5 s before", "< 1 s old, 0.5-1.5 s before",
                "< 1 s old, >= 1.5 s before", "seen again < 1 s after >= 1 s unseen", "had it 1-2 s",
                "had it >= 2 s")


BUDGET_SIZES = (0.3, 1.0, 2.0, 3.0, 5.0)  # m/s, the ends of budget's bins of the error's size
GROSS_MS = 3.0  # m/s: budget splits the rows this far off or more


def budget_rows(mot_path, tracks_path, states_path):
    """(kind, error, true speed, reported speed, along, across, (track, vehicle)) of each row
    roadscan-eval scores for vehicle speed; along and across: the reported velocity's error along the
    true velocity and across it (m/s), None when the vehicle moved slower than 0.5 m/s"""
    states, cls = load_states(states_path)
    rows, hit_t = {}, defaultdict(list)  # (frame, track) -> row; track -> [(t, time since its last hit)]
    last_hit, last_hits = {}, {}
    with open(tracks_path, newline="") as f:
        for r in csv.DictReader(f):
            k, t, h = int(r["track"]), float(r["t"]), int(r["hits"])
            rows[(int(r["frame"]), k)] = r
            if h != last_hits.get(k):  # a hit: remember when one came after a gap
                if k in last_hit and t - last_hit[k] >= 1.0:
                    hit_t[k].append(t)
                last_hit[k], last_hits[k] = t, h
    pairs = match_pairs(mot_path)
    t0 = min(v[0][0] for v in states.values())
    first_with, before, had, last_of = {}, {}, defaultdict(set), {}
    for frame, track, truth in pairs:
        key = (track, truth)
        if key not in first_with:
            first_with[key] = frame
            before[key] = last_of.get(truth)  # (frame, track) the vehicle was last matched, another track
        took = bool(had[track] - {truth})
        had[track].add(truth)
        last_of[truth] = (frame, track)
        r = rows.get((frame, track))
        if r is None or r["state"] != "confirmed" or cls.get(truth) not in VEHICLES:
            continue
        t = float(r["t"])
        s = at(states[truth], t)
        if s is None or math.hypot(s[0], s[1]) > 80.0:
            continue
        v = math.hypot(s[2], s[3])
        on = (frame - first_with[key]) * 0.1
        back = [x for x in hit_t[track] if x <= t]
        if t - t0 < 3.0:
            kind = BUDGET_KINDS[0]
        elif took and on < 2.0:
            kind = BUDGET_KINDS[1]
        elif float(r["age"]) < 1.0:
            b = before[key]
            gap = None if b is None else (first_with[key] - b[0]) * 0.1
            kind = BUDGET_KINDS[2] if gap is None else BUDGET_KINDS[3] if gap < 0.5 else \
                BUDGET_KINDS[4] if gap < 1.5 else BUDGET_KINDS[5]
        elif back and t - back[-1] < 1.0:
            kind = BUDGET_KINDS[6]
        else:
            kind = BUDGET_KINDS[7] if on < 2.0 else BUDGET_KINDS[8]
        along = across = None
        if v >= 0.5:
            ux, uy, vx, vy = s[2] / v, s[3] / v, float(r["vx"]), float(r["vy"])
            along, across = vx * ux + vy * uy - v, vy * ux - vx * uy
        yield kind, float(r["speed"]) - v, v, float(r["speed"]), along, across, key


def budget(*paths):
    if not paths or len(paths) % 3:
        sys.exit("budget: MOTDUMP TRACKS STATES triples")
    n, sq, se = Counter(), Counter(), Counter()
    nm, sa, sc = Counter(), Counter(), Counter()  # moving rows, squared velocity errors along and across
    zeroed, moving, slow = [0, 0.0], [0, 0.0], [0, 0.0]
    slow_pairs = Counter()  # (capture, track, vehicle) -> squared error of its rows reported under half
    size_n, size_sq = Counter(), Counter()  # by the error's size (BUDGET_SIZES)
    gross_sq, gross_kind = Counter(), Counter()  # rows GROSS_MS or more off: too fast / too slow, per kind
    for k in range(0, len(paths), 3):
        for kind, e, v, sp, along, across, pair in budget_rows(*paths[k:k + 3]):
            n[kind] += 1
            sq[kind] += e * e
            se[kind] += e
            size = bin_of(abs(e), BUDGET_SIZES, "m/s", 0.0)
            size_n[size] += 1
            size_sq[size] += e * e
            if abs(e) >= GROSS_MS:
                gross_sq["too fast" if e > 0 else "too slow"] += e * e
                gross_kind[kind] += e * e
            if along is not None:
                nm[kind] += 1
                sa[kind] += along * along
                sc[kind] += across * across
            if sp == 0.0 and v >= 1.0:
                zeroed[0] += 1
                zeroed[1] += e * e
            elif sp > 0.0 and v < 1.0:
                moving[0] += 1
                moving[1] += e * e
            if v >= 2.0 and sp < 0.5 * v:
                slow[0] += 1
                slow[1] += e * e
                slow_pairs[(k,) + pair] += e * e
    rows, total = sum(n.values()), sum(sq.values())
    if not rows:
        print("no confirmed vehicle rows matched within 80 m")
        return
    print(f"{len(paths) // 3} captures: {rows} rows, vehicle speed RMSE {math.sqrt(total / rows):.3f} m/s")
    for kind in BUDGET_KINDS:
        if n[kind]:
            print(f"  {kind:40s} rows {n[kind]:6d} ({100.0 * n[kind] / rows:5.1f} %)  squared error "
                  f"{100.0 * sq[kind] / total:5.1f} %  RMSE {math.sqrt(sq[kind] / n[kind]):.2f}  mean {se[kind] / n[kind]:+.2f}"
                  + (f"  velocity along {math.sqrt(sa[kind] / nm[kind]):.2f} across {math.sqrt(sc[kind] / nm[kind]):.2f}"
                     if nm[kind] else ""))
    for name, (m, q) in (("reported 0, moving >= 1 m/s", zeroed), ("reported moving, slower than 1 m/s", moving),
                         ("reported under half, moving >= 2 m/s", slow)):
        print(f"  {name:40s} rows {m:6d} ({100.0 * m / rows:5.1f} %)  squared error {100.0 * q / total:5.1f} %")
    if slow_pairs:
        (k, track, vehicle), q = max(slow_pairs.items(), key=lambda kv: kv[1])
        print(f"    the last in {len(slow_pairs)} pairs of a track and a vehicle, the largest (triple {k // 3 + 1}, "
              f"track {track}, vehicle {vehicle}) {100.0 * q / total:.1f} % of the squared error")
    print("  by the size of the error:")
    for size in bin_labels(BUDGET_SIZES, "m/s", 0.0):
        print(f"    {size:38s} rows {size_n[size]:6d} ({100.0 * size_n[size] / rows:5.1f} %)  squared error "
              f"{100.0 * size_sq[size] / total:5.1f} %")
    if gross_sq:
        print(f"    {GROSS_MS:g} m/s or more off: too fast {100.0 * gross_sq['too fast'] / total:.1f} %, too slow "
              f"{100.0 * gross_sq['too slow'] / total:.1f} % of the squared error; by kind: " +
              ", ".join(f"{kind} {100.0 * gross_kind[kind] / total:.1f} %" for kind in BUDGET_KINDS if gross_kind[kind]))


def speed_rows(mot_path, tracks_path, states, cls):
    """(frame, truth) -> the speed error of the confirmed row matched (IoU > 0.5) to that true vehicle
    within 80 m"""
    rows, out = track_rows(tracks_path), {}
    for frame, track, truth in match_pairs(mot_path):
        rs = scored_row(rows, frame, track, truth, states, cls)
        if rs is not None:
            out[(frame, truth)] = float(rs[0]["speed"]) - math.hypot(rs[1][2], rs[1][3])
    return out


def common(*paths):
    if len(paths) % 5:
        sys.exit(__doc__.strip())
    rms = lambda es: math.sqrt(sum(e * e for e in es) / len(es)) if es else float("nan")
    tot = {"a": [], "b": [], "ca": [], "cb": []}
    for k in range(0, len(paths), 5):
        states, cls = load_states(paths[k])
        a = speed_rows(paths[k + 1], paths[k + 2], states, cls)
        b = speed_rows(paths[k + 3], paths[k + 4], states, cls)
        both = sorted(set(a) & set(b))
        ca, cb = [a[x] for x in both], [b[x] for x in both]
        for key, v in (("a", list(a.values())), ("b", list(b.values())), ("ca", ca), ("cb", cb)):
            tot[key] += v
        print(f"{paths[k + 2]}: A {len(a)} rows {rms(list(a.values())):.3f} m/s, B {len(b)} rows {rms(list(b.values())):.3f}; "
              f"both {len(both)} rows: A {rms(ca):.3f}, B {rms(cb):.3f}")
    if len(paths) > 5:
        print(f"all: A {len(tot['a'])} rows {rms(tot['a']):.3f} m/s, B {len(tot['b'])} rows {rms(tot['b']):.3f}; "
              f"both {len(tot['ca'])} rows: A {rms(tot['ca']):.3f}, B {rms(tot['cb']):.3f}")
    return tot


YOUNG_RANGE_BINS = (20.0, 40.0, 60.0)  # m


def young_errors(*paths):
    """kind -> the speed errors (m/s) of the young tracks' rows of that kind, over the quadruples (MOTDUMP,
    TRACKS, STATES, OBJECTS); every row is in one kind of each of the four splits"""
    errs = defaultdict(list)
    for k in range(0, len(paths), 4):
        mot_path, tracks_path, states_path, objects_path = paths[k:k + 4]
        objs = defaultdict(list)  # frame -> (x, y, points, hidden at an end)
        with open(objects_path, newline="") as f:
            for r in csv.DictReader(f):
                objs[int(r["frame"])].append((float(r["x"]), float(r["y"]), int(r["points"]), int(r["occluded"]) & 3 != 0))
        for frame, track, r, v, took, first, t0 in matched_rows(mot_path, tracks_path, states_path):
            if float(r["age"]) >= 1.0 or float(r["t"]) - t0 < 3.0 or v < 1.0:
                continue
            x, y, pts, e = float(r["x"]), float(r["y"]), int(r["points"]), float(r["speed"]) - v
            cand = [o for o in objs[frame] if o[2] == pts] or objs[frame]
            hidden = min(cand, key=lambda o: math.hypot(o[0] - x, o[1] - y))[3] if cand else False
            hits = int(r["hits"])
            errs["hits " + (f"{hits}" if hits < 10 else "10 or more")].append(e)
            errs["reports " + ("too little" if e < -0.5 else "too much" if e > 0.5 else "within 0.5 m/s")].append(e)
            errs["range " + bin_of(math.hypot(x, y), YOUNG_RANGE_BINS, "m", 0.0)].append(e)
            errs["object marked hidden at an end" if hidden else "object not marked hidden"].append(e)
    return errs


def young(*paths):
    if not paths or len(paths) % 4:
        sys.exit(__doc__.strip())
    errs = young_errors(*paths)
    total = sum(e * e for e in errs["object marked hidden at an end"] + errs["object not marked hidden"])
    rows = len(errs["object marked hidden at an end"]) + len(errs["object not marked hidden"])
    if not rows:
        print("no rows of young tracks")
        return
    print(f"young tracks' rows (moving vehicles, past the first 3 s): {rows}, speed RMSE {math.sqrt(total / rows):.2f} m/s")
    order = [f"hits {h}" for h in range(3, 10)] + ["hits 10 or more"] + \
        [f"reports {w}" for w in ("too little", "too much", "within 0.5 m/s")] + \
        ["range " + b for b in bin_labels(YOUNG_RANGE_BINS, "m", 0.0)] + \
        ["object marked hidden at an end", "object not marked hidden"]
    for kind in order:
        es = errs.get(kind)
        if not es:
            continue
        sq = sum(e * e for e in es)
        print(f"  {kind:34s} rows {len(es):6d}  mean {sum(es) / len(es):+.2f}  RMSE {math.sqrt(sq / len(es)):.2f}  "
              f"squared error {100.0 * sq / total:5.1f} %")


def main(argv):
    modes = {"speed": speed, "ids": ids, "close": close, "traffic": traffic, "unmatched": unmatched, "matched": matched,
             "born": born, "spot": spot, "crossings": crossings, "late": late, "reacquired": reacquired,
             "budget": budget, "visible": visible, "common": common, "gaps": gaps, "young": young}
    if len(argv) < 2 or argv[0] not in modes or \
            (argv[0] not in ("close", "traffic", "matched", "born", "spot", "crossings", "late", "reacquired", "budget",
                             "visible", "common", "gaps", "young") and len(argv) != 3):
        sys.exit(__doc__.strip())
    modes[argv[0]](*argv[1:])


if __name__ == "__main__":
    main(sys.argv[1:])
