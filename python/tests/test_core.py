"""Keys, Values, noise models, robust kernels, built-in factors, FactorGraph, the Jacobian
check and information health, from Python."""
import copy

import numpy as np
import pytest
import slamkit as sk
from conftest import numeric_jacobian


def test_keys():
    k = sk.symbol("x", 3)
    assert sk.symbol_char(k) == "x" and sk.symbol_index(k) == 3
    assert sk.key_to_string(k) == "x3" and sk.key_to_string(42) == "42"
    with pytest.raises(ValueError):
        sk.symbol("xy", 1)
    with pytest.raises(ValueError):
        sk.symbol("x", 1 << 60)


def test_values_typed_access():
    v = sk.Values()
    v.insert(1, sk.SE2(1, 2, 0.3))
    v.insert(2, sk.SE3.exp(np.arange(6) * 0.1))
    v.insert(3, sk.SO2(0.2))
    v.insert(4, sk.SO3.from_rpy(0.1, 0.2, 0.3))
    v.insert(5, np.array([1.0, 2.0, 3.0]))
    v.insert(sk.symbol("l", 0), [4.0, 5.0])
    assert len(v) == 6 and v.size() == 6 and 5 in v and v.exists(1) and not v.exists(99)
    assert isinstance(v.at(1), sk.SE2) and isinstance(v[2], sk.SE3)
    assert isinstance(v.at(3), sk.SO2) and isinstance(v.at(4), sk.SO3)
    np.testing.assert_array_equal(v.at(5), [1, 2, 3])
    assert [v.type_name(k) for k in (1, 2, 3, 4, 5)] == ["SE2", "SE3", "SO2", "SO3", "Vector3"]
    np.testing.assert_array_equal(v.keys()[:5], [1, 2, 3, 4, 5])
    v.update(1, sk.SE2(0, 0, 0))
    assert v.at(1).x == 0
    v.set_fixed(1)
    assert v.is_fixed(1) and v.num_fixed() == 1
    v.set_fixed(1, False)
    assert v.num_fixed() == 0
    assert v.parameters().shape == (3 + 7 + 1 + 4 + 3 + 2,)
    np.testing.assert_allclose(v.se2_array([1]), [[0, 0, 0]])
    np.testing.assert_allclose(v.se3_array([2]), [v.at(2).vector()])
    w = v.copy()
    w.update(5, [0.0, 0.0, 0.0])
    assert v.at(5)[0] == 1.0 and copy.deepcopy(v).at(5)[0] == 1.0
    assert "6 variables" in repr(v)


def test_values_bad_input_raises():
    v = sk.Values()
    v.insert(1, sk.SE2())
    with pytest.raises(sk.InputError) as e:
        v.insert(1, sk.SE2())
    assert isinstance(e.value, ValueError) and e.value.field == "key"
    with pytest.raises(sk.InputError):
        v.at(7)
    with pytest.raises(ValueError):
        v.update(1, sk.SE3())  # wrong type
    with pytest.raises(ValueError):
        v.insert(2, [np.nan, 1.0])
    with pytest.raises(ValueError):
        v.insert(3, np.zeros(12))  # vectors up to 9
    with pytest.raises(ValueError):
        v.insert(4, np.zeros((2, 2)))
    with pytest.raises(TypeError):
        v.insert(-1, sk.SE2())  # keys are unsigned


def test_noise_models():
    u = sk.NoiseModel.unit(3)
    assert u.kind == sk.NoiseModel.Kind.UNIT and u.dim == 3
    d = sk.NoiseModel.diagonal([0.1, 0.2])
    np.testing.assert_allclose(d.whiten([1.0, 1.0]), [10.0, 5.0])
    np.testing.assert_allclose(sk.NoiseModel.isotropic(2, 0.5).information_matrix(), 4 * np.eye(2))
    omega = np.array([[4.0, 1.0], [1.0, 3.0]])
    n = sk.NoiseModel.information(omega)
    R = n.sqrt_information()
    np.testing.assert_allclose(R.T @ R, omega, atol=1e-12)
    np.testing.assert_allclose(sk.NoiseModel.covariance(np.linalg.inv(omega)).information_matrix(), omega, atol=1e-12)
    with pytest.raises(sk.NumericalError):
        sk.NoiseModel.information([[1.0, 2.0], [2.0, 1.0]])
    with pytest.raises(ValueError):
        sk.NoiseModel.information(np.ones((2, 3)))
    with pytest.raises(ValueError):
        sk.NoiseModel.diagonal([0.1, -1.0])
    with pytest.raises(ValueError):
        sk.NoiseModel.isotropic(2, np.nan)
    with pytest.raises(ValueError):
        sk.NoiseModel.unit(0)
    with pytest.raises(ValueError):
        d.whiten([1.0, 2.0, 3.0])


@pytest.mark.parametrize("cls,name", [(sk.HuberKernel, "huber"), (sk.CauchyKernel, "cauchy"),
                                      (sk.TukeyKernel, "tukey"), (sk.GemanMcClureKernel, "geman-mcclure"),
                                      (sk.DcsKernel, "dcs")])
def test_robust_kernels(cls, name):
    k = cls(1.5)
    assert k.name == name and k.delta == 1.5
    rho, d1, d2 = k.evaluate(0.01)
    assert abs(rho - 0.01) < 1e-4 and abs(d1 - 1.0) < 1e-2
    h = 1e-6
    s = 4.0
    assert abs((k.evaluate(s + h)[0] - k.evaluate(s - h)[0]) / (2 * h) - k.evaluate(s)[1]) < 1e-6
    assert sk.make_robust_kernel(name, 1.5).name == name
    assert sk.parse_robust_kernel(name + ":1.5").delta == 1.5
    with pytest.raises(ValueError):
        cls(-1.0)


def test_kernel_parse_errors():
    with pytest.raises(sk.InputError):
        sk.parse_robust_kernel("nope:1")
    with pytest.raises(sk.InputError):
        sk.make_robust_kernel("huber", -2.0)


def two_pose_problem():
    v = sk.Values()
    v.insert(0, sk.SE2(0, 0, 0))
    v.insert(1, sk.SE2(1.1, 0.1, 0.05))
    g = sk.FactorGraph()
    g.add(sk.PriorFactor(0, sk.SE2(0, 0, 0), sk.NoiseModel.isotropic(3, 0.01)))
    g.add(sk.BetweenFactorSE2(0, 1, sk.SE2(1, 0, 0), sk.NoiseModel.diagonal([0.1, 0.1, 0.05])))
    return g, v


def test_factor_graph_and_factors():
    g, v = two_pose_problem()
    assert len(g) == 2 and g.size() == 2
    assert isinstance(g[0], sk.PriorFactorSE2) and isinstance(g[-1], sk.BetweenFactorSE2)
    f = g[1]
    assert f.keys == [0, 1] and f.residual_dim == 3 and f.robust_kernel is None
    assert f.noise_model.dim == 3
    noise = g[1].noise_model
    reused = sk.BetweenFactorSE2(0, 1, sk.SE2(), noise)
    del g, f  # the copy of the noise model outlives the factor it came from
    g, _ = two_pose_problem()
    f = g[1]
    np.testing.assert_allclose(reused.noise_model.information_matrix(), np.diag([100.0, 100.0, 400.0]))
    r, (J0, J1) = f.error(v)
    assert r.shape == (3,) and J0.shape == (3, 3) and J1.shape == (3, 3)
    # Jacobian of the raw residual against central differences on the tangent space
    def residual_at(x1):
        w = v.copy()
        w.update(1, x1)
        return f.error(w)[0]
    np.testing.assert_allclose(J1, numeric_jacobian(residual_at, v.at(1), lambda z, d: z.plus(d), 3), atol=1e-6)
    cost, rw, Jw = f.linearize(v)
    np.testing.assert_allclose(cost, rw @ rw)
    np.testing.assert_allclose(g.cost(v), sum(g[i].cost(v) for i in range(len(g))))
    g.check_against(v)
    check = sk.check_jacobians(g, v)
    assert check.ok and bool(check) and check.factors_checked == 2
    assert "ok" in check.message().lower() or check.worst_error < 1e-6
    with pytest.raises(IndexError):
        g[5]


def test_all_builtin_factor_jacobians():
    v = sk.Values()
    v.insert(0, sk.SE2(0.3, -0.2, 0.4))
    v.insert(1, sk.SE2(1.1, 0.1, 0.05))
    v.insert(2, sk.SE3.exp([0.1, 0.2, 0.3, 0.2, -0.1, 0.3]))
    v.insert(3, sk.SE3.exp([1.0, 0.1, -0.2, 0.0, 0.3, 0.1]))
    v.insert(4, [2.0, 1.0])
    v.insert(5, [1.0, 2.0, 3.0])
    v.insert(6, sk.SO2(0.3))
    v.insert(7, sk.SO3.from_rpy(0.1, 0.2, 0.3))
    g = sk.FactorGraph()
    g.add(sk.BetweenFactorSE2(0, 1, sk.SE2(1, 0, 0.1), sk.NoiseModel.unit(3)))
    for form in ("quaternion", "log"):
        f = sk.BetweenFactorSE3(2, 3, sk.SE3.exp([1, 0, 0, 0, 0, 0.1]), sk.NoiseModel.unit(6), form=form)
        assert f.form == form
        g.add(f)
    g.add(sk.PosePointFactor2(0, 4, [1.0, 0.5], sk.NoiseModel.unit(2), kernel=sk.HuberKernel(1.0)))
    g.add(sk.PosePointFactor3(2, 5, [1.0, 0.5, 0.2], sk.NoiseModel.unit(3), sensor_offset=sk.SE3.exp([0.1] * 6)))
    for key, value in [(0, sk.SE2(0, 0, 0)), (2, sk.SE3()), (6, sk.SO2(0.1)), (7, sk.SO3()), (4, [0.0, 0.0]),
                       (5, [0.0, 0.0, 0.0])]:
        g.add(sk.PriorFactor(key, value, sk.NoiseModel.unit(v.at(key).dim if hasattr(v.at(key), "dim")
                                                             else len(v.at(key)))))
    check = sk.check_jacobians(g, v)
    assert check.ok, check.message()
    assert check.factors_checked == len(g) == 11
    assert g[3].robust_kernel.startswith("huber")
    assert isinstance(g[6], sk.PriorFactorSE3) and isinstance(g[10], sk.PriorFactorVector3)


def test_factor_bad_arguments():
    with pytest.raises(ValueError):
        sk.BetweenFactorSE2(0, 1, sk.SE2(), sk.NoiseModel.unit(2))  # wrong noise dimension
    with pytest.raises(ValueError):
        sk.PosePointFactor3(0, 1, [1.0, 2.0], sk.NoiseModel.unit(3))
    with pytest.raises(ValueError):
        sk.PriorFactor(0, [1.0, np.nan], sk.NoiseModel.unit(2))
    with pytest.raises(ValueError):
        sk.BetweenFactorSE3(0, 1, sk.SE3(), sk.NoiseModel.unit(6), form="euler")
    g, v = two_pose_problem()
    w = sk.Values()
    w.insert(0, sk.SE3())
    w.insert(1, sk.SE2())
    with pytest.raises(sk.InputError):
        g.cost(w)
    with pytest.raises(sk.InputError):
        g[1].error(w)


def test_information_health():
    c = sk.check_information(np.eye(3))
    assert c.status == sk.InformationStatus.POSITIVE_DEFINITE and c.min_eigenvalue == 1.0
    assert sk.check_information([[1, 0], [0, -1]]).status == sk.InformationStatus.INDEFINITE
    assert sk.check_information([[1, 0], [0, np.nan]]).status == sk.InformationStatus.NOT_FINITE
    P = sk.project_to_psd(np.array([[1.0, 0.0], [0.0, -1.0]]))
    assert np.linalg.eigvalsh(P).min() > 0
