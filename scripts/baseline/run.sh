#!/bin/bash
# Another tracker on roadscand's objects, scored as roadscan's tracker is (docs/tracking.md,
# "Against other trackers").
#
#   BASELINE="PROGRAM [ARGS]" [BASELINE_DIR=DIR] bash scripts/baseline/run.sh --sfx S [--confirmed] [--ours-sfx S]
#
# PROGRAM is a harness around the other tracker, built outside this repository (nothing of another
# project's code, nor a recipe that builds it, is kept here). It is run as
#   PROGRAM [ARGS] --objects O --frames F --assoc A --tracks T
# with absolute paths, from BASELINE_DIR when set (a harness that reads its tracker's configuration
# from a relative path, such as velocity.report's config/tuning.defaults.json): O and F are roadscand --no-tracking --objects-out and --frames-out of one run
# (docs/objects-and-lcm.md); it gives the tracker each frame's objects and writes A, the track each
# object went to (CSV frame,object,track,state; state confirmed or tentative; an object no track
# took is left out), and T, its tracks per frame in roadscand's --tracks-out columns. Its track
# numbers start at 1, are never reused, and name one track each (a harness numbers the tracker's own
# ids in order of first appearance when they are random).
# The captures are those scripts/tracking.sh made (out/results, and out/siteNN with --site): each one
# is replayed once with --no-tracking --objects-out (kept in out/baseline), its objects given to the
# harness, its cluster labels rewritten to the harness's tracks (relabel.py) and scored by
# roadscan-eval --tracking. --confirmed: only returns of tracks confirmed at the time are objects (as
# roadscand --labels-tracks confirmed). Then the real captures of ../shared/data, when there: each
# tracker's track rows, confirmed rows and tracks (no truth). Prints the means; JSON in
# out/baseline/<capture><sfx>.json, beside roadscan's out/tracking/<capture><ours-sfx>.json when there
# (scripts/tracking.sh's, made with that sfx).
set -euo pipefail
cd "$(dirname "$0")/../.."
which=all sfx= ours=
while [ $# -gt 0 ]; do
  case $1 in
    --confirmed) which=confirmed; shift;;
    --sfx) sfx=$2; shift 2;;
    --ours-sfx) ours=$2; shift 2;;
    *) echo "usage: BASELINE=\"PROGRAM [ARGS]\" $0 --sfx S [--confirmed] [--ours-sfx S]" >&2; exit 2;;
  esac
done
: "${BASELINE:?set BASELINE to the harness command (PROGRAM [ARGS])}"
[ -n "$sfx" ] || { echo "$0: --sfx names this run's files (out/baseline/<capture><sfx>...)" >&2; exit 2; }
read -r -a cmd <<< "$BASELINE"
(cd "${BASELINE_DIR:-.}" && command -v "${cmd[0]}" > /dev/null) || { echo "${cmd[0]}: not found" >&2; exit 1; }
mkdir -p out/baseline
root=$PWD
harness() { # OUT-PREFIX: the harness on its objects and frames, writing its assoc and tracks files (stale ones removed
  # first, so a harness that writes nothing is caught)
  local o=$1
  rm -f "$o$sfx-assoc.csv" "$o$sfx-tracks.csv"
  (cd "${BASELINE_DIR:-.}" && "${cmd[@]}" --objects "$root/$o-objects.csv" --frames "$root/$o-frames.csv" \
    --assoc "$root/$o$sfx-assoc.csv" --tracks "$root/$o$sfx-tracks.csv") ||
    { echo "$0: the harness failed on $o-objects.csv (exit $?): $BASELINE" >&2; exit 1; }
  [ -f "$o$sfx-assoc.csv" ] && [ -f "$o$sfx-tracks.csv" ] ||
    { echo "$0: the harness wrote no $o$sfx-assoc.csv or $o$sfx-tracks.csv: $BASELINE" >&2; exit 1; }
}
objects() { # PCAP BG OUT-PREFIX: the run's objects, frames and cluster labels
  local p=$1 bg=$2 o=$3
  if [ ! -f "$o-objects.csv" ] || [ ! -f "$o-clusters.csv" ] || [ ! -f "$o-frames.csv" ]; then
    build/bin/roadscand --pcap "$p" --fast --background "$bg" --no-publish --quiet --no-tracking --allow-root \
      --labels-out "$o-clusters.csv" --objects-out "$o-objects.csv" --frames-out "$o-frames.csv"
  fi
}
one() { # DIR CAPTURE
  local d=$1 c=$2 o=out/baseline/$2
  [ -f "$d/$c.pcap" ] || { echo "$c: no capture ($d/$c.pcap; scripts/tracking.sh makes it)"; return 0; }
  objects "$d/$c.pcap" "$d/$c.bg" "$o"
  harness "$o"
  python3 scripts/baseline/relabel.py "$o-clusters.csv" "$o-frames.csv" "$o$sfx-assoc.csv" "$o$sfx-labels.csv" "$which"
  build/bin/roadscan-eval --tracking "$d/$c.pcap" "$d/$c-truth.csv" "$o$sfx-labels.csv" --json --truth-states "$d/$c-states.csv" \
    --tracks "$o$sfx-tracks.csv" > "$o$sfx.json"
  rm -f "$o$sfx-labels.csv"
}
caps=()
for s in "" -site5 -site9; do for se in VLP-32C VLP-16; do for p in light rush; do caps+=("out/results $se-$p$s"); done; done; done
for s in 13 17 21 25 29 33; do for se in VLP-32C VLP-16; do for p in light rush; do caps+=("out/site$s $se-$p-site$s"); done; done; done
for c in "${caps[@]}"; do one $c; done
# the real captures of ../shared/data (no truth: what each tracker makes of them; the models learned
# on their first second, as docs/tracking.md's real-capture figures)
if [ -d ../shared/data ]; then
  for c in vlp-16-test-90deg-1-50-frames sample_velodyne_vlp16_gps monterey-first-100-packets; do
    p=../shared/data/$c.pcap o=out/baseline/real-$c
    [ -f "$p" ] || { echo "$c: not in ../shared/data"; continue; }
    [ -f "$o.bg" ] || build/bin/roadscan-learn "$p" --seconds 1 -o "$o.bg" > /dev/null 2>&1
    build/bin/roadscand --pcap "$p" --fast --background "$o.bg" --no-publish --quiet --allow-root --tracks-out "$o-ours.csv" \
      --objects-out "$o-objects.csv" --frames-out "$o-frames.csv"
    harness "$o"
    for w in "${cmd[0]##*/}:$o$sfx-tracks.csv" "roadscan:$o-ours.csv"; do
      f=${w#*:}
      echo "$c, ${w%%:*}: $(($(wc -l < "$f") - 1)) track rows, $(grep -c ',confirmed,' "$f" || true) confirmed," \
        "$(tail -n +2 "$f" | cut -d, -f3 | sort -u | wc -l) tracks"
    done
  done
else
  echo "../shared/data: absent, real captures skipped"
fi
python3 - "$sfx" "$ours" "${cmd[0]##*/}" <<'PY'
import json, os, sys
sfx, ours_sfx, name = sys.argv[1], sys.argv[2], sys.argv[3]
groups = {'the twelve': [f"{se}-{p}{s}" for s in ["", "-site5", "-site9"] for se in ["VLP-32C", "VLP-16"] for p in ["light", "rush"]],
          'held out (sites 13-25)': [f"{se}-{p}-site{s}" for s in [13, 17, 21, 25] for se in ["VLP-32C", "VLP-16"] for p in ["light", "rush"]],
          'sites 29 and 33': [f"{se}-{p}-site{s}" for s in [29, 33] for se in ["VLP-32C", "VLP-16"] for p in ["light", "rush"]]}
def line(js):
    m = lambda k: sum(j[k] for j in js) / len(js)
    return (f"MOTA {100*m('mota'):.2f} % IDF1 {100*m('idf1'):.2f} % switches {sum(j['id_switches'] for j in js)} "
            f"speed {m('speed_rmse_vehicles_80m'):.3f} m/s confirmed in 0.3 s {100*m('confirmed_within_0_3s'):.1f} %")
for g, caps in groups.items():
    for p in ['light', 'rush']:
        cs = [c for c in caps if f"-{p}" in c and os.path.exists(f"out/baseline/{c}{sfx}.json")]
        if not cs:
            continue
        print(f"{g}, {p} ({len(cs)}): {name} {line([json.load(open(f'out/baseline/{c}{sfx}.json')) for c in cs])}")
        ours = [f"out/tracking/{c}{ours_sfx}.json" for c in cs]
        if all(os.path.exists(f) for f in ours):
            print(f"{g}, {p} ({len(cs)}): roadscan {line([json.load(open(f)) for f in ours])}")
PY
