// Dynamic-feature filter and its scoring on synthetic point tracks: a static scene seen by a
// moving fisheye camera (TUM-VI intrinsics) plus a rigid group moving on its own; the static
// camera case, too few matches, and the undistortion into the virtual pinhole.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "slamkit/geometry/camera_models.h"
#include "slamkit/geometry/se3.h"
#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/frontend_scoring.h"

namespace slamkit {
namespace {

std::shared_ptr<CameraModel> tumvi_camera() {  // cam0 of TUM-VI (512x512 equidistant)
  return make_camera_model("equidistant", {190.978, 190.973, 254.932, 256.897, 0.00348239, 0.000715035, -0.00205324, 0.000202937},
                           512, 512);
}

struct TrackScene {
  std::vector<Eigen::Vector2d> prev, cur;
  std::vector<int> label;  // 0 static, 1 fast object, 2 slow object
};

// Points in the world, the camera moving from T0 to T1 (camera-from-world), objects moving rigidly.
TrackScene make_scene(const CameraModel& cam, const SE3& T0_cw, const SE3& T1_cw, const Eigen::Vector3d& fast_step,
                      const Eigen::Vector3d& slow_step, double noise_px, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> n(0.0, noise_px);
  TrackScene s;
  auto add = [&](const Eigen::Vector3d& pw, const Eigen::Vector3d& step, int label) {
    Eigen::Vector2d a, b;
    if (!cam.project(T0_cw.act(pw), &a) || !cam.project(T1_cw.act(pw + step), &b)) return;
    if (!cam.in_image(a, 2) || !cam.in_image(b, 2)) return;
    s.prev.push_back(a + Eigen::Vector2d(n(*rng), n(*rng)));
    s.cur.push_back(b + Eigen::Vector2d(n(*rng), n(*rng)));
    s.label.push_back(label);
  };
  for (int i = 0; i < 150; ++i) add(Eigen::Vector3d(4 * u(*rng), 3 * u(*rng), 6 + 4 * u(*rng)), Eigen::Vector3d::Zero(), 0);
  const Eigen::Vector3d fast_centre(-1.0, 0.0, 3.5), slow_centre(1.2, 0.3, 4.0);
  for (int i = 0; i < 30; ++i) add(fast_centre + 0.3 * Eigen::Vector3d(u(*rng), 3 * u(*rng), u(*rng)), fast_step, 1);
  for (int i = 0; i < 10; ++i) add(slow_centre + 0.3 * Eigen::Vector3d(u(*rng), 3 * u(*rng), u(*rng)), slow_step, 2);
  return s;
}

// Two views of a camera stepping about 10 cm sideways (camera-from-world T0 -> T1) and the noisy
// matches of the points both see; a point may move by `step` between the views.
struct SidewaysPair {
  SE3 T0, T1;
  std::vector<Eigen::Vector2d> prev, cur;
  std::vector<int> label;

  SidewaysPair(std::uniform_real_distribution<double>& u, std::mt19937& rng) {
    T0 = SE3::exp((Eigen::Matrix<double, 6, 1>() << 0.2 * u(rng), 0.1 * u(rng), 0.2 * u(rng), 0.05 * u(rng),
                   0.05 * u(rng), 0.05 * u(rng)).finished());
    T1 = SE3::exp((Eigen::Matrix<double, 6, 1>() << -0.1, 0.02 * u(rng), 0.02 * u(rng), 0.01 * u(rng),
                   0.01 * u(rng), 0.01 * u(rng)).finished()) * T0;
  }
  // Nothing if the point is not seen in both views.
  void add(const CameraModel& cam, const Eigen::Vector3d& pw, const Eigen::Vector3d& step, int l,
           std::normal_distribution<double>& n, std::mt19937& rng) {
    Eigen::Vector2d a, b;
    if (!cam.project(T0.act(pw), &a) || !cam.project(T1.act(pw + step), &b)) return;
    if (!cam.in_image(a, 2) || !cam.in_image(b, 2)) return;
    prev.push_back(a + Eigen::Vector2d(n(rng), n(rng))), cur.push_back(b + Eigen::Vector2d(n(rng), n(rng)));
    label.push_back(l);
  }
};

TEST(DynamicFeatureFilter, MovingCameraAndRigidGroupOnFisheyeTracks) {
  const auto cam = tumvi_camera();
  DynamicFeatureFilter filter({}, cam);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  DetectionScoreOptions so;
  so.label_speed_mps = {{1, 1.5}, {2, 0.1}};
  DetectionScore total;
  const double dt = 0.1;  // 10 Hz (vtest.avi's rate), or every second frame at 20 Hz
  for (int frame = 0; frame < 20; ++frame) {
    // The camera moves about 12 cm sideways and forward and turns by about a degree.
    const SE3 T0 = SE3::exp((Eigen::Matrix<double, 6, 1>() << 0.2 * u(rng), 0.1 * u(rng), 0.2 * u(rng), 0.05 * u(rng),
                             0.05 * u(rng), 0.05 * u(rng)).finished());
    const Eigen::Vector3d step_cam(0.1 + 0.03 * u(rng), 0.02 * u(rng), 0.05 * u(rng));
    const SE3 T1 = SE3::exp((Eigen::Matrix<double, 6, 1>() << -step_cam, 0.015 * u(rng), 0.015 * u(rng), 0.01 * u(rng))
                                .finished()) * T0;
    // The object walks at 1.5 m/s across the line of sight (vertical and in depth), the slow one at 0.1 m/s.
    const Eigen::Vector3d fast = 1.5 * dt * Eigen::Vector3d(0.2 * u(rng), 1.0, 0.5 * u(rng)).normalized();
    const Eigen::Vector3d slow = 0.1 * dt * Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const TrackScene s = make_scene(*cam, T0, T1, fast, slow, 0.2, &rng);
    const Classification c = filter.classify(s.prev, s.cur);
    ASSERT_EQ(c.status, ClassificationStatus::kEpipolar) << "frame " << frame;
    ASSERT_EQ(c.flags.size(), s.prev.size());
    EXPECT_EQ(c.n_static + c.n_dynamic + c.n_unknown, int(s.prev.size()));
    EXPECT_GT(c.static_ratio, 0.6);
    EXPECT_LT(c.static_ratio, 0.95);

    // The same tracks scored through a label image: each object point labels its pixel.
    LabelImage labels(512, 512);
    for (std::size_t i = 0; i < s.cur.size(); ++i) {
      if (s.label[i] == 0) continue;
      const int x = int(std::round(s.cur[i].x())), y = int(std::round(s.cur[i].y()));
      if (x >= 0 && y >= 0 && x < 512 && y < 512) labels.at(x, y) = std::uint16_t(s.label[i]);
    }
    const DetectionScore by_pixel = score_against_labels(s.cur, c.flags, labels, so);
    const DetectionScore by_feature = score_against_feature_labels(s.label, c.flags, so);
    // A flagged static feature rounding onto a mover's labelled pixel counts as a hit by pixel.
    EXPECT_NEAR(by_pixel.true_positive, by_feature.true_positive, 1);
    EXPECT_EQ(by_pixel.excluded, by_feature.excluded);
    total += by_feature;
  }
  std::printf("fisheye tracks, 20 frame pairs: precision %.3f recall %.3f (tp %ld fp %ld fn %ld tn %ld excluded %ld)\n",
              total.precision(), total.recall(), total.true_positive, total.false_positive, total.false_negative,
              total.true_negative, total.excluded);
  EXPECT_GT(total.true_positive, 400);
  EXPECT_GT(total.excluded, 100);
  EXPECT_GE(total.precision(), 0.9) << total.true_positive << " tp, " << total.false_positive << " fp";
  EXPECT_GE(total.recall(), 0.8) << total.true_positive << " tp, " << total.false_negative << " fn";
}

// A crowd moving as one (a queue of walkers) holding more matches than the background wins a RANSAC
// over all matches: the background is then flagged. Fitted on the trusted matches (static in their
// last test; here 30 of the 40 background points and 5 of the crowd's), the camera's motion is found
// and the crowd is flagged.
TEST(DynamicFeatureFilter, TrustedMatchesKeepTheCameraMotionUnderAMajorityCrowd) {
  const auto cam = tumvi_camera();
  DynamicFeatureFilter filter({}, cam);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> n(0.0, 0.2);
  DetectionScore fitted_on_all, fitted_on_trusted;
  for (int frame = 0; frame < 10; ++frame) {
    SidewaysPair v(u, rng);
    const Eigen::Vector3d crowd_step(0.0, 0.12, 0.03);  // the whole crowd walks 1.2 m/s for 0.1 s
    for (int i = 0; i < 40; ++i) v.add(*cam, Eigen::Vector3d(4 * u(rng), 3 * u(rng), 7 + 3 * u(rng)), Eigen::Vector3d::Zero(), 0, n, rng);
    for (int i = 0; i < 110; ++i) v.add(*cam, Eigen::Vector3d(1.5 * u(rng), 1.0 * u(rng), 2.5 + 0.5 * u(rng)), crowd_step, 1, n, rng);
    const auto& prev = v.prev;
    const auto& cur = v.cur;
    const auto& label = v.label;
    std::vector<char> trusted;
    int static_seen = 0, crowd_seen = 0;
    for (int l : label) {
      const int& seen = l == 0 ? static_seen : crowd_seen;
      trusted.push_back(l == 0 ? seen < 30 : seen < 5);
      ++(l == 0 ? static_seen : crowd_seen);
    }
    fitted_on_all += score_against_feature_labels(label, filter.classify(prev, cur).flags);
    fitted_on_trusted += score_against_feature_labels(label, filter.classify(prev, cur, &trusted).flags);
  }
  std::printf("majority crowd: fitted on all precision %.3f recall %.3f (fp %ld); on trusted %.3f / %.3f (fp %ld)\n",
              fitted_on_all.precision(), fitted_on_all.recall(), fitted_on_all.false_positive, fitted_on_trusted.precision(),
              fitted_on_trusted.recall(), fitted_on_trusted.false_positive);
  EXPECT_GE(fitted_on_trusted.precision(), 0.9);
  EXPECT_GE(fitted_on_trusted.recall(), 0.9);
  EXPECT_LT(fitted_on_all.recall(), 0.5);  // the crowd's motion won: the crowd is "static"
  const std::vector<Eigen::Vector2d> two(2, Eigen::Vector2d(100, 100));
  const std::vector<char> one(1, 1);
  EXPECT_THROW(filter.classify(two, two, &one), std::invalid_argument);
}

// The reverse of the crowd above (room2 high seed 5 after a walker covered the camera): every trusted
// track sits on one walker near the camera, the static scene is new or flagged. The model fitted on
// the trusted tracks is the walker's; the contest fits one on the tracks it flags and takes it when
// it passes more than ratio × as many matches. With a background of 25 points it must not: the
// walker's model passes more of them.
TEST(DynamicFeatureFilter, TrustContestRecoversFromATrustedSetOnOneWalker) {
  const auto cam = tumvi_camera();
  DynamicFeatureFilter filter({}, cam);
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> n(0.0, 0.2);
  for (const int background : {100, 25}) {
    DetectionScore trusted_model, after_contest;
    int lost = 0;
    for (int frame = 0; frame < 10; ++frame) {
      SidewaysPair v(u, rng);
      const Eigen::Vector3d walker_step(0.1, 0.0, 0.06);  // 1.2 m/s for 0.1 s
      for (int i = 0; i < background; ++i)
        v.add(*cam, Eigen::Vector3d(4 * u(rng), 3 * u(rng), 5 + 2 * u(rng)), Eigen::Vector3d::Zero(), 0, n, rng);
      for (int i = 0; i < 40; ++i) v.add(*cam, Eigen::Vector3d(0.4 * u(rng), 0.9 * u(rng), 1.5 + 0.2 * u(rng)), walker_step, 1, n, rng);
      const auto& prev = v.prev;
      const auto& cur = v.cur;
      const auto& label = v.label;
      std::vector<char> trusted;
      for (int l : label) trusted.push_back(l == 1);
      Classification c = filter.classify(prev, cur, &trusted);
      trusted_model += score_against_feature_labels(label, c.flags);
      lost += filter.contest(prev, cur, nullptr, 1.2, &c);
      after_contest += score_against_feature_labels(label, c.flags);
    }
    std::printf("walker trusted, %d background points: trusted model recall %.3f (fp %ld); contest lost %d of 10, "
                "then precision %.3f recall %.3f (fp %ld)\n",
                background, trusted_model.recall(), trusted_model.false_positive, lost, after_contest.precision(),
                after_contest.recall(), after_contest.false_positive);
    EXPECT_LT(trusted_model.recall(), 0.2);  // the walker's motion: the walker passes as static
    if (background == 100) {
      // The camera's model again: the background's false alarms gone (740 -> 8 with this seed); the
      // walker's points whose motion runs along their epipolar lines pass, as they do for any model.
      EXPECT_EQ(lost, 10);
      EXPECT_LE(after_contest.false_positive * 20, trusted_model.false_positive);
      EXPECT_GE(after_contest.precision(), 0.9);
      EXPECT_GE(after_contest.recall(), 0.6);
    } else {
      EXPECT_EQ(lost, 0);
    }
  }
  Classification none;  // not an epipolar result: nothing to contest
  EXPECT_FALSE(filter.contest({}, {}, nullptr, 1.2, &none));
}

TEST(DynamicFeatureFilter, WithoutTheDynamicGroupNearlyNothingIsFlagged) {
  const auto cam = tumvi_camera();
  DynamicFeatureFilter filter({}, cam);
  std::mt19937 rng(3);
  const SE3 T0;
  const SE3 T1 = SE3::exp((Eigen::Matrix<double, 6, 1>() << -0.06, 0.0, -0.02, 0.0, 0.01, 0.0).finished());
  TrackScene s = make_scene(*cam, T0, T1, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 0.2, &rng);
  const Classification c = filter.classify(s.prev, s.cur);
  ASSERT_EQ(c.status, ClassificationStatus::kEpipolar);
  EXPECT_LE(c.n_dynamic, int(0.02 * s.prev.size()));
  EXPECT_GE(c.static_ratio, 0.98);
  // The fundamental matrix holds for the virtual-pinhole pixels: p2ᵀ F p1 ≈ 0 on a static match.
  Eigen::Vector2d a, b;
  ASSERT_TRUE(filter.undistort(s.prev[0], &a) && filter.undistort(s.cur[0], &b));
  EXPECT_LT(std::abs(b.homogeneous().dot(c.F * a.homogeneous())) / (c.F * a.homogeneous()).head<2>().norm(), 1.0);
}

// A camera that only turns (E is ill-posed: any translation direction fits) with points out to the
// fisheye's rim: the rotation model keeps every static point static, the spherical test and the
// movers are still found (E is free to absorb some of them); repeated runs agree (seeded RANSAC).
TEST(DynamicFeatureFilter, PureRotationOnTheFisheyeRimRaisesNoFalseAlarms) {
  const auto cam = tumvi_camera();
  DynamicFeatureFilter filter({}, cam);
  std::mt19937 rng(11);
  long false_alarms = 0, hits = 0, movers = 0, statics = 0;
  for (int frame = 0; frame < 10; ++frame) {
    const SE3 T0 = SE3::exp((Eigen::Matrix<double, 6, 1>() << 0, 0, 0, 0.02 * frame, 0.1, 0).finished());
    const SE3 T1 = SE3::exp((Eigen::Matrix<double, 6, 1>() << 0, 0, 0, 0.01, 0.02, 0.01).finished()) * T0;
    const TrackScene s = make_scene(*cam, T0, T1, Eigen::Vector3d(0.15, 0, 0), Eigen::Vector3d::Zero(), 0.2, &rng);
    const Classification c = filter.classify(s.prev, s.cur);
    ASSERT_EQ(c.status, ClassificationStatus::kEpipolar);
    EXPECT_EQ(c.flags, filter.classify(s.prev, s.cur).flags);
    for (std::size_t i = 0; i < s.label.size(); ++i) {
      const bool dyn = c.flags[i] == FeatureMotion::kDynamic;
      if (s.label[i] == 0) ++statics, false_alarms += dyn;
      if (s.label[i] == 1) ++movers, hits += dyn;
    }
  }
  ASSERT_GT(statics, 500);
  EXPECT_LE(false_alarms, statics / 100);  // ≤ 1 %
  EXPECT_GE(hits, movers * 7 / 10);  // 0.75 measured: under pure rotation E can absorb a mover too
}

TEST(DynamicFeatureFilter, StaticCameraIsClassifiedByFlowAgainstTheDominantMotion) {
  const auto cam = tumvi_camera();
  DynamicFeatureFilter filter({}, cam);
  std::mt19937 rng(5);
  const SE3 T;
  const TrackScene s = make_scene(*cam, T, T, Eigen::Vector3d(0.06, 0.0, 0.0), Eigen::Vector3d::Zero(), 0.1, &rng);
  const Classification c = filter.classify(s.prev, s.cur);
  EXPECT_EQ(c.status, ClassificationStatus::kStaticCamera);
  EXPECT_LT(c.median_flow_px, 0.5);
  DetectionScoreOptions so;
  so.label_speed_mps = {{2, 0.0}};  // the second group stands still here
  const DetectionScore score = score_against_feature_labels(s.label, c.flags, so);
  EXPECT_GE(score.precision(), 0.95);
  EXPECT_GE(score.recall(), 0.9);
}

TEST(DynamicFeatureFilter, FewerThanEightMatchesAreAllUnknown) {
  DynamicFeatureFilter filter;
  std::vector<Eigen::Vector2d> a, b;
  for (int i = 0; i < 7; ++i) a.emplace_back(10.0 * i, 5.0 * i), b.emplace_back(10.0 * i + 3, 5.0 * i - 1);
  const Classification c = filter.classify(a, b);
  EXPECT_EQ(c.status, ClassificationStatus::kTooFewMatches);
  EXPECT_EQ(c.n_unknown, 7);
  EXPECT_EQ(c.static_ratio, 1.0);
  const Classification empty = filter.classify({}, {});
  EXPECT_EQ(empty.status, ClassificationStatus::kTooFewMatches);
  EXPECT_TRUE(empty.flags.empty());
  // Non-finite pixels are unknown, never a crash.
  a.emplace_back(std::nan(""), 1.0), b.emplace_back(1.0, 1.0);
  EXPECT_EQ(filter.classify(a, b).n_unknown, 8);
  EXPECT_THROW(filter.classify(a, {}), std::invalid_argument);
  EXPECT_THROW(DynamicFeatureFilter(DynamicFilterOptions{0.0}), std::invalid_argument);
}

TEST(DynamicFeatureFilter, UndistortsRadTanAndFisheyeToTheVirtualPinhole) {
  const auto radtan = make_camera_model("radtan", {458.654, 457.296, 367.215, 248.375, -0.283408, 0.0739591, 0.00019359, 1.76187e-05},
                                        752, 480);
  for (const auto& cam : {radtan, tumvi_camera()}) {
    DynamicFeatureFilter filter({}, cam);
    const Eigen::VectorXd k = cam->intrinsics();
    for (const Eigen::Vector3d p : {Eigen::Vector3d(0.3, -0.2, 1.0), Eigen::Vector3d(-0.5, 0.4, 1.5), Eigen::Vector3d(0, 0, 1)}) {
      Eigen::Vector2d uv, out;
      ASSERT_TRUE(cam->project(p, &uv));
      ASSERT_TRUE(filter.undistort(uv, &out));
      EXPECT_NEAR(out.x(), k[0] * p.x() / p.z() + k[2], 1e-6) << cam->model_name();
      EXPECT_NEAR(out.y(), k[1] * p.y() / p.z() + k[3], 1e-6) << cam->model_name();
    }
  }
}

TEST(FrontendScoring, CountsAndVacuousRatios) {
  LabelImage labels(10, 10);
  labels.at(5, 5) = 1;
  labels.at(6, 5) = 2;
  const std::vector<Eigen::Vector2d> uv{{5, 5}, {6.2, 4.9}, {1, 1}, {2, 2}, {20, 3}};
  const std::vector<FeatureMotion> flags{FeatureMotion::kDynamic, FeatureMotion::kDynamic, FeatureMotion::kDynamic,
                                         FeatureMotion::kUnknown, FeatureMotion::kStatic};
  DetectionScoreOptions o;
  o.label_speed_mps = {{2, 0.2}};
  const DetectionScore s = score_against_labels(uv, flags, labels, o);
  EXPECT_EQ(s.true_positive, 1);
  EXPECT_EQ(s.excluded, 1);
  EXPECT_EQ(s.false_positive, 1);
  EXPECT_EQ(s.true_negative, 1);
  EXPECT_EQ(s.unknown, 1);
  EXPECT_EQ(s.outside, 1);
  EXPECT_DOUBLE_EQ(s.precision(), 0.5);
  EXPECT_DOUBLE_EQ(s.recall(), 1.0);
  EXPECT_DOUBLE_EQ(DetectionScore{}.precision(), 1.0);
  EXPECT_THROW(score_against_labels(uv, {}, labels), std::invalid_argument);
}

// Patch rule: the labels under the feature's (2h+1)² patch decide; a patch straddling a silhouette
// is "mixed" (counted, not scored), where the centre rule calls it by its centre pixel.
TEST(FrontendScoring, PatchRuleSeparatesSilhouettes) {
  LabelImage labels(20, 20);
  for (int y = 0; y < 20; ++y)
    for (int x = 10; x < 20; ++x) labels.at(x, y) = 1;  // object 1 fills the right half
  const std::vector<Eigen::Vector2d> uv{{15, 10}, {10, 10}, {8, 10}, {3, 3}, {18.6, 19.4}};
  const std::vector<FeatureMotion> flags{FeatureMotion::kDynamic, FeatureMotion::kStatic, FeatureMotion::kDynamic,
                                         FeatureMotion::kStatic, FeatureMotion::kDynamic};
  DetectionScoreOptions centre;
  const DetectionScore c = score_against_labels(uv, flags, labels, centre);
  EXPECT_EQ(c.true_positive, 2);   // (15,10), (19,19)
  EXPECT_EQ(c.false_negative, 1);  // (10,10): its centre is on the object
  EXPECT_EQ(c.false_positive, 1);  // (8,10): its centre is static, two pixels from the edge
  EXPECT_EQ(c.true_negative, 1);
  EXPECT_EQ(c.mixed, 0);
  DetectionScoreOptions patch;
  patch.patch_half_size_px = 2;
  const DetectionScore p = score_against_labels(uv, flags, labels, patch);
  EXPECT_EQ(p.true_positive, 2);  // the corner patch (17..19)² is clipped to the image, all object
  EXPECT_EQ(p.false_negative, 0);
  EXPECT_EQ(p.false_positive, 0);
  EXPECT_EQ(p.true_negative, 1);
  EXPECT_EQ(p.mixed, 2);
  EXPECT_EQ(p.mixed_flagged, 1);
  EXPECT_DOUBLE_EQ(p.precision(), 1.0);
  // A slow object's patch is excluded, as under the centre rule.
  patch.label_speed_mps = {{1, 0.1}};
  const DetectionScore slow = score_against_labels(uv, flags, labels, patch);
  EXPECT_EQ(slow.excluded, 2);
  EXPECT_EQ(slow.true_positive, 0);
}

// Issue 13 scores objects "at 2–6 m": a feature on an object outside the distance range is neither a
// hit, a miss nor a false alarm (like a slow one); ids without a distance and the static scene are
// always scored; the range's ends are inside.
TEST(FrontendScoring, DistanceRangeExcludesNearAndFarObjects) {
  const std::vector<int> labels{1, 1, 2, 2, 3, 4, 5, 0, 0};
  const std::vector<FeatureMotion> flags{FeatureMotion::kDynamic, FeatureMotion::kStatic, FeatureMotion::kDynamic,
                                         FeatureMotion::kUnknown, FeatureMotion::kDynamic, FeatureMotion::kDynamic,
                                         FeatureMotion::kStatic, FeatureMotion::kDynamic, FeatureMotion::kStatic};
  DetectionScoreOptions o;
  o.label_distance_m = {{1, 1.2}, {2, 4.0}, {3, 7.5}, {4, 6.0}};  // 5: no distance known
  const DetectionScore s = score_against_feature_labels(labels, flags, o);
  EXPECT_EQ(s.excluded_range, 3);   // object 1 at 1.2 m (2 features), object 3 at 7.5 m
  EXPECT_EQ(s.true_positive, 2);    // object 2, object 4 (6.0 m: the range is closed)
  EXPECT_EQ(s.false_negative, 2);   // object 2 unknown, object 5 static
  EXPECT_EQ(s.false_positive, 1);   // the static scene is always scored
  EXPECT_EQ(s.true_negative, 1);
  EXPECT_DOUBLE_EQ(s.precision(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(s.recall(), 0.5);
  // A slow object is excluded as slow whatever its distance; without distances nothing is excluded by range.
  o.label_speed_mps = {{2, 0.1}};
  const DetectionScore slow = score_against_feature_labels(labels, flags, o);
  EXPECT_EQ(slow.excluded, 2);
  EXPECT_EQ(slow.excluded_range, 3);
  DetectionScoreOptions all;
  EXPECT_EQ(score_against_feature_labels(labels, flags, all).excluded_range, 0);
  DetectionScore sum = s;
  sum += s;
  EXPECT_EQ(sum.excluded_range, 6);
}

}  // namespace
}  // namespace slamkit
