#!/bin/bash
# velocity.report's tracker on roadscand's objects, scored as roadscan's tracker is
# (docs/tracking.md, "Against velocity.report's tracker").
#
#   VR_SRC=/path/to/velocity.report bash scripts/baseline/velocity-report.sh [--max-tracks N] [--confirmed] [--sfx S]
#     [--ours-sfx S]
#
# VR_SRC: a clone of github.com/banshee-data/velocity.report (measured at 390ba3c8d872); Go 1.26.
# The captures are those scripts/tracking.sh made (out/results, and out/siteNN with --site); each
# one is replayed with --no-tracking --objects-out, its objects given to that tracker frame by frame
# (scripts/baseline/rsbaseline.go), its labels rewritten to the tracks (relabel.py) and scored by
# roadscan-eval --tracking. --max-tracks: its capacity (its default, 100, counts deleted tracks for
# 5 s); --confirmed: only returns of tracks confirmed at the time are objects (as roadscand
# --labels-tracks confirmed). Then the real captures of ../shared/data, when there: each tracker's
# track rows, confirmed rows and tracks (no truth). Prints the means; JSON in
# out/baseline/<capture><sfx>.json, beside roadscan's out/tracking/<capture><ours-sfx>.json when there
# (scripts/tracking.sh's, made with that sfx).
set -euo pipefail
cd "$(dirname "$0")/../.."
max=0 which=all sfx=-vr ours=
while [ $# -gt 0 ]; do
  case $1 in
    --max-tracks) max=$2; shift 2;;
    --confirmed) which=confirmed; shift;;
    --sfx) sfx=$2; shift 2;;
    --ours-sfx) ours=$2; shift 2;;
    *) echo "usage: VR_SRC=DIR $0 [--max-tracks N] [--confirmed] [--sfx S] [--ours-sfx S]" >&2; exit 2;;
  esac
done
: "${VR_SRC:?set VR_SRC to a clone of velocity.report}"
[ -f "$VR_SRC/internal/lidar/l5tracks/tracking.go" ] || { echo "$VR_SRC: not a velocity.report clone" >&2; exit 1; }
mkdir -p out/baseline "$VR_SRC/cmd/rsbaseline"
cp scripts/baseline/rsbaseline.go "$VR_SRC/cmd/rsbaseline/main.go"
(cd "$VR_SRC" && go build -o "$OLDPWD/out/baseline/rsbaseline" ./cmd/rsbaseline)
bin=$PWD/out/baseline/rsbaseline
one() { # DIR CAPTURE
  local d=$1 c=$2 o=out/baseline/$2
  [ -f "$d/$c.pcap" ] || { echo "$c: no capture ($d/$c.pcap; scripts/tracking.sh makes it)"; return 0; }
  if [ ! -f "$o-objects.csv" ] || [ ! -f "$o-clusters.csv" ] || [ ! -f "$o-frames.csv" ]; then
    build/bin/roadscand --pcap "$d/$c.pcap" --fast --background "$d/$c.bg" --no-publish --quiet --no-tracking --allow-root \
      --labels-out "$o-clusters.csv" --objects-out "$o-objects.csv" --frames-out "$o-frames.csv"
  fi
  (cd "$VR_SRC" && "$bin" -objects "$OLDPWD/$o-objects.csv" -frames "$OLDPWD/$o-frames.csv" -assoc "$OLDPWD/$o$sfx-assoc.csv" \
     -tracks "$OLDPWD/$o$sfx-tracks.csv" -max-tracks "$max")
  python3 scripts/baseline/relabel.py "$o-clusters.csv" "$o-frames.csv" "$o$sfx-assoc.csv" "$o$sfx-labels.csv" "$which"
  build/bin/roadscan-eval --tracking "$d/$c.pcap" "$d/$c-truth.csv" "$o$sfx-labels.csv" --json --truth-states "$d/$c-states.csv" \
    --tracks "$o$sfx-tracks.csv" > "$o$sfx.json"
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
    (cd "$VR_SRC" && "$bin" -objects "$OLDPWD/$o-objects.csv" -frames "$OLDPWD/$o-frames.csv" -assoc "$OLDPWD/$o$sfx-assoc.csv" \
       -tracks "$OLDPWD/$o$sfx-tracks.csv" -max-tracks "$max")
    for w in "velocity.report:$o$sfx-tracks.csv" "roadscan:$o-ours.csv"; do
      f=${w#*:}
      echo "$c, ${w%%:*}: $(($(wc -l < "$f") - 1)) track rows, $(grep -c ',confirmed,' "$f" || true) confirmed," \
        "$(tail -n +2 "$f" | cut -d, -f3 | sort -u | wc -l) tracks"
    done
  done
else
  echo "../shared/data: absent, real captures skipped"
fi
python3 - "$sfx" "$ours" <<'PY'
import json, os, sys
sfx, ours_sfx = sys.argv[1], sys.argv[2]
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
        print(f"{g}, {p} ({len(cs)}): velocity.report {line([json.load(open(f'out/baseline/{c}{sfx}.json')) for c in cs])}")
        ours = [f"out/tracking/{c}{ours_sfx}.json" for c in cs]
        if all(os.path.exists(f) for f in ours):
            print(f"{g}, {p} ({len(cs)}): roadscan        {line([json.load(open(f)) for f in ours])}")
PY
