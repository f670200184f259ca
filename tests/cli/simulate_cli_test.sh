#!/usr/bin/env bash
# slamkit simulate through the binary: a TUM-VI room, an EuRoC sequence and a TUM file, the
# summary, JSON, true trajectory and SVG; same seed → same file, another seed → another file;
# clear errors with exit code 1 (2 for usage). Exit 77 (skipped) without the datasets, except
# under CI=true.
set -uo pipefail
slamkit=$1
root=$2
source "$(dirname "$0")/dataset.sh" "$root"
require_data vio
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$slamkit" simulate --vi room1 --duration 10 --dynamic high --seed 3 --data "$data" -o "$work/a.vis" --json "$work/a.json" \
  --truth "$work/a.tum" --plot "$work/a.svg" >"$work/out.txt" 2>"$work/err.txt" || fail "simulate room1: $(cat "$work/err.txt")"
grep -q "features/frame" "$work/out.txt" || fail "no summary: $(cat "$work/out.txt")"
grep -q "fitting a cubic B-spline" "$work/err.txt" || fail "no progress lines"
grep -q "<svg" "$work/a.svg" || fail "no SVG"
head -1 "$work/a.vis" | grep -qx "# slamkit visual-inertial simulation 1" || fail "not a simulation file"
[[ $(grep -vc "^#" "$work/a.tum") -eq 201 ]] || fail "truth should have 201 poses"
python3 - "$work/a.json" <<'PY' || fail "simulate JSON"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["kind"] == "simulate" and j["source"] == "room1" and j["dynamic"] == "high", j
assert j["frames"] == 201 and j["imu_samples"] == 2001, (j["frames"], j["imu_samples"])
assert abs(j["duration_s"] - 10.0) < 1e-9
assert j["features_per_frame"]["mean"] > 120, j["features_per_frame"]
assert j["camera"]["model"] == "equidistant" and j["camera"]["mask_radius_px"] == 300
assert 0 < j["dynamic_share"] < 1 and j["landmarks"]["groups"] > 0
assert j["spline_fit"]["position_rmse_m"] < 0.005
PY
"$slamkit" simulate --vi room1 --duration 10 --dynamic high --seed 3 --data "$data" -o "$work/b.vis" >/dev/null 2>&1 || fail "rerun"
cmp -s "$work/a.vis" "$work/b.vis" || fail "same seed gave a different file"
"$slamkit" simulate --vi room1 --duration 10 --dynamic high --seed 4 --data "$data" -o "$work/c.vis" >/dev/null 2>&1 || fail "seed 4"
cmp -s "$work/a.vis" "$work/c.vis" && fail "another seed gave the same file"

"$slamkit" simulate --vi euroc:V1_02 --duration 5 --data "$data" -o "$work/e.vis" --json "$work/e.json" >/dev/null 2>&1 \
  || fail "simulate euroc:V1_02"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert j['camera']['model']=='radtan' and j['dynamic_share']==0" \
  "$work/e.json" || fail "EuRoC JSON"
grep -q "^camera radtan 752 480" "$work/e.vis" || fail "EuRoC camera line"
"$slamkit" report "$work/a.json" "$work/e.json" -o "$work/report.html" >/dev/null 2>&1 || fail "report of simulate JSON"
grep -q 'id="simulations"' "$work/report.html" && grep -q "euroc:V1_02" "$work/report.html" || fail "no simulations table"
"$slamkit" simulate --vi "$data/vio/sim_trajectories/euroc_V1_01_easy.txt" --duration 5 --dynamic low --data "$data" \
  -o "$work/f.vis" >/dev/null 2>&1 || fail "simulate a TUM file"

"$slamkit" simulate --vi room9 --data "$data" -o "$work/x.vis" >"$work/err.txt" 2>&1
[[ $? -eq 1 ]] || fail "unknown sequence did not exit 1"
grep -q "unknown sequence 'room9'" "$work/err.txt" || fail "no clear message: $(cat "$work/err.txt")"
"$slamkit" simulate --vi room1 --data "$work/nowhere" -o "$work/x.vis" >"$work/err.txt" 2>&1
[[ $? -eq 1 ]] || fail "missing data did not exit 1"
grep -q "cannot open" "$work/err.txt" || fail "no clear message: $(cat "$work/err.txt")"
"$slamkit" simulate --vi room1 --dynamic crowd -o "$work/x.vis" >/dev/null 2>&1
[[ $? -eq 2 ]] || fail "bad --dynamic did not exit 2"
"$slamkit" simulate --vi room1 --data "$data" -o "$work/no/such/dir/x.vis" >"$work/err.txt" 2>&1
[[ $? -eq 1 ]] || fail "unwritable output did not exit 1"
echo "simulate CLI ok"
