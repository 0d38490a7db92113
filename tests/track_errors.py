#!/usr/bin/env python3
"""scripts/track-errors.py budget, visible, common, gaps and young on hand-made runs with known answers.

Four true cars at 5 m/s and five tracks, 10 Hz for 10 s:
  car 1: track 1 from the first frame to the last (the capture's first 3 s, then 2 s or more);
  car 2: track 2 born at 5 s (under 1 s old, its first track; then 1-2 s; at 7.0 s, 2 s), unseen
         from 7.1 s to 8.3 s and seen again at 8.4-9.2 s (under 1 s after 1 s or more unseen);
  car 3: track 3 until 4.9 s, then track 4 born at 6.0 s (under 1 s old, 1.1 s after its old track
         last had it);
  car 4: track 3 takes it at 8.0 s (took it over under 2 s ago).
Track 1 reports 0 in its rows at 6.0-6.4 s (reported 0 while moving; by the error's size, 5 m/s or
more, too slow); track 2 reports a velocity 1 m/s across its car's way in its first second (velocity
error across, none along; its speed 5 m/s, under 0.3 m/s off).

common: two cars over 100 frames; tracker A follows car 1 throughout reporting 0.5 m/s too fast and car
2 in frames 0-49 exactly; tracker B follows car 1 in frames 20-79 1 m/s too slow (tentative in 20-29)
and car 2 throughout 0.2 m/s too fast, and a walker (not a vehicle); the rows both score are car 1's
frames 30-79 and car 2's 0-49.

visible: five cars at 10 m/s across the east line (x 41.5) at 1.15 s, one lane each; car 1's
crossing counted; car 2 a true instance in every frame, car 3 from 3.0 s, car 4 from 5.0 s, car 5
never; a sixth crossing of the walk line by a walker, never an instance.

gaps: five walkers standing apart (10, 20, 35, 12 and 50 m from the sensor) and a car, 100 frames:
walker 1 on track 1, unmatched 1.5 s and back on it; walker 2 on track 2 (listed until frame 60), an
instance unmatched in frames 40-49, then a new track 3 from frame 70; walker 3 on track 4 (listed
throughout) and, after 5.1 s, on track 5, which had walker 4 in frames 0-19; walker 5 on track 6, then 7,
2.1 s unmatched, then track 6 again; the car on track 8 throughout.
young: a car at 10 m/s along y = 30 for 10 s; track 1 born on it at 4.0 s (confirmed from its third
hit), reporting 6, 8, 9, 12 m/s at hits 3-6 and 10 m/s after; its objects marked hidden at an end at
hits 3 and 4; track 2 born at 1.0 s on a second car (the capture's first 3 s: not counted).
Exit 0 when every row and crossing lands in its kind, 1 otherwise.
"""
import contextlib
import csv
import io
import importlib.util
import math
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
spec = importlib.util.spec_from_file_location("track_errors", os.path.join(ROOT, "scripts", "track-errors.py"))
te = importlib.util.module_from_spec(spec)
spec.loader.exec_module(te)

T0 = 1700000000.0
FRAMES = 100


def car_state(car, f):
    return 10.0 + 0.5 * f, 5.0 * car, 5.0, 0.0  # x, y, vx, vy: along x, one lane (5 m) per car


def main():
    with tempfile.TemporaryDirectory() as tmp:
        return check(tmp) or check_visible(tmp) or check_common(tmp) or check_gaps(tmp) or check_young(tmp)


def check_gaps(tmp):
    states_p, tracks_p, mot_p = (os.path.join(tmp, n) for n in ("gstates.csv", "gtracks.csv", "gmot.csv"))
    where = {1: (10.0, 0.0), 2: (0.0, 20.0), 3: (-35.0, 0.0), 4: (0.0, -12.0), 5: (0.0, -50.0), 9: (20.0, 20.0)}
    # (walker, track, first frame, last frame) of the matches; walker 2 an instance unmatched in 40-49
    spans = [(1, 1, 0, 29), (1, 1, 45, 99), (2, 2, 0, 39), (2, 3, 70, 99), (3, 4, 0, 29), (3, 5, 80, 99),
             (4, 5, 0, 19), (5, 6, 0, 19), (5, 7, 20, 39), (5, 6, 60, 99), (9, 8, 0, 99)]
    listed = {1: (0, 99), 2: (0, 60), 3: (70, 99), 4: (0, 99), 5: (0, 99), 6: (0, 99), 7: (20, 99), 8: (0, 99)}
    with open(states_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "id", "class", "x", "y", "vx", "vy", "heading", "length", "width", "height"])
        for fr in range(FRAMES):
            for k, (x, y) in where.items():
                w.writerow([f"{T0 + 0.1 * fr:.3f}", k, "car" if k == 9 else "pedestrian", x, y, 0.0, 0.0, 0.0,
                            4.5 if k == 9 else 0.5, 1.8 if k == 9 else 0.5, 1.5])
    with open(tracks_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["frame", "t", "track"])
        for track, (a, b) in listed.items():
            for fr in range(a, b + 1):
                w.writerow([fr, f"{T0 + 0.1 * fr:.3f}", track])
    with open(mot_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["frame", "truth", "pred", "iou"])
        for k, track, a, b in spans:
            for fr in range(a, b + 1):
                w.writerow([fr, k, 0, 0])
                w.writerow([fr, k, track + 2, 1.0])
        for fr in range(40, 50):
            w.writerow([fr, 2, 0, 0])
    away, back = te.gaps_counts(mot_p, tracks_p, states_p)
    want_away = {("all", "frames"): 315, ("all", "on another track"): 70, ("all", "on none"): 10,
                 ("range under 15 m", "frames"): 105, ("range 15-30 m", "frames"): 80,
                 ("range 15-30 m", "on another track"): 30, ("range 15-30 m", "on none"): 10,
                 ("range 30-45 m", "frames"): 50, ("range 30-45 m", "on another track"): 20,
                 ("range 45 m or more", "frames"): 80, ("range 45 m or more", "on another track"): 20,
                 ("nearest pedestrian 4 m or more", "frames"): 315,
                 ("nearest pedestrian 4 m or more", "on another track"): 70,
                 ("nearest pedestrian 4 m or more", "on none"): 10}
    got_away = {(wh, n): v for (g, wh, n), v in away.items() if g == "pedestrian"}
    want_back = {("1-2 s", "its track"): 1, ("2-4 s", "a new track"): 1, ("2-4 s", "its track ended"): 1,
                 ("4-6 s", "another road user's track"): 1, ("4-6 s", "its track still listed"): 1,
                 ("2-4 s", "a track it had earlier"): 1, ("2-4 s", "its track still listed"): 1}
    got_back = {(g, n): v for (gr, g, n), v in back.items() if gr == "pedestrian"}
    vehicle = {k: v for k, v in list(away.items()) + list(back.items()) if k[0] == "vehicle"}
    if got_away != want_away or got_back != want_back or vehicle != {("vehicle", "all", "frames"): 100}:
        print(f"gaps away {got_away}\nwanted {want_away}\nback {got_back}\nwanted {want_back}\nvehicle {vehicle}")
        return 1
    print("walkers' frames away and their returns after gaps in their kinds")
    return 0


def check_young(tmp):
    states_p, tracks_p, mot_p, objects_p = (os.path.join(tmp, n) for n in ("ystates.csv", "ytracks.csv", "ymot.csv",
                                                                           "yobjects.csv"))
    cars = {1: (lambda fr: (-40.0 + fr, 30.0)), 2: (lambda fr: (60.0 - fr, 35.0))}  # 10 m/s each, along x
    born = {1: 40, 2: 10}  # track k is born on car k at this frame
    reported = {3: 6.0, 4: 8.0, 5: 9.0, 6: 12.0}  # track 1's speed at these hits, 10 m/s at the others
    with open(states_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "id", "class", "x", "y", "vx", "vy", "heading", "length", "width", "height"])
        for fr in range(FRAMES):
            for k, pos in cars.items():
                x, y = pos(fr)
                w.writerow([f"{T0 + 0.1 * fr:.3f}", k, "car", x, y, 10.0 if k == 1 else -10.0, 0.0, 0.0, 4.5, 1.8, 1.5])
    with open(tracks_p, "w", newline="") as tf, open(mot_p, "w", newline="") as mf, \
            open(objects_p, "w", newline="") as of:
        tw, mw, ow = csv.writer(tf), csv.writer(mf), csv.writer(of)
        tw.writerow(["frame", "t", "track", "state", "x", "y", "speed", "hits", "age", "points"])
        mw.writerow(["frame", "truth", "pred", "iou"])
        ow.writerow(["frame", "object", "x", "y", "points", "occluded"])
        for fr in range(FRAMES):
            for k, pos in cars.items():
                if fr < born[k]:
                    continue
                hits = fr - born[k] + 1
                x, y = pos(fr)
                speed = reported.get(hits, 10.0) if k == 1 else 10.0
                tw.writerow([fr, f"{T0 + 0.1 * fr:.3f}", k, "confirmed" if hits >= 3 else "tentative", x, y, speed, hits,
                             f"{0.1 * (hits - 1):.3f}", 100])
                mw.writerow([fr, k, 0, 0])
                mw.writerow([fr, k, k + 2, 0.9])
                ow.writerow([fr, k, x, y, 100, 2 if k == 1 and hits in (3, 4) else 0])
    errs = te.young_errors(mot_p, tracks_p, states_p, objects_p)
    got = {k: sorted(round(e, 6) for e in v) for k, v in errs.items()}
    want = {"hits 3": [-4.0], "hits 4": [-2.0], "hits 5": [-1.0], "hits 6": [2.0], "hits 7": [0.0], "hits 8": [0.0],
            "hits 9": [0.0], "hits 10 or more": [0.0],
            "reports too little": [-4.0, -2.0, -1.0], "reports too much": [2.0],
            "reports within 0.5 m/s": [0.0, 0.0, 0.0, 0.0],
            "object marked hidden at an end": [-4.0, -2.0], "object not marked hidden": [-1.0, 0.0, 0.0, 0.0, 0.0, 2.0]}
    ranges = {k: v for k, v in got.items() if k.startswith("range")}
    got = {k: v for k, v in got.items() if not k.startswith("range")}
    # the car is at x = -40 + frame, y = 30: hits 3-10 are frames 42-49, 30.4-32.3 m from the sensor
    if got != want or ranges != {"range 20-40 m": [-4.0, -2.0, -1.0, 0.0, 0.0, 0.0, 0.0, 2.0]}:
        print(f"young {got}\nwanted {want}\nranges {ranges}")
        return 1
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        te.young(mot_p, tracks_p, states_p, objects_p)
    rmse = math.sqrt((16 + 4 + 1 + 4) / 8)
    if f"(moving vehicles, past the first 3 s): 8, speed RMSE {rmse:.2f} m/s" not in out.getvalue():
        print("young's summary:\n" + out.getvalue())
        return 1
    print("young tracks' rows in their kinds (hits, too little or too much, range, hidden end)")
    return 0


def check_visible(tmp):
    states_p, tracks_p, mot_p, cross_p = (os.path.join(tmp, n) for n in ("vstates.csv", "vtracks.csv", "vmot.csv",
                                                                          "vcross.csv"))
    lanes = {1: 6.0, 2: 9.0, 3: 12.0, 4: 15.0, 5: 17.0}
    first_seen = {2: 0, 3: 30, 4: 50}  # frames as a true instance from this one on; 1 and 5 never
    with open(states_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "id", "class", "x", "y", "vx", "vy", "heading", "length", "width", "height"])
        for fr in range(60):
            t = f"{T0 + 0.1 * fr:.3f}"
            for car, y in lanes.items():
                w.writerow([t, car, "car", 30.0 + 1.0 * fr, y, 10.0, 0.0, 0.0, 4.5, 1.8, 1.5])
            w.writerow([t, 6, "pedestrian", 30.0 + 0.14 * fr, 21.0, 1.4, 0.0, 0.0, 0.5, 0.5, 1.7])  # walk line at 1.07 s
    with open(tracks_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["frame", "t", "track"])
        for fr in range(60):
            w.writerow([fr, f"{T0 + 0.1 * fr:.3f}", 1])
    with open(mot_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["frame", "truth", "pred", "iou"])
        for fr in range(60):
            for car, a in first_seen.items():
                if fr >= a:
                    w.writerow([fr, car, 0, 0])
    with open(cross_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "line", "direction", "at", "class", "track", "speed", "how"])
        w.writerow([f"{T0 + 1.15:.3f}", "east", "backward", "1.50", "car", 1, "10.0", "seen"])
    n = te.visible_counts(mot_p, cross_p, tracks_p, states_p)
    k = te.VISIBLE_KINDS
    want = {("road", "missed"): 4, ("road", k[0]): 1, ("road", k[1]): 1, ("road", k[2]): 1, ("road", k[3]): 1,
            ("walk", "missed"): 1, ("walk", k[3]): 1}
    if dict(n) != want:
        print(f"visible {dict(n)}\nwanted {want}")
        return 1
    print("missed crossings in their kinds")
    return 0


def check(tmp):
    states_p, tracks_p, mot_p = (os.path.join(tmp, n) for n in ("states.csv", "tracks.csv", "mot.csv"))
    with open(states_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "id", "class", "x", "y", "vx", "vy", "heading", "length", "width", "height"])
        for fr in range(FRAMES):
            for car in (1, 2, 3, 4):
                x, y, vx, vy = car_state(car, fr)
                w.writerow([f"{T0 + 0.1 * fr:.3f}", car, "car", x, y, vx, vy, 0.0, 4.5, 1.8, 1.5])
    # (track, car, first frame, last frame, frames unseen): the track's rows and who it follows
    spans = [(1, 1, 0, 99, ()), (2, 2, 50, 92, range(71, 84)), (3, 3, 0, 49, ()), (4, 3, 60, 99, ()),
             (3, 4, 80, 99, ())]
    rows, mot = {}, []
    born, hits = {}, {}
    for track, car, a, b, unseen in spans:
        born.setdefault(track, a)
        for fr in range(a, b + 1):
            seen = fr not in unseen
            hits[track] = hits.get(track, 0) + (1 if seen else 0)
            x, y, vx, vy = car_state(car, fr)
            if track == 2 and fr < 60:
                vy = 1.0  # its first second: 1 m/s across the way
            speed = 0.0 if track == 1 and 60 <= fr <= 64 else 5.0
            rows[(fr, track)] = [fr, f"{T0 + 0.1 * fr:.3f}", track, "confirmed" if seen else "coasting", "car", x, y,
                                 0.0, vx, vy, speed, 0.0, 4.5, 1.8, 1.5, 100, hits[track], 0,
                                 f"{0.1 * (fr - born[track]):.3f}"]
            if seen:
                mot.append((fr, car, track + 2, 1.0))
    with open(tracks_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["frame", "t", "track", "state", "class", "x", "y", "z", "vx", "vy", "speed", "heading", "length",
                    "width", "height", "points", "hits", "misses", "age"])
        for key in sorted(rows):
            w.writerow(rows[key])
    with open(mot_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["frame", "truth", "pred", "iou"])
        for r in sorted(mot):
            w.writerow(r)

    got = {}
    zero = 0
    for kind, e, v, sp, along, across, _ in te.budget_rows(mot_p, tracks_p, states_p):
        got[kind] = got.get(kind, 0) + 1
        zero += sp == 0.0 and v >= 1.0
        if not math.isclose(v, 5.0, abs_tol=1e-9):
            print(f"true speed {v}, not 5")
            return 1
        want_across = 1.0 if kind == te.BUDGET_KINDS[2] else 0.0  # track 2's first second (car 2 along +x)
        if not (math.isclose(along, 0.0, abs_tol=1e-9) and math.isclose(across, want_across, abs_tol=1e-9)):
            print(f"{kind}: velocity error along {along}, across {across}; wanted 0 and {want_across}")
            return 1
    k = te.BUDGET_KINDS
    want = {
        k[0]: 30 + 30,          # tracks 1 and 3 before 3 s
        k[1]: 20,               # track 3 with car 4, 8.0-9.9 s (under 2 s with it)
        k[2]: 10,               # track 2, 5.0-5.9 s
        k[4]: 10,               # track 4, 6.0-6.9 s: car 3's old track last had it at 4.9 s
        k[6]: 9,                # track 2 seen again, 8.4-9.2 s
        k[7]: 10 + 10,          # track 2 6.0-6.9 s, track 4 7.0-7.9 s
        k[8]: 70 + 1 + 20 + 20,  # track 1 3.0-9.9 s, track 2 at 7.0 s, track 3 3.0-4.9 s, track 4 8.0-9.9 s
    }
    if got != want or zero != 5:
        print(f"kinds {got}\nwanted {want}\nreported 0 while moving: {zero}, wanted 5")
        return 1
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        te.budget(mot_p, tracks_p, states_p)
    slow = [ln for ln in out.getvalue().splitlines() if "reported under half" in ln or "pairs of a track" in ln]
    if len(slow) != 2 or "rows      5 " not in slow[0] or "in 1 pairs" not in slow[1] or \
            "(triple 1, track 1, vehicle 1)" not in slow[1]:
        print(f"reported under half: {slow}; wanted 5 rows in 1 pair (track 1, 6.0-6.4 s)")
        return 1
    # by size: track 1's five rows at 0 are 5 m/s off (all the squared error of 3 m/s or more, too slow, in
    # 2 s or more); every other row reports 5 m/s, 0 off (track 2's error in its first second is in its
    # velocity's direction, not in the speed column)
    size = {ln.split()[0]: ln for ln in out.getvalue().splitlines() if ln.startswith("    ") and "m/s" in ln}
    rows = sum(got.values())
    if "rows      5 " not in size.get("5", "") or f"rows {rows - 5:6d} " not in size.get("0-0.3", "") or \
            "rows      0 " not in size.get("3-5", "") or \
            "too fast 0.0 %, too slow 100.0 %" not in out.getvalue() or "had it >= 2 s 100.0 %" not in out.getvalue():
        print(f"by size: {size}; wanted 5 rows of 5 m/s or more, too slow, had it >= 2 s, {rows - 5} under 0.3")
        return 1
    print(f"{sum(got.values())} rows in their kinds; 5 reported 0 while moving, under half in 1 pair; "
          "5 rows 5 m/s or more off")
    return 0


def check_common(tmp):
    states_p = os.path.join(tmp, "cstates.csv")
    with open(states_p, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["t", "id", "class", "x", "y", "vx", "vy", "heading", "length", "width", "height"])
        for fr in range(FRAMES):
            t = f"{T0 + 0.1 * fr:.3f}"
            for car in (1, 2):
                x, y, vx, vy = car_state(car, fr)
                w.writerow([t, car, "car", x, y, vx, vy, 0.0, 4.5, 1.8, 1.5])
            w.writerow([t, 3, "pedestrian", 5.0, 5.0 + 0.1 * fr, 0.0, 1.0, 1.57, 0.5, 0.5, 1.7])

    def tracker(name, rows):  # rows: (frame, track, truth, state, speed)
        mot_p, tracks_p = os.path.join(tmp, f"{name}-mot.csv"), os.path.join(tmp, f"{name}-tracks.csv")
        with open(mot_p, "w", newline="") as m, open(tracks_p, "w", newline="") as t:
            wm, wt = csv.writer(m), csv.writer(t)
            wm.writerow(["frame", "truth", "pred", "iou"])
            wt.writerow(["frame", "t", "track", "state", "speed"])
            for fr, track, truth, state, v in rows:
                wm.writerow([fr, truth, track + 2, "0.900000"])
                wt.writerow([fr, f"{T0 + 0.1 * fr:.3f}", track, state, f"{v:.3f}"])
        return mot_p, tracks_p

    a = tracker("A", [(fr, 1, 1, "confirmed", 5.5) for fr in range(FRAMES)] +
                [(fr, 2, 2, "confirmed", 5.0) for fr in range(50)])
    b = tracker("B", [(fr, 7, 1, "tentative" if fr < 30 else "confirmed", 4.0) for fr in range(20, 80)] +
                [(fr, 8, 2, "confirmed", 5.2) for fr in range(FRAMES)] +
                [(fr, 9, 3, "confirmed", 3.0) for fr in range(FRAMES)])
    with contextlib.redirect_stdout(io.StringIO()):
        tot = te.common(states_p, *a, *b)
    rms = lambda es: math.sqrt(sum(e * e for e in es) / len(es))
    got = (len(tot["a"]), len(tot["b"]), len(tot["ca"]), round(rms(tot["ca"]), 4), round(rms(tot["cb"]), 4))
    want = (150, 150, 100, round(math.sqrt(50 * 0.25 / 100), 4), round(math.sqrt((50 * 1.0 + 50 * 0.04) / 100), 4))
    if got != want:
        print(f"common: rows A, B, both; RMSE A, B on both {got}\nwanted {want}")
        return 1
    print(f"common: {got[2]} rows both score, A {got[3]} B {got[4]} m/s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
