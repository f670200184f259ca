"""The DVI front end from Python (ImageFrontend, classify_matches, read_gray_image): moving
points break the epipolar constraint, real image pairs track and classify deterministically,
bad images and matches raise."""
import numpy as np
import pytest
import slamkit as sk

from conftest import data_root, require_data

K = np.array([[400.0, 0, 320], [0, 400.0, 240], [0, 0, 1]])


def project(points, R, t):
    cam = points @ R.T + t
    uv = cam @ K.T
    return uv[:, :2] / uv[:, 2:]


def two_views(seed=3, movers=12):
    """Static points seen from two poses of a translating, turning camera; the last `movers` move."""
    rng = np.random.default_rng(seed)
    points = rng.uniform([-4, -3, 4], [4, 3, 10], size=(150, 3))
    a = 0.05
    R = np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])
    moved = points.copy()
    moved[-movers:] += rng.choice([-1, 1], size=(movers, 1)) * np.array([0.0, 0.25, 0.0])  # vertical walk
    return project(points, np.eye(3), np.zeros(3)), project(moved, R, np.array([0.3, 0.0, 0.05]))


def test_moving_points_break_the_epipolar_constraint():
    p1, p2 = two_views()
    p1 += np.random.default_rng(0).normal(0, 0.1, p1.shape)  # tracking noise
    c = sk.classify_matches(p1, p2)
    assert c["status"] == "epipolar" and c["F"].shape == (3, 3)
    motion = c["motion"]
    assert (motion[-12:] == 2).all()  # every mover flagged dynamic
    assert (motion[:-12] == 2).mean() < 0.02  # static points pass
    assert c["static_ratio"] == pytest.approx((motion == 1).sum() / (motion != 0).sum())
    assert np.isfinite(c["distance_px"]).all() and c["median_flow_px"] > 1


def test_too_few_matches_is_a_reported_condition():
    p1, p2 = two_views()
    c = sk.classify_matches(p1[:5], p2[:5])
    assert c["status"] == "too_few_matches" and (c["motion"] == 0).all() and c["static_ratio"] == 1.0


def test_real_pair_tracks_and_classifies_deterministically():
    require_data("vio/dynamic_video")
    d = data_root() / "vio" / "dynamic_video"
    a, b = sk.read_gray_image(str(d / "rubberwhale1.png")), sk.read_gray_image(str(d / "rubberwhale2.png"))
    assert a.shape == (388, 584) and a.dtype == np.uint8
    runs = []
    for _ in range(2):
        f = sk.ImageFrontend(baseline_frames=1)
        first = f.process(a)
        assert first.status == "too_few_matches" and first.detected > 100 and (first.motion == 0).all()
        runs.append(f.process(b))
    r = runs[0]
    assert r.status == "epipolar" and r.tracked > 100 and r.uv.shape == (r.ids.size, 2)
    assert r.n_static + r.n_dynamic + r.n_isolated + r.n_unknown == r.ids.size
    assert 0.8 < r.static_ratio < 1.0 and r.n_dynamic > 0  # the whale and the wheel move
    assert r.n_contests_lost == 0  # a cold start, but the rigid scene's model wins on its own
    np.testing.assert_array_equal(r.motion, runs[1].motion)
    np.testing.assert_array_equal(r.uv, runs[1].uv)


def test_options_and_bad_input():
    o = sk.FrontendOptions(threshold_px=2.0, max_features=80)
    assert o.threshold_px == 2.0 and o.max_features == 80 and sk.ImageFrontend(o).options.max_features == 80
    with pytest.raises(TypeError):
        sk.FrontendOptions(no_such_option=1)
    with pytest.raises(TypeError):
        sk.ImageFrontend(o, threshold_px=1.0)
    f = sk.ImageFrontend()
    with pytest.raises(ValueError):
        f.process(np.zeros((48, 64)))  # float64, not uint8
    with pytest.raises(ValueError):
        f.process(np.zeros((48, 64, 3), np.uint8))
    f.process(np.zeros((48, 64), np.uint8))
    with pytest.raises(ValueError):
        f.process(np.zeros((40, 64), np.uint8))  # another size
    with pytest.raises(ValueError):
        sk.ImageFrontend(mask=np.ones((10, 10), np.uint8)).process(np.zeros((48, 64), np.uint8))
    with pytest.raises(sk.InputError):
        sk.read_gray_image("/no/such/image.png")
    p1, p2 = two_views()
    with pytest.raises(ValueError):
        sk.classify_matches(p1, p2[:-1])
    p1[0, 0] = np.nan
    with pytest.raises(ValueError):
        sk.classify_matches(p1, p2)
    with pytest.raises(ValueError):
        sk.classify_matches(p2, p2, threshold_px=float("nan"))


def test_trusted_model_and_essential_refinement_options():
    o = sk.FrontendOptions()
    assert o.trusted_model is True and o.trusted_min_tests == 1
    assert o.min_trusted_matches == 16 and o.refine_essential is True
    o = sk.FrontendOptions(trusted_model=False, trusted_min_tests=2, min_trusted_matches=24, refine_essential=False)
    f = sk.ImageFrontend(o).options
    assert (f.trusted_model, f.trusted_min_tests, f.min_trusted_matches, f.refine_essential) == (False, 2, 24, False)
    assert "trusted_model=False" in repr(o)


def test_known_rotation_options():
    o = sk.FrontendOptions()
    assert o.known_rotation is True and o.rotation_prior_sigma_rad == 0.0 and o.pure_rotation_share == 0.5
    o = sk.FrontendOptions(known_rotation=False, rotation_prior_sigma_rad=0.002, pure_rotation_share=0.7)
    assert (o.known_rotation, o.rotation_prior_sigma_rad, o.pure_rotation_share) == (False, 0.002, 0.7)
    assert "known_rotation=False" in repr(o)
    assert sk.FrontendOptions().cheirality is True
    assert sk.FrontendOptions(cheirality=False).cheirality is False
    f = sk.ImageFrontend(sk.FrontendOptions(known_rotation=True))
    frame = np.zeros((64, 64), np.uint8)
    assert f.process(frame, rotation=np.eye(3)).motion_model == "estimated"  # nothing tracked yet
    with pytest.raises(ValueError):
        f.process(frame, rotation=np.eye(2))


def test_klt_window_option():
    assert sk.FrontendOptions().klt_window == 21
    o = sk.FrontendOptions(klt_window=15)
    assert sk.ImageFrontend(o).options.klt_window == 15 and "klt_window=15" in repr(o)
    with pytest.raises(ValueError, match="klt_window"):
        sk.ImageFrontend(sk.FrontendOptions(klt_window=2))
    assert sk.FrontendOptions().klt_pyramid_levels == 3
    assert sk.ImageFrontend(klt_pyramid_levels=2).options.klt_pyramid_levels == 2
    with pytest.raises(ValueError, match="klt_pyramid_levels"):
        sk.ImageFrontend(klt_pyramid_levels=-1)


def test_rlof_refine_option():
    assert sk.FrontendOptions().rlof_refine == "track"  # the default since session 34
    assert sk.FrontendOptions(rlof_refine="test").rlof_refine == "test"
    with pytest.raises(ValueError, match="rlof_refine"):
        sk.FrontendOptions(rlof_refine="yes")
    o = sk.FrontendOptions(rlof_refine="on")
    assert sk.ImageFrontend(o).options.rlof_refine == "track" and "rlof_refine='track'" in repr(o)
    # A textured image moved by (3, 2) px: refined tracks land on the shift.
    rng = np.random.default_rng(5)
    base = (rng.random((140, 140)) * 255).astype(np.uint8)
    base = np.kron(base, np.ones((2, 2), np.uint8))[:240, :240]
    f = sk.ImageFrontend(o)
    r0 = f.process(np.ascontiguousarray(base[10:210, 10:210]))
    r1 = f.process(np.ascontiguousarray(base[8:208, 7:207]))
    first = dict(zip(r0.ids.tolist(), r0.uv))
    shift = np.array([uv - first[i] for i, uv in zip(r1.ids.tolist(), r1.uv) if i in first])
    assert len(shift) > 20
    np.testing.assert_allclose(np.median(shift, axis=0), [3.0, 2.0], atol=0.05)


def test_epipolar_search_options():
    o = sk.FrontendOptions()
    assert o.epipolar_search is False and o.epipolar_search_range_px == 0.0
    assert o.epipolar_search_ncc_drop == 0.05 and o.epipolar_search_min_ncc == 0.5
    o = sk.FrontendOptions(epipolar_search=True, epipolar_search_range_px=8.0, epipolar_search_ncc_drop=0.1,
                           epipolar_search_min_ncc=0.3)
    f = sk.ImageFrontend(o).options
    assert (f.epipolar_search, f.epipolar_search_range_px, f.epipolar_search_ncc_drop, f.epipolar_search_min_ncc) == (
        True, 8.0, 0.1, 0.3)
    assert "epipolar_search=True" in repr(o)
    with pytest.raises(ValueError):
        sk.ImageFrontend(epipolar_search=True, epipolar_search_ncc_drop=-1.0)


def basketball_pair():
    """The two basketball frames (players moving, camera still), or a skip without the data."""
    require_data("vio/dynamic_video")
    d = data_root() / "vio" / "dynamic_video"
    return sk.read_gray_image(str(d / "basketball1.png")), sk.read_gray_image(str(d / "basketball2.png"))


def check_options(defaults, changed, bad):
    """FrontendOptions: the defaults, the changed values through ImageFrontend and repr, and the
    bad values (field, value, message) raising ValueError."""
    o = sk.FrontendOptions()
    assert {k: getattr(o, k) for k in defaults} == defaults
    o = sk.FrontendOptions(**changed)
    f = sk.ImageFrontend(o).options
    assert {k: getattr(f, k) for k in changed} == changed
    for k, v in changed.items():
        assert f"{k}={v!r}" in repr(o)
    for field, value, message in bad:
        with pytest.raises(ValueError, match=message):
            sk.ImageFrontend(**{field: value})


def test_affine_realign_options():
    check_options({"affine_realign": True, "affine_min_correlation": 0.8, "affine_refit_model": True,  # since session 35
                   "threshold_px": 0.9},
                  {"affine_realign": False, "affine_min_correlation": 0.9, "affine_refit_model": False},
                  [("affine_min_correlation", float("nan"), "min_correlation"),
                   ("affine_min_correlation", 1.5, "min_correlation")])


def test_affine_realign_counts_on_a_real_pair():
    a, b = basketball_pair()
    frames = {}
    for mode in ("off", "on", "refit"):
        f = sk.ImageFrontend(baseline_frames=1, affine_realign=mode != "off", affine_refit_model=mode == "refit",
                             group_min_support=0)
        f.process(a)
        frames[mode] = f.process(b)
    off, on, refit = frames["off"], frames["on"], frames["refit"]
    assert off.n_realigned_affine == 0 and off.n_unflagged_affine == 0
    assert on.n_realigned_affine > 0 and 0 <= on.n_unflagged_affine <= on.n_realigned_affine
    assert on.n_dynamic == off.n_dynamic - on.n_unflagged_affine  # the same tracks and model; only flagged ones move
    assert refit.n_dynamic <= off.n_dynamic  # the refitted model (the default) may unflag more
    assert on.n_dynamic > 10 and refit.n_dynamic > 10  # the players still move


def test_group_rule_options():
    check_options({"group_min_support": 1, "group_radius_factor": 2.0},  # on by default since session 36
                  {"group_min_support": 2, "group_radius_factor": 3.0},
                  [("group_min_support", -1, "min_support"), ("group_radius_factor", float("nan"), "radius_factor")])


def test_trust_contest_options():
    check_options({"trust_contest_ratio": 1.5, "trust_contest_frames": 40},  # on by default since session 37
                  {"trust_contest_ratio": 2.0, "trust_contest_frames": -1},
                  [("trust_contest_ratio", bad, "trust_contest_ratio") for bad in (-1.0, float("nan"), float("inf"))])


def test_turned_flag_and_young_trust_options():
    check_options({"group_turned_min_support": 2, "group_turned_static_tests": 2, "young_trust_majority": True},  # s38
                  {"group_turned_min_support": 3, "group_turned_static_tests": 4, "young_trust_majority": False},
                  [("group_turned_min_support", -1, "turned_min_support"),
                   ("group_turned_static_tests", 0, "turned_static_tests"),
                   ("group_turned_static_tests", 17, "turned_static_tests")])


def test_young_trust_without_a_majority_claims_no_mover():
    a, b = basketball_pair()
    frames = {}
    # The second frame is young trust (one frame after the cold start); with a ratio above
    # static / flags no side has the majority, so every flag is isolated; with the rule off they stand.
    for majority in (False, True):
        f = sk.ImageFrontend(baseline_frames=1, trust_contest_ratio=50.0, young_trust_majority=majority)
        f.process(a)
        frames[majority] = f.process(b)
    off, on = frames[False], frames[True]
    assert not off.trust_undecided and off.n_dynamic > 0
    assert on.trust_undecided and on.n_dynamic == 0 and on.n_isolated == off.n_dynamic + off.n_isolated
    assert (on.motion == off.motion).all() and on.n_static == off.n_static and on.static_ratio == off.static_ratio


def test_group_rule_marks_isolated_flags_on_a_real_pair():
    a, b = basketball_pair()
    frames = {}
    for support in (0, 1):
        f = sk.ImageFrontend(baseline_frames=1, group_min_support=support)
        f.process(a)
        frames[support] = f.process(b)
    off, on = frames[0], frames[1]
    assert off.n_isolated == 0 and on.n_isolated >= 1
    # The same tracks and tests: the isolated flags keep their motion (2) but leave n_dynamic.
    assert (on.motion == off.motion).all() and on.n_static == off.n_static
    assert on.n_dynamic == off.n_dynamic - on.n_isolated and int(on.isolated.sum()) == on.n_isolated
    assert not off.isolated.any() and (on.motion[on.isolated] == 2).all()
    classified = on.n_static + on.n_dynamic + on.n_isolated
    assert abs(on.static_ratio - on.n_static / classified) < 1e-12  # M as before: isolated flags are not static
    # Every flag left has another one within 2 x 30 px.
    uv = on.uv[(on.motion == 2) & ~on.isolated]
    for p in uv:
        assert (((uv - p) ** 2).sum(axis=1) <= 60.0 ** 2).sum() >= 2


CAMCHAIN = """cam0:
  T_cam_imu:
    - [1.0, 0.0, 0.0, 0.0]
    - [0.0, 1.0, 0.0, 0.0]
    - [0.0, 0.0, 1.0, 0.0]
    - [0.0, 0.0, 0.0, 1.0]
  camera_model: pinhole
  distortion_coeffs: [0.0034823894022493434, 0.0007150348452162257, -0.0020532361418706202, 0.00020293673591811182]
  distortion_model: equidistant
  intrinsics: [190.97847715128717, 190.9733070521226, 254.93170605935475, 256.8974428996504]
  resolution: [512, 512]
"""


def test_gyro_klt_option_and_fallback(tmp_path):
    o = sk.FrontendOptions()
    assert o.gyro_klt == "off"
    o = sk.FrontendOptions(gyro_klt="on")
    assert o.gyro_klt == "seed" and "gyro_klt=" in repr(o)
    with pytest.raises(ValueError):
        sk.FrontendOptions(gyro_klt="yes")
    calib = tmp_path / "camchain.yaml"
    calib.write_text(CAMCHAIN)
    rng = np.random.default_rng(1)
    image = np.kron(rng.integers(0, 255, size=(64, 64)), np.ones((8, 8))).astype(np.uint8)  # 8-px blocks: corners
    yaw = np.array([[np.cos(0.02), 0, np.sin(0.02)], [0, 1, 0], [-np.sin(0.02), 0, np.cos(0.02)]])
    seeded = sk.ImageFrontend(sk.FrontendOptions(gyro_klt="seed"), calib=str(calib))
    no_camera = sk.ImageFrontend(sk.FrontendOptions(gyro_klt="seed"))
    for f in (seeded, no_camera):
        assert f.process(image, rotation=np.eye(3)).gyro_seeded is False  # nothing tracked yet
    assert seeded.process(image, rotation=yaw).gyro_seeded is True
    assert no_camera.process(image, rotation=yaw).gyro_seeded is False  # no camera model: unseeded
    bad = yaw * 2.0  # not a rotation: unseeded, no error
    frame = seeded.process(image, rotation=bad)
    assert frame.gyro_seeded is False and frame.tracked > 0


def test_mover_grace_option():
    check_options({"mover_grace_claims": 3},  # on by default since session 39
                  {"mover_grace_claims": 0},
                  [("mover_grace_claims", -1, "mover_grace_claims")])


def test_a_claimed_mover_keeps_its_flag_through_one_dip():
    a, b = basketball_pair()
    # a, b, a, b: the players move back and forth (three tests in a row claim them); b again: nothing
    # moves, every test is under the threshold. With grace the tracks claimed three times keep their flag.
    # (Back and forth the flags nearly match the static features: the young-trust rule is left out.)
    last = {}
    for grace in (0, 3):
        f = sk.ImageFrontend(baseline_frames=1, mover_grace_claims=grace, young_trust_majority=False)
        frames = [f.process(x) for x in (a, b, a, b, b)]
        last[grace] = frames
    off, on = last[0][-1], last[3][-1]
    assert off.n_dynamic == 0 and off.n_graced == 0 and not off.graced.any()
    claimed = [fr.n_dynamic for fr in last[3][1:4]]
    assert min(claimed) > 5, claimed
    assert on.n_graced > 5 and int(on.graced.sum()) == on.n_graced
    assert (on.motion[on.graced] == 2).all() and (off.motion[on.graced] == 1).all()
    # A graced track was claimed (flagged, not isolated) in each of the three tests before.
    for fr in last[3][1:4]:
        ids = set(fr.ids[(fr.motion == 2) & ~fr.isolated].tolist())
        assert set(on.ids[on.graced].tolist()) <= ids
    assert (on.ids == off.ids).all()
    # One dip only: a second frame under the threshold is static again.
    f = sk.ImageFrontend(baseline_frames=1, young_trust_majority=False)
    again = [f.process(x) for x in (a, b, a, b, b, b)][-1]
    assert again.n_graced == 0 and again.n_dynamic == 0
