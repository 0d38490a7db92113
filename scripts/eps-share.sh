#!/usr/bin/env bash
# How the adaptive FSPC's eps (max(--eps-share, the median row spacing) x range)
# was chosen (docs/clustering.md): every VLP-32C results capture (scripts/results.sh
# makes them: the four presets at the results site, light and rush at sites 5 and
# 9) and site 13 (light and rush, seeds 51 and 52, made in out/eps-share when absent;
# no parameter was looked at on it before this choice), labelled by roadscand with
# each --eps-share, scored by roadscan-eval (scripts/sweep.sh). The VLP-16's eps
# comes from its row spacing (0.035), so its captures do not change.
# Usage: scripts/eps-share.sh [SHARES...]   (default 0.03 0.025 0.02)
set -euo pipefail
[ $# -gt 0 ] || set -- 0.03 0.025 0.02
exec "$(dirname "$0")/sweep.sh" --eps-share out/eps-share out/eps-share VLP-32C 51 52 "$@"
