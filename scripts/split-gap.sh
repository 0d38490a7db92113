#!/usr/bin/env bash
# How the adaptive FSPC's split pass (clusters cut at gaps in range, --split-gap)
# was chosen and checked (docs/clustering.md): every results capture of both
# sensors (scripts/results.sh makes them) and site 13 with traffic seeds 61/62
# (light and rush, both sensors; made here when absent, in out/split-gap; the rule
# was found on the merged instances of site 9 and set before these were made),
# labelled by roadscand with each --split-gap (0 = off), scored by roadscan-eval
# (scripts/sweep.sh).
# Usage: scripts/split-gap.sh [GAPS...]   (default 0 0.5)
set -euo pipefail
[ $# -gt 0 ] || set -- 0 0.5
exec "$(dirname "$0")/sweep.sh" --split-gap out/split-gap out/split-gap "VLP-32C VLP-16" 61 62 "$@"
