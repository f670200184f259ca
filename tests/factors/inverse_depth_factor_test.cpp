// InverseDepthFactor: Jacobians w.r.t. both states and the inverse depth against central
// differences, with the pinhole and the equidistant fisheye model, and the residual at truth.
#include <gtest/gtest.h>

#include <random>

#include "slamkit/core/jacobian_check.h"
#include "slamkit/factors/inverse_depth_factor.h"

namespace slamkit {
namespace {

TEST(InverseDepthFactor, ZeroAtTruthAndJacobiansMatchNumeric) {
  std::mt19937 rng(9);
  std::normal_distribution<double> n;
  const auto rv = [&](double s) { return Eigen::Vector3d(s * n(rng), s * n(rng), s * n(rng)); };
  const std::vector<std::shared_ptr<const CameraModel>> cameras = {
      std::make_shared<PinholeCamera>(300, 310, 320, 240, 640, 480),
      std::make_shared<EquidistantCamera>(190.97, 190.97, 254.93, 256.90, 0.0034823894, 0.00071503484,
                                          -0.0020532361, 0.00020293673, 512, 512)};
  const SE3 T_imu_cam(SO3::exp(Eigen::Vector3d(-1.2, 0.1, -1.2)), Eigen::Vector3d(0.05, -0.07, -0.04));
  for (const auto& cam : cameras) {
    Values v;
    FactorGraph g;
    int made = 0;
    for (int i = 0; made < 10 && i < 1000; ++i) {
      ImuState a, k;
      a.R = SO3::exp(rv(1.0)), a.p = rv(1.0), a.v = rv(1.0);
      k.R = a.R.plus(rv(0.1)), k.p = a.p + rv(0.3), k.v = rv(1.0);
      // A point in front of both cameras.
      const SE3 T_wa = a.pose() * T_imu_cam, T_wk = k.pose() * T_imu_cam;
      const Eigen::Vector3d P = T_wa.act(Eigen::Vector3d(0.5 * n(rng), 0.5 * n(rng), 3.0 + n(rng) * 0.5));
      const Eigen::Vector3d Pa = T_wa.inverse().act(P), Pk = T_wk.inverse().act(P);
      Eigen::Vector2d uv;
      if (Pa.z() < 0.5 || Pk.z() < 0.5 || !cam->project(Pk, &uv)) continue;
      const Key xa = symbol('a', made), xk = symbol('k', made), l = symbol('l', made);
      v.insert(xa, a), v.insert(xk, k), v.insert(l, Eigen::Matrix<double, 1, 1>(1.0 / Pa.norm()));
      const InverseDepthFactor f(xa, xk, l, Pa, uv, cam, T_imu_cam, NoiseModel::unit(2));
      EXPECT_LT(f.error(a, k, Eigen::Matrix<double, 1, 1>(1.0 / Pa.norm()), nullptr, nullptr, nullptr).norm(), 1e-8);
      EXPECT_LT((f.world_point(a, 1.0 / Pa.norm()) - P).norm(), 1e-9);
      // Measured 3 px off, so the residual is not zero where the Jacobians are checked.
      g.emplace<InverseDepthFactor>(xa, xk, l, Pa, uv + Eigen::Vector2d(3, -2), cam, T_imu_cam, NoiseModel::unit(2));
      ++made;
    }
    ASSERT_EQ(made, 10) << cam->model_name();
    const JacobianCheckResult r = check_jacobians(g, v, 1e-5);
    EXPECT_TRUE(r.ok) << cam->model_name() << ": " << r.message();
  }
}

TEST(InverseDepthFactor, PointBehindTheCameraIsCappedNotNaN) {
  const auto cam = std::make_shared<PinholeCamera>(300, 300, 320, 240, 640, 480);
  const InverseDepthFactor f(1, 2, 3, Eigen::Vector3d(0, 0, 1), Eigen::Vector2d(320, 240), cam, SE3(), NoiseModel::unit(2));
  ImuState a, k;
  k.p = Eigen::Vector3d(0, 0, 5);  // the observer is beyond the point (depth 1)
  Eigen::Matrix<double, 2, 15> Ja, Jk;
  Eigen::Matrix<double, 2, 1> Jl;
  const Eigen::Vector2d r = f.error(a, k, Eigen::Matrix<double, 1, 1>(1.0), &Ja, &Jk, &Jl);
  EXPECT_TRUE(r.allFinite());
  EXPECT_DOUBLE_EQ(r(0), InverseDepthFactor::kOutOfView);
  EXPECT_TRUE(Ja.isZero() && Jk.isZero() && Jl.isZero());
}

}  // namespace
}  // namespace slamkit
