#!/usr/bin/env bash
# slamkit compare and the relaxer options of slamkit optimize through the binary: ranked table,
# JSON per back end, SVG, the report reading the comparison, --init toro, --solver hogman, and
# clear errors with exit code 1.
set -uo pipefail
slamkit=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$slamkit" compare sim:manhattan --solvers gn,sgd,toro,relax,mlr,hogman --time-budget 2 --json "$work/c.json" \
  --plot "$work/c.svg" >"$work/out.txt" 2>&1 || fail "compare exited non-zero: $(cat "$work/out.txt")"
grep -q "rank solver" "$work/out.txt" || fail "no ranked table"
grep -q "<svg" "$work/c.svg" || fail "no SVG"
python3 - "$work/c.json" <<'PY' || fail "compare JSON lacks keys"
import json, sys, math
j = json.load(open(sys.argv[1]))
assert j["kind"] == "compare" and len(j["runs"]) == 6, j.keys()
for r in j["runs"]:
    for k in ["solver", "final_chi2", "time_total_s", "iterations", "trace"]:
        assert k in r, (r["solver"], k)
    assert all(len(t) == 2 and math.isfinite(t[1]) for t in r["trace"]), r["solver"]
    assert r["final_chi2"] <= r["trace"][0][1], r["solver"]
PY
"$slamkit" report "$work/c.json" -o "$work/r.html" >/dev/null 2>&1 || fail "report refused the compare JSON"
grep -q "toro" "$work/r.html" || fail "report lacks the back ends"

"$slamkit" optimize sim:manhattan --init toro --solver lm -q --json "$work/o.json" >/dev/null 2>&1 || fail "--init toro failed"
"$slamkit" optimize sim:manhattan --solver hogman -q --json "$work/h.json" >/dev/null 2>&1 || fail "--solver hogman failed"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert j['solver']=='hogman' and j['final_chi2']<j['initial_chi2']" \
  "$work/h.json" || fail "hogman JSON"

"$slamkit" compare sim:manhattan --solvers gn,nope >"$work/err.txt" 2>&1
[[ $? -eq 1 ]] || fail "unknown back end did not exit 1"
grep -q "unknown back end 'nope'" "$work/err.txt" || fail "no clear message: $(cat "$work/err.txt")"
printf 'VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\nVERTEX_SE2 2 2 0 0\nVERTEX_SE2 3 3 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 1 0 1\nEDGE_SE2 2 3 1 0 0 1 0 0 1 0 1\n' >"$work/split.g2o"
"$slamkit" optimize "$work/split.g2o" --init sgd >"$work/err2.txt" 2>&1
[[ $? -eq 1 ]] || fail "disconnected graph did not exit 1"
grep -q "connected components" "$work/err2.txt" || fail "no clear message: $(cat "$work/err2.txt")"
echo "compare CLI ok"
