#!/usr/bin/env bash
# Runs `slamkit simulate` on every named sequence (TUM-VI room1–4, EuRoC V1_01, V1_02, V2_03) at
# every dynamic level for one seed and collects the JSON summaries (spline fit error, features
# per frame, dynamic share, static ratio, run time) into bench/results/simulate_sequences.json.
#   bench/simulate_sequences.sh BUILD_DIR [SEED]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
slamkit=${1:-$root/build}/bin/slamkit
seed=${2:-1}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
runs=()
for seq in room1 room2 room3 room4 euroc:V1_01 euroc:V1_02 euroc:V2_03; do
  for level in none low high; do
    name=${seq//:/_}_$level
    echo "== $seq --dynamic $level" >&2
    "$slamkit" simulate --vi "$seq" --seed "$seed" --dynamic "$level" -o "$work/$name.vis" --json "$work/$name.json" >&2
    runs+=("$work/$name.json")
  done
done
python3 - "$root/bench/results/simulate_sequences.json" "${runs[@]}" <<'PY'
import json, sys
runs = [json.load(open(p)) for p in sys.argv[2:]]
for r in runs:
    r.pop("output", None)
json.dump({"benchmark": "simulate_sequences", "runs": runs}, open(sys.argv[1], "w"), indent=1)
print("wrote", sys.argv[1])
PY
