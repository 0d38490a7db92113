#!/usr/bin/env bash
# The background on the real captures of ../shared/data: learn from the first
# frames, label the rest with the daemon's defaults, and count what comes out
# foreground (the scenes hold no moving object; in the 90-degree VLP-16 capture
# the sensor itself moves from frame 35 on, see docs/background.md).
# Usage: scripts/bg-real.sh [OUTDIR]   (default out/real)
set -euo pipefail
# roadscand refuses to run as root unless told (it needs no privilege to replay a file): these
# scripts are often run as root (containers, CI), so they say so
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
bin=${BIN:-build/bin}
out=${1:-out/real}
data=${RS_SHARED_DATA:-../shared/data}
mkdir -p "$out"
v16=$data/vlp-16-test-90deg-1-50-frames.pcap
mrpt=$data/sample_velodyne_vlp16_gps.pcap
[ -f "$v16" ] || { echo "no real captures in $data"; exit 0; }
printf '| capture | learned from | labelled | model | foreground returns | clusters per frame |\n'
printf '|---|---|---|---|---|---|\n'
# name capture learn-seconds (0 = all) first-frame last-frame
run() {
  local name=$1 cap=$2 secs=$3 from=$4 to=$5 method learn_desc
  for method in dbscan percentile; do
    if [ "$secs" = 0 ]; then
      $bin/roadscan-learn "$cap" -o "$out/$name-$method.bg" --method $method 2>/dev/null
      learn_desc="all frames"
    else
      $bin/roadscan-learn "$cap" -o "$out/$name-$method.bg" --method $method --seconds "$secs" 2>/dev/null
      learn_desc="first $secs s"
    fi
    $bin/roadscand --pcap "$cap" --fast --background "$out/$name-$method.bg" --no-publish --quiet \
      --frames-out "$out/$name-$method-frames.csv" 2>/dev/null
    python3 - "$out/$name-$method-frames.csv" "$from" "$to" "$name" "$learn_desc" "$method" <<'PY'
import csv, sys
path, a, b, name, learn, method = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), *sys.argv[4:7]
rows = [r for r in csv.DictReader(open(path)) if a <= int(r["frame"]) <= b and r["partial"] == "0"]
pts = sum(int(r["points"]) for r in rows)
fg = sum(int(r["foreground"]) for r in rows)
cl = sum(int(r["clusters"]) for r in rows)
print(f"| {name} | {learn} | frames {a}-{b} ({len(rows)}) | {method} | {100 * fg / pts:.2f} % ({fg} of {pts}) | {cl / len(rows):.2f} |")
PY
  done
}
run "VLP-16 90deg" "$v16" 1.5 31 50
run "VLP-16 90deg, static part" "$v16" 1.0 21 34
run "VLP-16 90deg" "$v16" 0 1 50
if [ -f "$mrpt" ]; then run "MRPT VLP-16" "$mrpt" 0 1 99; fi
# The pictures of docs/background.md (PICTURES=1): frame 45 of the 90-degree VLP-16, the sensor
# about 5 cm from where it learned (learned from the first 1.5 s), without the shift rule, with the
# shift rule alone, and with the defaults (what is seen behind near objects is background too)
if [ "${PICTURES:-0}" = 1 ]; then
  mkdir -p docs/img
  for v in "noshift:--shift-tol 0" "shift:--no-shift-behind" "behind:"; do
    name=${v%%:*} opts=${v#*:}
    # shellcheck disable=SC2086 # the options are words
    $bin/roadscand --pcap "$v16" --fast --learn-seconds 1.5 --no-publish --quiet --labels-out "$out/real-$name.csv" $opts 2>/dev/null
    $bin/roadscan-render "$v16" --frame 45 --labels "$out/real-$name.csv" --range 12 -o "docs/img/real-$name-45.png" 2>&1 | tail -1
  done
fi
