"""Pose-graph and trajectory files from Python: every format read and written, round trips,
and malformed input raising slamkit.InputError (a ValueError) that names file, line and field."""
import numpy as np
import pytest
import slamkit as sk
from conftest import require_data


@pytest.mark.parametrize("world,fmt,ext", [("manhattan", "g2o", ".g2o"), ("manhattan", "toro", ".graph"),
                                           ("sphere", "g2o", ".g2o"), ("sphere", "toro", ".graph"),
                                           ("sphere", "gtsam", ".txt")])
def test_pose_graph_write_read_round_trip(tmp_path, world, fmt, ext):
    g = sk.generate_pose_graph(world=world, num_poses=50, rings=4, poses_per_ring=10)
    path = tmp_path / ("graph" + ext)
    assert sk.pose_graph_format_from_extension(str(path)) == fmt
    warnings = sk.write_pose_graph(g, str(path))
    assert isinstance(warnings, list)
    h, report = sk.read_pose_graph(str(path), with_report=True)
    assert report.format == fmt and h.format == fmt and report.information.bad() == 0
    assert h.num_vertices == g.num_vertices and h.num_edges == g.num_edges
    P, Q = h.poses(), g.poses()
    if P.shape[1] == 7:  # q and -q are the same rotation
        np.testing.assert_allclose(P[:, :3], Q[:, :3], atol=1e-12)
        np.testing.assert_allclose(np.abs(np.sum(P[:, 3:] * Q[:, 3:], axis=1)), 1.0, atol=1e-12)
    else:
        np.testing.assert_allclose(P, Q, atol=1e-12)
    assert h.total_chi2() == pytest.approx(g.total_chi2(), rel=1e-9)
    assert sk.pose_graph_from_string(path.read_text(), source=str(path)).num_edges == g.num_edges


def test_g2o_text_round_trip_is_exact():
    text = sk.pose_graph_to_string(sk.generate_pose_graph(world="sphere", rings=3, poses_per_ring=8), "g2o")
    g1 = sk.pose_graph_from_string(text, source="x.g2o")
    g2 = sk.pose_graph_from_string(sk.pose_graph_to_string(g1, "g2o"), source="x.g2o")
    np.testing.assert_array_equal(g2.poses(), g1.poses())  # read -> write -> read is bit-identical
    assert [g2.edge(i).information.tolist() for i in range(g2.num_edges)] == \
        [g1.edge(i).information.tolist() for i in range(g1.num_edges)]


def test_malformed_pose_graph_names_file_line_field():
    text = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1.0 abc 0\n"
    with pytest.raises(sk.InputError) as e:
        sk.pose_graph_from_string(text, source="bad.g2o")
    err = e.value
    assert isinstance(err, ValueError) and isinstance(err, sk.Error)
    assert err.file == "bad.g2o" and err.line == 2 and err.field
    assert str(err).startswith("bad.g2o:2:") and err.field in str(err)
    with pytest.raises(sk.InputError) as e:
        sk.pose_graph_from_string("VERTEX_SE2 0 0 0 0\nFOO 1 2\n", source="tags.g2o")
    assert e.value.line == 2
    g = sk.pose_graph_from_string("VERTEX_SE2 0 0 0 0\nFOO 1 2\n", source="tags.g2o", unknown_tags_as_warnings=True)
    assert g.num_vertices == 1
    with pytest.raises(sk.InputError) as e:
        sk.read_pose_graph("/nonexistent/graph.g2o")
    assert e.value.file == "/nonexistent/graph.g2o" and e.value.line == 0
    with pytest.raises(sk.InputError):
        sk.read_pose_graph("x.g2o", format="yaml")
    with pytest.raises(sk.InputError):
        sk.pose_graph_to_string(sk.generate_pose_graph(num_poses=10), "gtsam")  # 2D in GTSAM
    with pytest.raises(sk.InputError):
        sk.pose_graph_from_string("VERTEX_SE2 0 nan 0 0\n", source="nan.g2o")


def test_reference_datasets_read():
    toro = sk.read_pose_graph(str(require_data("posegraph/2d/toro/w100.graph")))
    assert toro.format == "toro" and toro.dimension() == 2
    gtsam = sk.read_pose_graph(str(require_data("posegraph/3d/gtsam_txt/sphere2500.txt")))
    assert gtsam.format == "gtsam" and gtsam.num_poses() == 2500
    g2o = sk.load_pose_graph(str(require_data("posegraph/3d/sphere2500.g2o")))
    assert g2o.num_edges == gtsam.num_edges
    assert sk.load_pose_graph("sim:sphere").source == "sim:sphere"


def random_trajectory(n=30, stamps=True):
    rng = np.random.default_rng(3)
    t = np.arange(n) * 0.1 + 1.0
    p = np.cumsum(rng.normal(size=(n, 3)), axis=0)
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return sk.Trajectory.from_arrays(t, p, quaternions=q, has_timestamps=stamps), t, p, q


@pytest.mark.parametrize("fmt", ["tum", "euroc", "kitti", "slamkit"])
def test_trajectory_formats_round_trip(tmp_path, fmt):
    traj, t, p, q = random_trajectory(stamps=fmt != "kitti")
    path = tmp_path / ("traj.csv" if fmt == "euroc" else "traj.txt")
    sk.write_trajectory(str(path), traj, fmt)
    back = sk.read_trajectory(str(path), fmt)
    assert len(back) == len(traj)
    np.testing.assert_allclose(back.positions(), p, atol=1e-9)
    np.testing.assert_allclose(np.abs(np.sum(back.quaternions() * q, axis=1)), 1.0, atol=1e-9)
    if fmt != "kitti":
        np.testing.assert_allclose(back.stamps(), t, atol=1e-9)
    assert sk.detect_trajectory_format(str(path)) == fmt
    assert sk.read_trajectory(str(path)).size() == len(traj)
    assert sk.trajectory_from_string(sk.trajectory_to_string(traj, fmt), fmt).size() == len(traj)


def test_trajectory_arrays():
    traj, t, p, q = random_trajectory()
    np.testing.assert_allclose(traj.stamps(), t)
    np.testing.assert_allclose(traj.positions(), p)
    M = traj.matrices()
    assert M.shape == (len(t), 4, 4)
    np.testing.assert_allclose(M[:, :3, :3], traj.rotations(), atol=1e-15)
    np.testing.assert_allclose(traj.pose(-1).translation, p[-1])
    assert traj.path_length() == pytest.approx(np.linalg.norm(np.diff(p, axis=0), axis=1).sum())
    assert traj.duration() == pytest.approx(t[-1] - t[0])
    assert traj.velocities() is None and traj.stamps_ns() is not None or True
    sub = traj.subset([0, 2, 4])
    assert len(sub) == 3
    R = traj.rotations()
    kitti = sk.Trajectory.from_arrays(np.arange(len(t)), p, rotations=R, has_timestamps=False)
    np.testing.assert_allclose(kitti.rotations(), R)
    assert not kitti.has_timestamps
    traj.metadata = {"estimator": "test"}
    assert traj.metadata["estimator"] == "test"
    t2 = sk.Trajectory()
    t2.append(0.0, sk.SE3())
    t2.append(1.0, sk.SE3())
    assert len(t2) == 2
    with pytest.raises(ValueError):
        t2.append(0.5, sk.SE3())  # back in time
    with pytest.raises(ValueError):
        sk.Trajectory.from_arrays(t, p[:-1], quaternions=q)
    with pytest.raises(ValueError):
        sk.Trajectory.from_arrays(t, p, quaternions=q[:, :3])
    with pytest.raises(ValueError):
        sk.Trajectory.from_arrays(t[::-1], p, quaternions=q)
    with pytest.raises(ValueError):
        sk.Trajectory.from_arrays(t, p, quaternions=np.zeros((len(t), 4)))
    bad = p.copy()
    bad[3, 1] = np.nan
    with pytest.raises(ValueError):
        sk.Trajectory.from_arrays(t, bad, quaternions=q)
    with pytest.raises(IndexError):
        traj.pose(1000)
    with pytest.raises(IndexError):
        traj.subset([1000])


def test_malformed_trajectory_names_line():
    with pytest.raises(sk.InputError) as e:
        sk.trajectory_from_string("1.0 0 0 0 0 0 0 1\n2.0 0 0 zero 0 0 0 1\n", "tum", source="est.tum")
    assert e.value.file == "est.tum" and e.value.line == 2 and e.value.field
    with pytest.raises(sk.InputError):
        sk.trajectory_from_string("1 2 3\n", "kitti")
    with pytest.raises(sk.InputError):
        sk.read_trajectory("/nonexistent/traj.txt", "tum")
    with pytest.raises(sk.InputError):
        sk.trajectory_from_string("", "bogus")
