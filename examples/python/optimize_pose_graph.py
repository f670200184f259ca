#!/usr/bin/env python3
"""Optimize a pose graph from Python, as `slamkit optimize` does, and look at the result with NumPy.

    PYTHONPATH=build/python python3 examples/python/optimize_pose_graph.py [FILE|sim:sphere] [-o OUT.g2o]
"""
import argparse

import slamkit as sk  # import slamkit before numpy (it picks the fastest OpenBLAS kernels)
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("graph", nargs="?", default="sim:sphere?rings=12", help="g2o/TORO/GTSAM file or sim:NAME")
    ap.add_argument("-o", "--output", help="write the optimized graph (format from the extension)")
    ap.add_argument("--solver", default="gn", help="gn | lm | tr-lm | dogleg")
    ap.add_argument("--robust", default=None, help="robust kernel, e.g. cauchy:1")
    args = ap.parse_args()

    graph = sk.load_pose_graph(args.graph)
    print(f"{graph}: {graph.dimension()}D, chi2 {graph.total_chi2():.6g} as loaded")
    before = graph.poses()  # N×3 [x, y, theta] or N×7 [t, q]

    result = sk.optimize_pose_graph(graph, solver=args.solver, robust=args.robust, verbose=True)
    print(result.summary.report())
    print(f"init {result.init.used}: chi2 {result.input_chi2:.6g} -> {result.chi2_after_init:.6g}, "
          f"final {result.final_chi2:.10g} in {result.time_total_s:.3f} s")

    after = graph.poses()
    moved = np.linalg.norm(after[:, :3] - before[:, :3], axis=1) if after.shape[1] == 7 else \
        np.linalg.norm(after[:, :2] - before[:, :2], axis=1)
    print(f"poses moved by {moved.mean():.3f} m on average (max {moved.max():.3f} m)")
    worst = np.argsort(graph.edge_chi2())[-3:][::-1]
    print("largest edge chi2 after optimization:",
          ", ".join(f"{tuple(graph.edge_ids()[i])}: {graph.edge_chi2()[i]:.3g}" for i in worst))
    if args.output:
        for w in sk.write_pose_graph(graph, args.output):
            print("warning:", w)
        print("wrote", args.output)
    return 0 if result.summary.success() else 1


if __name__ == "__main__":
    raise SystemExit(main())
