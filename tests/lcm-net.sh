#!/bin/sh
# lcm-net.sh - roadscand over real LCM udpm:// in a private network namespace
# (nothing can leave the host). Run by check_daemon; it only runs the
# programs and leaves their output in DIR, the Check test asserts on it.
#   lcm-net.sh BIN DIR CAPTURE MODEL
# Re-executes itself under `unshare -n` (root) or `unshare -rn` (user namespaces).
set -u
if [ "${RS_IN_NETNS:-}" != 1 ]; then
  export RS_IN_NETNS=1
  unset LCM_DEFAULT_URL
  if unshare -n true 2>/dev/null; then exec unshare -n sh "$0" "$@"; fi
  if unshare -rn true 2>/dev/null; then exec unshare -rn sh "$0" "$@"; fi
  echo "no network namespace available (unshare -n / -rn)"; exit 77
fi
BIN=$1 T=$2 CAP=$3 MODEL=$4
# a subscriber says when it is subscribed; wait for that (60 s at most), never a fixed time
ready() {
  i=0
  while [ $i -lt 600 ] && ! grep -q "listening on" "$1" 2>/dev/null; do sleep 0.1; i=$((i + 1)); done
}
ip link set lo up
# 1. no multicast route: the daemon says what to run and does not start
"$BIN/roadscand" --pcap "$CAP" --fast --background "$MODEL" >"$T/noroute.txt" 2>&1
echo "$?" >"$T/noroute.status"
ip route add 224.0.0.0/4 dev lo
# 2. live: a subscriber and lcm-logger while the daemon replays at twice real time
lcm-logger -f "$T/run.lcmlog" >/dev/null 2>&1 &
logger=$!
"$BIN/roadscan-listen" --json --stats --timeout 5 >"$T/live.json" 2>"$T/live.err" &
l=$!
ready "$T/live.err"
"$BIN/roadscand" --pcap "$CAP" --speed 2 --background "$MODEL" --cluster fspc-adaptive --summary-seconds 0.5 >"$T/daemon.txt" 2>&1
echo "$?" >"$T/daemon.status"
wait $l
kill -INT $logger
wait $logger
# 3. the log read back, and 4. the log replayed by lcm-logplayer
"$BIN/roadscan-listen" --log "$T/run.lcmlog" --json >"$T/log.json" 2>"$T/log.err"
"$BIN/roadscan-listen" --json --timeout 3 >"$T/replay.json" 2>"$T/replay.err" &
l=$!
ready "$T/replay.err"
lcm-logplayer -s 4 "$T/run.lcmlog" >/dev/null 2>&1
wait $l
# 5. a subscriber that falls behind (200 ms per list at 20 lists/s)
"$BIN/roadscan-listen" --json --delay-ms 200 --timeout 3 >"$T/slow.json" 2>"$T/slow.err" &
l=$!
ready "$T/slow.err"
"$BIN/roadscand" --pcap "$CAP" --speed 2 --background "$MODEL" >"$T/daemon-slow.txt" 2>&1
wait $l
# 6. more clusters than fit in a 1400-byte datagram
"$BIN/roadscan-listen" --json --timeout 2 >"$T/trunc.json" 2>"$T/trunc.err" &
l=$!
ready "$T/trunc.err"
"$BIN/roadscand" --pcap "$CAP" --fast --background "$MODEL" --cluster ccl --max-datagram 1400 >"$T/daemon-trunc.txt" 2>&1
wait $l
exit 0
