#!/usr/bin/env bash
# Outputs through the binary: every output path is checked before the work starts; files are
# replaced atomically (a failed or killed run leaves the previous file intact); an empty graph
# says so; the settings a run echoes ("config") are a valid --config. Needs no dataset.
set -uo pipefail
slamkit=$1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
big='sim:manhattan?poses=20000'

# 1. An unwritable output fails at once: before loading (no "loaded" line, no iterations).
for opt in "-o" "--json" "--trajectory"; do
  ext=$([[ $opt == -o ]] && echo g2o || echo out)
  "$slamkit" optimize "$big" "$opt" /no/such/dir/out.$ext >"$work/out.txt" 2>&1 && fail "optimize $opt to a missing dir succeeded"
  grep -q "/no/such/dir/out.$ext" "$work/out.txt" || fail "optimize $opt: message does not name the path: $(cat "$work/out.txt")"
  grep -q "loaded\|iter" "$work/out.txt" && fail "optimize $opt: work started before the output check: $(cat "$work/out.txt")"
done
"$slamkit" optimize "$big" -o "$work/out.unknown" >"$work/out.txt" 2>&1 && fail "unknown output extension accepted"
grep -q "loaded" "$work/out.txt" && fail "unknown output extension found only after the work"
"$slamkit" optimize "$big" --json "$work" >"$work/out.txt" 2>&1 && fail "a directory as --json accepted"
grep -q "is a directory" "$work/out.txt" || fail "directory message: $(cat "$work/out.txt")"
"$slamkit" convert "$big" /no/such/dir/x.g2o >"$work/out.txt" 2>&1 && fail "convert to a missing dir succeeded"
grep -q "/no/such/dir/x.g2o" "$work/out.txt" || fail "convert message: $(cat "$work/out.txt")"
"$slamkit" info "$big" --json /no/such/dir/i.json >"$work/out.txt" 2>&1 && fail "info --json to a missing dir succeeded"
grep -q "vertices" "$work/out.txt" && fail "info worked before the output check"
printf '0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 1 1 0 0 0 0 1\n3 2 1 1 0 0 0 1\n' >"$work/t.tum"
for opt in "--json" "--plot"; do
  "$slamkit" eval ate "$work/t.tum" "$work/t.tum" "$opt" /no/such/dir/e >"$work/out.txt" 2>&1 && fail "eval $opt to a missing dir succeeded"
  grep -q "rmse" "$work/out.txt" && fail "eval $opt evaluated before the output check"
done
"$slamkit" eval ate "$work/t.tum" "$work/t.tum" --json "$work/ate.json" >/dev/null 2>&1 || fail "eval ate failed"
"$slamkit" report "$work/ate.json" -o /no/such/dir/r.html >"$work/out.txt" 2>&1 && fail "report to a missing dir succeeded"
grep -q "/no/such/dir/r.html" "$work/out.txt" || fail "report message: $(cat "$work/out.txt")"

for opt in "--json" "--plot"; do
  "$slamkit" compare "$big" "$opt" /no/such/dir/c >"$work/out.txt" 2>&1 && fail "compare $opt to a missing dir succeeded"
  grep -q "rank" "$work/out.txt" && fail "compare $opt ran before the output check"
done
"$slamkit" optimize 'sim:ba?cameras=20&points=200' --ply /no/such/dir/p.ply >"$work/out.txt" 2>&1 && fail "--ply to a missing dir succeeded"
grep -q "/no/such/dir/p.ply" "$work/out.txt" || fail "--ply message: $(cat "$work/out.txt")"
grep -q "iter" "$work/out.txt" && fail "bundle adjustment ran before the --ply check"

# 2. An empty graph says that it is empty.
: >"$work/empty.g2o"
"$slamkit" optimize "$work/empty.g2o" >"$work/out.txt" 2>&1 && fail "empty graph optimized"
grep -q "no vertices and no edges" "$work/out.txt" || fail "empty-graph message: $(cat "$work/out.txt")"
grep -q "empty.g2o" "$work/out.txt" || fail "empty-graph message does not name the file"

# 3. The settings echoed in a run's JSON ("config") are a valid --config that reproduces the run.
"$slamkit" optimize 'sim:manhattan?poses=300' --solver lm --max-iterations 7 --json "$work/run.json" -q >/dev/null 2>&1 || fail "lm run failed"
python3 -c "import json,sys; json.dump(json.load(open(sys.argv[1]))['config'], open(sys.argv[2],'w'))" "$work/run.json" "$work/cfg.json" || fail "no config in the JSON"
"$slamkit" optimize 'sim:manhattan?poses=300' --config "$work/cfg.json" --json "$work/again.json" -q >/dev/null 2>&1 || fail "--config from the echoed config failed"
python3 - "$work/run.json" "$work/again.json" <<'PY' || fail "config did not reproduce the run"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["config"] == b["config"] and a["solver"] == b["solver"] == "lm", (a["config"], b["config"])
assert a["final_chi2"] == b["final_chi2"], (a["final_chi2"], b["final_chi2"])
PY
printf '{\n  "solver": "gn",\n  "max_iterations": 1.5\n}\n' >"$work/bad.json"
"$slamkit" optimize sim:manhattan --config "$work/bad.json" >"$work/out.txt" 2>&1 && fail "fractional max_iterations accepted"
grep -q "bad.json:3: field 'max_iterations'" "$work/out.txt" || fail "config message lacks file:line:field: $(cat "$work/out.txt")"

# 4. A write that fails (full disk, simulated by a file-size limit) keeps the previous file.
"$slamkit" convert 'sim:manhattan?poses=50' "$work/keep.g2o" >/dev/null 2>&1 || fail "small convert failed"
cp "$work/keep.g2o" "$work/keep.orig"
( trap '' XFSZ; ulimit -f 64; exec "$slamkit" convert "$big" "$work/keep.g2o" ) >"$work/out.txt" 2>&1 && fail "write beyond the size limit succeeded"
grep -q "previous file kept" "$work/out.txt" || fail "failed-write message: $(cat "$work/out.txt")"
cmp -s "$work/keep.g2o" "$work/keep.orig" || fail "a failed write changed the previous file"
[[ $(ls "$work" | grep -c 'keep.g2o.tmp') == 0 ]] || fail "a failed write left its temporary file"

# 5. Killed (SIGKILL) at moments spread over the run, most of them in its last part where it
#    writes: the output is always the old file or the complete new one, never a part.
"$slamkit" convert "$big" "$work/big.g2o" >/dev/null 2>&1 || fail "reference convert failed"
start=$(date +%s%N)
"$slamkit" convert "$work/big.g2o" "$work/full.g2o" >/dev/null 2>&1 || fail "reference convert failed"
run_ms=$(( ($(date +%s%N) - start) / 1000000 ))
old=0 new=0
for percent in 30 60 75 85 90 95 98 100 105 110; do
  cp "$work/keep.orig" "$work/kill.g2o"
  "$slamkit" convert "$work/big.g2o" "$work/kill.g2o" >/dev/null 2>&1 &
  pid=$!
  sleep "$(awk -v ms="$run_ms" -v p="$percent" 'BEGIN { printf "%.3f", ms * p / 100000 }')"
  kill -9 "$pid" 2>/dev/null; wait "$pid" 2>/dev/null
  if cmp -s "$work/kill.g2o" "$work/keep.orig"; then old=$((old + 1))
  elif cmp -s "$work/kill.g2o" "$work/full.g2o"; then new=$((new + 1))
  else fail "killed at ${percent}% of ${run_ms} ms: the output is neither the old nor the new file"; fi
done
echo "killed writers: $old left the old file, $new the new one, none half a file (run ${run_ms} ms)"
echo "PASS"
