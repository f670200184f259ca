#!/usr/bin/env python3
"""Writes bench/results/SUMMARY.md from the JSON files the benchmarks wrote.

    python3 bench/summarize.py > bench/results/SUMMARY.md

Tables: end-to-end time of the default configuration against 0.7 x the issue's best peer,
every configuration, one iteration against one bare CHOLMOD factorize+solve, and slamkit
against Ceres 2.1 measured in the same run. Plain Python 3, standard library only.
"""
import json
import os
import platform
import subprocess
import sys

RESULTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results")


def load(name):
    path = os.path.join(RESULTS, name)
    if not os.path.exists(path):
        sys.exit(f"summarize.py: {path} is missing: run the benchmark first (bench/README.md)")
    with open(path) as f:
        return json.load(f)


def machine():
    try:
        lscpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        model = next((l.split(":", 1)[1].strip() for l in lscpu.splitlines() if l.startswith("Model name")), "?")
    except OSError:
        model = "?"
    return f"{model}, {os.cpu_count()} cores, {platform.system()} {platform.release()}"


SIDE_BY_SIDE = ["side_by_side.json", "side_by_side_large_s30.json", "side_by_side_large3d_s30.json"]


def main():
    pg = load("posegraph.json")
    it = load("iteration.json")
    ceres = load("ceres_peer.json")
    out = []
    w = out.append
    blas = next((r.get("blas", "") for r in pg if r.get("blas")), "?")
    w("# Benchmark results\n")
    w(f"Machine: {machine()}; BLAS: {blas}. Regenerate with the commands in bench/README.md, then")
    w("`python3 bench/summarize.py > bench/results/SUMMARY.md`. Times are medians; end-to-end is")
    w("initialization + optimization (file loading apart), default options (2 linearization threads,")
    w("1 BLAS thread).\n")

    # The issue's acceptance: peers built and run on this machine, interleaved (bench/side_by_side).
    w("## Side by side with g2o (and GTSAM when built) on this machine (speed goal: ratio <= 0.7)\n")
    w("`bench/side_by_side`: medians of interleaved rounds, end to end without loading; the peer is the")
    w("fastest configuration that reaches slamkit's chi2 x (1 + 1e-4). Large graphs: generated files, see")
    w("docs/pose_graph_scale.md.\n")
    w("| file | slamkit [s] | slamkit chi2 | fastest peer to that chi2 | peer [s] | ratio | peak MB slamkit / peer | rounds, date |")
    w("|---|---|---|---|---|---|---|---|")
    for name in SIDE_BY_SIDE:
        path = os.path.join(RESULTS, name)
        if not os.path.exists(path):
            continue
        with open(path) as f:
            sbs = json.load(f)
        meta = sbs.get("meta", {})
        for r in sbs.get("results", []):
            peer = r.get("fastest_peer") or "none reaches it"
            peer_s = f"{r['fastest_peer_s']:.4f}" if r.get("fastest_peer_s") else "-"
            ratio = f"{r['ratio']:.2f}" if r.get("ratio") else "-"
            peak_peer = r.get("fastest_peer_peak_rss_mb")
            peak = f"{r.get('slamkit_peak_rss_mb', float('nan')):.0f} / " + (f"{peak_peer:.0f}" if peak_peer else "-")
            w(f"| {r['file']} | {r['slamkit_s']:.4f} | {r['slamkit_chi2']:.6f} | {peer} | {peer_s} | {ratio} | {peak} | "
              f"{meta.get('rounds', '?')}, {meta.get('date_utc', '?')} |")

    w("\n## Default configuration vs the issue's best peer figures (measured on another machine: history)\n")
    w("| file | final chi2 | best chi2 | iterations | end-to-end [s] | best peer [s] | ratio | goal |")
    w("|---|---|---|---|---|---|---|---|")
    for r in pg:
        if not r["config"].startswith("default"):
            continue
        goal = ("met" if r["ratio_to_best_peer"] <= 0.7 else "MISSED") if r["speed_goal_0_7"] else "-"
        reached = "" if r["chi2_reached"] else " (NOT reached)"
        w(f"| {r['file']} | {r['final_chi2']:.6f}{reached} | {r['best_chi2']} | {r['iterations']} | "
          f"{r['time_end_to_end_s_median']:.4f} | {r['peer_seconds']} ({r['peer']}) | "
          f"{r['ratio_to_best_peer']:.3f} | {goal} |")

    w("\n## Every configuration\n")
    w("| file | config | final chi2 | reached | iterations | end-to-end [s] |")
    w("|---|---|---|---|---|---|")
    for r in pg:
        w(f"| {r['file']} | {r['config']} | {r['final_chi2']:.6f} | {'yes' if r['chi2_reached'] else 'no'} | "
          f"{r['iterations']} | {r['time_end_to_end_s_median']:.4f} |")

    w("\n## One iteration vs one bare CHOLMOD factorize + solve (bound: <= 1.3)\n")
    # With --benchmark_repetitions, take the median aggregate; otherwise the single run.
    runs = [b for b in it["benchmarks"] if b.get("aggregate_name") == "median"]
    key = "run_name"
    if not runs:
        runs, key = [b for b in it["benchmarks"] if b.get("run_type") == "iteration"], "name"
    times = {b[key]: b["real_time"] for b in runs}
    factorize = {b[key]: b.get("factorize_ms", float("nan")) for b in runs}
    files = sorted({n.split("/", 1)[1].rsplit("/min_time", 1)[0] for n in times if n.startswith("bare_cholmod/")})
    w("Two references: slamkit's CHOLMOD backend alone (its settings, relaxed supernodes), and CHOLMOD")
    w("called directly with its default settings. The ratios are the 2-thread iteration (the default)")
    w("over each; 1 thread for comparison.\n")
    w("| file | bare, slamkit settings [ms] | bare, CHOLMOD defaults [ms] | issue's figure [ms] | "
      "iteration, 1 thread [ms] | iteration, 2 threads [ms] | ratio to slamkit settings (1 / 2 threads) | "
      "ratio to CHOLMOD defaults (2 threads) | linearize 1/2 threads [ms] | retract+evaluate 1/2 [ms] | "
      "factorize alone / inside the 2-thread iteration [ms] |")
    w("|---|---|---|---|---|---|---|---|---|---|---|")
    issue_ms = {b[key]: b.get("issue_ms", float("nan")) for b in runs}  # from bench_data.h

    def t(prefix, f, arg=None, table=times):
        for n, v in table.items():
            if n.startswith(f"{prefix}/{f}/") and (arg is None or n.startswith(f"{prefix}/{f}/{arg}/")):
                return v
        return float("nan")

    for f in files:
        bare, defaults = t("bare_cholmod", f), t("bare_cholmod_defaults", f)
        i1, i2 = t("iteration", f, 1), t("iteration", f, 2)
        w(f"| {f} | {bare:.2f} | {defaults:.2f} | {t('bare_cholmod', f, table=issue_ms):g} | {i1:.2f} | {i2:.2f} | "
          f"{i1 / bare:.2f} / {i2 / bare:.2f} | {i2 / defaults:.2f} | "
          f"{t('linearize', f, 1):.2f} / {t('linearize', f, 2):.2f} | "
          f"{t('retract_and_evaluate', f, 1):.2f} / {t('retract_and_evaluate', f, 2):.2f} | "
          f"{t('bare_cholmod', f, table=factorize):.2f} / {t('iteration', f, 2, table=factorize):.2f} |")

    w("\n## slamkit vs Ceres 2.1, same process, same machine\n")
    w("Ceres: SPARSE_NORMAL_CHOLESKY (CHOLMOD on the same BLAS), 1 thread, g2o's error; from the file's")
    w("estimates, and from slamkit's initialization (its time included).\n")
    w("| file | slamkit [s] | chi2 | Ceres file init [s] | chi2 | Ceres slamkit init [s] | chi2 | "
      "ratio vs Ceres (file / slamkit init) |")
    w("|---|---|---|---|---|---|---|---|")
    for r in ceres:
        w(f"| {r['file']} | {r['slamkit_seconds']:.4f} | {r['slamkit_chi2']:.4f} | {r['ceres_file_init_seconds']:.4f} | "
          f"{r['ceres_file_init_chi2']:.4f} | {r['ceres_slamkit_init_seconds']:.4f} | {r['ceres_slamkit_init_chi2']:.4f} | "
          f"{r['ratio_vs_ceres_file_init']:.3f} / {r['ratio_vs_ceres_slamkit_init']:.3f} |")
    print("\n".join(out))


if __name__ == "__main__":
    main()
