#!/usr/bin/env bash
# End-to-end checks of `slamkit eval` and `slamkit report`: exit codes, error messages with
# file:line:field, the JSON document, and evo's KITTI 00 numbers through the command line.
#
# usage: cli_test.sh SLAMKIT_BINARY SOURCE_DIR WORK_DIR
set -uo pipefail

slamkit=$1
source_dir=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
cd "$work" || exit 1
failures=0

fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}

# expect CODE PATTERN -- command...: exit code and a pattern in stdout+stderr.
expect() {
  local code=$1 pattern=$2
  shift 3
  local out
  out=$("$@" 2>&1)
  local got=$?
  [[ $got -eq $code ]] || fail "'$*' exited $got, expected $code: $out"
  [[ -z "$pattern" ]] || grep -qE -- "$pattern" <<< "$out" || fail "'$*' output lacks /$pattern/: $out"
}

# Small synthetic trajectories (a square loop), TUM and EuRoC formats.
python3 - << 'EOF' || exit 1
import math
with open("ref.txt", "w") as r, open("est.txt", "w") as e, open("ref.csv", "w") as c:
    c.write("#timestamp [ns],x,y,z,qw,qx,qy,qz\n")
    for k in range(400):
        t = 100.0 + 0.05 * k
        a = 0.02 * k
        x, y, z = 5 * math.cos(a), 3 * math.sin(2 * a), 0.1 * math.sin(a)
        qw, qz = math.cos(a / 2), math.sin(a / 2)
        r.write(f"{t:.6f} {x} {y} {z} 0 0 {qz} {qw}\n")
        c.write(f"{round(t * 1e9)},{x},{y},{z},{qw},0,0,{qz}\n")
        if k % 2 == 0:
            e.write(f"{t + 0.002:.6f} {x + 0.05 * math.sin(5 * a)} {y} {z + 0.02} 0 0 {qz} {qw}\n")
EOF
printf '100.0 0 0 0 0 0 0 1\n100.1 0 0 x 0 0 0 1\n' > bad.txt

expect 0 "APE w.r.t. translation part" -- "$slamkit" eval ate est.txt ref.txt --json ate.json --plot ate.svg
expect 0 "matched +200 poses by timestamp" -- "$slamkit" eval ate est.txt ref.csv --ref-format euroc
expect 0 "pairs +[0-9]+" -- "$slamkit" eval rpe est.txt ref.txt --delta 1 --delta-unit m --all-pairs
expect 0 "Sim\\(3\\)" -- "$slamkit" eval ate est.txt ref.txt --align sim3 -r angle_deg
expect 0 "4-DoF" -- "$slamkit" eval ate est.txt ref.txt --align 4dof
expect 0 "" -- "$slamkit" eval rpe est.txt ref.txt --delta 0.5 --delta-unit s --json rpe.json
expect 1 "bad.txt:2: field 'tz': not a number" -- "$slamkit" eval ate bad.txt ref.txt
expect 1 "no matching timestamps" -- "$slamkit" eval ate est.txt ref.txt --t-offset 1000
expect 1 "no pairs" -- "$slamkit" eval rpe est.txt ref.txt --delta 1000 --delta-unit m
expect 2 "" -- "$slamkit" eval ate est.txt ref.txt --align affine
expect 2 "" -- "$slamkit" eval ate missing.txt ref.txt
expect 2 "" -- "$slamkit" eval rpe est.txt ref.txt --delta-unit km

# The JSON document (schema in docs/evaluation.md) and --json - on stdout.
python3 - << 'EOF' || fail "ate.json/rpe.json schema"
import json
a = json.load(open("ate.json"))
for k in ("kind", "label", "rmse", "mean", "median", "std", "min", "max", "sse", "pairs", "alignment",
          "association", "estimate", "reference", "options", "series", "translation", "rotation"):
    assert k in a, k
assert a["kind"] == "ate" and a["label"] == "est.txt" and a["pairs"] == 200
assert a["alignment"]["mode"] == "se3" and a["association"]["matched"] == 200
assert len(a["series"]["error"]) == 200 == len(a["series"]["est_xyz"])
r = json.load(open("rpe.json"))
assert r["kind"] == "rpe" and r["options"]["delta_unit"] == "s" and r["alignment"]["mode"] == "none"
assert len(r["series"]["pair_first"]) == r["pairs"]
EOF
"$slamkit" eval ate est.txt ref.txt --json - 2> /dev/null | python3 -c "import json,sys; assert json.load(sys.stdin)['kind'] == 'ate'" \
  || fail "--json - does not print a JSON document on stdout"
grep -q "<polyline" ate.svg || fail "ate.svg has no polyline"

# Report: eval runs and an optimizer summary; unknown kinds are errors.
expect 0 "wrote report.html" -- "$slamkit" report ate.json rpe.json "$source_dir/tests/eval/data/optimize_example.json" -o report.html
grep -q "<svg" report.html || fail "report.html has no svg"
echo '{"kind": "particle-cloud", "label": "ekf"}' > unknown.json
expect 1 "unknown.json: field 'kind': unknown kind" -- "$slamkit" report unknown.json -o r.html
echo '{"kind": "ate"' > broken.json
expect 1 "broken.json: not valid JSON" -- "$slamkit" report broken.json -o r.html

# evo's stored KITTI 00 results through the command line (skipped without the dataset).
data=${SLAMKIT_DATA:-../shared/datasets}
[[ "$data" = /* ]] || data="$source_dir/$data"
kitti="$data/vio/eval_reference"
if [[ -f "$kitti/KITTI_00_gt.txt" ]]; then
  "$slamkit" eval ate "$kitti/KITTI_00_ORB.txt" "$kitti/KITTI_00_gt.txt" --format kitti --align se3 --json kitti_ate.json > /dev/null
  "$slamkit" eval rpe "$kitti/KITTI_00_ORB.txt" "$kitti/KITTI_00_gt.txt" --delta 10 --delta-unit m --json kitti_rpe.json > /dev/null
  python3 - << 'EOF' || fail "KITTI numbers differ from evo's"
import json
for name, ref in (("kitti_ate.json", 1.3034497145650266), ("kitti_rpe.json", 0.22626134329310163)):
    got = json.load(open(name))["rmse"]
    assert abs(got - ref) <= 1e-6 * ref, (name, got, ref)
EOF
elif [[ "${CI:-}" == "true" ]]; then
  fail "dataset missing under CI: $kitti"
else
  echo "SKIPPED (KITTI part): dataset not found: $kitti"
fi

[[ $failures -eq 0 ]] || { echo "$failures check(s) failed"; exit 1; }
echo "all CLI checks passed"
