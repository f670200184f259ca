#!/usr/bin/env python3
"""Evaluate an estimated trajectory against ground truth (evo_ape / evo_rpe equivalents), get the
per-pose errors as NumPy arrays, and write the SVG figure and an HTML report.

    PYTHONPATH=build/python python3 examples/python/evaluate_trajectory.py [EST REF] [--out-dir DIR]

Without EST and REF it evaluates a pose graph optimized from a generated sphere against its
ground truth.
"""
import argparse
import os
import pathlib
import tempfile

import slamkit as sk
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("est", nargs="?")
    ap.add_argument("ref", nargs="?")
    ap.add_argument("--out-dir", default=None, help="where to write ate.svg and report.html")
    args = ap.parse_args()

    if args.est and args.ref:
        est, ref = sk.read_trajectory(args.est), sk.read_trajectory(args.ref)
        label = pathlib.Path(args.est).name
    else:
        graph, truth = sk.generate_pose_graph(world="sphere", rings=10, poses_per_ring=30, ground_truth=True)
        sk.optimize_pose_graph(graph)
        est, ref = graph.to_trajectory(), truth.to_trajectory()
        label = "optimized sphere"

    ate = sk.ate(est, ref, align="se3")
    print(ate.title)
    for key, value in ate.stats.to_dict().items():
        print(f"{key:>10}  {value:.6f}" if isinstance(value, float) else f"{key:>10}  {value}")
    errors = ate.errors  # one per associated pose, a NumPy array
    worst = int(np.argmax(errors))
    print(f"worst pose {worst}: {errors[worst]:.4f} m; 95th percentile {np.percentile(errors, 95):.4f} m")

    rpe = sk.rpe(est, ref, delta=1, delta_unit="f", relation="angle_deg")
    print(f"RPE (1 frame, rotation): rmse {rpe.rmse:.4f} deg over {len(rpe.pairs)} pairs")

    out_dir = pathlib.Path(args.out_dir or tempfile.mkdtemp(prefix="slamkit-eval-"))
    os.makedirs(out_dir, exist_ok=True)
    ate.plot(str(out_dir / "ate.svg"), label=label)
    sk.render_html_report([ate.to_dict(label=label), rpe.to_dict(label=label + " (RPE)")],
                          title="slamkit evaluation from Python", output=str(out_dir / "report.html"))
    print("wrote", out_dir / "ate.svg", "and", out_dir / "report.html")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
