#!/usr/bin/env bash
# slamkit optimize through the binary: JSON summary, errors and exit codes, and the chain
# optimize --trajectory → eval ate against ground truth. Exit 77 = skipped (no dataset).
set -uo pipefail
slamkit=$1 source_dir=$2
source "$(dirname "$0")/dataset.sh" "$source_dir"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# 1. Built-in graph, JSON with the documented keys.
"$slamkit" optimize sim:manhattan --json "$work/run.json" -q >"$work/out.txt" 2>&1 || fail "sim:manhattan exited non-zero: $(cat "$work/out.txt")"
python3 - "$work/run.json" <<'PY' || fail "summary JSON lacks keys"
import json, sys
j = json.load(open(sys.argv[1]))
need = ["initial_chi2", "final_chi2", "iterations", "linear_solves", "time_total_s", "time_linear_solver_s",
        "solver", "init", "linear_solver", "threads", "termination", "trace", "kind"]
missing = [k for k in need if k not in j]
assert not missing, missing
assert j["final_chi2"] < j["initial_chi2"] and j["solver"] == "gn" and j["init"] == "linear", j
PY
grep -q "termination" "$work/out.txt" || fail "no summary printed"

# 1b. BLAS kernels: the CLI never runs OpenBLAS's generic fallback when the CPU supports better
#     (it restarts itself with OPENBLAS_CORETYPE); a forced generic core type is respected and
#     reported with the better one.
"$slamkit" optimize sim:manhattan --json "$work/blas.json" -q >/dev/null 2>&1 || fail "sim:manhattan (blas) failed"
OPENBLAS_CORETYPE=Prescott "$slamkit" optimize sim:manhattan --json "$work/forced.json" -q >/dev/null 2>&1 ||
  fail "sim:manhattan with OPENBLAS_CORETYPE=Prescott failed"
python3 - "$work/blas.json" "$work/forced.json" <<'PY' || fail "BLAS kernel selection"
import json, sys
auto, forced = (json.load(open(p)) for p in sys.argv[1:3])
assert auto["blas_better_core"] == "", auto["blas"]
if forced["blas"].startswith("OpenBLAS"):
    assert forced["blas"] == "OpenBLAS Prescott", forced["blas"]
    flags = open("/proc/cpuinfo").read()
    if " avx2 " in flags and " fma " in flags:
        assert forced["blas_better_core"] in ("Haswell", "SkylakeX"), forced
PY

# 2. Errors: non-zero exit, message names the problem.
"$slamkit" optimize "$work/missing.g2o" >"$work/err.txt" 2>&1 && fail "missing file accepted"
grep -q "missing.g2o" "$work/err.txt" || fail "missing-file message does not name the file"
"$slamkit" optimize sim:manhattan --solver magic >"$work/err.txt" 2>&1 && fail "unknown solver accepted"
grep -q "unknown solver 'magic'" "$work/err.txt" || fail "unknown-solver message: $(cat "$work/err.txt")"
"$slamkit" optimize sim:manhattan --robust huber >"$work/err.txt" 2>&1 && fail "robust spec without delta accepted"
for bad in -1 nan; do
  "$slamkit" optimize sim:manhattan --keep-estimates-chi2-per-dof "$bad" >"$work/err.txt" 2>&1 && fail "--keep-estimates-chi2-per-dof $bad accepted"
  grep -q "keep_estimates_chi2_per_dof" "$work/err.txt" || fail "keep-estimates message: $(cat "$work/err.txt")"
done
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 nan\n' >"$work/nan.g2o"
"$slamkit" optimize "$work/nan.g2o" >"$work/err.txt" 2>&1 && fail "NaN accepted"
grep -q "nan.g2o:2" "$work/err.txt" || fail "NaN message lacks file:line: $(cat "$work/err.txt")"

# 3. Dataset checks (skip when the data is not there, unless CI).
require_data posegraph
"$slamkit" optimize "$data/posegraph/3d/cubicle.g2o" -q >"$work/err.txt" 2>&1 && fail "indefinite information accepted"
grep -q -- "--repair-information" "$work/err.txt" || fail "no repair hint: $(cat "$work/err.txt")"
# intel.g2o's own estimates fit its measurements (chi2/dof 0.23): init auto keeps them; 0 forces LAGO.
"$slamkit" optimize "$data/posegraph/2d/intel.g2o" --json "$work/intel.json" -q >/dev/null 2>&1 || fail "intel failed"
"$slamkit" optimize "$data/posegraph/2d/intel.g2o" --keep-estimates-chi2-per-dof 0 --json "$work/intel0.json" -q >/dev/null 2>&1 ||
  fail "intel with --keep-estimates-chi2-per-dof 0 failed"
python3 - "$work/intel.json" "$work/intel0.json" <<'PY' || fail "intel's start"
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
assert a["init"] == "none" and a["init_requested"] == "auto" and b["init"] == "linear", (a["init"], b["init"])
assert abs(a["final_chi2"] - b["final_chi2"]) < 1e-7 * b["final_chi2"], (a["final_chi2"], b["final_chi2"])
PY
# Ground truth of sphere2500: its noise-free measurements composed along the odometry.
"$slamkit" optimize "$data/posegraph/3d/gtsam_txt/sphere2500_groundtruth.txt" --init none --max-iterations 0 \
  --trajectory "$work/gt.tum" -q >/dev/null 2>&1 || fail "ground-truth export failed"
"$slamkit" optimize "$data/posegraph/3d/sphere2500.g2o" --trajectory "$work/est.tum" -q >/dev/null 2>&1 || fail "sphere2500 failed"
"$slamkit" eval ate "$work/est.tum" "$work/gt.tum" --align se3 --json "$work/ate.json" >/dev/null || fail "eval of the trajectory failed"
python3 - "$work/ate.json" <<'PY' || fail "ATE of sphere2500 out of range"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["pairs"] == 2500 and 0.05 < j["rmse"] < 0.5, (j["pairs"], j["rmse"])
print("sphere2500 ATE rmse %.4f m over %d poses" % (j["rmse"], j["pairs"]))
PY
echo "PASS"
