#!/usr/bin/env bash
# The pictures of docs/results.md: one frame of each VLP-32C preset's test
# capture (out/results, from scripts/results.sh) drawn by roadscan-render with
# the labels of the default pipeline; with OLD_BIN=DIR (the programs of an
# earlier build, e.g. commit 67e7a36: git worktree add /tmp/old 67e7a36 and
# build it) also with that build's labels, learned and run with its defaults.
# Usage: [OLD_BIN=DIR] scripts/pictures.sh [FRAME]   (default frame 100)
set -euo pipefail
# roadscand refuses to run as root unless told (it needs no privilege to replay a file): these
# scripts are often run as root (containers, CI), so they say so
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
bin=${BIN:-build/bin}
out=out/results
frame=${1:-100}
mkdir -p docs/img
for sc in light rush far storm; do
  tag=VLP-32C-$sc
  range=60; [ $sc = far ] && range=220
  $bin/roadscan-render "$out/$tag.pcap" --frame "$frame" --labels "$out/$tag-fspc-adaptive.csv" --range $range \
    -o "docs/img/$tag-after.png"
  if [ -n "${OLD_BIN:-}" ]; then
    $OLD_BIN/roadscan-learn "$out/$tag-learn.pcap" -o "$out/$tag-old.bg" 2>/dev/null
    $OLD_BIN/roadscand --pcap "$out/$tag.pcap" --fast --background "$out/$tag-old.bg" --no-publish --quiet \
      --labels-out "$out/$tag-old.csv" 2>/dev/null
    $bin/roadscan-render "$out/$tag.pcap" --frame "$frame" --labels "$out/$tag-old.csv" --range $range \
      -o "docs/img/$tag-before.png"
  fi
done
