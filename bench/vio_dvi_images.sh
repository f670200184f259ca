#!/usr/bin/env bash
# DVI on rendered images (issue 13 parts 1-3): per sequence, dynamic level (low, high) and seed,
# `slamkit simulate --vi SEQ --images DIR` renders the frames once, then `slamkit vio --images
# --image-dir DIR` runs the real front end (KLT + long-baseline epipolar test) on the pixels in
# baseline mode (--dvi off: every track used, alpha = 1) and in DVI mode (--dvi on), scoring every
# classified feature against the pixel labels. Summary (median, mean, min, max of ATE RMSE;
# precision / recall of "dynamic"; M; frames without vision; times, with the load average) in
# $OUT.json (default bench/results/vio_dvi_images.json) and a table in $OUT.md.
# Usage: bench/vio_dvi_images.sh [BUILD_DIR] [SEEDS] [DURATION_S] ["room1 room2 ..."] ["VIO OPTIONS"]
# WORK=DIR keeps the per-run JSON there (two instances on disjoint sequences may share it);
# IMAGES=DIR keeps the rendered folders there and reuses them; FIRST_SEED=N starts at seed N
# (with WORK, a later call can add seeds); LEVELS="high" runs one level only (default "low high"); SUMMARY_ONLY=1 only summarizes the runs already in WORK (SEEDS is then the number of seeds expected).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../build}
seeds=${2:-1}
duration=${3:-30}
seqs=${4:-room1 room2 room3 room4}
vio_args=${5:-}
out=${OUT:-$here/results/vio_dvi_images}
slamkit=$build/bin/slamkit
if [ -n "${WORK:-}" ]; then work=$WORK; mkdir -p "$work"; else work=$(mktemp -d); trap 'rm -rf "$work"' EXIT; fi
[ "${SUMMARY_ONLY:-0}" = 1 ] && seqs_run="" || seqs_run=$seqs
for seq in $seqs_run; do
  for level in ${LEVELS:-low high}; do
    for seed in $(seq "${FIRST_SEED:-1}" "$seeds"); do
      name=${seq//:/_}_${level}_$seed
      img=${IMAGES:-$work}/$name.images
      load=$(cut -d' ' -f1 /proc/loadavg)
      [ -n "${IMAGES:-}" ] && [ -f "$img/mav0/cam0/data.csv" ] || "$slamkit" simulate --vi "$seq" --seed "$seed" --dynamic "$level" --duration "$duration" --images "$img" \
        --json "$work/$name.simulate.json" >/dev/null 2>&1
      for mode in off on; do
        # shellcheck disable=SC2086
        "$slamkit" vio --sim "$seq" --seed "$seed" --dynamic "$level" --duration "$duration" --images --image-dir "$img" \
          --quiet --dvi "$mode" $vio_args --json "$work/$name.$mode.json" > "$work/$name.$mode.log" 2>&1 ||
          { echo "$name dvi $mode FAILED:"; tail -3 "$work/$name.$mode.log"; continue; }
        python3 -c "import json,sys; j=json.load(open(sys.argv[1])); j['load_average']=float(sys.argv[2]); json.dump(j,open(sys.argv[1],'w'))" \
          "$work/$name.$mode.json" "$load"
        grep -E "^(front end|ATE)" "$work/$name.$mode.log" | sed "s/^/$name dvi $mode: /"
      done
      [ -n "${IMAGES:-}" ] || rm -rf "$img"
    done
  done
done
python3 - "$work" "$out" "$seeds" "$duration" "$seqs" "$vio_args" <<'PY'
import json, sys, glob, os, statistics as st
work, out, seeds, duration, seqs, vio_args = sys.argv[1], sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), sys.argv[5].split(), sys.argv[6]
def stats(v): return {"median": st.median(v), "mean": st.mean(v), "min": min(v), "max": max(v)} if v else None
summary = {"kind": "vio_dvi_images", "sequences": seqs, "seeds": seeds, "duration_s": duration, "vio_args": vio_args,
           "classifier": "front end on rendered images (KLT + long-baseline epipolar test)", "results": {}}
md = ["| sequence | dynamic | seeds | baseline ATE median / mean / min / max [m] | DVI ATE median / mean / min / max [m] | DVI vs baseline (mean) | precision / recall (patch, movers at 2-6 m) | tp / fp / fn (2-6 m) | precision / recall (patch, any distance) | precision / recall (centre pixel) | mixed (flagged) | M mean / min | frames without vision (DVI) | DVI CPU ms / 50 ms frame | load |",
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
for seq in seqs:
    for level in ("low", "high"):
        key = f"{seq}_{level}"
        runs = {m: [json.load(open(f)) for f in sorted(glob.glob(os.path.join(work, f"{seq}_{level}_*.{m}.json")))] for m in ("off", "on")}
        if not runs["off"] or not runs["on"]: continue
        r = {}
        for m, name in (("off", "baseline"), ("on", "dvi")):
            rs = runs[m]
            fe = [x["frontend"] for x in rs]
            r[name] = {"ate_rmse_m": stats([x["ate_rmse"] for x in rs]),
                       "visual_frames_dropped": st.mean(x["visual_frames_dropped"] for x in rs),
                       "realtime_factor_cpu": st.mean(x["realtime_factor_cpu"] for x in rs),
                       "runs": [{"seed": x["vio"]["seed"], "ate_rmse": x["ate_rmse"], "visual_frames_dropped": x["visual_frames_dropped"],
                                 "dynamic_precision": x["dynamic_precision"], "dynamic_recall": x["dynamic_recall"],
                                 "dynamic_precision_centre": x["frontend"]["dynamic_precision_centre"],
                                 "dynamic_recall_centre": x["frontend"]["dynamic_recall_centre"],
                                 "frontend_cpu_ms_per_frame": x["frontend"]["frontend_cpu_ms_per_frame"],
                                 "window_cpu_ms_per_frame": 1e3 * x["cpu_time_s"] / x["frontend"]["frames"],
                                 "dvi_pipeline_cpu_ms_per_frame": x["dvi_pipeline_cpu_ms_per_frame"],
                                 "dvi_pipeline_realtime_factor_cpu": x["dvi_pipeline_realtime_factor_cpu"],
                                 "static_ratio": x["frontend"]["static_ratio"], "load_average": x.get("load_average"),
                                 "frames_static_below_theta": x.get("frames_static_below_theta"),
                                 "image_ms_per_frame": x["frontend"]["image_ms_per_frame"],
                                 "tracking_ms_per_frame": x["frontend"]["tracking_ms_per_frame"],
                                 "classification_ms_per_frame": x["frontend"]["classification_ms_per_frame"],
                                 "solve_ms_per_frame": x["solve_time_per_frame_ms"]["mean"],
                                 "marginalization_ms_per_frame": x["marginalization_time_per_frame_ms"]["mean"]} for x in rs]}
        fe = [x["frontend"] for x in runs["on"]]
        tp = sum(f["score"]["true_positive"] for f in fe); fp = sum(f["score"]["false_positive"] for f in fe)
        fn = sum(f["score"]["false_negative"] for f in fe)
        mixed = sum(f["score"]["mixed"] for f in fe); mixed_flagged = sum(f["score"]["mixed_flagged"] for f in fe)
        ctp = sum(f["score_centre"]["true_positive"] for f in fe); cfp = sum(f["score_centre"]["false_positive"] for f in fe)
        cfn = sum(f["score_centre"]["false_negative"] for f in fe)
        al = [f.get("score_all_distances", f["score"]) for f in fe]
        atp = sum(a["true_positive"] for a in al); afp = sum(a["false_positive"] for a in al); afn = sum(a["false_negative"] for a in al)
        r["classifier"] = {"rule": "patch (labels under the KLT window; mixed patches counted, not scored); movers at "
                                   "score min..max distance from the camera (default 2-6 m; slower than 0.3 m/s excluded)",
                           "excluded_distance": sum(f["score"].get("excluded_distance", 0) for f in fe),
                           "all_distances": {"precision": atp / (atp + afp) if atp + afp else 1.0,
                                             "recall": atp / (atp + afn) if atp + afn else 1.0,
                                             "true_positive": atp, "false_positive": afp, "false_negative": afn},
                           "precision": tp / (tp + fp) if tp + fp else 1.0, "recall": tp / (tp + fn) if tp + fn else 1.0,
                           "true_positive": tp, "false_positive": fp, "false_negative": fn,
                           "mixed": mixed, "mixed_flagged": mixed_flagged,
                           "centre_pixel": {"precision": ctp / (ctp + cfp) if ctp + cfp else 1.0,
                                            "recall": ctp / (ctp + cfn) if ctp + cfn else 1.0,
                                            "true_positive": ctp, "false_positive": cfp, "false_negative": cfn},
                           "static_ratio_mean": st.mean(f["static_ratio"]["mean"] for f in fe),
                           "static_ratio_min": min(f["static_ratio"]["min"] for f in fe)}
        b, d = r["baseline"]["ate_rmse_m"]["mean"], r["dvi"]["ate_rmse_m"]["mean"]
        r["dvi_vs_baseline_mean_ate_change"] = (d - b) / b
        loads = [x.get("load_average") for x in runs["on"] if x.get("load_average") is not None]
        r["load_average"] = stats(loads)
        pipe = [x["dvi_pipeline_cpu_ms_per_frame"] for x in runs["on"]]
        r["dvi_pipeline_cpu_ms_per_frame"] = stats(pipe)
        r["frame_period_ms"] = 50.0
        summary["results"][key] = r
        f4 = lambda s: " / ".join(f"{s[k]:.4f}" for k in ("median", "mean", "min", "max"))
        c = r["classifier"]
        md.append(f"| {seq} | {level} | {len(runs['on'])} | {f4(r['baseline']['ate_rmse_m'])} | {f4(r['dvi']['ate_rmse_m'])} | "
                  f"{100 * r['dvi_vs_baseline_mean_ate_change']:+.1f} % | {c['precision']:.3f} / {c['recall']:.3f} | "
                  f"{c['true_positive']} / {c['false_positive']} / {c['false_negative']} | "
                  f"{c['all_distances']['precision']:.3f} / {c['all_distances']['recall']:.3f} | "
                  f"{c['centre_pixel']['precision']:.3f} / {c['centre_pixel']['recall']:.3f} | {c['mixed']} ({c['mixed_flagged']}) | "
                  f"{c['static_ratio_mean']:.3f} / {c['static_ratio_min']:.3f} | {r['dvi']['visual_frames_dropped']:.1f} | "
                  f"{r['dvi_pipeline_cpu_ms_per_frame']['mean']:.1f} | "
                  f"{r['load_average']['mean'] if loads else float('nan'):.1f} |")
# Pooled over the sequences, per level: classifier counts and the mean of the per-sequence ATE changes.
for level in ("low", "high"):
    rs = [v for k, v in summary["results"].items() if k.endswith("_" + level)]
    if not rs: continue
    tp = sum(v["classifier"]["true_positive"] for v in rs); fp = sum(v["classifier"]["false_positive"] for v in rs)
    fn = sum(v["classifier"]["false_negative"] for v in rs)
    ctp = sum(v["classifier"]["centre_pixel"]["true_positive"] for v in rs); cfp = sum(v["classifier"]["centre_pixel"]["false_positive"] for v in rs)
    cfn = sum(v["classifier"]["centre_pixel"]["false_negative"] for v in rs)
    atp = sum(v["classifier"]["all_distances"]["true_positive"] for v in rs)
    afp = sum(v["classifier"]["all_distances"]["false_positive"] for v in rs)
    afn = sum(v["classifier"]["all_distances"]["false_negative"] for v in rs)
    changes = [v["dvi_vs_baseline_mean_ate_change"] for v in rs]
    summary.setdefault("pooled", {})[level] = {
        "precision": tp / (tp + fp) if tp + fp else 1.0, "recall": tp / (tp + fn) if tp + fn else 1.0,
        "true_positive": tp, "false_positive": fp, "false_negative": fn,
        "precision_all_distances": atp / (atp + afp) if atp + afp else 1.0,
        "recall_all_distances": atp / (atp + afn) if atp + afn else 1.0,
        "precision_centre": ctp / (ctp + cfp) if ctp + cfp else 1.0, "recall_centre": ctp / (ctp + cfn) if ctp + cfn else 1.0,
        "dvi_vs_baseline_change": stats(changes)}
    p = summary["pooled"][level]
    md.append(f"| all | {level} | | | | mean {100 * p['dvi_vs_baseline_change']['mean']:+.1f} % (min {100 * p['dvi_vs_baseline_change']['min']:+.1f}, "
              f"max {100 * p['dvi_vs_baseline_change']['max']:+.1f}) | {p['precision']:.3f} / {p['recall']:.3f} | "
              f"{p['true_positive']} / {p['false_positive']} / {p['false_negative']} | "
              f"{p['precision_all_distances']:.3f} / {p['recall_all_distances']:.3f} | "
              f"{p['precision_centre']:.3f} / {p['recall_centre']:.3f} | | | | | |")
json.dump(summary, open(out + ".json", "w"), indent=1)
open(out + ".md", "w").write("\n".join(md) + "\n")
print("\n".join(md))
print("wrote", out + ".json", out + ".md")
PY
