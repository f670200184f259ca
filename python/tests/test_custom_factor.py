"""CustomFactor: factors written in Python. The same problem built from Python factors and from
the built-in BetweenFactorSE2 optimizes to the same result; errors in the Python function
surface as Python exceptions, never as crashes."""
import numpy as np
import pytest
import slamkit as sk


def between_se2_error(z):
    """g2o's EDGE_SE2 error e = t2v(Z^-1 Xi^-1 Xj) with J_j = J_E, J_i = -J_E Ad(Xj^-1 Xi)."""
    z_inv = z.inverse()

    def error(values, jacobians):
        xi, xj = values
        E = z_inv * xi.between(xj)
        e = np.array([E.x, E.y, E.theta])
        if not jacobians:
            return e
        c, s = np.cos(E.theta), np.sin(E.theta)
        J_E = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        J_j = J_E
        J_i = -J_E @ xj.between(xi).adjoint()
        return e, [J_i, J_j]

    return error


def python_copy_of(problem, kernel=None):
    """The pose-graph problem with every BetweenFactorSE2 replaced by a CustomFactor."""
    graph = sk.FactorGraph()
    for k in range(len(problem.graph)):
        f = problem.graph[k]
        noise = sk.NoiseModel.information(f.noise_model.information_matrix())
        graph.add(sk.CustomFactor(f.keys, [sk.SE2, "SE2"], noise, between_se2_error(f.measured), kernel=kernel))
    return graph


@pytest.fixture(scope="module")
def problem():
    g = sk.generate_pose_graph(world="manhattan", num_poses=120, seed=4)
    return sk.build_pose_graph_problem(g)


def test_python_factor_matches_builtin(problem):
    py_graph = python_copy_of(problem)
    check = sk.check_jacobians(py_graph, problem.values)
    assert check.ok, check.message()
    assert abs(py_graph.cost(problem.values) - problem.graph.cost(problem.values)) < 1e-9 * problem.graph.cost(
        problem.values)
    for algorithm in ("lm", "gn"):
        v_builtin, v_python = problem.values.copy(), problem.values.copy()
        opt = sk.Optimizer(algorithm=algorithm, num_threads=1)
        s_builtin = opt.optimize(problem.graph, v_builtin)
        s_python = opt.optimize(py_graph, v_python)
        assert s_builtin.success() and s_python.success()
        assert s_python.iterations == s_builtin.iterations
        assert abs(s_python.final_cost - s_builtin.final_cost) <= 1e-9 * s_builtin.final_cost
        assert s_python.final_cost < 0.1 * s_python.initial_cost
        keys = [int(k) for k in v_builtin.keys()]
        np.testing.assert_allclose(v_python.se2_array(keys), v_builtin.se2_array(keys), atol=1e-9)


def test_python_factor_with_robust_kernel_matches_builtin():
    g = sk.generate_pose_graph(world="manhattan", num_poses=120, seed=4)
    robust = sk.build_pose_graph_problem(g, robust="cauchy:1")
    py_graph = python_copy_of(robust, kernel=sk.CauchyKernel(1.0))
    assert py_graph[0].robust_kernel.startswith("cauchy")
    v_b, v_p = robust.values.copy(), robust.values.copy()
    s_b = sk.Optimizer(algorithm="lm").optimize(robust.graph, v_b)
    s_p = sk.Optimizer(algorithm="lm").optimize(py_graph, v_p)
    assert abs(s_p.final_cost - s_b.final_cost) <= 1e-9 * s_b.final_cost and s_p.iterations == s_b.iterations


def test_python_factor_on_worker_threads(problem):
    py_graph = python_copy_of(problem)
    v1, v2 = problem.values.copy(), problem.values.copy()
    s1 = sk.Optimizer(algorithm="lm", num_threads=1).optimize(py_graph, v1)
    s2 = sk.Optimizer(algorithm="lm", num_threads=2).optimize(py_graph, v2)
    assert s2.threads == 2 and s1.final_cost == s2.final_cost  # linearization is deterministic


def test_range_only_localization_with_vector_variable():
    beacons = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, 10.0], [10.0, 10.0]])
    truth = np.array([2.0, 3.0])
    graph = sk.FactorGraph()
    for b in beacons:
        rng_b = np.linalg.norm(truth - b)

        def error(values, jacobians, b=b, rng_b=rng_b):
            d = values[0] - b
            n = np.linalg.norm(d)
            r = np.array([n - rng_b])
            return (r, [(d / n).reshape(1, 2)]) if jacobians else r

        graph.add(sk.CustomFactor([0], [2], sk.NoiseModel.isotropic(1, 0.1), error))
    v = sk.Values()
    v.insert(0, [8.0, 8.0])
    assert sk.check_jacobians(graph, v).ok
    s = sk.Optimizer(algorithm="lm").optimize(graph, v)
    assert s.success()
    np.testing.assert_allclose(v.at(0), truth, atol=1e-6)
    assert graph[0].types == ["Vector2"] and "CustomFactor" in repr(graph[0])


def single_factor_graph(fn, types=(sk.SE2,), dim=3):
    g = sk.FactorGraph()
    g.add(sk.CustomFactor([0], list(types), sk.NoiseModel.unit(dim), fn))
    v = sk.Values()
    v.insert(0, sk.SE2(1, 2, 0.1))
    return g, v


def test_python_exception_propagates():
    def broken(values, jacobians):
        raise KeyError("boom from Python")

    g, v = single_factor_graph(broken)
    with pytest.raises(KeyError, match="boom"):
        sk.Optimizer().optimize(g, v)
    with pytest.raises(KeyError):
        g.cost(v)
    with pytest.raises(KeyError):
        sk.Optimizer(num_threads=2).optimize(g, v)


def test_wrong_shapes_raise():
    g, v = single_factor_graph(lambda values, jac: np.zeros(2))
    with pytest.raises(ValueError, match="residual has shape"):
        g.cost(v)
    with pytest.raises(ValueError, match="must return"):
        sk.Optimizer().optimize(g, v)
    g, v = single_factor_graph(lambda values, jac: (np.zeros(3), [np.zeros((3, 2))]) if jac else np.zeros(3))
    with pytest.raises(ValueError, match="Jacobian 0 has shape"):
        sk.Optimizer().optimize(g, v)
    g, v = single_factor_graph(lambda values, jac: (np.zeros(3), []) if jac else np.zeros(3))
    with pytest.raises(ValueError, match="Jacobians"):
        sk.Optimizer().optimize(g, v)
    g, v = single_factor_graph(lambda values, jac: "nonsense")
    with pytest.raises(ValueError):
        g.cost(v)


def test_non_finite_residual_is_reported_not_crashing():
    g, v = single_factor_graph(lambda values, jac: (np.full(3, np.nan), [np.eye(3)]) if jac else np.full(3, np.nan))
    with pytest.raises(sk.NumericalError):
        g.cost(v)
    s = sk.Optimizer().optimize(g, v)
    assert not s.success() and s.termination == "non-finite cost"


def test_constructor_checks():
    f = lambda values, jac: np.zeros(3)  # noqa: E731
    with pytest.raises(ValueError):
        sk.CustomFactor([0, 1], [sk.SE2], sk.NoiseModel.unit(3), f)
    with pytest.raises(ValueError):
        sk.CustomFactor([0], ["SE4"], sk.NoiseModel.unit(3), f)
    with pytest.raises(ValueError):
        sk.CustomFactor([0], [sk.SE2], sk.NoiseModel.unit(3), f, residual_dim=2)
    with pytest.raises(TypeError):
        sk.CustomFactor([0], [sk.SE2], sk.NoiseModel.unit(3), "not callable")
    with pytest.raises(ValueError):
        sk.CustomFactor([], [], sk.NoiseModel.unit(3), f)
    g = sk.FactorGraph()
    g.add(sk.CustomFactor([0], ["SE3"], sk.NoiseModel.unit(3), f))
    v = sk.Values()
    v.insert(0, sk.SE2())
    with pytest.raises(sk.InputError):
        sk.Optimizer().optimize(g, v)  # the variable is an SE2, the factor wants an SE3
