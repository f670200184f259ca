// The calibration section of a pose graph: sensor parameters estimated together with the
// trajectory (Kümmerle et al. 2012; g2o's sclam2d and offset types).
//
// A calibrated edge is an ordinary pose–pose GraphEdge whose measurement is a function of
// calibration parameters; it carries its raw measurement in GraphEdge::calibrated and its
// GraphEdge::pose2/pose3 holds the *effective* body-frame relative pose at the current
// parameter values (so initialization, gauge and component logic see a plain pose edge):
//   kSensorOffset2  EDGE_SE2_CALIB i j s        z ≈ (Xi S)⁻¹ (Xj S),   S a VERTEX_SE2 offset
//   kOffsetParams2  EDGE_SE2_OFFSET i j a b     z ≈ (Xi Sa)⁻¹ (Xj Sb), Sa, Sb PARAMS_SE2OFFSET
//   kOffsetParams3  EDGE_SE3_OFFSET i j a b     z ≈ (Xi Sa)⁻¹ (Xj Sb), Sa, Sb PARAMS_SE3OFFSET
//   kOdomDifferential EDGE_SE2_ODOM_DIFFERENTIAL_CALIB i j k   raw (v_l, v_r, dt), K = (k_l, k_r, b)
//   kOdomLinear     EDGE_SE2_ODOM_LINEAR_CALIB i j k (slamkit)  raw (Δx, Δy, Δθ), K ∈ R^{3×3}
// Effective measurement: offsets Sa z Sb⁻¹; odometry U(K) (differential_drive_motion, K u).
// The error is t2v(z⁻¹ (Xi Sa)⁻¹ (Xj Sb)) resp. t2v(U⁻¹ Xi⁻¹ Xj), information in its coordinates.
//
// Parameters: calibration *vertices* share the vertex id space (g2o VERTEX_SE2 used as an
// offset, VERTEX_ODOM_DIFFERENTIAL, slamkit's VERTEX_ODOM_LINEAR) and are estimated unless
// FIXed; g2o *parameters* (PARAMS_SE2OFFSET here, PARAMS_SE3OFFSET in PoseGraph::sensor_offsets,
// shared with EDGE_SE3_TRACKXYZ) are constants, as in g2o, unless estimate_offset_parameters.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "slamkit/geometry/se2.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {

enum class CalibrationKind : std::uint8_t { kOffset2, kOdomDifferential, kOdomLinear };
enum class CalibratedEdgeKind : std::uint8_t { kSensorOffset2, kOffsetParams2, kOffsetParams3, kOdomDifferential, kOdomLinear };

const char* to_string(CalibrationKind kind);
const char* to_string(CalibratedEdgeKind kind);
/// Number of parameters: 3 (offset x, y, θ), 3 (k_l, k_r, b), 9 (K row-major).
int calibration_dim(CalibrationKind kind);

/// A calibration variable stored as a vertex.
struct CalibrationVertex {
  std::int64_t id = 0;
  CalibrationKind kind = CalibrationKind::kOffset2;
  Eigen::VectorXd value;  ///< kOffset2 (x, y, θ); kOdomDifferential (k_l, k_r, b); kOdomLinear K row-major
  bool estimate = true;   ///< false: held at its value (FIX)
  int line = 0;
};

/// The raw measurement of a calibrated edge (see above).
struct CalibratedMeasurement {
  CalibratedEdgeKind kind = CalibratedEdgeKind::kSensorOffset2;
  std::int64_t param_a = 0;  ///< the offset / odometry vertex, or the PARAMS id of the from side
  std::int64_t param_b = 0;  ///< PARAMS id of the to side (kOffsetParams*); = param_a otherwise
  SE2 sensor2;               ///< sensor-frame relative pose (kSensorOffset2, kOffsetParams2)
  SE3 sensor3;               ///< kOffsetParams3
  Eigen::Vector3d odometry = Eigen::Vector3d::Zero();  ///< (v_l, v_r, dt) or (Δx, Δy, Δθ)
};

/// A Gaussian prior on a calibration vertex: e = value ⊟ mean (tangent of SE(2) for offsets,
/// the difference for vectors), information in those coordinates.
struct CalibrationPrior {
  std::int64_t id = 0;
  Eigen::VectorXd mean;
  Eigen::MatrixXd information;
  int line = 0;
};

struct CalibrationSection {
  std::vector<CalibrationVertex> vertices;
  std::map<int, SE2> offset_parameters2;  ///< g2o PARAMS_SE2OFFSET
  bool estimate_offset_parameters = false;  ///< PARAMS_* used by offset edges become variables
  std::vector<CalibrationPrior> priors;

  bool empty() const { return vertices.empty() && offset_parameters2.empty() && priors.empty(); }
  const CalibrationVertex* find(std::int64_t id) const;
  CalibrationVertex* find(std::int64_t id);
};

/// SE(2) from (x, y, θ).
inline SE2 to_se2(const Eigen::Vector3d& v) { return SE2(v[0], v[1], v[2]); }

/// Differential-drive motion U(K) = (x, y, θ) from wheel velocities over dt, K = (k_l, k_r, b):
/// s = k v dt, θ = (s_r − s_l)/b, d = (s_l + s_r)/2, (x, y) = d (sinθ/θ, (1 − cosθ)/θ) (series
/// near θ = 0); J_K = ∂(x, y, θ)/∂K. b must be non-zero.
Eigen::Vector3d differential_drive_motion(const Eigen::Vector3d& K, double v_left, double v_right, double dt,
                                          Eigen::Matrix3d* J_K = nullptr);
/// K u for K row-major in `k`.
Eigen::Vector3d linear_odometry_motion(const Eigen::Matrix<double, 9, 1>& k, const Eigen::Vector3d& u);

}  // namespace slamkit
