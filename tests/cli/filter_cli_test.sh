#!/usr/bin/env bash
# slamkit filter through the binary: outputs checked before the work, bad options fail with a
# clear message and exit 1, a small generated world runs every built filter, the JSON has the
# issue's keys and `slamkit report` shows the filter runs side by side. Needs no dataset.
set -uo pipefail
slamkit=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

# 1. Unwritable outputs fail before any run starts.
for opt in --json --plot --trajectory; do
  "$slamkit" filter --algorithm ekf --world generated:30 --steps 400 "$opt" /no/such/dir/x >"$work/out.txt" 2>&1 \
    && fail "filter $opt to a missing dir succeeded"
  grep -q "/no/such/dir/x" "$work/out.txt" || fail "filter $opt: message does not name the path: $(cat "$work/out.txt")"
  grep -q "runs \[" "$work/out.txt" && fail "filter $opt: runs started before the output check"
done

# 2. Bad input: exit code 1 and a message naming the field.
"$slamkit" filter --algorithm ekf --world generated:abc >"$work/out.txt" 2>&1; [[ $? == 1 ]] || fail "generated:abc exit code"
grep -q "generated:N" "$work/out.txt" || fail "generated:abc message: $(cat "$work/out.txt")"
"$slamkit" filter --algorithm ekf --world "$work/missing.txt" >"$work/out.txt" 2>&1 && fail "missing map accepted"
printf '#type columns rows\nlm 2 2\n1 2\nnan 4\n\nwp 2 1\n5 6\n' >"$work/bad.txt"
"$slamkit" filter --algorithm ekf --world "$work/bad.txt" >"$work/out.txt" 2>&1; [[ $? == 1 ]] || fail "bad map exit code"
grep -q "bad.txt:4" "$work/out.txt" || fail "bad map: no file:line in $(cat "$work/out.txt")"
"$slamkit" filter --algorithm fastslam2 --association jcbb --world generated:30 >"$work/out.txt" 2>&1; [[ $? == 1 ]] || fail "fastslam2 jcbb exit code"
grep -q "known or nn" "$work/out.txt" || fail "fastslam2 jcbb message: $(cat "$work/out.txt")"
"$slamkit" filter --algorithm seif --active 0 --world generated:30 >"$work/out.txt" 2>&1 && fail "--active 0 accepted"

# 3. Every built filter on a small world; JSON keys of the issue; report side by side.
for alg in ekf eif seif seif-entropy fastslam1 fastslam2; do
  "$slamkit" filter --algorithm "$alg" --world generated:30 --steps 1200 --runs 4 --active 4 --particles 30 \
    --json "$work/$alg.json" --plot "$work/$alg.svg" --trajectory "$work/$alg.tum" >"$work/$alg.txt" 2>&1 \
    || fail "$alg run failed: $(cat "$work/$alg.txt")"
  grep -q "ANEES" "$work/$alg.txt" || fail "$alg: no summary"
  for key in rmse_position rmse_heading anees anees_bounds fraction_in_bounds time_per_step_ms landmarks runs; do
    grep -q "\"$key\"" "$work/$alg.json" || fail "$alg JSON lacks $key"
  done
  grep -q '"mean"' "$work/$alg.json" || fail "$alg: time_per_step_ms has no mean"
  grep -q "<svg" "$work/$alg.svg" || fail "$alg: no SVG"
  [[ $(grep -vc '^#' "$work/$alg.tum") == 150 ]] || fail "$alg: trajectory has $(grep -vc '^#' "$work/$alg.tum") poses, expected 150"
done
"$slamkit" report "$work"/ekf.json "$work"/seif.json "$work"/seif-entropy.json -o "$work/r.html" >/dev/null 2>&1 \
  || fail "report on filter runs failed"
grep -q "Landmark-SLAM filters" "$work/r.html" || fail "report has no filter section"
grep -q "seif-entropy" "$work/r.html" || fail "report does not list entropy-SEIF"
echo '{"kind": "filter", "runs": 3}' >"$work/broken.json"
"$slamkit" report "$work/broken.json" -o "$work/r2.html" >"$work/out.txt" 2>&1 && fail "broken filter JSON accepted"
grep -q "broken.json" "$work/out.txt" || fail "broken filter JSON message: $(cat "$work/out.txt")"
echo "filter CLI: all checks passed"
