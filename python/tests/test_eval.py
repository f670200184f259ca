"""Trajectory evaluation from Python: ATE/RPE on KITTI 00 equal evo's stored results (every
statistic and every per-pose error), association, alignment, pair selection, statistics,
the run document, the SVG figure and the HTML report."""
import io
import json
import zipfile

import numpy as np
import pytest
import slamkit as sk
from conftest import require_data

REL_TOL = 1e-6  # the acceptance tolerance of tests/eval/evo_reference_test.cpp


def evo_result(name):
    """stats.json and the per-pair error array of one of evo's stored results (zip)."""
    with zipfile.ZipFile(require_data(f"vio/eval_reference/{name}.zip")) as z:
        return json.loads(z.read("stats.json")), np.load(io.BytesIO(z.read("error_array.npz")))


@pytest.fixture(scope="module")
def kitti():
    gt = sk.read_trajectory(str(require_data("vio/eval_reference/KITTI_00_gt.txt")), "kitti")
    orb = sk.read_trajectory(str(require_data("vio/eval_reference/KITTI_00_ORB.txt")), "kitti")
    return orb, gt


def expect_evo(stats, evo_stats):
    for key in ("rmse", "mean", "median", "std", "min", "max", "sse"):
        assert getattr(stats, key) == pytest.approx(evo_stats[key], rel=REL_TOL), key


def test_kitti_ate_equals_evo(kitti):
    est, ref = kitti
    evo_stats, evo_errors = evo_result("orb_ape")
    r = sk.ate(est, ref)  # evo_ape kitti KITTI_00_gt.txt KITTI_00_ORB.txt -a
    assert r.association.by_index and r.stats.count == 4541 and len(r.association) == 4541
    expect_evo(r.stats, evo_stats)
    assert r.rmse == r.stats.rmse == pytest.approx(1.3034497145650266, rel=REL_TOL)
    assert r.errors.shape == evo_errors.shape
    assert np.max(np.abs(r.errors - evo_errors)) < 1e-9
    assert r.title.startswith("APE w.r.t. translation part (m)")
    same = sk.evaluate(est, ref, metric="ate", align="se3")
    assert same.stats.rmse == r.stats.rmse


def test_kitti_rpe_equals_evo(kitti):
    est, ref = kitti
    evo_stats, evo_errors = evo_result("orb_rpe")
    r = sk.rpe(est, ref, delta=10.0, delta_unit="m")  # evo_rpe kitti ... --delta 10 --delta_unit m
    expect_evo(r.stats, evo_stats)
    assert np.max(np.abs(r.errors - evo_errors)) < 1e-9
    assert r.pairs.shape == (len(r.errors), 2)
    aligned = sk.rpe(est, ref, delta=10.0, delta_unit="m", align="se3")
    assert aligned.stats.rmse == pytest.approx(r.stats.rmse, rel=1e-9)  # RPE ignores a rigid alignment


def test_pipeline_pieces_agree_with_evaluate(kitti):
    est, ref = kitti
    a = sk.associate(est, ref)
    assert a.by_index and len(a.est_ids) == len(est)
    S = sk.compute_alignment(est, ref, "se3")
    assert abs(S.scale - 1.0) < 1e-15
    aligned = sk.apply_alignment(est, S)
    errs = sk.compute_ate(aligned, ref)
    r = sk.ate(est, ref)
    np.testing.assert_allclose(errs.errors, r.errors, atol=1e-12)
    np.testing.assert_allclose(errs.translation, r.translation_errors, atol=1e-12)
    assert errs.rotation_deg.shape == r.rotation_errors_deg.shape
    st = sk.compute_statistics(errs.errors)
    assert st.rmse == pytest.approx(r.stats.rmse, rel=1e-12) and st.count == len(errs.errors)
    assert set(st.to_dict()) >= {"rmse", "mean", "median", "std", "min", "max", "sse", "count"}
    pairs = sk.select_pairs(aligned, 10.0, "m")
    rpe = sk.compute_rpe(aligned, ref, delta=10.0, delta_unit="m")
    np.testing.assert_array_equal(rpe.pairs, pairs)
    np.testing.assert_allclose(rpe.errors, sk.rpe(est, ref, delta=10.0, delta_unit="m").errors, atol=1e-9)
    sim = sk.ate(est, ref, align="sim3")
    assert sim.rmse <= r.rmse + 1e-12 and sim.alignment.scale != 1.0


def synthetic_pair(n=200, noise=0.01):
    rng = np.random.default_rng(1)
    t = np.arange(n) * 0.05
    p = np.stack([np.cos(t), np.sin(t), 0.1 * t], axis=1) * 5
    q = np.stack([np.zeros(n), np.zeros(n), np.sin(t / 2), np.cos(t / 2)], axis=1)  # yaw = t
    ref = sk.Trajectory.from_arrays(t, p, quaternions=q)
    R = sk.SO3.from_rpy(0.1, 0.05, 0.8)
    S = sk.Similarity3(R.matrix(), [1.0, 2.0, 0.5], 1.0)
    est = sk.Trajectory.from_arrays(t + 0.002, S.apply(p + rng.normal(scale=noise, size=p.shape)),
                                    quaternions=np.array([(R * sk.SO3(qk)).quaternion() for qk in q]))
    return est, ref


def test_timestamp_association_alignment_modes_and_relations():
    est, ref = synthetic_pair()
    a = sk.associate(est, ref, max_diff=0.01)
    assert not a.by_index and len(a) == len(est)
    with pytest.raises(sk.Error):
        sk.associate(est, ref, max_diff=0.001, offset=10.0)  # nothing matches
    r = sk.ate(est, ref)
    assert r.rmse < 0.05
    assert sk.ate(est, ref, align="none").rmse > 1.0
    for mode in ("none", "origin", "se3", "sim3", "4dof", "scale"):
        assert np.isfinite(sk.ate(est, ref, align=mode).rmse)
    for rel in ("trans_part", "angle_deg", "angle_rad", "rot_part", "full", "point_distance"):
        assert np.isfinite(sk.evaluate(est, ref, relation=rel).rmse)
    for unit, delta in (("f", 5), ("m", 1.0), ("d", 5.0), ("r", 0.1), ("s", 1.0)):
        rr = sk.rpe(est, ref, delta=delta, delta_unit=unit)
        assert rr.pairs.shape[1] == 2 and np.isfinite(rr.rmse)
    assert len(sk.rpe(est, ref, delta=5, all_pairs=True).errors) > len(sk.rpe(est, ref, delta=5).errors)
    assert np.isfinite(sk.rpe(est, ref, delta=5, pairs_from_reference=True).rmse)
    for bad in (dict(align="se4"), dict(relation="nope"), dict(metric="xyz"), dict(delta_unit="q", metric="rpe")):
        with pytest.raises(sk.InputError):
            sk.evaluate(est, ref, **bad)
    with pytest.raises(ValueError):
        sk.evaluate(est, ref, max_diff=np.nan)
    with pytest.raises(ValueError):
        sk.compute_statistics([])
    with pytest.raises(ValueError):
        sk.compute_statistics([1.0, np.nan])


def test_run_document_plot_and_report(tmp_path):
    est, ref = synthetic_pair()
    r = sk.ate(est, ref)
    doc = r.to_dict(label="synthetic", est_path="est.tum", ref_path="ref.tum")
    assert doc["kind"] == "ate" and doc["rmse"] == r.rmse and doc["label"] == "synthetic"
    svg = r.plot(str(tmp_path / "ate.svg"))
    assert svg.startswith("<?xml") and "<svg" in svg and (tmp_path / "ate.svg").read_text() == svg
    rpe_doc = sk.rpe(est, ref, delta=5).to_dict(label="rpe")
    run_file = tmp_path / "rpe.json"
    run_file.write_text(json.dumps(rpe_doc))
    opt = sk.optimize_pose_graph(sk.generate_pose_graph(num_poses=200), as_dict=True)
    opt["label"] = "manhattan"
    html = sk.render_html_report([doc, str(run_file), opt], title="Python report",
                                 output=str(tmp_path / "report.html"))
    assert "<html" in html.lower() and "Python report" in html and "synthetic" in html and "manhattan" in html
    assert (tmp_path / "report.html").read_text() == html
    with pytest.raises(sk.InputError):
        sk.render_html_report([{"kind": "unknown"}])
    with pytest.raises(sk.InputError):
        sk.render_html_report([str(tmp_path / "missing.json")])
    with pytest.raises(sk.InputError):
        r.plot(str(tmp_path / "no" / "dir" / "x.svg"))


def test_single_figures():
    est, ref = synthetic_pair()
    a, b = sk.ate(est, ref), sk.ate(est, ref, align="sim3")
    for svg in (sk.plot_trajectories([a, b.to_dict(label="sim3")]), sk.plot_trajectories([a], view="side"),
                sk.plot_error_over_time([a]), sk.plot_error_over_time([a, b]), sk.plot_error_along_path(a),
                sk.plot_error_histogram([a, b])):
        assert svg.lstrip().startswith("<svg") and svg.rstrip().endswith("</svg>")
    with pytest.raises(ValueError):
        sk.plot_trajectories([a], view="front")
    with pytest.raises(ValueError):
        sk.plot_error_histogram([])
    with pytest.raises(ValueError):
        sk.plot_error_over_time([a], width=np.nan)
    with pytest.raises(sk.InputError):
        sk.plot_error_along_path({"kind": "ate"})
