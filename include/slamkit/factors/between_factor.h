// Relative-pose factors between two poses Xi, Xj with measurement Z (pose of j in frame i).
//
// BetweenFactorSE2:  e = t2v(Z⁻¹ Xi⁻¹ Xj) = [t; θ]                (g2o EDGE_SE2)
// BetweenFactorSE3:  kQuaternion  e = [t; q.vec], q.w ≥ 0          (g2o EDGE_SE3:QUAT, default)
//                    kLog         e = Log(Z⁻¹ Xi⁻¹ Xj) = [ρ; φ]     (GTSAM BetweenFactor<Pose3>)
// The quaternion form matches g2o's chi2 and information layout (rotation information
// w.r.t. q.vec ≈ φ/2); the log form is the geodesic error. Jacobians are analytic
// (pose_graph_error.h for the g2o forms; Jr⁻¹ chains for the log form).
#pragma once

#include "slamkit/core/factor.h"
#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {

class BetweenFactorSE2 final : public FactorN<3, SE2, SE2> {
 public:
  BetweenFactorSE2(Key i, Key j, const SE2& measured, std::shared_ptr<const NoiseModel> noise,
                   std::shared_ptr<const RobustKernel> kernel = nullptr)
      : FactorN({i, j}, std::move(noise), std::move(kernel)),
        measured_(measured),
        measured_rotation_t_(measured.rotation().matrix().transpose()) {}
  Residual error(const SE2& Xi, const SE2& Xj, Jacobian<SE2>* J_i, Jacobian<SE2>* J_j) const override;
  double linearize(const double* const* params, double* residual, double* const* jacobians) const override {
    return linearize_typed(*this, params, residual, jacobians);  // error() without a virtual call
  }
  const SE2& measured() const { return measured_; }

 private:
  SE2 measured_;
  Eigen::Matrix2d measured_rotation_t_;  // R_zᵀ, used by every evaluation
};

enum class Se3ErrorForm { kQuaternion, kLog };

class BetweenFactorSE3 final : public FactorN<6, SE3, SE3> {
 public:
  BetweenFactorSE3(Key i, Key j, const SE3& measured, std::shared_ptr<const NoiseModel> noise,
                   std::shared_ptr<const RobustKernel> kernel = nullptr, Se3ErrorForm form = Se3ErrorForm::kQuaternion)
      : FactorN({i, j}, std::move(noise), std::move(kernel)), measured_(measured), form_(form) {}
  Residual error(const SE3& Xi, const SE3& Xj, Jacobian<SE3>* J_i, Jacobian<SE3>* J_j) const override;
  double linearize(const double* const* params, double* residual, double* const* jacobians) const override {
    return linearize_typed(*this, params, residual, jacobians);
  }
  const SE3& measured() const { return measured_; }
  Se3ErrorForm form() const { return form_; }

 private:
  SE3 measured_;
  Se3ErrorForm form_;
};

}  // namespace slamkit
