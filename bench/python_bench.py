#!/usr/bin/env python3
"""Python bindings benchmark (issue 17), results in bench/results/python.json.

1. sphere2500 optimized from Python vs from C++: optimize_pose_graph with the CLI's defaults,
   end to end (ordering + initialization + optimization; loading apart). C++ is
   build/bench/posegraph_bench (its time_total_s), Python the wall time of
   slamkit.optimize_pose_graph() around the same call. The runs are interleaved (C++, Python,
   C++, ...) so that a slow phase of a shared machine hits both; median of --repeat each. Both
   sides are timed warm: each C++ process runs twice and reports its second run, the Python
   process does one warm-up run first.
2. CustomFactor overhead: a 2D pose graph whose BetweenFactorSE2 factors are replaced by
   Python factors computing the same error and Jacobians, optimized with the same options
   (1 thread); overhead per factor evaluation = (t_python - t_builtin) / evaluations.

    PYTHONPATH=build/python python3 bench/python_bench.py [--repeat 5] [--out bench/results/python.json]
"""
import argparse
import json
import os
import pathlib
import platform
import statistics
import subprocess
import sys
import tempfile
import time

import slamkit as sk  # before numpy: picks the OpenBLAS kernels (slamkit/__init__.py)
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]


def data_root():
    p = pathlib.Path(os.environ.get("SLAMKIT_DATA", "../shared/datasets"))
    return (p if p.is_absolute() else ROOT / p).resolve()


def cpp_run(bench_exe, only):
    with tempfile.TemporaryDirectory() as tmp:
        out = pathlib.Path(tmp) / "r.json"
        subprocess.run([str(bench_exe), "--repeat", "2", "--only", only, "--out", str(out)], check=True,
                       stdout=subprocess.DEVNULL)
        r = json.loads(out.read_text())[0]
    return r["time_end_to_end_s_all"][1], r["final_chi2"], r["blas"]  # run 1 warms the process up


def python_run(original):
    g = original.copy()
    t0 = time.perf_counter()
    r = sk.optimize_pose_graph(g)
    wall = time.perf_counter() - t0
    return wall, r.time_total_s, r.final_chi2, r.summary.blas


def between_se2_error(z):
    """g2o's EDGE_SE2 error e = t2v(Z^-1 Xi^-1 Xj), J_j = J_E, J_i = -J_E Ad(Xj^-1 Xi)."""
    z_inv = z.inverse()

    def error(values, jacobians):
        xi, xj = values
        E = z_inv * xi.between(xj)
        e = np.array([E.x, E.y, E.theta])
        if not jacobians:
            return e
        c, s = np.cos(E.theta), np.sin(E.theta)
        J_E = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        return e, [-J_E @ xj.between(xi).adjoint(), J_E]

    return error


def custom_factor_overhead(repeat):
    g = sk.generate_pose_graph(world="manhattan", num_poses=2000, seed=1)
    problem = sk.build_pose_graph_problem(g)
    calls = [0]
    py_graph = sk.FactorGraph()
    for k in range(len(problem.graph)):
        f = problem.graph[k]
        inner = between_se2_error(f.measured)

        def counted(values, jacobians, inner=inner):
            calls[0] += 1
            return inner(values, jacobians)

        py_graph.add(sk.CustomFactor(f.keys, [sk.SE2, sk.SE2],
                                     sk.NoiseModel.information(f.noise_model.information_matrix()), counted))
    opt = sk.Optimizer(algorithm="lm", num_threads=1, max_iterations=10, function_tolerance=0.0,
                       gradient_tolerance=0.0, parameter_tolerance=0.0)
    t_builtin, t_python, evals = [], [], 0
    for _ in range(repeat):
        v = problem.values.copy()
        t0 = time.perf_counter()
        s_b = opt.optimize(problem.graph, v)
        t_builtin.append(time.perf_counter() - t0)
        v = problem.values.copy()
        calls[0] = 0
        t0 = time.perf_counter()
        s_p = opt.optimize(py_graph, v)
        t_python.append(time.perf_counter() - t0)
        evals = calls[0]
    tb, tp = statistics.median(t_builtin), statistics.median(t_python)
    # The binding's share: FactorGraph.cost (residuals only) with the real Python factors and
    # with Python factors that return a constant residual (no NumPy work at all).
    zero = np.zeros(3)
    noop_graph = sk.FactorGraph()
    for k in range(len(problem.graph)):
        f = problem.graph[k]
        noop_graph.add(sk.CustomFactor(f.keys, [sk.SE2, sk.SE2], sk.NoiseModel.unit(3), lambda values, jac: zero))

    def per_call_us(graph, n=20):
        t = []
        for _ in range(n):
            t0 = time.perf_counter()
            graph.cost(problem.values)
            t.append(time.perf_counter() - t0)
        return 1e6 * statistics.median(t) / len(problem.graph)

    cost_builtin, cost_python, cost_noop = per_call_us(problem.graph), per_call_us(py_graph), per_call_us(noop_graph)
    return {
        "problem": "sim:manhattan (2000 poses), BetweenFactorSE2 vs CustomFactor with the same error, "
                   "LM, 10 iterations, 1 thread",
        "factors": len(problem.graph),
        "iterations": s_p.iterations,
        "python_factor_evaluations": evals,
        "same_final_cost": abs(s_p.final_cost - s_b.final_cost) <= 1e-9 * s_b.final_cost,
        "time_builtin_s_median": tb,
        "time_python_factors_s_median": tp,
        "time_builtin_s_all": t_builtin,
        "time_python_factors_s_all": t_python,
        "slowdown": tp / tb,
        "overhead_per_evaluation_us": 1e6 * (tp - tb) / evals,
        "residual_only_us_per_factor": {"builtin": cost_builtin, "python": cost_python,
                                        "python_constant_residual": cost_noop},
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--bench", default=str(ROOT / "build" / "bench" / "posegraph_bench"))
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "python.json"))
    args = ap.parse_args()
    path = data_root() / "posegraph" / "3d" / "sphere2500.g2o"
    if not path.exists():
        print(f"SKIPPED: dataset not found: {path} (set SLAMKIT_DATA)")
        return 0
    original = sk.read_pose_graph(str(path))
    python_run(original)  # warm-up, as the first of the two C++ runs in each process
    cpp, py_wall, py_internal = [], [], []
    for k in range(args.repeat):
        t, cpp_chi2, cpp_blas = cpp_run(args.bench, "sphere2500")
        cpp.append(t)
        wall, internal, py_chi2, py_blas = python_run(original)
        py_wall.append(wall)
        py_internal.append(internal)
        print(f"run {k + 1}/{args.repeat}: C++ {t:.4f} s, Python {wall:.4f} s (library-internal {internal:.4f} s)",
              flush=True)
    c, p = statistics.median(cpp), statistics.median(py_wall)
    sphere = {
        "file": "sphere2500.g2o",
        "config": "optimize_pose_graph defaults (gn, auto init = chordal), threads 0",
        "time_cpp_s_median": c,
        "time_python_s_median": p,
        "ratio_python_to_cpp": p / c,
        "ratio_per_round_median": statistics.median(pw / pc for pw, pc in zip(py_wall, cpp)),
        "acceptance_max_ratio": 1.05,
        "met": p / c <= 1.05,
        "time_cpp_s_all": cpp,
        "time_python_s_all": py_wall,
        "time_python_library_internal_s_all": py_internal,
        "binding_overhead_s_median": statistics.median(w - i for w, i in zip(py_wall, py_internal)),
        "final_chi2_cpp": cpp_chi2,
        "final_chi2_python": py_chi2,
        "blas_cpp": cpp_blas,
        "blas_python": py_blas,
    }
    print(f"sphere2500: C++ {c:.4f} s, Python {p:.4f} s, ratio {p / c:.3f} (acceptance <= 1.05), median of the "
          f"per-round ratios {sphere['ratio_per_round_median']:.3f}", flush=True)
    overhead = custom_factor_overhead(args.repeat)
    print(f"CustomFactor: {overhead['slowdown']:.1f}x the built-in factor, "
          f"{overhead['overhead_per_evaluation_us']:.1f} us per evaluation; residual only: "
          f"{overhead['residual_only_us_per_factor']}", flush=True)
    result = {
        "machine": {"cpu": platform.processor() or platform.machine(), "cores": os.cpu_count(),
                    "python": sys.version.split()[0], "numpy": np.__version__, "slamkit": sk.__version__},
        "repeat": args.repeat,
        "sphere2500": sphere,
        "custom_factor": overhead,
    }
    pathlib.Path(args.out).write_text(json.dumps(result, indent=2) + "\n")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
