#!/usr/bin/env bash
# Static-scene VIO acceptance (issue 12): `slamkit vio --sim SEQ --seed S` (simulated in memory,
# started by the visual-inertial initializer: no ground truth after the first frame) on TUM-VI
# room1-4 and EuRoC V1_01, V1_02, V2_03, seeds 1..N (default 5), at most JOBS (default 2) runs at
# a time, and the summary (median, mean, min, max of ATE RMSE; start-up; timing) in
# bench/results/vio_static.json (+ .md).
# Usage: bench/vio_static.sh [BUILD_DIR] [SEEDS] [DURATION_S (0: whole path)] [SEQUENCES...]
# Environment: JOBS (parallel runs, ≤ 2 on the shared machine), OUT (result basename),
#              VIO_ARGS (extra `slamkit vio` options; the speed figure "on 2 cores" is
#              JOBS=1 VIO_ARGS="--threads 2": one run at a time, both cores in its window solver).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../build}
seeds=${2:-5}
duration=${3:-0}
shift $(( $# < 3 ? $# : 3 ))
sequences=("$@")
[ ${#sequences[@]} -eq 0 ] && sequences=(room1 room2 room3 room4 euroc:V1_01 euroc:V1_02 euroc:V2_03)
jobs=${JOBS:-2}
out=${OUT:-$here/results/vio_static}
slamkit=$build/bin/slamkit
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export slamkit work duration
export VIO_ARGS=${VIO_ARGS:-}
load_start=$(cut -d' ' -f1 /proc/loadavg)
for seq in "${sequences[@]}"; do
  for seed in $(seq 1 "$seeds"); do echo "$seq $seed"; done
done | xargs -P "$jobs" -L 1 bash -c '
  seq=$0 seed=$1 name=${0//:/_}_$1
  if "$slamkit" vio --sim "$seq" --seed "$seed" --duration "$duration" --quiet $VIO_ARGS --json "$work/$name.json" \
       >"$work/$name.log" 2>&1; then
    grep -E "^(ATE|start-up)" "$work/$name.log" | sed "s/^/$seq seed $seed: /"
  else
    echo "{\"failed\": true, \"source\": \"$seq\", \"seed\": $seed, \"message\": $(tail -1 "$work/$name.log" | python3 -c "import json,sys; print(json.dumps(sys.stdin.read().strip()))")}" >"$work/$name.fail"
    echo "$seq seed $seed: FAILED: $(tail -1 "$work/$name.log")"
  fi'
load=$(cut -d' ' -f1 /proc/loadavg)  # timings on a shared machine: record its load
python3 - "$work" "$out" "$seeds" "$duration" "$VIO_ARGS" "$load" "$load_start" "$jobs" <<'PY'
import json, sys, glob, os, statistics as st
work, out, seeds, duration, args = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
rows, failed = {}, {}
for f in sorted(glob.glob(os.path.join(work, "*.json"))):
    j = json.load(open(f))
    rows.setdefault(j["vio"]["source"], []).append(j)
for f in sorted(glob.glob(os.path.join(work, "*.fail"))):
    j = json.load(open(f))
    failed.setdefault(j["source"], []).append({"seed": j["seed"], "message": j["message"]})
summary = {"seeds": seeds, "duration_s": duration or "whole path", "acceptance_ate_rmse_m": 0.05,
           "vio_args": args, "load_average_at_end": float(sys.argv[6]),
           "load_average_at_start": float(sys.argv[7]), "jobs": int(sys.argv[8]), "command": "bench/vio_static.sh BUILD %d %g" % (seeds, duration), "sequences": {}}
def stats(x):
    return {"median": st.median(x), "mean": st.mean(x), "min": min(x), "max": max(x)}
for src in sorted(set(rows) | set(failed)):
    runs = sorted(rows.get(src, []), key=lambda r: r["vio"]["seed"])
    e = {"runs_ok": len(runs), "runs_failed": failed.get(src, [])}
    if runs:
        ate = [r["ate_rmse"] for r in runs]
        ini = [r["initialization"] for r in runs]
        e.update({
            "ate_rmse_m": stats(ate),
            "rpe_rmse_1s_m": st.mean(r["rpe_rmse"] for r in runs),
            "initialization": {"method": ini[0]["method"],
                               "initialized_at_s": stats([r["initialized_at_s"] for r in runs]),
                               "attempts": stats([i["attempts"] for i in ini]),
                               "scale_error": stats([i["scale_error"] for i in ini]),
                               "gravity_error_deg": stats([i["gravity_error_deg"] for i in ini]),
                               "velocity_error_mps": stats([i["velocity_error_mps"] for i in ini])},
            "realtime_factor": {"min": min(r["realtime_factor"] for r in runs), "mean": st.mean(r["realtime_factor"] for r in runs)},
            "realtime_factor_cpu": {"min": min(r["realtime_factor_cpu"] for r in runs), "mean": st.mean(r["realtime_factor_cpu"] for r in runs)},
            "time_per_frame_ms": {"mean": st.mean(r["time_per_frame_ms"]["mean"] for r in runs),
                                  "max": max(r["time_per_frame_ms"]["max"] for r in runs)},
            "solve_time_per_frame_ms": st.mean(r["solve_time_per_frame_ms"]["mean"] for r in runs),
            "marginalization_time_per_frame_ms": st.mean(r["marginalization_time_per_frame_ms"]["mean"] for r in runs),
            "keyframes": st.mean(r["keyframes"] for r in runs),
            "features_per_frame": st.mean(r["features_per_frame"] for r in runs),
            "iterations_per_keyframe": st.mean(r.get("iterations_per_keyframe", 0) for r in runs),
            "solver": runs[0].get("solver", "generic"),
            "threads": runs[0].get("threads", 1),
            "runs": [{"seed": r["vio"]["seed"], "ate_rmse": r["ate_rmse"], "rpe_rmse": r["rpe_rmse"],
                      "initialized_at_s": r["initialized_at_s"], "realtime_factor": r["realtime_factor"],
                      "realtime_factor_cpu": r["realtime_factor_cpu"], "solve_ms": r["solve_time_per_frame_ms"]["mean"],
                      "marginalization_ms": r["marginalization_time_per_frame_ms"]["mean"]} for r in runs]})
    e["met"] = bool(runs) and not failed.get(src) and len(runs) == seeds and max(r["ate_rmse"] for r in runs) <= 0.05
    summary["sequences"][src] = e
json.dump(summary, open(out + ".json", "w"), indent=1)
with open(out + ".md", "w") as md:
    md.write("# VIO, static scene (`%s`)\n\n" % summary["command"])
    md.write("Duration: %s; seeds 1..%d; start-up: visual-inertial initializer unless stated; extra args: `%s`; "
             "%d runs at a time; load average %.1f at the start, %.1f at the end.\n\n"
             % (summary["duration_s"], seeds, args or "none", summary["jobs"], summary["load_average_at_start"],
                summary["load_average_at_end"]))
    md.write("| sequence | runs | ATE median [m] | mean | min | max | ≤ 0.05 m | init at [s] | init scale err | init gravity err [°] | keyframes | real time × wall mean (CPU mean) | solve / marg. ms per frame |\n")
    md.write("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n")
    for src, e in summary["sequences"].items():
        if "ate_rmse_m" not in e:
            md.write("| %s | 0 ok, %d failed | | | | | no | | | | | | |\n" % (src, len(e["runs_failed"])))
            continue
        a, i = e["ate_rmse_m"], e["initialization"]
        md.write("| %s | %d ok, %d failed | %.4f | %.4f | %.4f | %.4f | %s | %.2f | %.3f | %.2f | %.0f | %.1f (%.1f) | %.2f / %.2f |\n" % (
            src, e["runs_ok"], len(e["runs_failed"]), a["median"], a["mean"], a["min"], a["max"],
            "yes" if e["met"] else "no", i["initialized_at_s"]["median"], i["scale_error"]["median"],
            i["gravity_error_deg"]["median"], e["keyframes"], e["realtime_factor"]["mean"],
            e["realtime_factor_cpu"]["mean"], e["solve_time_per_frame_ms"], e["marginalization_time_per_frame_ms"]))
print("wrote", out + ".json", "and", out + ".md")
PY
