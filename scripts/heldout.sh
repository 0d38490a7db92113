#!/usr/bin/env bash
# A held-out site, default settings: light and rush captures of both sensors
# at site SITE, learned on LEARN_SEED for 150 s and scored on TEST_SEED for
# 30 s (scripts/site-captures.sh, in out/site<SITE>), labelled by roadscand's
# defaults and scored by roadscan-eval. One markdown row per
# capture. docs/background.md: site 13 (seeds 61/62) and site 17 (71/72),
# made after the rules they check.
# Usage: scripts/heldout.sh SITE LEARN_SEED TEST_SEED
set -euo pipefail
# roadscand refuses to run as root unless told (it needs no privilege to replay a file): these
# scripts are often run as root (containers, CI), so they say so
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
if [ $# -ne 3 ]; then
  sed -n 8p "$0" >&2
  exit 2
fi
site=$1 seed_learn=$2 seed_test=$3
bin=${BIN:-build/bin}
dir=out/site$site
scripts/site-captures.sh "$dir" "$site" "$seed_learn" "$seed_test" VLP-32C VLP-16
echo "| capture | precision | recall | IoU | matched instances | static kept | objects kept |"
echo "|---|---|---|---|---|---|---|"
for sensor in VLP-32C VLP-16; do
  for sc in light rush; do
    tag=$sensor-$sc-site$site
    $bin/roadscand --pcap "$dir/$tag.pcap" --fast --background "$dir/$tag.bg" --no-publish --no-tracking --quiet \
      --labels-out "$dir/$tag-labels.csv" 2>/dev/null
    $bin/roadscan-eval "$dir/$tag.pcap" "$dir/$tag-truth.csv" "$dir/$tag-labels.csv" --json > "$dir/$tag.json" 2>/dev/null
    python3 - "$tag" "$dir/$tag.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[2]))
t, b = j["target"], j["background"]
p = lambda v: f"{100 * v:.2f} %"
print(f"| {sys.argv[1]} | {p(t['precision'])} | {p(t['recall'])} | {p(t['iou'])} | "
      f"{j['matched']} / {j['instances']} ({p(j['matched'] / j['instances'])}) | "
      f"{100 * b['static_kept']:.3f} % | {100 * b['targets_kept']:.3f} % |")
PY
  done
done
