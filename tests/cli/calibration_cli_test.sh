#!/usr/bin/env bash
# slamkit optimize with calibration variables, through the binary: JSON `calibration` and
# `calibration_truth`, the unobservable warning, -o round trip, strict errors.
set -uo pipefail
slamkit=$1 source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# 1. sim:calib2d: estimates with sigmas, truth within 4 sigma.
"$slamkit" optimize sim:calib2d --json "$work/run.json" -o "$work/out.g2o" -q >"$work/out.txt" 2>&1 ||
  fail "sim:calib2d exited non-zero: $(cat "$work/out.txt")"
grep -q "odometry\[518\].baseline" "$work/out.txt" || fail "no calibration table printed"
python3 - "$work/run.json" <<'PY' || fail "calibration JSON wrong"
import json, sys
j = json.load(open(sys.argv[1]))
truth = {t["name"]: t["value"] for t in j["calibration_truth"]}
assert len(j["calibration"]) == 6, j["calibration"]
for c in j["calibration"]:
    assert set(["name", "value", "sigma"]) <= set(c), c
    assert abs(c["value"] - truth[c["name"]]) < 4 * c["sigma"], c
assert not j["calibration_warnings"], j["calibration_warnings"]
PY
# 2. The written graph carries the sclam2d tags and reads back.
grep -q "^VERTEX_ODOM_DIFFERENTIAL " "$work/out.g2o" || fail "no VERTEX_ODOM_DIFFERENTIAL written"
grep -q "^EDGE_SE2_CALIB " "$work/out.g2o" || fail "no EDGE_SE2_CALIB written"
"$slamkit" optimize "$work/out.g2o" -q --json "$work/again.json" >/dev/null 2>&1 || fail "written graph does not optimize"
# 3. Calibration off: a clearly higher chi2.
"$slamkit" optimize sim:calib2d --calibrate none --json "$work/off.json" -q >/dev/null 2>&1 || fail "--calibrate none failed"
python3 - "$work/run.json" "$work/off.json" <<'PY' || fail "calibration off does not raise chi2"
import json, sys
on, off = (json.load(open(p))["final_chi2"] for p in sys.argv[1:3])
assert off > 3 * on, (on, off)
PY
# 4. A straight line: the warning names the baseline.
"$slamkit" optimize "sim:calib2d?path=line" -q >"$work/line.txt" 2>&1 || fail "straight line exited non-zero"
grep -q "odometry\[518\].baseline is unobservable" "$work/line.txt" || fail "no unobservable warning: $(cat "$work/line.txt")"
# 5. Strict input: a missing offset vertex names file, line and field; bad --calibrate is refused.
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nEDGE_SE2_CALIB 0 1 9 1 0 0 1 0 0 1 0 1\n' >"$work/bad.g2o"
"$slamkit" optimize "$work/bad.g2o" -q >"$work/bad.txt" 2>&1 && fail "bad file accepted"
grep -q "bad.g2o:3" "$work/bad.txt" || fail "error does not name the line: $(cat "$work/bad.txt")"
grep -q "offset_id" "$work/bad.txt" || fail "error does not name the field: $(cat "$work/bad.txt")"
"$slamkit" optimize sim:calib2d --calibrate wheels -q >/dev/null 2>&1 && fail "--calibrate wheels accepted"
# 6. Every calibration tag (the fuzz seeds), priors included, reads and optimizes.
"$slamkit" optimize "$source_dir/tests/fuzz/seeds/g2o/calibration_2d.g2o" -q >"$work/seed2.txt" 2>&1 ||
  fail "2D seed failed: $(cat "$work/seed2.txt")"
grep -q "odometry\[11\].k_left" "$work/seed2.txt" && grep -q "offset\[10\].theta" "$work/seed2.txt" &&
  grep -q "odometry_linear\[12\].K11" "$work/seed2.txt" || fail "2D seed: calibration table incomplete"
"$slamkit" optimize "$source_dir/tests/fuzz/seeds/g2o/calibration_3d.g2o" --calibrate offset -q >"$work/seed3.txt" 2>&1 ||
  fail "3D seed failed: $(cat "$work/seed3.txt")"
grep -q "params_se3offset\[0\]" "$work/seed3.txt" || fail "3D seed: no offset estimate"
echo "calibration CLI: all checks passed"
