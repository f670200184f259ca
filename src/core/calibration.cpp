#include "slamkit/core/calibration.h"

#include <cmath>

namespace slamkit {

const char* to_string(CalibrationKind kind) {
  switch (kind) {
    case CalibrationKind::kOffset2: return "offset2";
    case CalibrationKind::kOdomDifferential: return "odometry_differential";
    case CalibrationKind::kOdomLinear: return "odometry_linear";
  }
  return "?";
}

const char* to_string(CalibratedEdgeKind kind) {
  switch (kind) {
    case CalibratedEdgeKind::kSensorOffset2: return "EDGE_SE2_CALIB";
    case CalibratedEdgeKind::kOffsetParams2: return "EDGE_SE2_OFFSET";
    case CalibratedEdgeKind::kOffsetParams3: return "EDGE_SE3_OFFSET";
    case CalibratedEdgeKind::kOdomDifferential: return "EDGE_SE2_ODOM_DIFFERENTIAL_CALIB";
    case CalibratedEdgeKind::kOdomLinear: return "EDGE_SE2_ODOM_LINEAR_CALIB";
  }
  return "?";
}

int calibration_dim(CalibrationKind kind) { return kind == CalibrationKind::kOdomLinear ? 9 : 3; }

const CalibrationVertex* CalibrationSection::find(std::int64_t id) const {
  for (const CalibrationVertex& v : vertices)
    if (v.id == id) return &v;
  return nullptr;
}

CalibrationVertex* CalibrationSection::find(std::int64_t id) {
  for (CalibrationVertex& v : vertices)
    if (v.id == id) return &v;
  return nullptr;
}

Eigen::Vector3d differential_drive_motion(const Eigen::Vector3d& K, double v_left, double v_right, double dt,
                                          Eigen::Matrix3d* J_K) {
  const double sl = K[0] * v_left * dt, sr = K[1] * v_right * dt, b = K[2];
  const double theta = (sr - sl) / b, d = 0.5 * (sl + sr);
  // f = sinθ/θ, g = (1 − cosθ)/θ and their derivatives; Taylor series near 0.
  double f, g, df, dg;
  if (std::abs(theta) < 1e-4) {
    const double t2 = theta * theta;
    f = 1.0 - t2 / 6.0, df = -theta / 3.0;
    g = theta / 2.0 - theta * t2 / 24.0, dg = 0.5 - t2 / 8.0;
  } else {
    const double s = std::sin(theta), c = std::cos(theta);
    f = s / theta, g = (1.0 - c) / theta;
    df = (theta * c - s) / (theta * theta);
    dg = (theta * s - (1.0 - c)) / (theta * theta);
  }
  if (J_K) {
    // ∂/∂s_l, ∂/∂s_r, ∂/∂b of (x, y, θ); θ_sl = −1/b, θ_sr = 1/b, θ_b = −θ/b, d_s = 1/2.
    const double th[3] = {-1.0 / b, 1.0 / b, -theta / b};
    const double dd[3] = {0.5, 0.5, 0.0};
    const double chain[3] = {v_left * dt, v_right * dt, 1.0};  // ∂(s_l, s_r, b)/∂(k_l, k_r, b)
    for (int k = 0; k < 3; ++k) {
      (*J_K)(0, k) = (dd[k] * f + d * df * th[k]) * chain[k];
      (*J_K)(1, k) = (dd[k] * g + d * dg * th[k]) * chain[k];
      (*J_K)(2, k) = th[k] * chain[k];
    }
  }
  return Eigen::Vector3d(d * f, d * g, theta);
}

Eigen::Vector3d linear_odometry_motion(const Eigen::Matrix<double, 9, 1>& k, const Eigen::Vector3d& u) {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(k.data()) * u;
}

}  // namespace slamkit
