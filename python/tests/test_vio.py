"""The visual-inertial estimator from Python (simulate_visual_inertial, run_vio): the same run as
`slamkit vio --sim`, bit-identical for any thread count, DVI dropping frames by theta, bad input."""
import json
import subprocess

import numpy as np
import pytest
import slamkit as sk

from conftest import cli_path, data_root, require_data

SEQUENCE = dict(sequence="room1", duration=8.0, dynamic="high", seed=2)


@pytest.fixture(scope="module")
def sim():
    require_data("vio/tumvi")
    return sk.simulate_visual_inertial(**SEQUENCE, data=str(data_root()))


def test_simulated_run_and_its_estimate(sim):
    assert sim.source == "room1" and sim.dynamic == "high" and sim.seed == 2
    assert sim.num_frames > 100 and sim.num_imu_samples >= 9 * sim.num_frames
    assert abs(sim.duration - SEQUENCE["duration"]) < 0.1 and 0.0 < sim.static_ratio_min < 1.0
    r = sk.run_vio(sim)
    assert r.frames > 0 and 0 < r.keyframes <= r.frames and r.startup_method
    assert r.estimate.size() == r.truth.size() > r.frames - 1
    assert sk.ate(r.estimate, r.truth).stats.rmse < 0.05  # issue 12's bound
    assert r.visual_frames_dropped == 0  # the baseline keeps every frame's vision


def test_thread_count_does_not_change_the_estimate(sim):
    one, two = sk.run_vio(sim, threads=1), sk.run_vio(sim, threads=2)
    np.testing.assert_array_equal(one.estimate.positions(), two.estimate.positions())


def test_dvi_drops_the_frames_whose_static_share_is_below_theta(sim):
    r = sk.run_vio(sim, dvi=True, alpha="M", theta="1.0")
    assert r.static_ratio_min < 1.0 and r.visual_frames_dropped > 0
    assert sk.run_vio(sim, dvi=True, theta="0.0").visual_frames_dropped == 0


def test_dvi_startup_leaves_out_dynamic_features(sim):
    dvi = sk.run_vio(sim, dvi=True)
    assert dvi.startup_dynamic_left_out > 0 and 0.0 < dvi.startup_rotation_rms_deg < 2.0
    assert 0.0 < dvi.startup_scale_rel_sigma <= 0.25
    assert sk.run_vio(sim, dvi=True, dvi_startup=False).startup_dynamic_left_out == 0
    assert sk.run_vio(sim).startup_dynamic_left_out == 0  # the baseline uses every feature
    with pytest.raises(ValueError, match="max_rotation_rms_deg"):
        sk.run_vio(sim, max_rotation_rms_deg=float("nan"))
    with pytest.raises(ValueError, match="max_scale_rel_sigma"):
        sk.run_vio(sim, max_scale_rel_sigma=-1.0)


def test_matches_the_cli(sim, tmp_path):
    out = tmp_path / "vio.json"
    subprocess.run([cli_path(), "vio", "--sim", "room1", "--duration", "8", "--dynamic", "high", "--seed", "2",
                    "--data", str(data_root()), "--json", str(out), "--quiet"], check=True, capture_output=True)
    cli = json.loads(out.read_text())
    r = sk.run_vio(sim)
    assert sk.ate(r.estimate, r.truth).stats.rmse == pytest.approx(cli["ate_rmse"], rel=1e-12)
    assert r.keyframes == cli["keyframes"]


def test_bad_input_raises(sim):
    with pytest.raises(sk.InputError):
        sk.simulate_visual_inertial("room9")
    with pytest.raises(ValueError):
        sk.simulate_visual_inertial("room1", duration=float("nan"))
    with pytest.raises(ValueError):
        sk.run_vio(sim, threads=0)
    with pytest.raises(sk.InputError):
        sk.run_vio(sim, dvi=True, alpha="M^x")
    with pytest.raises(sk.InputError):
        sk.run_vio(sim, dvi=True, theta="2")
