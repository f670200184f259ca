#!/usr/bin/env python3
"""A factor written in Python (like GTSAM's CustomFactor): 2D range-only localization plus a
pose with a heading prior. The function gets the variables' values and returns the residual,
and the Jacobians (w.r.t. x ⊞ δ) when asked; check_jacobians compares them with central
differences before optimizing. Python factors cost about 16 µs per evaluation (docs/python.md):
use them for prototypes and small problems, and C++ FactorN for large ones.

    PYTHONPATH=build/python python3 examples/python/custom_factor.py
"""
import slamkit as sk
import numpy as np

BEACONS = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, 10.0], [10.0, 10.0]])
TRUTH = sk.SE2(2.0, 3.0, 0.4)
SENSOR = np.array([0.5, 0.0])  # range sensor mounted 0.5 m ahead of the robot centre


def range_factor(beacon, measured, sigma=0.05):
    """e = ||R s + t - b|| - range for a robot pose X = (R, t) and sensor offset s."""

    def error(values, jacobians):
        (pose,) = values
        p, J_p_pose, _ = pose.act(SENSOR, jacobians=True)  # sensor position and d p / d(pose ⊞ δ)
        d = p - beacon
        n = np.linalg.norm(d)
        r = np.array([n - measured])
        if not jacobians:
            return r
        return r, [((d / n) @ J_p_pose).reshape(1, 3)]  # (1×2)(2×3): d e / d(pose ⊞ δ)

    return sk.CustomFactor([0], [sk.SE2], sk.NoiseModel.isotropic(1, sigma), error)


def main():
    graph = sk.FactorGraph()
    sensor_truth = TRUTH.act(SENSOR)
    for b in BEACONS:
        graph.add(range_factor(b, np.linalg.norm(sensor_truth - b)))
    graph.add(sk.PriorFactor(0, sk.SE2(0, 0, 0.4), sk.NoiseModel.diagonal([1e3, 1e3, 0.01])))  # a compass

    values = sk.Values()
    values.insert(0, sk.SE2(8.0, 8.0, 0.0))
    check = sk.check_jacobians(graph, values)
    print(check.message())
    summary = sk.Optimizer(algorithm="lm").optimize(graph, values, verbose=True)
    print(summary.report())
    est = values.at(0)
    print(f"estimate {est}, truth {TRUTH}")
    ok = check.ok and np.allclose(est.vector(), TRUTH.vector(), atol=1e-4)
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
