#!/usr/bin/env bash
# Background subtraction figures: for each preset, learn on one simulated
# capture of the site (150 s, seed 11) and evaluate on another (30 s, seed 12),
# with the learned (DBSCAN) model and with the per-cell percentile baseline.
# The captures are made when absent (FRESH=1: always; the simulator is deterministic).
# Usage: scripts/bg-figures.sh [SENSOR] [OUTDIR]   (default VLP-32C, out/bg)
set -euo pipefail
# roadscand refuses to run as root unless told (it needs no privilege to replay a file): these
# scripts are often run as root (containers, CI), so they say so
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
sensor=${1:-VLP-32C}
out=${2:-out/bg}
bin=${BIN:-build/bin}
mkdir -p "$out"
printf '| scenario | model | static as background | objects kept | foliage/noise as background | learn time |\n'
printf '|---|---|---|---|---|---|\n'
for sc in light rush far storm; do
  if [ "${FRESH:-0}" = 1 ] || [ ! -s "$out/$sc-learn.pcap" ] || [ ! -s "$out/$sc-test.csv" ]; then
    $bin/roadscan-sim --sensor "$sensor" --scenario $sc --seconds 150 --seed 11 -o "$out/$sc-learn.pcap" --labels "$out/$sc-learn.csv" 2>/dev/null
    $bin/roadscan-sim --sensor "$sensor" --scenario $sc --seconds 30 --seed 12 -o "$out/$sc-test.pcap" --labels "$out/$sc-test.csv" 2>/dev/null
  fi
  for method in dbscan percentile; do
    t0=$(date +%s.%N)
    $bin/roadscan-learn "$out/$sc-learn.pcap" -o "$out/$sc-$method.bg" --method $method 2>/dev/null
    t1=$(date +%s.%N)
    $bin/roadscand --pcap "$out/$sc-test.pcap" --fast --background "$out/$sc-$method.bg" \
      --labels-out "$out/$sc-$method-pred.csv" --quiet 2>/dev/null
    json=$($bin/roadscan-eval "$out/$sc-test.pcap" "$out/$sc-test.csv" "$out/$sc-$method-pred.csv" --json 2>/dev/null)
    python3 - "$sc" "$method" "$t0" "$t1" "$json" <<'PY'
import json, sys
sc, method, t0, t1, j = sys.argv[1], sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), json.loads(sys.argv[5])
b = j["background"]
f = lambda v: "n/a" if v is None else f"{100*v:.2f} %"
print(f"| {sc} | {method} | {f(b['static_kept'])} | {f(b['targets_kept'])} | {f(b['foliage_background'])} | {t1-t0:.1f} s |")
PY
  done
done
