"""slamkit geometry from Python: SO2, SE2, SO3, SE3, Similarity3, Umeyama. Every Jacobian the
bindings return is checked against central differences of J = d Log(out^-1 out(in ⊞ δ)) / dδ."""
import pickle

import numpy as np
import pytest
import slamkit as sk
from conftest import numeric_jacobian

rng = np.random.default_rng(7)
GROUPS = [(sk.SO2, 1, 2), (sk.SE2, 3, 2), (sk.SO3, 3, 3), (sk.SE3, 6, 3)]


def random_element(G, dim):
    return G.exp(rng.normal(scale=0.8, size=dim))


def group_jacobian(out_fn, x, dim):
    """d Log(out(x)^-1 out(x ⊞ δ)) / dδ for a group-valued out_fn (x a group element or a vector)."""
    y0 = out_fn(x)
    plus = (lambda z, d: z + d) if isinstance(x, np.ndarray) else (lambda z, d: z.plus(d))
    return numeric_jacobian(lambda z: np.atleast_1d(y0.between(out_fn(z)).log()), x, plus, dim)


@pytest.mark.parametrize("G,dim,pdim", GROUPS)
def test_exp_log_round_trip_and_compose(G, dim, pdim):
    tau = rng.normal(scale=0.5, size=dim)
    X = G.exp(tau)
    np.testing.assert_allclose(np.atleast_1d(X.log()), tau, atol=1e-12)
    Y = random_element(G, dim)
    np.testing.assert_allclose((X * Y).matrix(), X.matrix() @ Y.matrix(), atol=1e-12)
    np.testing.assert_allclose((X * X.inverse()).matrix(), G.identity().matrix(), atol=1e-12)
    np.testing.assert_allclose(X.between(Y).matrix(), (X.inverse() * Y).matrix(), atol=1e-12)
    np.testing.assert_allclose(np.atleast_1d(X.plus(tau).minus(X)), tau, atol=1e-10)
    assert G.dim == dim
    assert repr(X).startswith(G.__name__ + "(")


@pytest.mark.parametrize("G,dim,pdim", GROUPS)
def test_jacobians_match_numeric(G, dim, pdim):
    X, Y = random_element(G, dim), random_element(G, dim)
    _, Ja, Jb = X.compose(Y, jacobians=True)
    np.testing.assert_allclose(Ja, group_jacobian(lambda a: a * Y, X, dim), atol=1e-6)
    np.testing.assert_allclose(Jb, group_jacobian(lambda b: X * b, Y, dim), atol=1e-6)
    _, Ji = X.inverse(jacobians=True)
    np.testing.assert_allclose(Ji, group_jacobian(lambda a: a.inverse(), X, dim), atol=1e-6)
    _, Ja, Jb = X.between(Y, jacobians=True)
    np.testing.assert_allclose(Ja, group_jacobian(lambda a: a.between(Y), X, dim), atol=1e-6)
    np.testing.assert_allclose(Jb, group_jacobian(lambda b: X.between(b), Y, dim), atol=1e-6)
    # log: d Log(X ⊞ δ) / dδ; exp: d Log(Exp(τ)^-1 Exp(τ + δ)) / dδ = Jr(τ).
    tau, Jl = X.log(jacobians=True)
    np.testing.assert_allclose(
        Jl, numeric_jacobian(lambda z: np.atleast_1d(z.log()), X, lambda z, d: z.plus(d), dim), atol=1e-6)
    t = rng.normal(scale=0.5, size=dim)
    _, Je = G.exp(t, jacobians=True)
    np.testing.assert_allclose(Je, group_jacobian(lambda v: G.exp(v), t, dim).reshape(dim, dim), atol=1e-6)
    np.testing.assert_allclose(Je, G.right_jacobian(t), atol=1e-12)
    np.testing.assert_allclose(G.left_jacobian(t), G.right_jacobian(-t), atol=1e-12)
    np.testing.assert_allclose(G.right_jacobian_inverse(t) @ G.right_jacobian(t), np.eye(dim), atol=1e-9)
    np.testing.assert_allclose(G.left_jacobian_inverse(t) @ G.left_jacobian(t), np.eye(dim), atol=1e-9)
    # plus / minus
    d = rng.normal(scale=0.3, size=dim)
    _, Jx, Jd = X.plus(d, jacobians=True)
    np.testing.assert_allclose(Jx, group_jacobian(lambda a: a.plus(d), X, dim), atol=1e-6)
    np.testing.assert_allclose(Jd, group_jacobian(lambda v: X.plus(v), d, dim).reshape(dim, dim), atol=1e-6)
    _, Jx, Jy = X.minus(Y, jacobians=True)
    np.testing.assert_allclose(
        Jx, numeric_jacobian(lambda z: np.atleast_1d(z.minus(Y)), X, lambda z, e: z.plus(e), dim), atol=1e-6)
    np.testing.assert_allclose(
        Jy, numeric_jacobian(lambda z: np.atleast_1d(X.minus(z)), Y, lambda z, e: z.plus(e), dim), atol=1e-6)
    # adjoint: X Exp(τ) = Exp(Ad τ) X
    lhs = X * G.exp(t)
    rhs = G.exp(X.adjoint() @ t) * X
    np.testing.assert_allclose(lhs.matrix(), rhs.matrix(), atol=1e-9)


@pytest.mark.parametrize("G,dim,pdim", GROUPS)
def test_act_on_points_and_arrays(G, dim, pdim):
    X = random_element(G, dim)
    M = X.matrix()
    R, t = (M, np.zeros(pdim)) if M.shape[0] == pdim else (M[:pdim, :pdim], M[:pdim, pdim])
    pts = rng.normal(size=(5, pdim))
    out = X.act(pts)
    assert out.shape == (5, pdim)
    np.testing.assert_allclose(out, pts @ R.T + t, atol=1e-12)
    p, Jx, Jp = X.act(pts[0], jacobians=True)
    np.testing.assert_allclose(p, out[0], atol=1e-12)
    np.testing.assert_allclose(Jx.reshape(pdim, dim), numeric_jacobian(lambda z: z.act(pts[0]), X,
                                                                        lambda z, d: z.plus(d), dim), atol=1e-6)
    np.testing.assert_allclose(Jp, R, atol=1e-12)


@pytest.mark.parametrize("G,dim,pdim", GROUPS)
def test_pickle_round_trip(G, dim, pdim):
    X = random_element(G, dim)
    np.testing.assert_allclose(pickle.loads(pickle.dumps(X)).matrix(), X.matrix(), atol=1e-15)


def test_constructors_and_conversions():
    R = sk.SO3.from_rpy(0.1, -0.2, 0.3)
    np.testing.assert_allclose(R.to_rpy(), [0.1, -0.2, 0.3], atol=1e-12)
    q = R.quaternion()
    np.testing.assert_allclose(sk.SO3(q).matrix(), R.matrix(), atol=1e-15)
    np.testing.assert_allclose(sk.SO3.from_quaternion(q).matrix(), R.matrix(), atol=1e-15)
    np.testing.assert_allclose(sk.SO3.from_matrix(R.matrix()).quaternion(), q, atol=1e-15)
    T = sk.SE3(R, [1.0, 2.0, 3.0])
    np.testing.assert_allclose(sk.SE3.from_matrix(T.matrix()).matrix(), T.matrix(), atol=1e-15)
    np.testing.assert_allclose(sk.SE3.from_matrix(T.matrix()[:3]).matrix(), T.matrix(), atol=1e-15)
    np.testing.assert_allclose(sk.SE3.from_vector(T.vector()).matrix(), T.matrix(), atol=1e-15)
    np.testing.assert_allclose(sk.SE3(q, [1, 2, 3]).translation, [1, 2, 3])
    np.testing.assert_allclose(T.rotation.matrix(), R.matrix())
    P = sk.SE2(1.0, 2.0, 0.5)
    assert (P.x, P.y, P.theta) == (1.0, 2.0, 0.5)
    np.testing.assert_allclose(sk.SE2.from_matrix(P.matrix()).vector(), [1, 2, 0.5], atol=1e-15)
    np.testing.assert_allclose(sk.SE2.from_vector([1, 2, 0.5]).matrix(), P.matrix())
    np.testing.assert_allclose(sk.SE2(sk.SO2(0.5), [1, 2]).matrix(), P.matrix())
    np.testing.assert_allclose(P.translation, [1, 2])
    assert abs(P.rotation.angle - 0.5) < 1e-15
    assert abs(sk.SO2.from_matrix(sk.SO2(0.3).matrix()).angle - 0.3) < 1e-15
    assert abs(sk.SO2(4.0).angle - (4.0 - 2 * np.pi)) < 1e-12  # wrapped to (-pi, pi]


def test_bad_arguments_raise_never_crash():
    with pytest.raises(ValueError):
        sk.SE3.exp(np.zeros(5))
    with pytest.raises(ValueError):
        sk.SE3.exp([np.nan] * 6)
    with pytest.raises(ValueError):
        sk.SE2(np.inf, 0, 0)
    with pytest.raises(ValueError):
        sk.SO3([0, 0, 0, 0])
    with pytest.raises(ValueError):
        sk.SO3([np.nan, 0, 0, 1])
    with pytest.raises(ValueError):
        sk.SE3.from_matrix(np.eye(3))
    with pytest.raises(ValueError):
        sk.SE3.identity().act(np.zeros((4, 2)))
    with pytest.raises(ValueError):
        sk.SE3.identity().act(np.zeros((2, 2, 3)))
    with pytest.raises(ValueError):
        sk.SE2.identity().act(np.zeros((3, 2)), jacobians=True)
    with pytest.raises(ValueError):
        sk.SO3.from_matrix([[1, 2], [3, 4]])
    with pytest.raises(ValueError):
        sk.SE3.exp("not an array")


def test_similarity_and_umeyama():
    S_true = sk.Similarity3(sk.SO3.from_rpy(0.2, 0.1, -0.4).matrix(), [1.0, -2.0, 0.5], 1.7)
    src = rng.normal(size=(50, 3))
    dst = S_true.apply(src)
    S = sk.umeyama(src, dst, with_scale=True)
    np.testing.assert_allclose(S.matrix(), S_true.matrix(), atol=1e-10)
    assert abs(S.scale - 1.7) < 1e-12
    np.testing.assert_allclose(S.inverse().apply(dst), src, atol=1e-10)
    np.testing.assert_allclose(S.rigid_part().rotation.matrix(), S_true.rotation, atol=1e-10)
    np.testing.assert_allclose(S.apply(src[0]), dst[0], atol=1e-10)
    rigid = sk.umeyama(src, sk.Similarity3(S_true.rotation, S_true.translation).apply(src))
    assert abs(rigid.scale - 1.0) < 1e-15
    yaw = sk.Similarity3(sk.SO3.from_rpy(0, 0, 0.7).matrix(), [1, 2, 3])
    np.testing.assert_allclose(sk.umeyama_yaw(src, yaw.apply(src)).matrix(), yaw.matrix(), atol=1e-10)
    with pytest.raises(ValueError):
        sk.umeyama(src, dst[:10])
    with pytest.raises(ValueError):
        sk.umeyama(src[:, :2], dst[:, :2])
    with pytest.raises(ValueError):
        sk.umeyama(src[:2], dst[:2])  # degenerate: std::invalid_argument
    with pytest.raises(ValueError):
        sk.Similarity3(np.eye(3), [0, 0, 0], np.nan)
