#!/usr/bin/env bash
# The simulator next to the real sensor (docs/simulator.md): the static-scene
# statistics of roadscan-scenestats on the real static VLP-16 capture (the 34
# frames before the sensor moves) and the MRPT VLP-16, and on simulated empty
# sites (no traffic) with the physical sensor on, VLP-16 at 20 Hz as the real
# one, and VLP-32C at 10 Hz; plus the same VLP-16 site with a thin beam and no
# motor drift (the simulator before it had a physical sensor).
# Usage: scripts/sim-vs-real.sh [OUTDIR]   (default out/simreal)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN:-build/bin}
out=${1:-out/simreal}
data=${RS_SHARED_DATA:-../shared/data}
mkdir -p "$out"
empty="--scenario light --set vehicles_per_min=0 --set pedestrians_per_min=0"
$bin/roadscan-sim --sensor VLP-16 --hz 20 $empty --seconds 5 --seed 3 -o "$out/v16.pcap" --labels "$out/v16.csv" 2>/dev/null
$bin/roadscan-sim --sensor VLP-16 --hz 20 $empty --set beam_samples=1 --set rpm_offset=0 --set rpm_jitter=0 \
  --set noise_tail=0 --set range_noise=0.015 --set dropout=0.002 --seconds 5 --seed 3 -o "$out/v16-thin.pcap" --labels "$out/v16-thin.csv" 2>/dev/null
$bin/roadscan-sim --sensor VLP-32C --hz 10 $empty --seconds 5 --seed 3 -o "$out/v32.pcap" --labels "$out/v32.csv" 2>/dev/null
inputs=() names=()
if [ -f "$data/vlp-16-test-90deg-1-50-frames.pcap" ]; then
  inputs+=("$data/vlp-16-test-90deg-1-50-frames.pcap@1-34") names+=("real VLP-16 static part")
fi
if [ -f "$data/sample_velodyne_vlp16_gps.pcap" ]; then
  inputs+=("$data/sample_velodyne_vlp16_gps.pcap") names+=("real VLP-16 (MRPT)")
fi
inputs+=("$out/v16.pcap" "$out/v16-thin.pcap" "$out/v32.pcap")
names+=("sim VLP-16 20 Hz" "sim VLP-16 thin beam and exact motor" "sim VLP-32C 10 Hz")
IFS=,
$bin/roadscan-scenestats "${inputs[@]}" --names "${names[*]}"
