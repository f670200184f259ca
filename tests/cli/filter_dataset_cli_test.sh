#!/usr/bin/env bash
# slamkit filter --dataset through the binary: bad specs and malformed dataset files fail with
# exit 1 and a message naming the field or file:line; on MRCLAM robot 2 (known association)
# EKF and FastSLAM 2.0 run the whole sequence, beat dead reckoning against the Vicon, and write
# the issue's JSON keys, a TUM trajectory (one pose per scan) and an SVG. The bad-input checks
# need no data; the MRCLAM part exits 77 (skipped) without the datasets, 1 under CI=true.
set -uo pipefail
slamkit=$1
source "$(dirname "$0")/dataset.sh" "$2"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# 1. Bad specs: exit 1, the message names the spec.
for spec in "nosuch:x" "mrclam:$work" "mrclam:$work:9" "mrclam::2" "victoria:"; do
  "$slamkit" filter --algorithm ekf --dataset "$spec" >"$work/out.txt" 2>&1; rc=$?
  [[ $rc == 1 ]] || fail "spec '$spec': exit code $rc"
  grep -q "dataset" "$work/out.txt" || fail "spec '$spec': message $(cat "$work/out.txt")"
done
"$slamkit" filter --algorithm ekf --dataset "mrclam:$work/none:1" >"$work/out.txt" 2>&1; [[ $? == 1 ]] || fail "missing folder exit code"
grep -q "$work/none" "$work/out.txt" || fail "missing folder: message does not name it: $(cat "$work/out.txt")"
"$slamkit" filter --algorithm ekf --dataset "mrclam:$work/none:1" --runs 3 >"$work/out.txt" 2>&1; [[ $? == 1 ]] || fail "--runs 3 accepted"
grep -q "runs" "$work/out.txt" || fail "--runs 3 message: $(cat "$work/out.txt")"
# A malformed Victoria Park odometry file: file and line named.
mkdir -p "$work/vp"
printf '0 1.0 0.0\n25 1.0 0.0\n50 abc 0.0\n' >"$work/vp/vp_odometry.txt"
printf '10 1 5.0 0.1\n' >"$work/vp/vp_trees.txt"
printf '0 0 0\n' >"$work/vp/vp_gps.txt"
"$slamkit" filter --algorithm fastslam2 --association nn --dataset "victoria:$work/vp" >"$work/out.txt" 2>&1
[[ $? == 1 ]] || fail "malformed odometry exit code: $(cat "$work/out.txt")"
grep -q "vp_odometry.txt:3" "$work/out.txt" || fail "malformed odometry: no file:line in $(cat "$work/out.txt")"

# 2. MRCLAM robot 2, the whole sequence.
require_data landmark/MRCLAM_Dataset7
mrclam=$data/landmark/MRCLAM_Dataset7
for alg in ekf fastslam2; do
  "$slamkit" filter --algorithm "$alg" --dataset "mrclam:$mrclam:2" --particles 30 --json "$work/$alg.json" \
    --plot "$work/$alg.svg" --trajectory "$work/$alg.tum" >"$work/$alg.txt" 2>&1 || fail "$alg on MRCLAM failed: $(cat "$work/$alg.txt")"
  grep -q "scan 1000/" "$work/$alg.txt" || fail "$alg: no progress lines"
  grep -q "<svg" "$work/$alg.svg" || fail "$alg: no SVG"
  python3 - "$work/$alg.json" "$work/$alg.tum" <<'PY' || fail "$alg: JSON or trajectory wrong"
import json, math, sys
j = json.load(open(sys.argv[1]))
for k in ["rmse_position", "rmse_heading", "anees", "anees_bounds", "fraction_in_bounds", "time_per_step_ms", "landmarks", "runs"]:
    assert k in j, k
assert j["runs"] == 1 and j["landmarks"] == 15 and j["finite"], j
assert set(j["time_per_step_ms"]) == {"mean", "max"}
assert math.isfinite(j["rmse_position"]) and j["rmse_position"] < j["dead_reckoning_rmse_position"], j
poses = [l for l in open(sys.argv[2]) if not l.startswith("#")]
assert len(poses) == j["scans"], (len(poses), j["scans"])
PY
done
"$slamkit" report "$work/ekf.json" "$work/fastslam2.json" -o "$work/r.html" >/dev/null 2>&1 || fail "report refused the dataset JSON"
echo "filter --dataset CLI: all checks passed"
