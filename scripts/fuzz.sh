#!/usr/bin/env bash
# Builds the fuzz targets of tests/fuzz/ with clang's libFuzzer (and ASan +
# UBSan) and runs each for S seconds (default 60), starting from the seeds
# fuzz-seeds makes and the committed corpus (tests/fuzz/corpus/<target>/).
# A crash, a leak or a hang fails the run and leaves its input in
# out/fuzz/<target>/: add it to tests/fuzz/corpus/<target>/, where every
# test run replays it. Usage: scripts/fuzz.sh [SECONDS] [TARGET...]
set -euo pipefail
cd "$(dirname "$0")/.."
secs=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(stream capture lcm files stages values)
bash scripts/install-deps.sh
need=()
for p in clang libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || need+=("$p")
done
if [ ${#need[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -q
  $SUDO apt-get install -y -q --no-install-recommends "${need[@]}"
fi
CC=clang cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Debug -DRS_FUZZ=ON -DRS_BUILD_TESTS=OFF >/dev/null
cmake --build build-fuzz -j "$(nproc)"
rm -rf build-fuzz/seeds
build-fuzz/bin/fuzz-seeds build-fuzz/seeds >/dev/null
status=0
for t in "${targets[@]}"; do
  work=build-fuzz/corpus/$t
  mkdir -p "$work" "out/fuzz/$t"
  cp -n build-fuzz/seeds/$t/* "$work"/ 2>/dev/null || true
  cp -n tests/fuzz/corpus/$t/* "$work"/ 2>/dev/null || true
  log=build-fuzz/fuzz-$t.log
  if build-fuzz/bin/fuzz_$t -max_total_time="$secs" -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 \
       -artifact_prefix="out/fuzz/$t/" "$work" >"$log" 2>&1; then
    execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    echo "== fuzz_$t: $execs executions in $secs s, no crash (corpus $(ls "$work" | wc -l) inputs)"
  else
    echo "== fuzz_$t: FAILED (input in out/fuzz/$t/; log $log):"
    grep -E "ERROR|SUMMARY|==[0-9]+==" "$log" | head -20
    status=1
  fi
done
exit $status
