#!/usr/bin/env bash
# soak.sh [MINUTES] - roadscand replaying flat out for MINUTES (default 60) with
# everything on (background kept current, clustering, tracking, counting,
# LCM over udpm:// with a subscriber), in a private network namespace;
# its resident memory sampled every 5 s. Passes when the daemon is still
# running at the end, never stopped making frames (for 2 minutes), and its resident memory at
# the end is within 1 % of what it was after the warm-up (the first fifth,
# at least 60 s: the background updater's first relearns, the allocator's
# arenas). The test command runs 5 minutes of it (scripts/test.sh); results
# in out/soak/ (rss.csv: seconds, resident KiB, frames processed).
#   Needs a release build in build/ (scripts/test.sh makes it; RS_BIN=DIR names another).
set -euo pipefail
cd "$(dirname "$0")/.."
minutes=${1:-60}
bin=${RS_BIN:-$PWD/build/bin}
out=$PWD/out/soak
export ROADSCAN_ALLOW_ROOT=1 # as root in containers and CI; the daemon needs no privilege here
if [ "${RS_IN_NETNS:-}" != 1 ]; then
  export RS_IN_NETNS=1
  unset LCM_DEFAULT_URL
  if unshare -n true 2>/dev/null; then exec unshare -n bash "$0" "$@"; fi
  if unshare -rn true 2>/dev/null; then exec unshare -rn bash "$0" "$@"; fi
  echo "soak.sh: no network namespace available (unshare -n / -rn)" >&2
  exit 1
fi
ip link set lo up
ip route add 224.0.0.0/4 dev lo
mkdir -p "$out"
rm -f "$out/daemon.txt" "$out/listen.txt"
# a minute of rush hour at a VLP-32C site, and its background
if [ ! -s "$out/site.pcap" ] || [ ! -s "$out/site.model" ]; then
  "$bin/roadscan-sim" --sensor VLP-32C --scenario rush --seconds 60 --seed 31 -o "$out/site.pcap" \
    --labels "$out/site-truth.csv" >/dev/null
  "$bin/roadscan-learn" "$out/site.pcap" -o "$out/site.model" >/dev/null 2>&1
fi
"$bin/roadscan-listen" --quiet --stats >"$out/listen.txt" 2>&1 &
listener=$!
"$bin/roadscand" --pcap "$out/site.pcap" --loop --fast --background "$out/site.model" --update-minutes 1 \
  --update-every 20 --count-line "north 0 20 20 20" --summary-seconds 5 >"$out/daemon.txt" 2>&1 &
daemon=$!
trap 'kill -KILL $daemon $listener 2>/dev/null || true' EXIT
total=$((minutes * 60))
warm=$((total / 5))
[ "$warm" -lt 60 ] && warm=60
echo "seconds,rss_kib,frames" >"$out/rss.csv"
start=$(date +%s)
rss_warm=0
last_frames=0
last_check=0
status=0
while :; do
  sleep 5
  now=$(($(date +%s) - start))
  if ! kill -0 "$daemon" 2>/dev/null; then
    echo "soak.sh: the daemon ended after $now s:" >&2
    tail -20 "$out/daemon.txt" >&2
    status=1
    break
  fi
  rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$daemon/status")
  frames=$({ grep -ao 'totals: [0-9]* frames' "$out/daemon.txt" || true; } | tail -1 | tr -dc 0-9)
  frames=${frames:-0}
  echo "$now,$rss,$frames" >>"$out/rss.csv"
  # progress: the daemon logs its totals every 5 s; every 120 s they must have grown (a flat-out
  # replay waits for each relearn of the background, which takes long on a loaded machine)
  if [ $((now - last_check)) -ge 120 ]; then
    if [ "$frames" -le "$last_frames" ]; then
      echo "soak.sh: no frame processed in the 120 s before $now s" >&2
      status=1
      break
    fi
    last_frames=$frames
    last_check=$now
  fi
  [ "$rss_warm" = 0 ] && [ "$now" -ge "$warm" ] && rss_warm=$rss
  [ "$now" -ge "$total" ] && break
done
if [ "$status" = 0 ]; then
  kill -INT "$daemon"
  wait "$daemon" || status=$?
else
  kill -KILL "$daemon" 2>/dev/null || true
fi
kill -INT "$listener" 2>/dev/null || true
wait "$listener" 2>/dev/null || true
rss_end=$(tail -1 "$out/rss.csv" | cut -d, -f2)
frames_end=$(grep -ao 'frames: [0-9]* processed' "$out/daemon.txt" | tail -1 | tr -dc 0-9 || true)
echo "soak.sh: $minutes min flat out: ${frames_end:-?} frames processed; resident memory $rss_warm KiB after the warm-up ($warm s), $rss_end KiB at the end"
if [ "$status" != 0 ]; then
  echo "soak.sh: FAIL: the daemon failed (status $status)" >&2
  exit 1
fi
if [ "$rss_warm" = 0 ] || [ $((rss_end * 100)) -gt $((rss_warm * 101)) ]; then
  echo "soak.sh: FAIL: resident memory grew by more than 1 % after the warm-up" >&2
  exit 1
fi
echo "soak.sh: resident memory flat (within 1 %)"
