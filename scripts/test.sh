#!/usr/bin/env bash
# Installs dependencies, then builds and runs every test twice: a plain
# release build and an AddressSanitizer + UndefinedBehaviorSanitizer build.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
jobs=$(nproc)
for variant in release asan; do
  dir="build"; opts=(-DCMAKE_BUILD_TYPE=Release)
  if [ "$variant" = asan ]; then dir="build-asan"; opts=(-DCMAKE_BUILD_TYPE=Debug -DRS_SANITIZE=ON); fi
  echo "== $variant build ($dir)"
  cmake -S . -B "$dir" -G Ninja "${opts[@]}" >/dev/null
  cmake --build "$dir" -j "$jobs"
  echo "== $variant tests"
  ctest --test-dir "$dir" --output-on-failure -j "$jobs"
done
