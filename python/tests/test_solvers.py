"""Optimizer, OptimizerOptions, Summary and IterationSummary from Python; the GIL is released
while the optimizer runs."""
import threading
import time

import numpy as np
import pytest
import slamkit as sk


@pytest.fixture(scope="module")
def problem():
    return sk.build_pose_graph_problem(sk.generate_pose_graph(world="sphere", rings=8, poses_per_ring=20, seed=2))


def test_options_keywords_and_defaults():
    o = sk.OptimizerOptions()
    assert o.algorithm == "lm" and o.max_iterations == 100 and o.function_tolerance == 1e-5
    assert o.gradient_tolerance == 1e-10 and o.parameter_tolerance == 1e-8 and o.blas_threads == 1
    assert o.linear_solver == "auto" and o.ordering == "auto" and o.gn_patience == 3
    o = sk.OptimizerOptions(algorithm="dogleg", max_iterations=7, ordering="amd", linear_solver="eigen")
    assert (o.algorithm, o.max_iterations, o.ordering, o.linear_solver) == ("dogleg", 7, "amd", "eigen")
    o.tr_initial_radius = 10.0
    assert o.tr_initial_radius == 10.0 and "dogleg" in repr(o)
    with pytest.raises(TypeError, match="unknown option"):
        sk.OptimizerOptions(max_iteration=3)
    with pytest.raises(sk.InputError):
        sk.OptimizerOptions(algorithm="newton")
    with pytest.raises(sk.InputError):
        sk.OptimizerOptions(ordering="random")
    with pytest.raises(TypeError):
        sk.Optimizer(sk.OptimizerOptions(), max_iterations=3)
    assert sk.Optimizer(o).options.algorithm == "dogleg"


@pytest.mark.parametrize("algorithm", ["gn", "lm", "tr-lm", "dogleg"])
def test_every_algorithm_converges(problem, algorithm):
    v = problem.values.copy()
    s = sk.Optimizer(algorithm=algorithm).optimize(problem.graph, v)
    assert s.success(), s.report()
    assert s.final_cost < 0.5 * s.initial_cost
    assert abs(problem.graph.cost(v) - s.final_cost) <= 1e-9 * s.final_cost
    assert s.options.algorithm == algorithm


def test_summary_contents(problem):
    v = problem.values.copy()
    s = sk.Optimizer(algorithm="lm").optimize(problem.graph, v)
    assert s.num_variables == len(v) and s.num_fixed == 1 and s.num_factors == len(problem.graph)
    assert s.tangent_dim == 6 * (len(v) - 1) and s.iterations == len(s.trace) - 1
    assert s.trace[0].iteration == 0 and s.trace[-1].cost == pytest.approx(s.final_cost)
    np.testing.assert_allclose(s.costs, [it.cost for it in s.trace])
    assert s.accepted_steps <= s.iterations and s.linear_solves >= s.accepted_steps
    assert s.time_total_s > 0 and s.linear_solver and s.ordering and s.blas
    assert "termination" in s.report().lower()
    d = s.to_dict()
    assert d["kind"] == "optimize" and d["iterations"] == s.iterations and d["final_chi2"] == s.final_cost
    assert isinstance(s.to_json(), str) and s.termination in ("function tolerance", "gradient tolerance",
                                                              "parameter tolerance")
    assert "IterationSummary" in repr(s.trace[1]) and s.trace[1].accepted in (True, False)


def test_callback_and_verbose(problem, capsys):
    seen = []
    v = problem.values.copy()
    s = sk.Optimizer(algorithm="lm").optimize(problem.graph, v, callback=lambda it: seen.append(it.iteration))
    assert seen == list(range(s.iterations + 1))
    v = problem.values.copy()
    s = sk.Optimizer(algorithm="lm").optimize(problem.graph, v, callback=lambda it: it.iteration < 2)
    assert s.termination == "user callback" and s.iterations == 2
    v = problem.values.copy()
    sk.Optimizer(algorithm="gn").optimize(problem.graph, v, verbose=True)
    out = capsys.readouterr().out
    assert out.count("\n") >= 3 and "cost" in out.splitlines()[0]

    def broken(it):
        raise RuntimeError("stop from callback")

    with pytest.raises(RuntimeError, match="stop from callback"):
        sk.Optimizer().optimize(problem.graph, problem.values.copy(), callback=broken)
    with pytest.raises(TypeError):
        sk.Optimizer().optimize(problem.graph, problem.values.copy(), callback=3)


def test_gil_is_released_while_optimizing():
    g = sk.generate_pose_graph(world="sphere", rings=30, poses_per_ring=40, seed=1)
    problem = sk.build_pose_graph_problem(g)
    done = threading.Event()
    result = {}

    def run():
        result["summary"] = sk.Optimizer(algorithm="lm", num_threads=1, max_iterations=30).optimize(
            problem.graph, problem.values)
        done.set()

    t = threading.Thread(target=run)
    start = time.perf_counter()
    t.start()
    ticks, last, worst_gap = 0, time.perf_counter(), 0.0
    while not done.is_set():
        now = time.perf_counter()
        worst_gap = max(worst_gap, now - last)
        last = now
        ticks += 1
    t.join()
    elapsed = time.perf_counter() - start
    assert result["summary"].success()
    # With the GIL held, this loop would stall for the whole run; released, it keeps spinning
    # (only Python's 5 ms switch interval and the scheduler interrupt it).
    assert elapsed > 0.05, "problem too small to tell"
    assert ticks > 1000 and worst_gap < 0.5 * elapsed, (ticks, worst_gap, elapsed)
