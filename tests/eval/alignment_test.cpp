// Alignment of associated trajectories: each mode recovers the transform that generated the
// estimate, applies it to poses and velocities, and rejects degenerate input.
#include "slamkit/eval/alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

/// A wiggly 3-D path with varying orientation and velocities.
Trajectory make_reference(std::size_t n = 200) {
  Trajectory t;
  for (std::size_t k = 0; k < n; ++k) {
    const double s = 0.05 * static_cast<double>(k);
    TrajectorySample x;
    x.stamp = s;
    x.T_world_body = SE3(SO3::from_rpy(0.1 * std::sin(s), 0.2 * std::cos(0.7 * s), s),
                         Eigen::Vector3d(5 * std::cos(s), 3 * std::sin(1.3 * s), 0.5 * s));
    x.v_world = Eigen::Vector3d(-5 * std::sin(s), 3.9 * std::cos(1.3 * s), 0.5);
    t.push_back(x);
  }
  return t;
}

/// est = S⁻¹ applied to ref, so that aligning est with S gives back ref.
Trajectory make_estimate(const Trajectory& ref, const Similarity3& S) { return apply_alignment(ref, S.inverse()); }

double max_position_error(const Trajectory& a, const Trajectory& b) {
  double e = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    e = std::max(e, (a[k].T_world_body.translation() - b[k].T_world_body.translation()).norm());
  return e;
}

double max_rotation_error(const Trajectory& a, const Trajectory& b) {
  double e = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k)
    e = std::max(e, a[k].T_world_body.rotation().between(b[k].T_world_body.rotation()).log().norm());
  return e;
}

Similarity3 make_similarity(double yaw_only, double scale) {
  Similarity3 S;
  S.R = yaw_only ? Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitZ()).toRotationMatrix()
                 : Eigen::Matrix3d(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1, -2, 0.5).normalized()));
  S.t = Eigen::Vector3d(10, -4, 2);
  S.scale = scale;
  return S;
}

TEST(Alignment, Se3Sim3And4DofRecoverTheirTransforms) {
  const Trajectory ref = make_reference();
  struct Case {
    AlignmentMode mode;
    Similarity3 S;
  };
  for (const Case& c : {Case{AlignmentMode::kSe3, make_similarity(false, 1.0)},
                        Case{AlignmentMode::kSim3, make_similarity(false, 2.5)},
                        Case{AlignmentMode::kPosYaw, make_similarity(true, 1.0)},
                        Case{AlignmentMode::kScale, Similarity3{Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 0.4}}}) {
    SCOPED_TRACE(to_string(c.mode));
    const Trajectory est = make_estimate(ref, c.S);
    const Similarity3 S = compute_alignment(est, ref, c.mode);
    EXPECT_LT((S.R - c.S.R).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_LT((S.t - c.S.t).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_NEAR(S.scale, c.S.scale, 1e-9);
    const Trajectory aligned = apply_alignment(est, S);
    EXPECT_LT(max_position_error(aligned, ref), 1e-9);
    EXPECT_LT(max_rotation_error(aligned, ref), 1e-9);
    for (std::size_t k = 0; k < ref.size(); ++k) EXPECT_LT((*aligned[k].v_world - *ref[k].v_world).norm(), 1e-9);
  }
}

TEST(Alignment, OriginMakesTheFirstPosesCoincide) {
  const Trajectory ref = make_reference();
  const Trajectory est = make_estimate(ref, make_similarity(false, 1.0));
  const Trajectory aligned = apply_alignment(est, compute_alignment(est, ref, AlignmentMode::kOrigin));
  EXPECT_LT(max_position_error(aligned, ref), 1e-9);  // a rigid transform: origin alignment recovers it
  Trajectory noisy = est;
  noisy[0].T_world_body = noisy[0].T_world_body * SE3::exp((SE3::Tangent() << 0.1, 0, 0, 0, 0.02, 0).finished());
  const Trajectory a2 = apply_alignment(noisy, compute_alignment(noisy, ref, AlignmentMode::kOrigin));
  EXPECT_LT((a2[0].T_world_body.translation() - ref[0].T_world_body.translation()).norm(), 1e-12);
  EXPECT_LT(a2[0].T_world_body.rotation().between(ref[0].T_world_body.rotation()).log().norm(), 1e-12);
}

TEST(Alignment, NoneIsIdentityAndFirstNUsesAPrefix) {
  const Trajectory ref = make_reference();
  const Trajectory est = make_estimate(ref, make_similarity(false, 1.0));
  const Similarity3 I = compute_alignment(est, ref, AlignmentMode::kNone);
  EXPECT_EQ(I.R, Eigen::Matrix3d::Identity());
  EXPECT_EQ(I.t, Eigen::Vector3d::Zero());
  // Corrupt the tail: aligning with the first 50 poses still recovers the transform.
  Trajectory bent = est;
  for (std::size_t k = 100; k < bent.size(); ++k)
    bent[k].T_world_body = SE3(bent[k].T_world_body.rotation(), bent[k].T_world_body.translation() + Eigen::Vector3d(3, 0, 0));
  const Similarity3 S = compute_alignment(bent, ref, AlignmentMode::kSe3, 50);
  EXPECT_LT((S.t - make_similarity(false, 1.0).t).norm(), 1e-9);
  EXPECT_GT((compute_alignment(bent, ref, AlignmentMode::kSe3).t - S.t).norm(), 0.1);
}

TEST(Alignment, KeepsTheSourceRotationInStep) {
  Trajectory ref = make_reference(20);
  for (std::size_t k = 0; k < ref.size(); ++k) ref[k].source_rotation = ref[k].T_world_body.rotation().matrix();
  const Similarity3 S = make_similarity(false, 1.0);
  const Trajectory moved = apply_alignment(ref, S);
  for (std::size_t k = 0; k < ref.size(); ++k)
    EXPECT_LT((*moved[k].source_rotation - moved[k].T_world_body.rotation().matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Alignment, DegenerateAndMismatchedInputThrow) {
  Trajectory line;
  for (int k = 0; k < 10; ++k) line.push_back(k, SE3(SO3(), Eigen::Vector3d(k, 0, 0)));
  EXPECT_THROW(compute_alignment(line, line, AlignmentMode::kSe3), Error);
  EXPECT_THROW(compute_alignment(line, make_reference(10), AlignmentMode::kSim3), Error);
  EXPECT_THROW(compute_alignment(line, make_reference(11), AlignmentMode::kNone), Error);
  EXPECT_EQ(parse_alignment_mode("posyaw"), AlignmentMode::kPosYaw);
  EXPECT_THROW(parse_alignment_mode("affine"), InputError);
  for (AlignmentMode m : {AlignmentMode::kNone, AlignmentMode::kOrigin, AlignmentMode::kSe3, AlignmentMode::kSim3,
                          AlignmentMode::kPosYaw, AlignmentMode::kScale})
    EXPECT_EQ(parse_alignment_mode(to_string(m)), m);
}

}  // namespace
}  // namespace slamkit
