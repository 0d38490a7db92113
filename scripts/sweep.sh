#!/usr/bin/env bash
# One roadscand option, several values, every results capture: how a clustering
# parameter was chosen and checked (docs/clustering.md). scripts/eps-share.sh and
# scripts/split-gap.sh call this with their option, sensors and site-13 seeds.
#
#   scripts/sweep.sh OPTION SITE13_DIR OUT_DIR "SENSORS" LEARN_SEED TEST_SEED VALUE...
#
# The captures of scripts/results.sh (out/results; run it first) and site 13
# (site_seed 13, light and rush, learned on LEARN_SEED for 150 s, scored on
# TEST_SEED for 30 s; made in SITE13_DIR when absent, its models always learned
# anew by the current roadscan-learn) are labelled by roadscand with OPTION VALUE
# (--no-tracking; labels and scores in OUT_DIR) and scored by roadscan-eval.
# Prints one markdown row per capture and value.
set -euo pipefail
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
if [ $# -lt 7 ]; then
  sed -n 6p "$0" >&2
  exit 2
fi
option=$1 site13=$2 out=$3 sensors=$4 seed_learn=$5 seed_test=$6
shift 6
bin=${BIN:-build/bin}
res=out/results
mkdir -p "$out"
scripts/site-captures.sh "$site13" 13 "$seed_learn" "$seed_test" $sensors
echo "| capture | $option | precision | recall | IoU | matched instances | merged | split | clusters cut |"
echo "|---|---|---|---|---|---|---|---|---|"
for sensor in $sensors; do
  for tag in $sensor-light $sensor-rush $sensor-far $sensor-storm $sensor-light-site5 $sensor-rush-site5 \
    $sensor-light-site9 $sensor-rush-site9 $sensor-light-site13 $sensor-rush-site13; do
    dir=$res
    [ "${tag%site13}" = "$tag" ] || dir=$site13
    [ -s "$dir/$tag.pcap" ] && [ -s "$dir/$tag.bg" ] || { echo "| $tag | no capture: run scripts/results.sh |"; continue; }
    for v in "$@"; do
      # the summary says how many clusters the split pass cut (0 when it is off)
      cut=$($bin/roadscand --pcap "$dir/$tag.pcap" --fast --background "$dir/$tag.bg" --no-publish --no-tracking \
        "$option" "$v" --labels-out "$out/$tag-$v.csv" 2>&1 | sed -n 's/.* \([0-9]*\) cut at range gaps.*/\1/p')
      $bin/roadscan-eval "$dir/$tag.pcap" "$dir/$tag-truth.csv" "$out/$tag-$v.csv" --json > "$out/$tag-$v.json" 2>/dev/null
      python3 - "$tag" "$v" "$out/$tag-$v.json" "${cut:-?}" <<'PY'
import json, sys
j = json.load(open(sys.argv[3]))
t = j["target"]
p = lambda v: f"{100 * v:.2f} %"
print(f"| {sys.argv[1]} | {sys.argv[2]} | {p(t['precision'])} | {p(t['recall'])} | {p(t['iou'])} | "
      f"{j['matched']} / {j['instances']} ({p(j['matched'] / j['instances'])}) | {j['merged']} | {j['split']} | "
      f"{sys.argv[4]} |")
PY
    done
  done
done
