#!/usr/bin/env bash
# Builds the reader fuzzers (clang, libFuzzer + AddressSanitizer + UBSan, libraries
# instrumented too) and runs them on a corpus seeded from tests/fuzz/seeds/. Each target checks
# that what reads also writes and reads back to the same values (tests/fuzz/*.h, *.cpp).
#
#   scripts/fuzz.sh [TARGET] [SECONDS]
#     TARGET   g2o | toro | gtsam | bal | traj_tum | traj_euroc | traj_kitti | traj_slamkit | mrclam | landmark_dataset | sim_spec |
#              config | vi_sim | image_sequence | all   (default: all, one after the other)
#     SECONDS  time per target            (default: 60)
#
# The corpus grows in fuzz-corpus/<target>/ (git-ignored); a crash is saved as
# fuzz-corpus/crash-<target>-<hash> and reproduces with: build-fuzz/fuzz/fuzz_<target> FILE.
# The log of each run (exec count, coverage) is fuzz-corpus/<target>.log.
# Environment: SLAMKIT_FUZZ_BUILD (build dir, default build-fuzz), JOBS (build jobs, default 2).
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
target=${1:-all}
seconds=${2:-60}
build=${SLAMKIT_FUZZ_BUILD:-$root/build-fuzz}
jobs=${JOBS:-2}

all_targets=(g2o toro gtsam bal traj_tum traj_euroc traj_kitti traj_slamkit mrclam landmark_dataset sim_spec config vi_sim image_sequence)
if [[ "$target" == all ]]; then
  targets=("${all_targets[@]}")
elif [[ " ${all_targets[*]} " == *" $target "* ]]; then
  targets=("$target")
else
  echo "usage: $0 [${all_targets[*]// /|}|all] [SECONDS]" >&2; exit 2
fi

dictionary() {
  case "$1" in
    traj_* | image_sequence) echo trajectory.dict ;;
    sim_spec) echo sim.dict ;;
    config) echo json.dict ;;
    vi_sim) echo vi_sim.dict ;;
    bal | mrclam | landmark_dataset) echo '' ;;
    *) echo pose_graph.dict ;;
  esac
}

if [[ ! -f "$build/CMakeCache.txt" ]]; then
  CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DSLAMKIT_BUILD_FUZZERS=ON -DSLAMKIT_BUILD_TESTS=OFF -DSLAMKIT_BUILD_BENCHMARKS=OFF -DSLAMKIT_BUILD_EXAMPLES=OFF
fi
cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"

mkdir -p "$root/fuzz-corpus"
status=0
for t in "${targets[@]}"; do
  corpus="$root/fuzz-corpus/$t"
  mkdir -p "$corpus"
  cp -n "$root/tests/fuzz/seeds/$t/"* "$corpus/" 2>/dev/null || true
  echo "== fuzz_$t for ${seconds}s, corpus $corpus"
  "$build/fuzz/fuzz_$t" "$corpus" \
    $(d=$(dictionary "$t"); [[ -n $d ]] && echo "-dict=$root/tests/fuzz/$d") -max_len=4096 -max_total_time="$seconds" \
    -print_final_stats=1 -artifact_prefix="$root/fuzz-corpus/crash-$t-" 2>&1 | tee "$root/fuzz-corpus/$t.log" \
    | grep -E "^#[0-9]+[[:space:]]+(INITED|DONE)|^Done|stat::|ERROR|SUMMARY|property|crash-" || true
  if grep -qE "ERROR: |SUMMARY: |fuzz property violated|deadly signal" "$root/fuzz-corpus/$t.log"; then
    echo "fuzz_$t FOUND A BUG (see $root/fuzz-corpus/$t.log)" >&2
    status=1
  fi
done
exit $status
