#!/usr/bin/env bash
# How the adaptive FSPC's eps (max(--eps-share, the median row spacing) x range)
# was chosen (docs/clustering.md): every VLP-32C results capture (scripts/results.sh
# makes them: the four presets at the results site, light and rush at sites 5 and
# 9) and site 13 (light and rush, seeds 51 and 52, made here when absent; no
# parameter was looked at on it before this choice), labelled by roadscand with
# each --eps-share, scored by roadscan-eval. The VLP-16's eps comes from its row
# spacing (0.035), so its captures do not change.
# Usage: scripts/eps-share.sh [SHARES...]   (default 0.03 0.025 0.02)
set -euo pipefail
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
bin=${BIN:-build/bin}
res=out/results
out=out/eps-share
mkdir -p "$out"
shares=("$@")
[ ${#shares[@]} -gt 0 ] || shares=(0.03 0.025 0.02)
for sc in light rush; do
  tag=VLP-32C-$sc-site13
  if [ ! -s "$res/$tag.pcap" ] || [ ! -s "$res/$tag-truth.csv" ]; then
    $bin/roadscan-sim --sensor VLP-32C --scenario $sc --set site_seed=13 --seconds 150 --seed 51 \
      -o "$res/$tag-learn.pcap" --labels "$res/$tag-learn.csv" 2>/dev/null
    $bin/roadscan-sim --sensor VLP-32C --scenario $sc --set site_seed=13 --seconds 30 --seed 52 \
      -o "$res/$tag.pcap" --labels "$res/$tag-truth.csv" 2>/dev/null
  fi
  [ -s "$res/$tag.bg" ] || $bin/roadscan-learn "$res/$tag-learn.pcap" -o "$res/$tag.bg" 2>/dev/null
done
echo "| capture | --eps-share | precision | recall | IoU | matched instances | merged | split |"
echo "|---|---|---|---|---|---|---|---|"
for tag in VLP-32C-light VLP-32C-rush VLP-32C-far VLP-32C-storm VLP-32C-light-site5 VLP-32C-rush-site5 \
  VLP-32C-light-site9 VLP-32C-rush-site9 VLP-32C-light-site13 VLP-32C-rush-site13; do
  [ -s "$res/$tag.pcap" ] && [ -s "$res/$tag.bg" ] || { echo "| $tag | no capture: run scripts/results.sh |"; continue; }
  for s in "${shares[@]}"; do
    $bin/roadscand --pcap "$res/$tag.pcap" --fast --background "$res/$tag.bg" --no-publish --no-tracking \
      --eps-share "$s" --labels-out "$out/$tag-$s.csv" --quiet 2>/dev/null
    $bin/roadscan-eval "$res/$tag.pcap" "$res/$tag-truth.csv" "$out/$tag-$s.csv" --json > "$out/$tag-$s.json" 2>/dev/null
    python3 - "$tag" "$s" "$out/$tag-$s.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[3]))
t = j["target"]
p = lambda v: f"{100 * v:.2f} %"
print(f"| {sys.argv[1]} | {sys.argv[2]} | {p(t['precision'])} | {p(t['recall'])} | {p(t['iou'])} | "
      f"{j['matched']} / {j['instances']} ({p(j['matched'] / j['instances'])}) | {j['merged']} | {j['split']} |")
PY
  done
done
