// ATE and RPE: closed-form cases for every pose relation, invariances, and agreement with
// the 4×4-matrix definitions (evo's rpe_base / ape_base) on random trajectories.
#include "slamkit/eval/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

Trajectory random_walk(std::size_t n, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Trajectory t;
  SE3 T;
  for (std::size_t k = 0; k < n; ++k) {
    SE3::Tangent d;
    d << 1.0 + 0.2 * g(rng), 0.2 * g(rng), 0.1 * g(rng), 0.05 * g(rng), 0.05 * g(rng), 0.2 * g(rng);
    T = T * SE3::exp(d);
    t.push_back(0.1 * static_cast<double>(k), T);
  }
  return t;
}

Trajectory perturbed(const Trajectory& ref, std::mt19937& rng, double sigma) {
  std::normal_distribution<double> g(0.0, sigma);
  Trajectory t;
  for (const auto& s : ref) {
    SE3::Tangent d;
    d << g(rng), g(rng), g(rng), g(rng), g(rng), g(rng);
    t.push_back(s.stamp, s.T_world_body * SE3::exp(d));
  }
  return t;
}

double angle_of(const Eigen::Matrix3d& R) { return SO3::from_matrix(R).log().norm(); }

/// evo's formulas on plain matrices.
double matrix_error(const Eigen::Matrix4d& E, PoseRelation r) {
  switch (r) {
    case PoseRelation::kTranslation: return E.topRightCorner<3, 1>().norm();
    case PoseRelation::kAngleDeg: return angle_of(E.topLeftCorner<3, 3>()) * 180.0 / kPi;
    case PoseRelation::kAngleRad: return angle_of(E.topLeftCorner<3, 3>());
    case PoseRelation::kRotationPart: return (E.topLeftCorner<3, 3>() - Eigen::Matrix3d::Identity()).norm();
    case PoseRelation::kFull: return (E - Eigen::Matrix4d::Identity()).norm();
    default: return 0.0;
  }
}

const PoseRelation kMatrixRelations[] = {PoseRelation::kTranslation, PoseRelation::kAngleDeg, PoseRelation::kAngleRad,
                                         PoseRelation::kRotationPart, PoseRelation::kFull};

TEST(Metrics, AteMatchesTheMatrixDefinition) {
  std::mt19937 rng(1);
  const Trajectory ref = random_walk(100, rng);
  const Trajectory est = perturbed(ref, rng, 0.1);
  for (PoseRelation r : kMatrixRelations) {
    SCOPED_TRACE(to_string(r));
    const PoseErrors e = compute_ate(est, ref, r);
    ASSERT_EQ(e.errors.size(), 100u);
    for (std::size_t k = 0; k < ref.size(); ++k) {
      const Eigen::Matrix4d E = est[k].T_world_body.matrix().inverse() * ref[k].T_world_body.matrix();
      EXPECT_NEAR(e.errors[k], matrix_error(E, r), 1e-9);
      EXPECT_NEAR(e.translation[k], matrix_error(E, PoseRelation::kTranslation), 1e-9);
      EXPECT_NEAR(e.rotation_deg[k], matrix_error(E, PoseRelation::kAngleDeg), 1e-7);
    }
  }
}

TEST(Metrics, RpeMatchesTheMatrixDefinition) {
  std::mt19937 rng(2);
  const Trajectory ref = random_walk(120, rng);
  const Trajectory est = perturbed(ref, rng, 0.05);
  for (PoseRelation r : kMatrixRelations) {
    SCOPED_TRACE(to_string(r));
    RpeOptions opt;
    opt.delta = 7;
    opt.relation = r;
    const RpeErrors e = compute_rpe(est, ref, opt);
    ASSERT_EQ(e.pairs.size(), 17u);  // 0, 7, …, 119
    for (std::size_t k = 0; k < e.pairs.size(); ++k) {
      const auto [i, j] = e.pairs[k];
      const Eigen::Matrix4d Q = ref[i].T_world_body.matrix().inverse() * ref[j].T_world_body.matrix();
      const Eigen::Matrix4d P = est[i].T_world_body.matrix().inverse() * est[j].T_world_body.matrix();
      EXPECT_NEAR(e.errors[k], matrix_error(Q.inverse() * P, r), 1e-9);
    }
  }
}

TEST(Metrics, ClosedFormCases) {
  Trajectory ref, shifted, turned;
  const double theta = 5.0 * kPi / 180.0;
  for (int k = 0; k < 20; ++k) {
    const SE3 T(SO3::from_rpy(0.1 * k, 0.0, 0.3 * k), Eigen::Vector3d(k, 0.5 * k, 0));
    ref.push_back(k, T);
    shifted.push_back(k, SE3(T.rotation(), T.translation() + Eigen::Vector3d(0.3, 0.4, 0.0)));
    turned.push_back(k, T * SE3(SO3::from_rpy(0, 0, theta), Eigen::Vector3d::Zero()));
  }
  for (double e : compute_ate(shifted, ref, PoseRelation::kTranslation).errors) EXPECT_NEAR(e, 0.5, 1e-12);
  for (double e : compute_ate(shifted, ref, PoseRelation::kAngleDeg).errors) EXPECT_NEAR(e, 0.0, 1e-6);
  for (double e : compute_ate(turned, ref, PoseRelation::kAngleDeg).errors) EXPECT_NEAR(e, 5.0, 1e-9);
  for (double e : compute_ate(turned, ref, PoseRelation::kAngleRad).errors) EXPECT_NEAR(e, theta, 1e-11);
  // ‖R − I‖_F = 2√2 sin(θ/2) for a rotation by θ.
  for (double e : compute_ate(turned, ref, PoseRelation::kRotationPart).errors)
    EXPECT_NEAR(e, 2.0 * std::sqrt(2.0) * std::sin(theta / 2), 1e-12);
  for (double e : compute_ate(turned, ref, PoseRelation::kTranslation).errors) EXPECT_NEAR(e, 0.0, 1e-12);
  for (double e : compute_ate(ref, ref, PoseRelation::kFull).errors) EXPECT_NEAR(e, 0.0, 1e-12);
}

TEST(Metrics, RpeOfAScaledStraightLine) {
  // The estimate moves 1.1 m where the reference moves 1 m: every 1-frame RPE is 0.1 m.
  Trajectory ref, est;
  for (int k = 0; k < 30; ++k) ref.push_back(k, SE3(SO3(), Eigen::Vector3d(k, 0, 0))), est.push_back(k, SE3(SO3(), Eigen::Vector3d(1.1 * k, 0, 0)));
  RpeOptions opt;
  for (PoseRelation r : {PoseRelation::kTranslation, PoseRelation::kPointDistance}) {
    opt.relation = r;
    const RpeErrors e = compute_rpe(est, ref, opt);
    ASSERT_EQ(e.errors.size(), 29u);
    for (double v : e.errors) EXPECT_NEAR(v, 0.1, 1e-12);
  }
  // Pairs from the reference: 2 m of path is 2 reference steps (but 1.8 estimate steps).
  opt.delta = 2.0;
  opt.delta_unit = DeltaUnit::kMeters;
  opt.pairs_from_reference = true;
  EXPECT_EQ(compute_rpe(est, ref, opt).pairs.front(), (std::pair<std::size_t, std::size_t>{2, 4}));
  opt.pairs_from_reference = false;
  EXPECT_EQ(compute_rpe(est, ref, opt).pairs.front(), (std::pair<std::size_t, std::size_t>{2, 4}));  // 2.2 m ≥ 2
}

TEST(Metrics, RpeIsInvariantToARigidMotionOfTheEstimate) {
  std::mt19937 rng(3);
  const Trajectory ref = random_walk(60, rng);
  const Trajectory est = perturbed(ref, rng, 0.02);
  const SE3 S(SO3::from_rpy(0.3, -0.2, 1.0), Eigen::Vector3d(5, -3, 2));
  Trajectory moved;
  for (const auto& s : est) moved.push_back(s.stamp, S * s.T_world_body);
  RpeOptions opt;
  opt.delta = 3;
  opt.all_pairs = true;
  const RpeErrors a = compute_rpe(est, ref, opt), b = compute_rpe(moved, ref, opt);
  ASSERT_EQ(a.errors.size(), b.errors.size());
  for (std::size_t k = 0; k < a.errors.size(); ++k) EXPECT_NEAR(a.errors[k], b.errors[k], 1e-9);
}

TEST(Metrics, LengthMismatchThrows) {
  std::mt19937 rng(4);
  const Trajectory a = random_walk(10, rng), b = random_walk(11, rng);
  EXPECT_THROW(compute_ate(a, b, PoseRelation::kTranslation), Error);
  EXPECT_THROW(compute_rpe(a, b, RpeOptions{}), Error);
  EXPECT_THROW(compute_ate(Trajectory(), Trajectory(), PoseRelation::kTranslation), Error);
}

}  // namespace
}  // namespace slamkit
