"""Bad input from Python raises a Python exception and never crashes the interpreter: each case
runs in a fresh interpreter, which must exit with a traceback (exit code 1), not a signal."""
import os
import subprocess
import sys

import pytest

CASES = {
    "gauge unknown": 'sk.initialize_pose_graph(sk.generate_pose_graph(num_poses=10), "odometry", [999])',
    "gauge empty": 'sk.initialize_pose_graph(sk.generate_pose_graph(num_poses=10), "odometry", [])',
    "gauge on a point": 'g=sk.PoseGraph(); g.add_pose(0, sk.SE2()); g.add_point(1, [1, 2]); '
                        'g.add_edge(0, 1, [1, 2], np.eye(2)); sk.initialize_pose_graph(g, "linear", [1])',
    "empty problem": "sk.Optimizer().optimize(sk.FactorGraph(), sk.Values())",
    "all variables fixed": "g, v = sk.FactorGraph(), sk.Values(); v.insert(0, [1.0]); v.set_fixed(0); "
                           "g.add(sk.PriorFactor(0, [0.0], sk.NoiseModel.unit(1))); sk.Optimizer().optimize(g, v)",
    "factor on a missing key": "g = sk.FactorGraph(); g.add(sk.PriorFactor(5, [0.0], sk.NoiseModel.unit(1))); "
                               "v = sk.Values(); v.insert(0, [1.0]); sk.Optimizer().optimize(g, v)",
    "self edge": "g = sk.PoseGraph(); g.add_pose(0, sk.SE2()); g.add_edge(0, 0, sk.SE2(), np.eye(3)); "
                 "sk.optimize_pose_graph(g)",
    "graph without edges": "g = sk.PoseGraph(); g.add_pose(0, sk.SE2()); sk.optimize_pose_graph(g)",
    "empty graph": "sk.optimize_pose_graph(sk.PoseGraph())",
    "thousands of threads": "p = sk.build_pose_graph_problem(sk.generate_pose_graph(num_poses=30)); "
                            "sk.Optimizer(num_threads=100000).optimize(p.graph, p.values)",
    "NaN tolerance": "p = sk.build_pose_graph_problem(sk.generate_pose_graph(num_poses=30)); "
                     "sk.Optimizer(function_tolerance=float('nan')).optimize(p.graph, p.values)",
    "NaN tolerance pipeline": "sk.optimize_pose_graph(sk.generate_pose_graph(num_poses=30), gradient_tolerance=-1)",
    "write to a missing folder": 'sk.write_pose_graph(sk.generate_pose_graph(num_poses=10), "/nonexistent/x.g2o")',
    "negative RPE delta": "t = sk.generate_pose_graph(num_poses=10).to_trajectory(); sk.rpe(t, t, delta=-1)",
    "NaN pair delta": "t = sk.generate_pose_graph(num_poses=10).to_trajectory(); sk.select_pairs(t, np.nan)",
    "KITTI lengths differ": "sk.ate(sk.Trajectory.from_arrays([0, 1, 2], np.zeros((3, 3)), has_timestamps=False), "
                            "sk.Trajectory.from_arrays([0, 1], np.zeros((2, 3)), has_timestamps=False))",
    "too few poses to align": "t = sk.Trajectory.from_arrays([0, 1], np.zeros((2, 3))); sk.ate(t, t)",
    "degenerate rotation matrix": "sk.SE3.from_matrix(np.zeros((4, 4)))",
    "degenerate SO3 matrix": "sk.SO3.from_matrix(-np.eye(3))",
    "rotations that are not": "sk.Trajectory.from_arrays([0.0], [[0, 0, 0]], rotations=np.zeros((1, 3, 3)))",
    "zero quaternions": 'g = sk.generate_pose_graph(world="sphere", rings=3, poses_per_ring=5); '
                        "g.set_poses(np.zeros((15, 7)))",
    "negative generator size": "sk.generate_pose_graph(num_poses=-5)",
    "unaligned ATE": "t = sk.generate_pose_graph(num_poses=10).to_trajectory(); sk.compute_ate(t, t.subset([0, 1]))",
    "unaligned RPE": "t = sk.generate_pose_graph(num_poses=10).to_trajectory(); sk.compute_rpe(t, t.subset([0, 1]))",
    "collinear Umeyama": "p = np.outer(np.arange(5), [1, 0, 0]).astype(float); sk.umeyama(p, p)",
    "empty report": "sk.render_html_report([])",
    "NaN in report": 'sk.render_html_report([{"kind": float("nan")}])',
    "empty vector variable": "sk.Values().insert(0, [])",
    "3-D array as points": "sk.SE3().act(np.zeros((2, 2, 3)))",
    "string as matrix": 'sk.NoiseModel.information("abc")',
    "ragged list": "sk.SE3.exp([[1, 2], [3]])",
    "custom factor returns None": "g = sk.FactorGraph(); "
                                  "g.add(sk.CustomFactor([0], [1], sk.NoiseModel.unit(1), lambda v, j: None)); "
                                  "v = sk.Values(); v.insert(0, [1.0]); sk.Optimizer().optimize(g, v)",
    "empty trajectories": "sk.associate(sk.Trajectory(), sk.Trajectory())",
    "edge index": "sk.PoseGraph().edge_error(0)",
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_raises_never_crashes(name):
    code = "import slamkit as sk\nimport numpy as np\n" + CASES[name]
    env = dict(os.environ)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, env=env)
    assert p.returncode == 1, f"exit code {p.returncode} (negative: killed by a signal)\n{p.stderr}"
    last = p.stderr.strip().splitlines()[-1]
    assert "Error" in last or "Exception" in last, p.stderr
