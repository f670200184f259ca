"""Pose graphs from Python: the PoseGraph type, the generators, the problem builder, the
initializers, and optimize_pose_graph against `slamkit optimize` (same chi2 to 1e-12)."""
import json
import subprocess

import numpy as np
import pytest
import slamkit as sk
from conftest import cli_path, require_data


def test_sphere2500_same_chi2_as_cli(tmp_path):
    path = require_data("posegraph/3d/sphere2500.g2o")
    out = tmp_path / "cli.json"
    subprocess.run([cli_path(), "optimize", str(path), "--json", str(out), "-q"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    cli = json.loads(out.read_text())
    g = sk.read_pose_graph(str(path))
    r = sk.optimize_pose_graph(g)
    assert r.summary.success()
    assert abs(r.final_chi2 - cli["final_chi2"]) <= 1e-12 * cli["final_chi2"], (r.final_chi2, cli["final_chi2"])
    assert abs(r.input_chi2 - cli["initial_chi2"]) <= 1e-12 * cli["initial_chi2"]
    assert r.summary.iterations == cli["iterations"] and r.init.used == cli["init"] == "chordal"
    assert abs(g.total_chi2() - r.final_chi2) <= 1e-12 * r.final_chi2  # estimates written back
    d = sk.pose_graph_result_dict(r, g)
    for key in ("final_chi2", "initial_chi2", "iterations", "init", "solver", "vertices", "edges"):
        assert d[key] == cli[key], key
    assert [it["cost"] for it in d["trace"]] == [it["cost"] for it in cli["trace"]]


def test_cli_options_map_to_keywords(tmp_path):
    g = sk.load_pose_graph("sim:manhattan?seed=3")
    spec_out = tmp_path / "cli.json"
    subprocess.run([cli_path(), "optimize", "sim:manhattan?seed=3", "--solver", "lm", "--init", "odometry",
                    "--robust", "cauchy:1", "--max-iterations", "20", "--json", str(spec_out), "-q"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    cli = json.loads(spec_out.read_text())
    d = sk.optimize_pose_graph(g, solver="lm", init="odometry", robust="cauchy:1", max_iterations=20, as_dict=True)
    assert d["final_chi2"] == pytest.approx(cli["final_chi2"], rel=1e-12)
    assert d["final_cost"] == pytest.approx(cli["final_cost"], rel=1e-12)
    assert d["solver"] == "lm" and d["init"] == "odometry" and d["kind"] == "optimize"


def test_cli_config_file_keys_are_keywords(tmp_path):
    """Every optimizer key of `slamkit optimize --config` is a keyword of optimize_pose_graph;
    the load keys (format, repair_information) are keywords of load_pose_graph."""
    config = {"solver": "lm", "init": "odometry", "robust": "huber:2", "robust_loop_closures_only": True,
              "max_iterations": 15, "threads": 1, "blas_threads": 1, "function_tolerance": 1e-6,
              "gradient_tolerance": 1e-10, "parameter_tolerance": 1e-8, "linear_solver": "auto", "ordering": "amd",
              "repair_information": False, "format": "auto", "keep_estimates_chi2_per_dof": 0.5}
    path = tmp_path / "opts.json"
    path.write_text(json.dumps(config))
    cli_out = tmp_path / "cli.json"
    subprocess.run([cli_path(), "optimize", "sim:manhattan", "--config", str(path), "--json", str(cli_out), "-q"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    load_keys = {k: config.pop(k) for k in ("repair_information", "format")}
    g = sk.load_pose_graph("sim:manhattan", **load_keys)
    d = sk.optimize_pose_graph(g, as_dict=True, **config)
    assert d["final_chi2"] == pytest.approx(json.loads(cli_out.read_text())["final_chi2"], rel=1e-12)


def test_optimize_options_and_errors():
    g = sk.generate_pose_graph(world="manhattan", num_poses=300, seed=5)
    r = sk.optimize_pose_graph(g.copy(), solver="dogleg", init="spanning-tree", robust=sk.HuberKernel(2.0),
                               robust_loop_closures_only=True, threads=1, ordering="amd", linear_solver="eigen")
    assert r.summary.success() and r.init.used == "spanning-tree" and r.final_chi2 < r.input_chi2
    assert r.summary.options.algorithm == "dogleg" and r.summary.ordering.lower().startswith("amd")
    seen = []
    sk.optimize_pose_graph(g.copy(), callback=lambda it: seen.append(it.cost))
    assert len(seen) >= 2
    for bad in (dict(solver="sgd"), dict(init="magic"), dict(robust="huber"), dict(ordering="x"),
                dict(se3_error="euler")):
        with pytest.raises(ValueError):
            sk.optimize_pose_graph(g.copy(), **bad)
    with pytest.raises(sk.InputError):
        sk.optimize_pose_graph(g.copy(), init="chordal")  # 3D method on a 2D graph
    for bad in (-1.0, float("nan")):
        with pytest.raises(ValueError):
            sk.optimize_pose_graph(g.copy(), keep_estimates_chi2_per_dof=bad)


def test_auto_init_keeps_estimates_that_fit_the_noise():
    """init="auto" starts from estimates whose chi2 is below their degrees of freedom (here an
    optimized graph with its information divided by 4: same minimizer), unless told not to."""
    g = sk.generate_pose_graph(world="manhattan", num_poses=300, seed=5)
    first = sk.optimize_pose_graph(g)
    assert first.init.used == "linear"
    scaled = sk.PoseGraph()
    for vid in g.vertex_ids():
        scaled.add_pose(int(vid), g.vertex(int(vid)).estimate)
    for i in range(g.num_edges):
        e = g.edge(i)
        scaled.add_edge(e.from_id, e.to_id, e.measured, 0.25 * e.information)
    kept = sk.optimize_pose_graph(scaled.copy())
    assert kept.init.used == "none" and any("estimates fit" in n for n in kept.notes)
    assert kept.final_chi2 == pytest.approx(0.25 * first.final_chi2, rel=1e-9)
    forced = sk.optimize_pose_graph(scaled.copy(), keep_estimates_chi2_per_dof=0.0)
    assert forced.init.used == "linear" and forced.final_chi2 == pytest.approx(kept.final_chi2, rel=1e-9)


def test_generators_and_specs():
    g, truth = sk.generate_pose_graph(world="sphere", rings=5, poses_per_ring=12, seed=9, ground_truth=True)
    assert g.dimension() == 3 and g.num_poses() == 60 and truth.num_poses() == 60
    assert truth.total_chi2() < g.total_chi2()
    o = sk.PoseGraphSimOptions(world="manhattan", num_poses=100)
    g2 = sk.generate_pose_graph(o)
    assert g2.dimension() == 2 and g2.num_poses() == 100
    np.testing.assert_array_equal(sk.generate_pose_graph(o).poses(), g2.poses())  # deterministic
    spec = sk.parse_sim_spec("sim:sphere?seed=3&rings=20")
    assert spec.world == "sphere" and spec.seed == 3 and spec.rings == 20
    assert sk.parse_sim_spec("file.g2o") is None
    assert "PoseGraphSimOptions(world='manhattan'" in repr(o)
    with pytest.raises(sk.InputError):
        sk.generate_pose_graph(world="moon")
    with pytest.raises(TypeError):
        sk.generate_pose_graph(o, rings=3)
    with pytest.raises(ValueError):
        sk.generate_pose_graph(radius=np.nan, world="sphere")


def test_pose_graph_built_in_python():
    g = sk.PoseGraph()
    info = np.diag([100.0, 100.0, 400.0])
    g.add_pose(0, sk.SE2(0, 0, 0))
    g.add_pose(1, sk.SE2(1.2, 0.1, 0.0))
    g.add_pose(2, sk.SE2(2.1, -0.2, 0.1))
    g.add_point(10, [1.0, 1.0])
    g.add_edge(0, 1, sk.SE2(1, 0, 0), info)
    g.add_edge(1, 2, sk.SE2(1, 0, 0), info)
    g.add_edge(0, 2, sk.SE2(2, 0, 0), info)
    g.add_edge(1, 10, [0.0, 1.0], np.eye(2) * 50)
    assert g.num_vertices == 4 and g.num_edges == 4 and g.dimension() == 2 and g.num_points() == 1
    assert g.vertex(1).kind == "pose2" or g.vertex(1).kind.lower().startswith("pose")
    assert isinstance(g.vertex(1).estimate, sk.SE2) and g.has_vertex(10) and not g.has_vertex(3)
    e = g.edge(3)
    assert (e.from_id, e.to_id) == (1, 10) and e.information.shape == (2, 2)
    np.testing.assert_array_equal(g.edge_ids(), [[0, 1], [1, 2], [0, 2], [1, 10]])
    np.testing.assert_array_equal(g.pose_ids(), [0, 1, 2])
    np.testing.assert_allclose(g.edge_chi2().sum(), g.total_chi2())
    assert g.edge_error(0).shape == (3,) and g.count_connected_components() == 1
    ids, notes = g.gauge_vertices()
    assert ids == [0] and notes
    assert g.check_information().positive_definite == 4
    problem = sk.build_pose_graph_problem(g)
    assert len(problem.graph) == 4 and len(problem.values) == 4 and problem.gauge == [0]
    r = sk.optimize_pose_graph(g, solver="lm")
    assert r.final_chi2 < 1e-2 * r.input_chi2
    P = g.poses()
    assert P.shape == (3, 3)
    g.set_poses(P * 0)
    assert g.total_chi2() > 0 and g.points().shape == (1, 3)
    sk.copy_estimates(problem.values, g)
    assert abs(g.total_chi2() - r.input_chi2) < 1e-9
    t = g.to_trajectory()
    assert len(t) == 3
    with pytest.raises(ValueError):
        g.add_pose(0, sk.SE2())  # duplicate id
    with pytest.raises(sk.InputError):
        g.add_edge(0, 99, sk.SE2(), info)
    with pytest.raises(ValueError):
        g.add_edge(0, 1, sk.SE2(), np.eye(2))
    with pytest.raises(ValueError):
        g.add_edge(0, 1, sk.SE3(), info)
    with pytest.raises(ValueError):
        g.add_edge(0, 1, sk.SE2(), np.full((3, 3), np.nan))
    with pytest.raises(ValueError):
        g.set_poses(np.zeros((2, 3)))
    with pytest.raises(IndexError):
        g.edge(7)


def test_problem_builder_and_initializers():
    g = sk.generate_pose_graph(world="sphere", rings=6, poses_per_ring=15, seed=3)
    for method in ("odometry", "spanning-tree", "chordal", "auto", "none"):
        h = g.copy()
        s = sk.initialize_pose_graph(h, method)
        assert s.requested == method and (s.used == "chordal" if method == "auto" else s.used == method)
    h = g.copy()
    sk.initialize_pose_graph(h, "chordal")
    assert h.total_chi2() < g.total_chi2()
    p = sk.build_pose_graph_problem(g, robust="huber:1", se3_error="log")
    assert p.graph[0].robust_kernel.startswith("huber") and p.graph[0].form == "log"
    p = sk.build_pose_graph_problem(g, robust=sk.CauchyKernel(1.0), robust_loop_closures_only=True)
    kernels = {p.graph[i].robust_kernel is None for i in range(len(p.graph))}
    assert kernels == {True, False}
    bad = g.copy()
    bad.add_pose(10_000, sk.SE3())
    bad.add_edge(0, 10_000, sk.SE3(), np.diag([1.0, 1, 1, 1, 1, -1]))
    with pytest.raises(sk.InputError) as e:
        sk.build_pose_graph_problem(bad)
    assert isinstance(e.value, ValueError)
    assert bad.repair_information() == 1
    sk.build_pose_graph_problem(bad)
