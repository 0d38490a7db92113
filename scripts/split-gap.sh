#!/usr/bin/env bash
# How the adaptive FSPC's split pass (clusters cut at gaps in range, --split-gap)
# was chosen and checked (docs/clustering.md): every results capture of both
# sensors (scripts/results.sh makes them) and site 13 with traffic seeds 61/62
# (light and rush, both sensors; made here when absent, in out/split-gap; the rule
# was found on the merged instances of site 9 and set before these were made),
# labelled by roadscand with each --split-gap (0 = off), scored by roadscan-eval.
# Usage: scripts/split-gap.sh [GAPS...]   (default 0 0.5)
set -euo pipefail
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
bin=${BIN:-build/bin}
res=out/results
out=out/split-gap
mkdir -p "$out"
gaps=("$@")
[ ${#gaps[@]} -gt 0 ] || gaps=(0 0.5)
for sensor in VLP-32C VLP-16; do
  for sc in light rush; do
    tag=$sensor-$sc-site13
    if [ ! -s "$out/$tag.pcap" ] || [ ! -s "$out/$tag-truth.csv" ]; then
      $bin/roadscan-sim --sensor $sensor --scenario $sc --set site_seed=13 --seconds 150 --seed 61 \
        -o "$out/$tag-learn.pcap" --labels "$out/$tag-learn.csv" 2>/dev/null
      $bin/roadscan-sim --sensor $sensor --scenario $sc --set site_seed=13 --seconds 30 --seed 62 \
        -o "$out/$tag.pcap" --labels "$out/$tag-truth.csv" 2>/dev/null
    fi
    [ -s "$out/$tag.bg" ] || $bin/roadscan-learn "$out/$tag-learn.pcap" -o "$out/$tag.bg" 2>/dev/null
  done
done
echo "| capture | --split-gap | matched instances | merged | split | clusters cut |"
echo "|---|---|---|---|---|---|"
for sensor in VLP-32C VLP-16; do
  for tag in $sensor-light $sensor-rush $sensor-far $sensor-storm $sensor-light-site5 $sensor-rush-site5 \
    $sensor-light-site9 $sensor-rush-site9 $sensor-light-site13 $sensor-rush-site13; do
    dir=$res
    [ "${tag%site13}" = "$tag" ] || dir=$out
    [ -s "$dir/$tag.pcap" ] && [ -s "$dir/$tag.bg" ] || { echo "| $tag | no capture: run scripts/results.sh |"; continue; }
    for g in "${gaps[@]}"; do
      cut=$($bin/roadscand --pcap "$dir/$tag.pcap" --fast --background "$dir/$tag.bg" --no-publish --no-tracking \
        --split-gap "$g" --labels-out "$out/$tag-$g.csv" 2>&1 | sed -n 's/.* \([0-9]*\) cut at range gaps.*/\1/p')
      $bin/roadscan-eval "$dir/$tag.pcap" "$dir/$tag-truth.csv" "$out/$tag-$g.csv" --json > "$out/$tag-$g.json" 2>/dev/null
      python3 - "$tag" "$g" "$out/$tag-$g.json" "${cut:-?}" <<'PY'
import json, sys
j = json.load(open(sys.argv[3]))
p = lambda v: f"{100 * v:.2f} %"
print(f"| {sys.argv[1]} | {sys.argv[2]} | {j['matched']} / {j['instances']} ({p(j['matched'] / j['instances'])}) | "
      f"{j['merged']} | {j['split']} | {sys.argv[4]} |")
PY
    done
  done
done
