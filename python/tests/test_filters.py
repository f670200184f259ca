"""The landmark-SLAM filters from Python: a filter stepped by hand over a simulated run, EKF and
EIF agreeing, the Monte-Carlo summary equal to `slamkit filter --json`, and bad input refused."""
import json
import subprocess

import numpy as np
import pytest
import slamkit as sk
from conftest import cli_path


def world():
    return sk.generate_landmark_world(30, seed=1)


def step_through(f, run, steps):
    for k in range(steps):
        v, steer = run["controls"][k]
        f.predict(v, steer, run["dt"])
        if run["observations"][k] is not None:
            f.update(run["observations"][k])
    return f


def test_ekf_tracks_the_truth_and_agrees_with_the_eif():
    landmarks, waypoints = world()
    run = sk.simulate_landmark_run(landmarks, waypoints, seed=3, steps=800)
    assert run["true_poses"].shape == (800, 3) and run["controls"].shape == (800, 2)
    ekf = step_through(sk.make_landmark_filter("ekf"), run, 800)
    eif = step_through(sk.make_landmark_filter("eif"), run, 800)
    e = ekf.pose() - run["true_poses"][799]
    P = ekf.pose_covariance()
    assert e @ np.linalg.solve(P, e) < 16.3  # chi2_3 at 99.9%
    np.testing.assert_allclose(ekf.pose(), eif.pose(), atol=1e-6)
    ids, means, covs = ekf.landmarks()
    assert len(ids) == means.shape[0] == covs.shape[0] > 0 and covs.shape[1:] == (2, 2)
    np.testing.assert_allclose(means, landmarks[ids], atol=3.0)
    C = ekf.joint_covariance([int(ids[0])])
    assert C.shape == (5, 5) and np.allclose(C, C.T)
    assert ekf.name == "ekf" and ekf.last_update()["observations"] >= 0


@pytest.mark.parametrize("name", ["seif-entropy", "fastslam2"])
def test_monte_carlo_summary_matches_the_cli(tmp_path, name):
    landmarks, waypoints = world()
    out = tmp_path / "run.json"
    subprocess.run([cli_path(), "filter", "--algorithm", name, "--world", "generated:30", "--steps", "600", "--runs", "3",
                    "--active", "4", "--particles", "20", "--threads", "1", "--json", str(out)], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    cli = json.loads(out.read_text())
    d = sk.run_filter_monte_carlo(name, landmarks, waypoints, runs=3, steps=600, active_landmarks=4, particles=20,
                                  threads=1)
    assert d["runs"] == cli["runs"] == 3 and d["finite"]
    for key in ("rmse_position", "rmse_heading", "anees", "fraction_in_bounds"):
        assert d[key] == pytest.approx(cli[key], rel=1e-12), key
    assert list(d["anees_bounds"]) == pytest.approx(cli["anees_bounds"])


def test_bad_input_raises(tmp_path):
    landmarks, waypoints = world()
    with pytest.raises(sk.InputError):
        sk.make_landmark_filter("ukf")
    with pytest.raises(sk.InputError):
        sk.make_landmark_filter("fastslam1", association="jcbb")
    f = sk.make_landmark_filter("ekf")
    with pytest.raises(ValueError):
        f.predict(3.0, 0.0, 0.0)
    with pytest.raises(ValueError):
        f.update(np.zeros((2, 2)))
    with pytest.raises(ValueError):
        sk.simulate_landmark_run(landmarks[:, :1], waypoints)
    bad = tmp_path / "map.txt"
    bad.write_text("#type columns rows\nlm 2 2\n1 2\nnan 4\n\nwp 2 1\n5 6\n")
    with pytest.raises(sk.InputError) as e:
        sk.read_landmark_map(str(bad))
    assert e.value.line == 4
    with pytest.raises(ValueError):
        sk.run_filter_monte_carlo("ekf", landmarks, waypoints, runs=0)
