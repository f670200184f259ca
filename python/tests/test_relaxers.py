"""The classic relaxers (SGD, TORO, relaxation, MLR, HOG-Man) and compare_backends from Python:
each reduces chi2 on a generated graph, matches the CLI, is deterministic, and refuses bad input."""
import json
import subprocess

import numpy as np
import pytest
import slamkit as sk
from conftest import cli_path


def graph():
    return sk.generate_pose_graph(num_poses=300, seed=5)


@pytest.mark.parametrize("name", ["sgd", "toro", "relaxation", "multilevel", "hogman"])
def test_each_relaxer_reduces_chi2_in_place(name):
    g = graph()
    sk.initialize_pose_graph(g, "odometry")
    start = g.total_chi2()
    runs = {"sgd": lambda: sk.optimize_sgd(g, max_iterations=30), "toro": lambda: sk.optimize_toro(g, max_iterations=30),
            "relaxation": lambda: sk.optimize_relaxation(g, max_iterations=30),
            "multilevel": lambda: sk.optimize_multilevel(g, max_iterations=30),
            "hogman": lambda: sk.optimize_hogman(g, max_iterations=30)}
    s = runs[name]()
    assert s.initial_chi2 == pytest.approx(start, rel=1e-12)
    assert s.final_chi2 < start and s.final_chi2 == pytest.approx(g.total_chi2(), rel=1e-9)
    assert s.trace[0].iteration == 0 and len(s.trace) == s.iterations + 1
    assert s.to_dict()["final_chi2"] == pytest.approx(s.final_chi2) and s.report()


def test_sgd_is_deterministic_and_the_callback_can_stop_it():
    a, b = graph(), graph()
    sk.initialize_pose_graph(a, "odometry"), sk.initialize_pose_graph(b, "odometry")
    sa, sb = sk.optimize_sgd(a, seed=7, max_iterations=10), sk.optimize_sgd(b, seed=7, max_iterations=10)
    assert sa.final_chi2 == sb.final_chi2
    np.testing.assert_array_equal(a.poses(), b.poses())
    c = graph()
    s = sk.optimize_sgd(c, max_iterations=50, callback=lambda it: it.iteration < 2)
    assert s.iterations == 2 and s.termination == "user callback"


def test_order_options_reach_the_solvers():
    # Seeds only matter once the random order starts: after the file-order iterations for SGD.
    runs = {}
    for seed in (1, 2):
        g = graph()
        sk.initialize_pose_graph(g, "odometry")
        runs[seed] = sk.optimize_sgd(g, seed=seed, file_order_iterations=0, max_iterations=5).final_chi2
    assert runs[1] != runs[2]
    g = graph()
    assert sk.optimize_toro(g, seed=3, shuffle_in_gradient_phase=False, max_iterations=5).iterations > 0
    with pytest.raises(ValueError):
        sk.optimize_sgd(graph(), file_order_iterations=-1)


def test_hogman_online_and_compare_match_the_cli(tmp_path):
    g = graph()
    online = sk.hogman_online(g)
    assert online.graph_size[-1] == 300 and len(online.time_per_pose_s) == len(online.graph_size)
    assert online.final_chi2 > 0 and online.levels >= 1 and online.top_solved.sum() >= 1
    path = tmp_path / "g.g2o"
    sk.write_pose_graph(graph(), str(path))
    out = tmp_path / "cmp.json"
    solvers = ["gn", "sgd", "toro"]
    subprocess.run([cli_path(), "compare", str(path), "--solvers", ",".join(solvers), "--time-budget", "5",
                    "--json", str(out)], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    cli = json.loads(out.read_text())
    c = sk.compare_backends(sk.read_pose_graph(str(path)), solvers=solvers, time_budget_s=5)
    assert {r["solver"] for r in c["runs"]} == set(solvers)
    assert c["start_chi2"] == pytest.approx(cli["start_chi2"], rel=1e-12)
    gn = [r for r in c["runs"] if r["solver"] == "gn"][0]
    assert gn["final_chi2"] == pytest.approx(c["best_chi2"], rel=1e-3) and gn["trace"][0][0] == 0


def test_bad_input_raises():
    g = graph()
    with pytest.raises(ValueError):
        sk.optimize_sgd(g, max_iterations=-1)
    with pytest.raises(ValueError):
        sk.optimize_relaxation(g, over_relaxation=2.5)
    with pytest.raises(ValueError):
        sk.optimize_toro(g, time_budget_s=float("nan"))
    with pytest.raises(TypeError):
        sk.optimize_toro(g, callback=3)
    with pytest.raises(ValueError):
        sk.compare_backends(g, time_budget_s=0)
    disconnected = sk.pose_graph_from_string("VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n", source="d.g2o")
    with pytest.raises(sk.InputError):
        sk.optimize_sgd(disconnected)
