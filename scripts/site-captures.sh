#!/usr/bin/env bash
# The captures of one simulated site, for the held-out checks (scripts/heldout.sh,
# scripts/sweep.sh): per sensor, light and rush, a 150 s learning capture
# (LEARN_SEED) and a 30 s test capture (TEST_SEED) with its point labels and true
# states, at roadscan-sim --set site_seed=SITE, in DIR as
# SENSOR-PRESET-siteSITE{-learn.pcap,.pcap,-truth.csv,-states.csv}; made when
# absent. The background models (.bg) are always learned anew by the current
# roadscan-learn. SIM_SET="--set K=V ..." adds simulator settings to every capture (a leaning
# sensor: scripts/tracking.sh --site with lean=).
# LEARN_ARGS="..." adds roadscan-learn options to every model (a rule off, e.g. --sparse-cover 0).
# Usage: scripts/site-captures.sh DIR SITE LEARN_SEED TEST_SEED SENSOR...
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 5 ]; then
  sed -n 11p "$0" >&2
  exit 2
fi
dir=$1 site=$2 seed_learn=$3 seed_test=$4
shift 4
bin=${BIN:-build/bin}
mkdir -p "$dir"
for sensor in "$@"; do
  for sc in light rush; do
    tag=$sensor-$sc-site$site
    if [ ! -s "$dir/$tag.pcap" ] || [ ! -s "$dir/$tag-truth.csv" ] || [ ! -s "$dir/$tag-states.csv" ] ||
      [ ! -s "$dir/$tag-learn.pcap" ]; then
      $bin/roadscan-sim --sensor "$sensor" --scenario $sc --set site_seed="$site" ${SIM_SET:-} --seconds 150 --seed "$seed_learn" \
        -o "$dir/$tag-learn.pcap" --labels "$dir/$tag-learn.csv" 2>/dev/null
      # the capture is the same with or without --truth-states
      $bin/roadscan-sim --sensor "$sensor" --scenario $sc --set site_seed="$site" ${SIM_SET:-} --seconds 30 --seed "$seed_test" \
        -o "$dir/$tag.pcap" --labels "$dir/$tag-truth.csv" --truth-states "$dir/$tag-states.csv" 2>/dev/null
    fi
    $bin/roadscan-learn "$dir/$tag-learn.pcap" -o "$dir/$tag.bg" ${LEARN_ARGS:-} 2>/dev/null
  done
done
