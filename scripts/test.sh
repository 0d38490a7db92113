#!/usr/bin/env bash
# Installs dependencies, then builds and runs every test: a plain release
# build, an AddressSanitizer + UndefinedBehaviorSanitizer build, and a
# ThreadSanitizer build of the suites that run threads; soaks the release
# daemon for 5 minutes; builds the package; then runs every fuzz target for
# 30 s (libFuzzer, clang).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)
# PyPI's lcm for the Python example's test, velodyne-decoder and scipy for the
# decoder cross-check, motmetrics for the tracking cross-check, prometheus-client
# to parse the exporter's page, jsonschema for the bridge's messages, selenium
# to drive chromium on the live view (each skipped, and said so, without them)
if [ ! -x build/pyvenv/bin/python ] || ! build/pyvenv/bin/python -c 'import lcm, velodyne_decoder, scipy, motmetrics, prometheus_client, jsonschema, selenium' 2>/dev/null; then
  mkdir -p build
  { [ -x build/pyvenv/bin/python ] || python3 -m venv build/pyvenv; } &&
    build/pyvenv/bin/pip install -q --disable-pip-version-check lcm velodyne-decoder scipy motmetrics prometheus-client jsonschema selenium ||
    echo "== note: PyPI packages missing; the Python example's test or a cross-check will be skipped"
fi
export RS_PYTHON=$PWD/build/pyvenv/bin/python
run() { # name dir ctest-args cmake-args...
  local name=$1 dir=$2 filter=$3; shift 3
  echo "== $name build ($dir)"
  cmake -S . -B "$dir" -G Ninja "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
  echo "== $name tests"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" $filter
}
run release build "" -DCMAKE_BUILD_TYPE=Release
echo "== soak: the daemon flat out for 5 minutes, resident memory flat (scripts/soak.sh 60: the hour)"
bash scripts/soak.sh 5
run asan+ubsan build-asan "" -DCMAKE_BUILD_TYPE=Debug -DRS_SANITIZE=ON
run tsan build-tsan "-R ^(ring|pipeline|tools|lcm|bgupdate)$" -DCMAKE_BUILD_TYPE=Debug -DRS_SANITIZE=thread
echo "== Debian package"
bash scripts/package.sh
echo "== fuzz targets, 30 s each (scripts/fuzz.sh; hours: scripts/fuzz.sh 3600)"
bash scripts/fuzz.sh 30
