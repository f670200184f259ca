#!/usr/bin/env bash
# slamkit vio through the binary: a short simulated room (slamkit simulate), progress lines,
# the JSON keys of issue 12 read by `slamkit report`, the TUM trajectory, and clear errors
# with exit code 1 on a missing, truncated or reordered simulation file. Exit 77 (skipped)
# without the datasets.
set -uo pipefail
slamkit=$1
source "$(dirname "$0")/dataset.sh" "$2"
require_data vio
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$slamkit" simulate --vi room1 --duration 6 --seed 2 -o "$work/r.sim" --data "$data" >/dev/null 2>&1 || fail "simulate failed"
"$slamkit" vio --sim "$work/r.sim" --json "$work/v.json" --trajectory "$work/v.tum" --plot "$work/v.svg" \
  >"$work/out.txt" 2>&1 || fail "vio exited non-zero: $(cat "$work/out.txt")"
grep -q "frame .* solve .* marg" "$work/out.txt" || fail "no progress lines: $(cat "$work/out.txt")"
grep -q "<svg" "$work/v.svg" || fail "no SVG"
[[ $(grep -vc '^#' "$work/v.tum") -gt 100 ]] || fail "short trajectory"
python3 - "$work/v.json" <<'PY' || fail "vio JSON lacks keys or is not finite"
import json, sys, math
j = json.load(open(sys.argv[1]))
for k in ["ate_rmse", "rpe_rmse", "realtime_factor", "keyframes", "features_per_frame", "initialized_at_s"]:
    assert k in j and math.isfinite(j[k]), k
assert j["kind"] == "ate" and j["ate_rmse"] < 0.5, j["ate_rmse"]
assert set(j["time_per_frame_ms"]) == {"mean", "max"}
PY
"$slamkit" report "$work/v.json" -o "$work/r.html" >/dev/null 2>&1 || fail "report refused the vio JSON"

"$slamkit" vio --sim "$work/missing.sim" >"$work/e1.txt" 2>&1
[[ $? -eq 1 ]] || fail "missing file did not exit 1"
head -c 20000 "$work/r.sim" >"$work/cut.sim"
"$slamkit" vio --sim "$work/cut.sim" >"$work/e2.txt" 2>&1
[[ $? -eq 1 ]] || fail "truncated file did not exit 1: $(cat "$work/e2.txt")"
grep -q "cut.sim" "$work/e2.txt" || fail "error does not name the file: $(cat "$work/e2.txt")"
echo "vio CLI ok"
