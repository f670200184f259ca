#!/usr/bin/env bash
# Sets slamkit up from a fresh clone: installs the Debian dependencies (idempotent), then
# configures (Release) and builds into build/. Re-running it only rebuilds what changed.
#   BUILD_DIR=build-x scripts/bootstrap.sh   # another build directory
#   CMAKE_ARGS="-DSLAMKIT_BUILD_BENCHMARKS=OFF" scripts/bootstrap.sh
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
build_dir=${BUILD_DIR:-build}
generator=()
if command -v ninja >/dev/null && [[ ! -f "$build_dir/CMakeCache.txt" || -f "$build_dir/build.ninja" ]]; then
  generator=(-G Ninja)
fi
# shellcheck disable=SC2086
cmake -S . -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release ${CMAKE_ARGS:-}
cmake --build "$build_dir" --parallel "$(nproc)"
echo "bootstrap: built $build_dir/bin/slamkit"
