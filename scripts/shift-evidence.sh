#!/usr/bin/env bash
# The shift rule's gate (docs/background.md, "A displaced sensor"): per frame,
# the evidence of a displaced sensor as a share of the frame's returns
# (roadscand --frames-out, columns shift_evidence and points; gathered up to
# what the gate needs, so a displaced frame shows at least 0.15 %), on the
# results captures (scripts/results.sh makes them) and on the real VLP-16
# learned from its first 1.5 s; then what the rule costs without its gate
# (--shift-gate 0) and without the rule (--shift-tol 0) on the rush captures.
# Usage: scripts/shift-evidence.sh [OUTDIR]   (default out/shift)
set -euo pipefail
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
bin=${BIN:-build/bin}
res=out/results
out=${1:-out/shift}
data=${RS_SHARED_DATA:-../shared/data}
mkdir -p "$out"
stats() { # label frames.csv [from to]
  python3 - "$@" <<'PY'
import csv, sys
label, path = sys.argv[1], sys.argv[2]
a, b = (int(sys.argv[3]), int(sys.argv[4])) if len(sys.argv) > 4 else (1, 10**9)
rows = [r for r in csv.DictReader(open(path)) if r["partial"] == "0" and a <= int(r["frame"]) <= b]
sh = sorted(100.0 * int(r["shift_evidence"]) / int(r["points"]) for r in rows)
disp = sum(int(r["displaced"]) for r in rows)
print(f"| {label} | {len(rows)} | {sh[len(sh) // 2]:.3f} % | {sh[int(0.99 * (len(sh) - 1))]:.3f} % | {sh[-1]:.3f} % | {disp} |")
PY
}
echo "| capture | frames | median | 99th percentile | max | displaced |"
echo "|---|---|---|---|---|---|"
for f in "$res"/*.bg; do
  tag=$(basename "$f" .bg)
  [ -f "$res/$tag.pcap" ] || continue
  case $tag in *-old) continue ;; esac
  $bin/roadscand --pcap "$res/$tag.pcap" --fast --background "$f" --no-publish --no-tracking --quiet \
    --frames-out "$out/$tag-frames.csv" 2>/dev/null
  stats "$tag" "$out/$tag-frames.csv"
done
v16=$data/vlp-16-test-90deg-1-50-frames.pcap
if [ -f "$v16" ]; then
  $bin/roadscan-learn "$v16" -o "$out/real.bg" --seconds 1.5 2>/dev/null
  $bin/roadscand --pcap "$v16" --fast --background "$out/real.bg" --no-publish --quiet --frames-out "$out/real-frames.csv" 2>/dev/null
  stats "real VLP-16, frames 1-30 (still)" "$out/real-frames.csv" 1 30
  stats "real VLP-16, frames 31-50 (moving)" "$out/real-frames.csv" 31 50
  python3 - "$out/real-frames.csv" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["partial"] == "0" and int(r["frame"]) >= 31]
print("real VLP-16 frames 31-50, evidence % (displaced):", " ".join(
    f"{r['frame']}:{100.0 * int(r['shift_evidence']) / int(r['points']):.2f}{'*' if r['displaced'] == '1' else ''}" for r in rows))
PY
fi
echo
echo "| capture | rule | precision | static kept | objects kept |"
echo "|---|---|---|---|---|"
for tag in VLP-32C-rush VLP-16-rush VLP-32C-rush-site5 VLP-16-rush-site5 VLP-32C-rush-site9 VLP-16-rush-site9; do
  [ -f "$res/$tag.pcap" ] || continue
  for rule in "gated:" "no gate:--shift-gate 0" "off:--shift-tol 0"; do
    $bin/roadscand --pcap "$res/$tag.pcap" --fast --background "$res/$tag.bg" ${rule#*:} --no-publish --no-tracking \
      --quiet --labels-out "$out/$tag-labels.csv" 2>/dev/null
    $bin/roadscan-eval "$res/$tag.pcap" "$res/$tag-truth.csv" "$out/$tag-labels.csv" --json 2>/dev/null |
      python3 -c "import json,sys; j=json.load(sys.stdin); b=j['background']; print(f\"| $tag | ${rule%%:*} | {100*j['target']['precision']:.2f} % | {100*b['static_kept']:.2f} % | {100*b['targets_kept']:.2f} % |\")"
  done
done
