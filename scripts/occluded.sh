#!/usr/bin/env bash
# The background's occlusion rule (docs/background.md, "Hidden, not gone"):
# on the results captures (scripts/results.sh makes them), each model learned
# with the rule (the default) and without it (roadscan-learn --occluded 0),
# labelled by roadscand with the default clustering, scored by roadscan-eval.
# Usage: scripts/occluded.sh [OUTDIR]   (default out/occluded)
set -euo pipefail
export ROADSCAN_ALLOW_ROOT=1
cd "$(dirname "$0")/.."
bin=${BIN:-build/bin}
res=out/results
out=${1:-out/occluded}
mkdir -p "$out"
echo "| capture | rule | precision | matched | static kept | objects kept |"
echo "|---|---|---|---|---|---|"
for tag in VLP-32C-light VLP-32C-rush VLP-16-light VLP-16-rush VLP-32C-rush-site5 VLP-16-rush-site5 VLP-32C-rush-site9 \
           VLP-16-rush-site9; do
  [ -f "$res/$tag-learn.pcap" ] && [ -f "$res/$tag.pcap" ] || continue
  for rule in "on:0.2" "off:0"; do
    $bin/roadscan-learn "$res/$tag-learn.pcap" -o "$out/$tag-${rule%%:*}.bg" --occluded "${rule#*:}" 2>/dev/null
    $bin/roadscand --pcap "$res/$tag.pcap" --fast --background "$out/$tag-${rule%%:*}.bg" --no-publish --no-tracking \
      --quiet --labels-out "$out/$tag-labels.csv" 2>/dev/null
    $bin/roadscan-eval "$res/$tag.pcap" "$res/$tag-truth.csv" "$out/$tag-labels.csv" --json 2>/dev/null |
      python3 -c "import json,sys; j=json.load(sys.stdin); b=j['background']; print(f\"| $tag | ${rule%%:*} | {100*j['target']['precision']:.2f} % | {100*j['matched']/j['instances']:.2f} % | {100*b['static_kept']:.2f} % | {100*b['targets_kept']:.3f} % |\")"
  done
done
