#!/usr/bin/env bash
# Installs dependencies, builds, and runs the daemon on a sample capture with
# its original timing: the real VLP-16 capture in ../shared/data when present,
# otherwise a synthetic one. Results land in out/.
set -euo pipefail
# roadscand refuses to run as root unless told (it needs no privilege to replay a file): these
# scripts are often run as root (containers, CI), so they say so
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)"
mkdir -p out
sample=../shared/data/vlp-16-test-90deg-1-50-frames.pcap
if [ ! -f "$sample" ]; then
  sample=out/synthetic-vlp32c.pcap
  build/bin/roadscan-synth --model VLP-32C --seconds 3 -o "$sample"
fi
echo "== roadscand on $sample (original timing)"
build/bin/roadscand --pcap "$sample" --frames-out out/frames.csv
echo "== out/frames.csv (first lines)"
head -4 out/frames.csv | cut -d, -f1-8
build/bin/roadscan-export "$sample" --frame 5 -o out/frame-5.pcd
echo "== its static scene learned from the first second; frame 20 drawn to out/sample-frame20.png"
build/bin/roadscan-learn "$sample" --seconds 1 -o out/sample.bg
build/bin/roadscan-render "$sample" --frame 20 --background out/sample.bg --range 15 -o out/sample-frame20.png
echo "== a simulated intersection at rush hour: learn its static scene, subtract it, score it"
build/bin/roadscan-sim --sensor VLP-32C --scenario rush --seconds 90 --seed 11 -o out/site.pcap --labels out/site.csv
build/bin/roadscan-learn out/site.pcap -o out/site.bg --image out/site-background.png
build/bin/roadscan-sim --sensor VLP-32C --scenario rush --seconds 10 --seed 7 -o out/rush.pcap --labels out/rush-truth.csv
build/bin/roadscand --pcap out/rush.pcap --fast --background out/site.bg --labels-out out/rush-pred.csv \
  --tracks-out out/rush-tracks.csv --quiet
echo "== its objects followed over time (labels: 2 + track id; out/rush-tracks.csv: one line per track per frame)"
build/bin/roadscan-eval --tracking out/rush.pcap out/rush-truth.csv out/rush-pred.csv
build/bin/roadscan-render out/rush.pcap --frame 50 --background out/site.bg --range 60 -o out/rush-frame50.png
echo "== the daemon at the original timing, publishing object lists over LCM; roadscan-listen prints them"
if ip route get 239.255.76.67 >/dev/null 2>&1; then
  build/bin/roadscan-listen --timeout 3 > out/objects.txt &
  listener=$!
  sleep 0.3
  build/bin/roadscand --pcap out/rush.pcap --background out/site.bg --pose "0 0 3 0 0 0"
  wait $listener || true
else
  echo "(no multicast route on this host: publishing to an LCM log file instead)"
  rm -f "$PWD/out/objects.lcmlog"
  build/bin/roadscand --pcap out/rush.pcap --background out/site.bg --pose "0 0 3 0 0 0" \
    --lcm-url "file://$PWD/out/objects.lcmlog?mode=w"
  build/bin/roadscan-listen --log out/objects.lcmlog > out/objects.txt
fi
echo "== out/objects.txt (first frame)"
sed -n '1,12p' out/objects.txt
echo "== decode + frame assembly throughput"
build/bin/roadscan-bench --seconds 0.3
