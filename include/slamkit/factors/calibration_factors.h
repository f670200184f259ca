// Factors that estimate sensor parameters together with the trajectory (Kümmerle et al.,
// "Simultaneous parameter calibration, localization, and mapping", Advanced Robotics 2012;
// g2o's sclam2d types).
//
// SensorOffsetFactor<G> (G = SE2 | SE3), keys Xi, Xj, S: a relative pose measured between
// sensor frames, the sensor mounted at offset S on the robot,
//     e = t2v(Z⁻¹ · (Xi S)⁻¹ · (Xj S))               (g2o EDGE_SE2_CALIB; EDGE_SE3_OFFSET with one offset)
// SensorOffsetPairFactor<G>, keys Xi, Xj, Sa, Sb: the same with two offsets (Xi Sa)⁻¹ (Xj Sb)
// (g2o EDGE_SE2_OFFSET / EDGE_SE3_OFFSET with two parameter ids).
// The error t2v is g2o's: SE(2) → [t; θ], SE(3) → [t; q.vec], q.w ≥ 0 (core/pose_graph_error.h).
// Jacobians by the chain rule through Pi = Xi Sa, Pj = Xj Sb: with J_Pi, J_Pj of the plain
// between error, Xi ⊞ δ = Pi ⊞ Ad(Sa⁻¹) δ, so J_Xi = J_Pi Ad(Sa⁻¹), J_Sa = J_Pi (same for j).
//
// DifferentialDriveOdometryFactor, keys Xi, Xj, K = (k_l, k_r, b): raw wheel velocities
// (v_l, v_r) over dt (g2o's VelocityMeasurement), wheel increments s = k v dt, baseline b:
//     θ = (s_r − s_l)/b,  d = (s_l + s_r)/2,  U(K) = (d sinθ/θ, d (1 − cosθ)/θ, θ)
//     e = t2v(U(K)⁻¹ · Xi⁻¹ · Xj)                    (g2o EDGE_SE2_ODOM_DIFFERENTIAL_CALIB)
// LinearOdometryFactor, keys Xi, Xj, K ∈ R⁹ (a 3×3 matrix, row-major): a measured increment
// u = (Δx, Δy, Δθ) corrected linearly, U(K) = v2t(K u), e = t2v(U⁻¹ Xi⁻¹ Xj) (the paper's
// general linear odometry model; identity K = no correction).
// All Jacobians analytic (tests/factors/calibration_factor_test.cpp checks them numerically).
#pragma once

#include <Eigen/Core>

#include "slamkit/core/calibration.h"
#include "slamkit/core/factor.h"
#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {

using Vector9d = Eigen::Matrix<double, 9, 1>;

template <class G>
class SensorOffsetFactor final : public FactorN<G::kDim, G, G, G> {
  using Base = FactorN<G::kDim, G, G, G>;

 public:
  using typename Base::Residual;
  using GJ = typename Base::template Jacobian<G>;
  SensorOffsetFactor(Key i, Key j, Key offset, const G& measured, std::shared_ptr<const NoiseModel> noise,
                     std::shared_ptr<const RobustKernel> kernel = nullptr)
      : Base({i, j, offset}, std::move(noise), std::move(kernel)), measured_(measured) {}
  Residual error(const G& Xi, const G& Xj, const G& S, GJ* J_i, GJ* J_j, GJ* J_s) const override;
  const G& measured() const { return measured_; }

 private:
  G measured_;
};

template <class G>
class SensorOffsetPairFactor final : public FactorN<G::kDim, G, G, G, G> {
  using Base = FactorN<G::kDim, G, G, G, G>;

 public:
  using typename Base::Residual;
  using GJ = typename Base::template Jacobian<G>;
  SensorOffsetPairFactor(Key i, Key j, Key offset_i, Key offset_j, const G& measured,
                         std::shared_ptr<const NoiseModel> noise, std::shared_ptr<const RobustKernel> kernel = nullptr)
      : Base({i, j, offset_i, offset_j}, std::move(noise), std::move(kernel)), measured_(measured) {}
  Residual error(const G& Xi, const G& Xj, const G& Sa, const G& Sb, GJ* J_i, GJ* J_j, GJ* J_a,
                 GJ* J_b) const override;

 private:
  G measured_;
};

/// e = t2v(Z⁻¹ (Xi Sa)⁻¹ (Xj Sb)) and its Jacobians (any may be null); shared by the two above.
Eigen::Vector3d offset_between_error(const SE2& Z, const SE2& Xi, const SE2& Xj, const SE2& Sa, const SE2& Sb,
                                     Eigen::Matrix3d* J_i, Eigen::Matrix3d* J_j, Eigen::Matrix3d* J_a,
                                     Eigen::Matrix3d* J_b);
Eigen::Matrix<double, 6, 1> offset_between_error(const SE3& Z, const SE3& Xi, const SE3& Xj, const SE3& Sa,
                                                 const SE3& Sb, Eigen::Matrix<double, 6, 6>* J_i,
                                                 Eigen::Matrix<double, 6, 6>* J_j, Eigen::Matrix<double, 6, 6>* J_a,
                                                 Eigen::Matrix<double, 6, 6>* J_b);

/// e = t2v(v2t(u)⁻¹ Xi⁻¹ Xj) with Jacobians w.r.t. Xi, Xj and the parameters u = (x, y, θ) of U.
Eigen::Vector3d pose2_error_wrt_measurement(const Eigen::Vector3d& u, const SE2& Xi, const SE2& Xj,
                                            Eigen::Matrix3d* J_i, Eigen::Matrix3d* J_j, Eigen::Matrix3d* J_u);

class DifferentialDriveOdometryFactor final : public FactorN<3, SE2, SE2, Eigen::Vector3d> {
 public:
  /// measured = (v_l, v_r, dt) as in g2o's EDGE_SE2_ODOM_DIFFERENTIAL_CALIB.
  DifferentialDriveOdometryFactor(Key i, Key j, Key params, const Eigen::Vector3d& measured,
                                  std::shared_ptr<const NoiseModel> noise,
                                  std::shared_ptr<const RobustKernel> kernel = nullptr)
      : FactorN({i, j, params}, std::move(noise), std::move(kernel)), measured_(measured) {}
  Residual error(const SE2& Xi, const SE2& Xj, const Eigen::Vector3d& K, Jacobian<SE2>* J_i, Jacobian<SE2>* J_j,
                 Jacobian<Eigen::Vector3d>* J_k) const override;

 private:
  Eigen::Vector3d measured_;
};

class LinearOdometryFactor final : public FactorN<3, SE2, SE2, Vector9d> {
 public:
  /// measured = raw increment (Δx, Δy, Δθ); K row-major.
  LinearOdometryFactor(Key i, Key j, Key params, const Eigen::Vector3d& measured, std::shared_ptr<const NoiseModel> noise,
                       std::shared_ptr<const RobustKernel> kernel = nullptr)
      : FactorN({i, j, params}, std::move(noise), std::move(kernel)), measured_(measured) {}
  Residual error(const SE2& Xi, const SE2& Xj, const Vector9d& K, Jacobian<SE2>* J_i, Jacobian<SE2>* J_j,
                 Jacobian<Vector9d>* J_k) const override;

 private:
  Eigen::Vector3d measured_;
};

/// Identity correction (row-major 3×3 identity).
Vector9d identity_linear_odometry();

}  // namespace slamkit
