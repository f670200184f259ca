#!/usr/bin/env bash
# DVI back end at feature level (issue 13 part 2): slamkit simulate --vi SEQ --dynamic low|high,
# then slamkit vio in baseline mode (--dvi off: dynamic features used as static, α = 1) and in
# DVI mode (--dvi on, the simulator's static/dynamic labels as the classifier), seeds 1..N;
# summary (median, mean, min, max of ATE RMSE, static ratio, visual frames dropped) in
# bench/results/vio_dvi_sim.json.
# Usage: bench/vio_dvi_sim.sh [BUILD_DIR] [SEEDS] [DURATION_S] [SEQUENCE] ["DVI OPTIONS"]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../build}
seeds=${2:-3}
duration=${3:-30}
seq=${4:-room1}
dvi_args=${5:---alpha M --theta 0.5}
slamkit=$build/bin/slamkit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for level in low high; do
  for seed in $(seq 1 "$seeds"); do
    name=${seq//:/_}_${level}_$seed
    "$slamkit" simulate --vi "$seq" --seed "$seed" --dynamic "$level" --duration "$duration" -o "$work/$name.sim" >/dev/null 2>&1
    "$slamkit" vio --sim "$work/$name.sim" --quiet --dvi off --json "$work/$name.baseline.json" | tail -1 | sed "s/^/$level seed $seed baseline: /"
    # shellcheck disable=SC2086
    "$slamkit" vio --sim "$work/$name.sim" --quiet --dvi on $dvi_args --json "$work/$name.dvi.json" | tail -1 | sed "s/^/$level seed $seed dvi: /"
  done
done
python3 - "$work" "$here/results/vio_dvi_sim.json" "$seeds" "$duration" "$seq" "$dvi_args" <<'PY'
import json, sys, glob, os, statistics as st
work, out, seeds, duration, seq, dvi_args = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5], sys.argv[6]
def stats(v): return {"median": st.median(v), "mean": st.mean(v), "min": min(v), "max": max(v)}
summary = {"sequence": seq, "seeds": seeds, "duration_s": duration, "dvi_args": dvi_args,
           "classifier": "simulator labels (SimLabelClassifier)", "levels": {}}
for level in ("low", "high"):
    lv = {}
    for mode in ("baseline", "dvi"):
        runs = [json.load(open(f)) for f in sorted(glob.glob(os.path.join(work, f"*_{level}_*.{mode}.json")))]
        lv[mode] = {"ate_rmse_m": stats([r["ate_rmse"] for r in runs]),
                    "static_ratio": {"mean": st.mean(r["static_ratio"]["mean"] for r in runs),
                                     "min": min(r["static_ratio"]["min"] for r in runs)},
                    "visual_frames_dropped": st.mean(r["visual_frames_dropped"] for r in runs),
                    "realtime_factor_cpu": st.mean(r["realtime_factor_cpu"] for r in runs),
                    "runs": [{"seed": r["vio"]["seed"], "ate_rmse": r["ate_rmse"],
                              "visual_frames_dropped": r["visual_frames_dropped"]} for r in runs]}
    b, d = lv["baseline"]["ate_rmse_m"]["mean"], lv["dvi"]["ate_rmse_m"]["mean"]
    lv["dvi_vs_baseline_mean_ate_change"] = (d - b) / b
    summary["levels"][level] = lv
json.dump(summary, open(out, "w"), indent=1)
print("wrote", out)
PY
