"""Every public name of the module is exercised: each class has an instance made by a real call
whose every property is read (and repr'd), each function is called by some test file. A new
binding without a test fails here."""
import pathlib
import re

import numpy as np
import pytest
import slamkit as sk

from conftest import data_root

EXCEPTIONS = {"Error", "InputError", "NumericalError"}


def instances():
    g, truth = sk.generate_pose_graph(world="sphere", rings=4, poses_per_ring=10, ground_truth=True)
    text = sk.pose_graph_to_string(g, "g2o")
    read, report = sk.pose_graph_from_string(text, source="x.g2o"), None
    edges_only = "\n".join(line for line in text.splitlines() if line.startswith("EDGE"))
    import tempfile, os  # noqa: E401
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "edges.g2o")
        open(path, "w").write(edges_only + "\n")
        eo, report = sk.read_pose_graph(path, with_report=True)
    assert report.edges_only and report.completed_estimates == eo.num_vertices
    assert report.warnings == [] and report.repaired_information == 0
    problem = sk.build_pose_graph_problem(read)
    result = sk.optimize_pose_graph(read)
    est, ref = read.to_trajectory(), truth.to_trajectory()
    ate, rpe = sk.ate(est, ref), sk.rpe(est, ref)
    ba = sk.generate_ba_problem(cameras=4, points=60)
    ba_result = sk.optimize_bundle_adjustment(ba.copy())
    relaxed = sk.generate_pose_graph(num_poses=40)
    relaxer = sk.optimize_toro(relaxed, max_iterations=3)
    online = sk.hogman_online(sk.generate_pose_graph(num_poses=40))
    calib, _ = sk.generate_calibration_problem(laps=1)
    calib_report = sk.optimize_pose_graph(calib).calibration
    vio = {}
    if (data_root() / "vio" / "tumvi").exists():  # else test_vio.py skips (fails under CI) visibly
        vi = sk.simulate_visual_inertial("room1", duration=8.0, data=str(data_root()))
        vio = {"VisualInertialSim": vi, "VioResult": sk.run_vio(vi)}
    texture = np.random.default_rng(1).integers(0, 256, size=(96, 128), dtype=np.uint8)
    frontend = sk.ImageFrontend(sk.FrontendOptions(max_features=40))
    frontend.process(texture)
    frame = frontend.process(np.roll(texture, 2, axis=1))
    v = sk.Values()
    v.insert(0, [1.0, 2.0])
    v.insert(1, sk.SO3())
    return {
        "SO2": sk.SO2(0.1), "SE2": sk.SE2(1, 2, 3), "SO3": sk.SO3(), "SE3": sk.SE3(), "Similarity3": sk.Similarity3(),
        "Values": problem.values, "NoiseModel": sk.NoiseModel.unit(2), "RobustKernel": sk.HuberKernel(1.0),
        "HuberKernel": sk.HuberKernel(1.0), "CauchyKernel": sk.CauchyKernel(1.0), "TukeyKernel": sk.TukeyKernel(1.0),
        "GemanMcClureKernel": sk.GemanMcClureKernel(1.0), "DcsKernel": sk.DcsKernel(1.0),
        "Factor": problem.graph[0], "BetweenFactorSE3": problem.graph[0],
        "BetweenFactorSE2": sk.BetweenFactorSE2(0, 1, sk.SE2(), sk.NoiseModel.unit(3)),
        "PosePointFactor2": sk.PosePointFactor2(0, 1, [0, 0], sk.NoiseModel.unit(2)),
        "PosePointFactor3": sk.PosePointFactor3(0, 1, [0, 0, 0], sk.NoiseModel.unit(3)),
        "PriorFactorSE2": sk.PriorFactor(0, sk.SE2(), sk.NoiseModel.unit(3)),
        "PriorFactorSE3": sk.PriorFactor(0, sk.SE3(), sk.NoiseModel.unit(6)),
        "PriorFactorSO2": sk.PriorFactor(0, sk.SO2(), sk.NoiseModel.unit(1)),
        "PriorFactorSO3": sk.PriorFactor(0, sk.SO3(), sk.NoiseModel.unit(3)),
        "PriorFactorVector2": sk.PriorFactor(0, [0.0, 0.0], sk.NoiseModel.unit(2)),
        "PriorFactorVector3": sk.PriorFactor(0, [0.0, 0.0, 0.0], sk.NoiseModel.unit(3)),
        "CustomFactor": sk.CustomFactor([0], [2], sk.NoiseModel.unit(2), lambda values, jac: values[0]),
        "FactorGraph": problem.graph, "JacobianCheckResult": sk.check_jacobians(problem.graph, problem.values),
        "InformationStatus": sk.InformationStatus.SINGULAR,
        "InformationCheck": sk.check_information(np.diag([1.0, 0.0])),
        "InformationHealth": read.check_information(), "GraphVertex": read.vertex(0), "GraphEdge": read.edge(0),
        "PoseGraph": read, "Trajectory": est, "OptimizerOptions": sk.OptimizerOptions(),
        "IterationSummary": result.summary.trace[1], "Summary": result.summary, "Optimizer": sk.Optimizer(),
        "InitSummary": result.init, "PoseGraphProblem": problem, "PoseGraphResult": result,
        "PoseGraphSimOptions": sk.PoseGraphSimOptions(), "PoseGraphReadReport": report,
        "ErrorStatistics": ate.stats, "Association": ate.association, "PoseErrors": sk.compute_ate(est, ref),
        "RpeErrors": sk.compute_rpe(est, ref), "EvalResult": ate, "EvalResult_rpe": rpe,
        "BalProblem": ba, "BaSimOptions": sk.BaSimOptions(), "BundleAdjustmentResult": ba_result,
        "RelaxerSummary": relaxer, "RelaxerIteration": relaxer.trace[-1], "HogmanOnlineResult": online,
        "CalibrationReport": calib_report, "CalibrationParameterEstimate": calib_report.parameters[0],
        "CalibrationSimOptions": sk.CalibrationSimOptions(), "LandmarkFilter": sk.make_landmark_filter("ekf"),
        "FrontendOptions": frontend.options, "ImageFrontend": frontend, "FrontendFrame": frame,
        **vio,
    }


def public_classes():
    return sorted(n for n in dir(sk) if not n.startswith("_") and isinstance(getattr(sk, n), type)
                  and n not in EXCEPTIONS)


def test_every_class_has_an_instance_and_its_properties_read():
    made = instances()
    needs_data = set() if "VioResult" in made else {"VisualInertialSim", "VioResult"}
    missing = [n for n in public_classes() if n not in made and n not in needs_data]
    assert not missing, f"classes without an instance in this test: {missing}"
    for name, obj in made.items():
        repr(obj)
        for attr in dir(type(obj)):
            if attr.startswith("_"):
                continue
            if isinstance(getattr(type(obj), attr, None), property):
                getattr(obj, attr)  # every getter runs without raising
    assert made["InformationCheck"].status == sk.InformationStatus.SINGULAR
    assert made["EvalResult"].error_index.shape == made["EvalResult"].errors.shape
    assert made["EvalResult"].est.size() == made["EvalResult"].ref.size()
    assert made["CustomFactor"].error_function is not None


def test_every_function_is_called_by_a_test():
    text = "".join(p.read_text() for p in pathlib.Path(__file__).parent.glob("test_*.py"))
    functions = [n for n in dir(sk) if not n.startswith("_") and callable(getattr(sk, n))
                 and not isinstance(getattr(sk, n), type)]
    uncalled = [n for n in functions if not re.search(r"\bsk\." + n + r"\(", text)]
    assert not uncalled, f"functions no test calls: {uncalled}"


def test_blas_runtime_and_version():
    info = sk.blas_runtime()
    assert set(info) == {"vendor", "core", "config", "better_core"}
    assert sk.__version__.count(".") == 2


def test_pose_graph_remaining_members():
    g = sk.generate_pose_graph(num_poses=20)
    g.fixed = [0]
    assert g.fixed == [0] and g.gauge_vertices()[0] == [0]
    np.testing.assert_array_equal(g.vertex_ids(), g.pose_ids())
    assert g.complete_estimates_by_odometry() == 0  # every vertex has an estimate
    assert g.vertex(3).id == 3 and g.vertex(3).has_estimate


def test_exceptions_hierarchy():
    assert issubclass(sk.InputError, ValueError) and issubclass(sk.InputError, sk.Error)
    assert issubclass(sk.NumericalError, ArithmeticError) and issubclass(sk.Error, RuntimeError)
    with pytest.raises(sk.InputError) as e:
        sk.parse_robust_kernel("huber:x")
    assert e.value.field and e.value.line == 0


def doc_text(obj):
    """The docstring without pybind11's generated signature lines."""
    name = getattr(obj, "__name__", "?")
    lines = [line.strip() for line in (obj.__doc__ or "").splitlines()]
    return " ".join(line for line in lines if line and not line.startswith(name + "(")
                    and line != "Overloaded function." and not line[:2].rstrip(".").isdigit())


def test_everything_has_a_docstring():
    missing = []
    for n in dir(sk):
        o = getattr(sk, n)
        if n.startswith("_") or not callable(o):
            continue
        if not doc_text(o):
            missing.append(n)
        if isinstance(o, type) and n not in EXCEPTIONS:
            for attr, v in vars(o).items():
                if not attr.startswith("_") and callable(v) and not isinstance(v, type) and not doc_text(v):
                    missing.append(f"{n}.{attr}")
    assert not missing, f"without a docstring: {missing}"
