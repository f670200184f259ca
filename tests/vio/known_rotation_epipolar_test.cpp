// The IMU-aided epipolar model (vio/known_rotation_epipolar.h) and its use by DynamicFeatureFilter:
// the 2-point solver is exact on noise-free matches, degenerate inputs (fewer than 2 matches, pure
// rotation, NaN, a matrix that is no rotation) are reported conditions, and with the true rotation a
// rigid crowd holding most of the matches no longer takes over the camera's motion model.
#include "slamkit/vio/known_rotation_epipolar.h"

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

struct Matches {
  std::vector<Eigen::Vector3d> b1, b2;
};

// Static points in front of both cameras, x_c2 = R x_c1 + t, seen as unit bearings.
Matches static_matches(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, int n, std::mt19937* rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Matches m;
  while (static_cast<int>(m.b1.size()) < n) {
    const Eigen::Vector3d x1(3 * u(*rng), 2 * u(*rng), 5 + 3 * u(*rng));
    m.b1.push_back(x1.normalized()), m.b2.push_back((R * x1 + t).normalized());
  }
  return m;
}

Eigen::Matrix3d rotation(const Eigen::Vector3d& w) { return SO3::exp(w).matrix(); }

TEST(KnownRotationEpipolar, TwoPointSolverIsExactOnNoiseFreeMatches) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix3d R = rotation(Eigen::Vector3d(0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng)));
    const Eigen::Vector3d t = Eigen::Vector3d(u(rng), u(rng), 0.5 * u(rng)).normalized() * 0.2;
    const Matches m = static_matches(R, t, 60, &rng);
    Eigen::Vector3d t2;
    ASSERT_TRUE(translation_from_two_matches(R, m.b1[0], m.b2[0], m.b1[1], m.b2[1], &t2));
    EXPECT_NEAR(std::abs(t2.dot(t.normalized())), 1.0, 1e-9) << "trial " << trial;
    for (std::size_t i = 0; i < m.b1.size(); ++i) EXPECT_LT(known_rotation_angle(R, t, m.b1[i], m.b2[i]), 1e-12);
    const KnownRotationModel fit = fit_known_rotation(m.b1, m.b2, R);
    ASSERT_EQ(fit.status, KnownRotationStatus::kTranslation) << to_string(fit.status);
    EXPECT_NEAR(std::abs(fit.t.dot(t.normalized())), 1.0, 1e-9);
    EXPECT_NEAR(fit.t.norm(), 1.0, 1e-12);
    EXPECT_EQ(fit.inliers, 60);
    EXPECT_EQ(fit.usable, 60);
    EXPECT_LT((fit.R - R).norm(), 1e-12);  // held: no prior given
  }
}

TEST(KnownRotationEpipolar, DegenerateInputsAreReportedConditions) {
  std::mt19937 rng(5);
  const Eigen::Matrix3d R = rotation(Eigen::Vector3d(0.02, -0.03, 0.01));
  const Matches m = static_matches(R, Eigen::Vector3d(0.1, 0.0, 0.05), 40, &rng);
  // Fewer than 2 matches, also after NaN and zero bearings are skipped.
  EXPECT_EQ(fit_known_rotation({}, {}, R).status, KnownRotationStatus::kTooFewMatches);
  EXPECT_EQ(fit_known_rotation({m.b1[0]}, {m.b2[0]}, R).status, KnownRotationStatus::kTooFewMatches);
  const Eigen::Vector3d nan(std::nan(""), 0.0, 1.0);
  const KnownRotationModel skipped = fit_known_rotation({m.b1[0], nan, Eigen::Vector3d::Zero()}, {m.b2[0], m.b2[1], m.b2[2]}, R);
  EXPECT_EQ(skipped.status, KnownRotationStatus::kTooFewMatches);
  EXPECT_EQ(skipped.usable, 1);
  // NaN bearings among good ones are skipped; the model is still found.
  Matches with_nan = m;
  with_nan.b1[3] = nan, with_nan.b2[7] = nan;
  const KnownRotationModel fit = fit_known_rotation(with_nan.b1, with_nan.b2, R);
  EXPECT_EQ(fit.status, KnownRotationStatus::kTranslation);
  EXPECT_EQ(fit.usable, 38);
  EXPECT_TRUE(std::isnan(known_rotation_angle(R, fit.t, Eigen::Vector3d::Zero(), m.b2[0])));
  // A NaN or non-rotation matrix is rejected.
  Eigen::Matrix3d bad = R;
  bad(1, 2) = std::nan("");
  EXPECT_EQ(fit_known_rotation(m.b1, m.b2, bad).status, KnownRotationStatus::kInvalidRotation);
  EXPECT_EQ(fit_known_rotation(m.b1, m.b2, 1.01 * R).status, KnownRotationStatus::kInvalidRotation);
  EXPECT_EQ(fit_known_rotation(m.b1, m.b2, -R).status, KnownRotationStatus::kInvalidRotation);  // det −1
  // Two matches without parallax define no translation.
  Eigen::Vector3d t;
  EXPECT_FALSE(translation_from_two_matches(R, m.b1[0], R * m.b1[0], m.b1[1], R * m.b1[1], &t));
  EXPECT_FALSE(translation_from_two_matches(R, m.b1[0], m.b2[0], m.b1[0], m.b2[0], &t));  // the same plane twice
  EXPECT_THROW(fit_known_rotation(m.b1, {}, R), std::invalid_argument);
  KnownRotationOptions o;
  o.pure_rotation_share = 0.0;
  EXPECT_THROW(fit_known_rotation(m.b1, m.b2, R, o), std::invalid_argument);
}

// A camera that only turns: t is undefined; every static point fits the rotation, a mover does not.
TEST(KnownRotationEpipolar, PureRotationJudgesByTheRotationResidual) {
  std::mt19937 rng(7);
  const Eigen::Matrix3d R = rotation(Eigen::Vector3d(0.01, 0.05, -0.02));
  Matches m = static_matches(R, Eigen::Vector3d::Zero(), 50, &rng);
  // Ten movers translate together by 10 cm at 3-8 m (a crowd a RANSAC on t alone would accept).
  for (int i = 0; i < 10; ++i) m.b2[i] = (m.b2[i] * 6.0 + Eigen::Vector3d(0.1, 0.0, 0.0)).normalized();
  const KnownRotationModel fit = fit_known_rotation(m.b1, m.b2, R);
  ASSERT_EQ(fit.status, KnownRotationStatus::kPureRotation) << to_string(fit.status);
  EXPECT_EQ(fit.t, Eigen::Vector3d::Zero());
  EXPECT_EQ(fit.informative, 10);
  EXPECT_EQ(fit.inliers, 40);
  const double f = 190.0;  // px per rad
  for (int i = 0; i < 50; ++i) {
    const double d = f * known_rotation_angle(fit.R, fit.t, m.b1[i], m.b2[i]);
    if (i < 10) EXPECT_GT(d, 1.0) << i;
    else EXPECT_LT(d, 1e-9) << i;
  }
}

// A rotation prior lets the refinement take out a gyro bias error, and only as far as the data ask.
TEST(KnownRotationEpipolar, RefinementUnderAPriorCorrectsABiasedRotation) {
  std::mt19937 rng(9);
  std::normal_distribution<double> n(0.0, 0.2 / 190.0);  // 0.2 px
  const Eigen::Matrix3d R = rotation(Eigen::Vector3d(0.03, -0.02, 0.04));
  Matches m = static_matches(R, Eigen::Vector3d(0.15, 0.02, 0.05), 120, &rng);
  for (auto& b : m.b2) b = (b + Eigen::Vector3d(n(rng), n(rng), n(rng))).normalized();
  const Eigen::Matrix3d biased = rotation(Eigen::Vector3d(0.004, 0.0, -0.003)) * R;  // 0.005 rad ≈ 1 px
  KnownRotationOptions held, prior;
  prior.rotation_prior_sigma_rad = 0.01;
  const KnownRotationModel a = fit_known_rotation(m.b1, m.b2, biased, held);
  const KnownRotationModel b = fit_known_rotation(m.b1, m.b2, biased, prior);
  ASSERT_EQ(b.status, KnownRotationStatus::kTranslation);
  const double err_held = SO3::from_matrix(a.R * R.transpose()).log().norm();
  const double err_prior = SO3::from_matrix(b.R * R.transpose()).log().norm();
  std::printf("rotation error: held %.5f rad, refined under the prior %.5f rad; inliers %d / %d of 120\n", err_held,
              err_prior, a.inliers, b.inliers);
  EXPECT_NEAR(err_held, 0.005, 1e-6);
  EXPECT_LT(err_prior, 0.001);
  EXPECT_GT(b.inliers, a.inliers);
}

std::shared_ptr<CameraModel> tumvi_camera() {
  return make_camera_model("equidistant", {190.978, 190.973, 254.932, 256.897, 0.00348239, 0.000715035, -0.00205324, 0.000202937},
                           512, 512);
}

// Pixel matches of world points seen by cameras T0 (pw) and T1 (pw2: where the point is then), with
// pixel noise, kept when both project inside the image; label 0 static, > 0 a mover.
struct PixelMatches {
  std::vector<Eigen::Vector2d> prev, cur;
  std::vector<int> label;
  void add(const CameraModel& cam, const SE3& T0, const SE3& T1, const Eigen::Vector3d& pw, const Eigen::Vector3d& pw2,
           int l, std::normal_distribution<double>& n, std::mt19937& rng) {
    Eigen::Vector2d a, b;
    if (!cam.project(T0.act(pw), &a) || !cam.project(T1.act(pw2), &b)) return;
    if (!cam.in_image(a, 2) || !cam.in_image(b, 2)) return;
    prev.push_back(a + Eigen::Vector2d(n(rng), n(rng))), cur.push_back(b + Eigen::Vector2d(n(rng), n(rng)));
    label.push_back(l);
  }
};

// 40 static points against a rigid crowd of 110 that walks and turns as one (a group on a turning
// path, 0.1 s): E fitted on all matches takes the crowd's motion; with the camera's rotation known
// only the background has a translation that explains it, and the crowd is flagged. (A crowd that
// translates without turning shares the camera's rotation: the known rotation cannot set it apart;
// the trusted tracks do, docs/frontend.md.)
TEST(KnownRotationEpipolar, KnownRotationKeepsTheCameraMotionUnderATurningMajorityCrowd) {
  const auto cam = tumvi_camera();
  DynamicFilterOptions fo;
  fo.known_rotation = false;
  DynamicFeatureFilter estimated(fo, cam);  // the option off: a given rotation is not used
  fo.known_rotation = true;
  DynamicFeatureFilter known(fo, cam);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> n(0.0, 0.2);
  DetectionScore score_estimated, score_known;
  int known_frames = 0;
  for (int frame = 0; frame < 10; ++frame) {
    const SE3 T0 = SE3::exp((Eigen::Matrix<double, 6, 1>() << 0.2 * u(rng), 0.1 * u(rng), 0.2 * u(rng), 0.05 * u(rng),
                             0.05 * u(rng), 0.05 * u(rng)).finished());
    const SE3 T1 = SE3::exp((Eigen::Matrix<double, 6, 1>() << -0.1, 0.02 * u(rng), 0.02 * u(rng), 0.01 * u(rng),
                             0.01 * u(rng), 0.01 * u(rng)).finished()) * T0;
    // The crowd turns by 6° about the vertical (y, down in the camera) around its centre and moves 12 cm (across the epipolar lines, as in the trusted-track test).
    const Eigen::Vector3d centre(0.0, 0.0, 3.5);
    const SE3 crowd_motion = SE3(SO3::exp(Eigen::Vector3d(0.0, 0.1, 0.0)), centre + Eigen::Vector3d(0.0, 0.12, 0.03)) *
                             SE3(SO3(), -centre);
    PixelMatches m;
    auto add = [&](const Eigen::Vector3d& pw, const Eigen::Vector3d& pw2, int l) { m.add(*cam, T0, T1, pw, pw2, l, n, rng); };
    for (int i = 0; i < 40; ++i) {
      const Eigen::Vector3d p(4 * u(rng), 3 * u(rng), 7 + 3 * u(rng));
      add(p, p, 0);
    }
    for (int i = 0; i < 110; ++i) {
      const Eigen::Vector3d p = centre + Eigen::Vector3d(1.5 * u(rng), 1.0 * u(rng), 2.0 * u(rng));
      add(p, crowd_motion.act(p), 1);
    }
    const Eigen::Matrix3d R_c2_c1 = (T1 * T0.inverse()).rotation().matrix();  // x_c2 = R x_c1 + t
    const Classification e = estimated.classify(m.prev, m.cur, nullptr, &R_c2_c1);
    EXPECT_EQ(e.motion_model, MotionModel::kEstimated);
    score_estimated += score_against_feature_labels(m.label, e.flags);
    const Classification c = known.classify(m.prev, m.cur, nullptr, &R_c2_c1);
    ASSERT_EQ(c.status, ClassificationStatus::kEpipolar);
    known_frames += c.motion_model == MotionModel::kKnownRotation;
    score_known += score_against_feature_labels(m.label, c.flags);
    // The same matches without a rotation: the estimated model, as before.
    EXPECT_EQ(known.classify(m.prev, m.cur).motion_model, MotionModel::kEstimated);
  }
  std::printf("turning majority crowd: estimated E precision %.3f recall %.3f; known rotation %.3f / %.3f (fp %ld fn %ld)\n",
              score_estimated.precision(), score_estimated.recall(), score_known.precision(), score_known.recall(),
              score_known.false_positive, score_known.false_negative);
  EXPECT_EQ(known_frames, 10);
  EXPECT_LT(score_estimated.recall(), 0.5);  // the crowd's motion won
  EXPECT_GE(score_known.precision(), 0.95);
  EXPECT_GE(score_known.recall(), 0.95);
}

// Through the filter: a bad rotation or no camera model falls back to the estimated model and says so.
TEST(KnownRotationEpipolar, FilterFallsBackAndReportsWhenTheRotationIsUnusable) {
  std::mt19937 rng(13);
  const Eigen::Matrix3d R = rotation(Eigen::Vector3d(0.01, 0.02, 0.0));
  const Eigen::Vector3d t(0.1, 0.0, 0.02);
  const auto cam = tumvi_camera();
  std::vector<Eigen::Vector2d> prev, cur;
  const Matches m = static_matches(R, t, 80, &rng);
  for (std::size_t i = 0; i < m.b1.size(); ++i) {
    Eigen::Vector2d a, b;
    if (cam->project(m.b1[i], &a) && cam->project(m.b2[i], &b)) prev.push_back(a), cur.push_back(b);
  }
  ASSERT_GE(prev.size(), 60u);
  DynamicFilterOptions fo;
  fo.known_rotation = true;
  const DynamicFeatureFilter filter(fo, cam);
  const Classification good = filter.classify(prev, cur, nullptr, &R);
  EXPECT_EQ(good.motion_model, MotionModel::kKnownRotation);
  EXPECT_EQ(good.n_dynamic, 0);
  EXPECT_NEAR(std::abs(good.t.dot(t.normalized())), 1.0, 1e-6);
  // epipolar_distance agrees with classify's distances under the known-rotation model.
  EXPECT_NEAR(filter.epipolar_distance(good, prev[5], cur[5]), good.distance_px[5], 1e-9);
  Eigen::Matrix3d bad = R;
  bad(0, 0) = std::nan("");
  const Classification fallback = filter.classify(prev, cur, nullptr, &bad);
  EXPECT_EQ(fallback.motion_model, MotionModel::kRotationRejected);
  EXPECT_EQ(fallback.status, ClassificationStatus::kEpipolar);
  EXPECT_EQ(fallback.n_static + fallback.n_dynamic, static_cast<int>(prev.size()));
  const DynamicFeatureFilter no_camera(fo);  // pixels without intrinsics: no bearings
  EXPECT_EQ(no_camera.classify(prev, cur, nullptr, &R).motion_model, MotionModel::kRotationRejected);
  // Fewer than min_matches: the filter's condition, as without a rotation.
  const std::vector<Eigen::Vector2d> few(prev.begin(), prev.begin() + 5), few2(cur.begin(), cur.begin() + 5);
  EXPECT_EQ(filter.classify(few, few2, nullptr, &R).status, ClassificationStatus::kTooFewMatches);
  // A turning camera without translation: the pure-rotation model.
  std::vector<Eigen::Vector2d> turned;
  std::vector<Eigen::Vector2d> from;
  for (std::size_t i = 0; i < m.b1.size(); ++i) {
    Eigen::Vector2d a, b;
    if (cam->project(m.b1[i], &a) && cam->project(R * m.b1[i], &b)) from.push_back(a), turned.push_back(b);
  }
  const Classification pure = filter.classify(from, turned, nullptr, &R);
  EXPECT_EQ(pure.motion_model, MotionModel::kPureRotation);
  EXPECT_EQ(pure.n_dynamic, 0);
  EXPECT_NEAR(filter.epipolar_distance(pure, from[2], turned[2]), pure.distance_px[2], 1e-9);
  fo.pure_rotation_share = 1.5;
  EXPECT_THROW(DynamicFeatureFilter(fo, cam), std::invalid_argument);
}


// Pinhole mode (a radtan camera with spherical = false): the known-rotation model is scored by the
// virtual-pinhole distance to the line of F = K⁻ᵀ [t]× R K⁻¹ (and to π(R b1) under pure rotation),
// mapped to raw pixels; static points pass, a mover moved 3 px across its line is flagged.
TEST(KnownRotationEpipolar, PinholeModeScoresTheLineDistanceInRawPixels) {
  const auto cam = make_camera_model("radtan", {458.654, 457.296, 367.215, 248.375, -0.283408, 0.0739591, 0.00019359, 1.76187e-05},
                                     752, 480);
  std::mt19937 rng(17);
  const Eigen::Matrix3d R = rotation(Eigen::Vector3d(0.01, -0.02, 0.005));
  DynamicFilterOptions fo;
  fo.spherical = false;
  const DynamicFeatureFilter filter(fo, cam);
  for (const Eigen::Vector3d t : {Eigen::Vector3d(0.1, 0.01, 0.02), Eigen::Vector3d(0.0, 0.0, 0.0)}) {
    const Matches m = static_matches(R, t, 120, &rng);
    std::vector<Eigen::Vector2d> prev, cur;
    for (std::size_t i = 0; i < m.b1.size(); ++i) {
      Eigen::Vector2d a, b;
      if (m.b1[i].z() > 0.5 && m.b2[i].z() > 0.5 && cam->project(m.b1[i], &a) && cam->project(m.b2[i], &b) &&
          cam->in_image(a, 2) && cam->in_image(b, 2))
        prev.push_back(a), cur.push_back(b);
    }
    ASSERT_GE(prev.size(), 40u);
    cur[0] += Eigen::Vector2d(0.0, 3.0);  // a mover: 3 px off (vertical: across a horizontal-ish line)
    const Classification c = filter.classify(prev, cur, nullptr, &R);
    const bool pure = t.norm() == 0.0;
    ASSERT_EQ(c.motion_model, pure ? MotionModel::kPureRotation : MotionModel::kKnownRotation);
    EXPECT_EQ(c.flags[0], FeatureMotion::kDynamic) << c.distance_px[0];
    EXPECT_GT(c.distance_px[0], pure ? 2.9 : 1.0);
    for (std::size_t i = 1; i < prev.size(); ++i) EXPECT_LT(c.distance_px[i], 0.05) << i;
    EXPECT_NEAR(filter.epipolar_distance(c, prev[0], cur[0]), c.distance_px[0], 1e-9);
  }
}

// Cheirality (session 31): static points have a non-negative parallax toward t once t is oriented;
// a point that slides backwards along its epipolar line has a negative one, of its displacement's size.
TEST(KnownRotationEpipolar, ParallaxIsPositiveForStaticPointsAndOrientsTheTranslation) {
  std::mt19937 rng(17);
  const Eigen::Matrix3d R = rotation(Eigen::Vector3d(0.02, -0.05, 0.01));
  const Eigen::Vector3d t(0.15, 0.02, 0.05);
  const Matches m = static_matches(R, t, 80, &rng);
  const Eigen::Vector3d tu = t.normalized();
  for (std::size_t i = 0; i < m.b1.size(); ++i) {
    EXPECT_GE(known_rotation_parallax(R, tu, m.b1[i], m.b2[i]), 0.0) << i;
    EXPECT_LE(known_rotation_parallax(R, -tu, m.b1[i], m.b2[i]), 0.0) << i;
  }
  // Whatever sign the solver returns, the static scene fixes it.
  EXPECT_LT((orient_translation(R, -tu, m.b1, m.b2, 1e-3, 1e-4) - tu).norm(), 1e-15);
  EXPECT_LT((orient_translation(R, tu, m.b1, m.b2, 1e-3, 1e-4) - tu).norm(), 1e-15);
  const KnownRotationModel fit = fit_known_rotation(m.b1, m.b2, R);  // the fit returns t so oriented
  ASSERT_EQ(fit.status, KnownRotationStatus::kTranslation);
  EXPECT_NEAR(fit.t.dot(tu), 1.0, 1e-9);
  // A point at depth 5 m moved back along its epipolar circle, past R b1: it stays on the plane
  // (distance 0) but its parallax is negative by the angle it moved beyond R b1.
  const Eigen::Vector3d a = R * Eigen::Vector3d(0.2, 0.1, 1.0).normalized();
  const Eigen::Vector3d u = (tu - tu.dot(a) * a).normalized();
  const Eigen::Vector3d behind = std::cos(0.01) * a - std::sin(0.01) * u;
  const Eigen::Vector3d b1 = Eigen::Vector3d(0.2, 0.1, 1.0).normalized();
  EXPECT_LT(known_rotation_angle(R, tu, b1, behind), 1e-12);
  EXPECT_NEAR(known_rotation_parallax(R, tu, b1, behind), -0.01, 1e-12);
  // Degenerate inputs: no translation or the epipole gives 0, a zero bearing NaN.
  EXPECT_EQ(known_rotation_parallax(R, Eigen::Vector3d::Zero(), b1, behind), 0.0);
  EXPECT_EQ(known_rotation_parallax(R, a, R.transpose() * a, a), 0.0);
  EXPECT_TRUE(std::isnan(known_rotation_parallax(R, tu, Eigen::Vector3d::Zero(), behind)));
  EXPECT_THROW(orient_translation(R, tu, m.b1, {}, 1e-3, 1e-4), std::invalid_argument);
}

// Through the filter: movers sliding backwards along their epipolar lines are invisible to the
// distance to the plane and caught by the cheirality test; the static points are not flagged by it.
TEST(KnownRotationEpipolar, CheiralityCatchesMoversSlidingBackAlongTheirEpipolarLines) {
  const auto cam = tumvi_camera();
  DynamicFilterOptions fo;
  fo.cheirality = false;
  DynamicFeatureFilter plane_only(fo, cam);
  fo.cheirality = true;
  DynamicFeatureFilter with_cheirality(fo, cam);
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> n(0.0, 0.1);
  DetectionScore plane, cheir;
  for (int frame = 0; frame < 10; ++frame) {
    const SE3 T0 = SE3::exp((Eigen::Matrix<double, 6, 1>() << 0.2 * u(rng), 0.1 * u(rng), 0.2 * u(rng), 0.05 * u(rng),
                             0.05 * u(rng), 0.05 * u(rng)).finished());
    const Eigen::Vector3d step(0.15, 0.02 * u(rng), 0.02 * u(rng));  // the camera moves 15 cm sideways
    const SE3 T1 = SE3::exp((Eigen::Matrix<double, 6, 1>() << step, 0.02 * u(rng), 0.02 * u(rng), 0.02 * u(rng))
                                .finished()) * T0;
    const Eigen::Vector3d centre_cam1 = T0.inverse().translation(), centre_cam2 = T1.inverse().translation();
    PixelMatches m;
    auto add = [&](const Eigen::Vector3d& pw, const Eigen::Vector3d& pw2, int l) { m.add(*cam, T0, T1, pw, pw2, l, n, rng); };
    for (int i = 0; i < 100; ++i) {
      const Eigen::Vector3d p = T0.inverse().act(Eigen::Vector3d(4 * u(rng), 3 * u(rng), 5 + 3 * u(rng)));
      add(p, p, 0);
    }
    // Movers in the epipolar plane of (camera 1 centre, camera 2 centre, point), moving with the camera
    // and farther (a point moving like the camera looks infinitely far: its parallax turns negative).
    for (int i = 0; i < 15; ++i) {
      const Eigen::Vector3d p = T0.inverse().act(Eigen::Vector3d(2 * u(rng), 1.5 * u(rng), 4 + u(rng)));
      add(p, p + 1.6 * (centre_cam2 - centre_cam1), 1);
    }
    const Eigen::Matrix3d R_c2_c1 = (T1 * T0.inverse()).rotation().matrix();
    const Classification a = plane_only.classify(m.prev, m.cur, nullptr, &R_c2_c1);
    const Classification b = with_cheirality.classify(m.prev, m.cur, nullptr, &R_c2_c1);
    ASSERT_EQ(b.motion_model, MotionModel::kKnownRotation);
    plane += score_against_feature_labels(m.label, a.flags);
    cheir += score_against_feature_labels(m.label, b.flags);
  }
  std::printf("movers sliding back along their epipolar lines: plane distance only precision %.3f recall %.3f; "
              "with cheirality %.3f / %.3f (fp %ld)\n",
              plane.precision(), plane.recall(), cheir.precision(), cheir.recall(), cheir.false_positive);
  EXPECT_LT(plane.recall(), 0.1);
  EXPECT_GE(cheir.recall(), 0.9);
  EXPECT_LE(cheir.false_positive, plane.false_positive + 2);
  EXPECT_GE(cheir.precision(), 0.95);
}

}  // namespace
}  // namespace slamkit
