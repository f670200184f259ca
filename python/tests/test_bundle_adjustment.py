"""Bundle adjustment from Python: BalProblem arrays, the BAL reader/writer, sim:ba, and
optimize_bundle_adjustment against `slamkit optimize --format bal` and the Ceres reference cost."""
import json
import subprocess

import numpy as np
import pytest
import slamkit as sk
from conftest import cli_path, require_data


def small_problem():
    p, truth = sk.generate_ba_problem(ground_truth=True, cameras=12, points=400, seed=3)
    return p, truth


def test_generated_problem_converges_below_the_truth_cost():
    p, truth = small_problem()
    assert p.num_cameras == 12 and p.num_points == 400 and p.num_observations == p.pixels.shape[0]
    start = p.cost()
    r = sk.optimize_bundle_adjustment(p)
    assert r.summary.success() and r.summary.linear_solver.startswith("Schur complement")
    assert r.initial_cost == pytest.approx(start, rel=1e-12)
    assert r.final_cost == pytest.approx(p.cost(), rel=1e-9)  # estimates written back
    assert r.final_cost < truth.cost()  # the optimum fits the noisy pixels better than the truth


def test_arrays_round_trip_and_text_is_exact():
    p, _ = small_problem()
    q = sk.BalProblem(p.cameras, p.points, p.camera_index, p.point_index, p.pixels)
    assert sk.bal_to_string(q) == sk.bal_to_string(p)
    r = sk.bal_from_string(sk.bal_to_string(p), source="x.bal")
    np.testing.assert_array_equal(r.cameras, p.cameras)
    np.testing.assert_array_equal(r.points, p.points)
    c = p.copy()
    c.points = p.points + 1.0
    assert np.all(c.points == p.points + 1.0) and not np.all(p.points == c.points)


def test_normalize_and_perturb_keep_their_promises():
    p, _ = small_problem()
    cost = p.cost()
    scale = sk.normalize_bal(p)
    assert scale > 0 and p.cost() == pytest.approx(cost, rel=1e-9)
    before = p.points.copy()
    sk.perturb_bal(p, point_sigma=0.5, seed=2)
    assert np.abs(p.points - before).max() > 0
    sk.validate_bal_geometry(p)


def test_same_cost_as_the_cli(tmp_path):
    p, _ = small_problem()
    path = tmp_path / "problem.bal"
    sk.write_bal(p, str(path))
    out = tmp_path / "cli.json"
    subprocess.run([cli_path(), "optimize", str(path), "--format", "bal", "--json", str(out), "-q"], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    cli = json.loads(out.read_text())
    q = sk.read_bal(str(path))
    r = sk.optimize_bundle_adjustment(q)
    assert r.final_cost == pytest.approx(cli["final_cost"], rel=1e-9)  # both ½ Σ‖r‖²


def test_robust_kernel_options_and_callback():
    p, _ = small_problem()
    seen = []
    o = sk.bundle_adjustment_options()
    o.max_iterations = 3
    r = sk.optimize_bundle_adjustment(p, robust="huber:2", options=o, callback=lambda it: seen.append(it.cost))
    assert r.summary.iterations <= 3 and len(seen) == r.summary.iterations + 1
    assert sk.BaSimOptions(cameras=5).cameras == 5


def test_trafalgar21_reaches_the_ceres_cost():
    p = sk.read_bal(str(require_data("bal/problem-21-11315-pre.txt")))
    r = sk.optimize_bundle_adjustment(p)
    assert r.initial_cost == pytest.approx(4.413e6, abs=0.001e6)
    assert 3.0379e4 * 0.99 < r.final_cost < 3.0379e4 * 1.001  # Ceres 2.1: 3.0379e4


def test_bad_input_raises():
    with pytest.raises(sk.InputError) as e:
        sk.bal_from_string("1 1 1\n0 0 1.0 x\n", source="bad.bal")
    assert e.value.file == "bad.bal" and e.value.line == 2
    p, _ = small_problem()
    with pytest.raises(ValueError):
        sk.BalProblem(p.cameras, p.points, [0, 99], [0, 0], [[0, 0], [1, 1]])  # camera out of range
    with pytest.raises(ValueError):
        sk.BalProblem(p.cameras[:, :8], p.points, [0], [0], [[0, 0]])  # wrong shape
    with pytest.raises(ValueError):
        p.points = np.zeros((3, 3))  # the count must stay
    with pytest.raises(ValueError):
        sk.perturb_bal(p, point_sigma=float("nan"))
    with pytest.raises(TypeError):
        sk.generate_ba_problem(cameraz=3)
