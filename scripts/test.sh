#!/usr/bin/env bash
# Installs dependencies, then builds and runs every test: a plain release
# build, an AddressSanitizer + UndefinedBehaviorSanitizer build, and a
# ThreadSanitizer build of the suites that run threads.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)
run() { # name dir ctest-args cmake-args...
  local name=$1 dir=$2 filter=$3; shift 3
  echo "== $name build ($dir)"
  cmake -S . -B "$dir" -G Ninja "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
  echo "== $name tests"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs" $filter
}
run release build "" -DCMAKE_BUILD_TYPE=Release
run asan+ubsan build-asan "" -DCMAKE_BUILD_TYPE=Debug -DRS_SANITIZE=ON
run tsan build-tsan "-R ^(ring|pipeline|tools)$" -DCMAKE_BUILD_TYPE=Debug -DRS_SANITIZE=thread
