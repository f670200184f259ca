#!/usr/bin/env bash
# slamkit simulate --images through the binary: a short rendered room1 sequence in the
# EuRoC/ASL layout (images, labels, IMU, ground truth, calibration, objects), labels present
# with --dynamic high, same seed → same images; an unwritable folder and an unknown sequence
# fail at once with exit code 1. Exit 77 (skipped) without the datasets, except under CI=true.
set -uo pipefail
slamkit=$1
root=$2
source "$root/tests/cli/dataset.sh" "$root"
require_data vio
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$slamkit" simulate --vi room1 --duration 2 --dynamic high --seed 2 --data "$data" --images "$work/a" --threads 2 \
  --json "$work/a.json" >"$work/out.txt" 2>"$work/err.txt" || fail "simulate --images: $(cat "$work/err.txt")"
grep -q "ms/frame rendering" "$work/out.txt" || fail "no rendering summary: $(cat "$work/out.txt")"
grep -q "ms/frame render" "$work/err.txt" || fail "no progress line"
for f in mav0/cam0/data.csv mav0/labels0/data.csv mav0/imu0/data.csv mav0/state_groundtruth_estimate0/data.csv \
         times.txt objects.csv camchain.yaml imu.yaml groundtruth.tum; do
  [[ -s $work/a/$f ]] || fail "missing $f"
done
frames=$(wc -l <"$work/a/times.txt")
[[ $frames -ge 38 && $frames -le 42 ]] || fail "expected ~41 frames at 20 Hz, got $frames"
[[ $(ls "$work/a/mav0/cam0/data" | wc -l) -eq $frames ]] || fail "cam0 PNG count"
[[ $(ls "$work/a/mav0/labels0/data" | wc -l) -eq $frames ]] || fail "labels0 PNG count"
python3 - "$work/a.json" "$work/a" <<'PY' || fail "JSON or layout"
import json, sys, os
j = json.load(open(sys.argv[1]))
assert j["images"]["frames"] == j["frames"] and j["images"]["render_ms_per_frame"] > 0, j
cam = [l.split(",") for l in open(os.path.join(sys.argv[2], "mav0/cam0/data.csv")) if not l.startswith("#")]
times = [l.strip() for l in open(os.path.join(sys.argv[2], "times.txt"))]
assert [c[0] for c in cam] == times, "cam0 stamps != times.txt"
assert all(c[1].strip() == c[0] + ".png" for c in cam)
PY
# Same seed, same images.
"$slamkit" simulate --vi room1 --duration 2 --dynamic high --seed 2 --data "$data" --images "$work/b" --threads 1 \
  >/dev/null 2>&1 || fail "rerun"
first=$(head -1 "$work/b/times.txt")
cmp -s "$work/a/mav0/cam0/data/$first.png" "$work/b/mav0/cam0/data/$first.png" || fail "same seed, other image"
# Bad input: unwritable folder (a file in the way), unknown sequence; both before any work.
touch "$work/file"
"$slamkit" simulate --vi room1 --data "$data" --images "$work/file/x" >/dev/null 2>"$work/err2.txt"
[[ $? -eq 1 ]] || fail "unwritable folder: exit code"
grep -q "images" "$work/err2.txt" || fail "unwritable folder: message $(cat "$work/err2.txt")"
"$slamkit" simulate --vi room9 --data "$data" --images "$work/c" >/dev/null 2>"$work/err3.txt"
[[ $? -eq 1 ]] || fail "unknown sequence: exit code"
grep -q "unknown sequence" "$work/err3.txt" || fail "unknown sequence: message $(cat "$work/err3.txt")"
"$slamkit" simulate --vi room1 --data "$data" >/dev/null 2>&1
[[ $? -eq 1 ]] || fail "no output: exit code"
echo "PASS"
