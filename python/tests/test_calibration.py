"""Calibration inside the pose graph from Python: sim:calib2d/3d with their truth, estimated by
optimize_pose_graph(calibrate=...), with the same numbers as `slamkit optimize`."""
import json
import math
import subprocess

import pytest
import slamkit as sk
from conftest import cli_path


def test_calib2d_estimates_lie_within_four_sigma_of_the_truth():
    g, truth = sk.generate_calibration_problem(world="calib2d", laps=2, seed=4)
    r = sk.optimize_pose_graph(g, calibrate="auto")
    est = r.calibration.as_dict()
    assert set(truth) <= set(est), (truth, est)
    for name, true_value in truth.items():
        value, sigma = est[name]
        assert math.isfinite(sigma) and sigma > 0
        assert abs(value - true_value) < 4 * sigma, (name, value, true_value, sigma)
    assert r.calibration.covariance.shape == (len(r.calibration.parameters),) * 2
    p = r.calibration.parameters[0]
    assert p.observable and p.excitation > 0 and p.name in repr(p)


def test_calibrate_none_keeps_the_nominal_values_and_matches_the_cli(tmp_path):
    g, _, true_graph = sk.generate_calibration_problem(world="calib3d", seed=2, ground_truth=True)
    assert true_graph.num_vertices == g.num_vertices
    r = sk.optimize_pose_graph(g, calibrate="none")
    assert r.calibration.parameters == []
    out = tmp_path / "cli.json"
    subprocess.run([cli_path(), "optimize", "sim:calib2d?seed=3", "--json", str(out), "-q"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    cli = json.loads(out.read_text())
    d = sk.optimize_pose_graph(sk.load_pose_graph("sim:calib2d?seed=3"), as_dict=True)
    assert d["final_chi2"] == pytest.approx(cli["final_chi2"], rel=1e-12)
    assert [c["name"] for c in d["calibration"]] == [c["name"] for c in cli["calibration"]]
    for a, b in zip(d["calibration"], cli["calibration"]):
        assert a["value"] == pytest.approx(b["value"], rel=1e-12)
    assert sk.CalibrationSimOptions(laps=2).laps == 2


def test_bad_calibration_options_raise():
    g, _ = sk.generate_calibration_problem(laps=1)
    with pytest.raises(sk.InputError):
        sk.optimize_pose_graph(g, calibrate="wheels")
    with pytest.raises(sk.InputError):
        sk.generate_calibration_problem(world="calib4d")
    with pytest.raises(TypeError):
        sk.generate_calibration_problem(lapz=2)
