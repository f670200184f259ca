// UTIAS MRCLAM robot logs (RobotN_Odometry.dat: t v ω, commanded; RobotN_Groundtruth.dat:
// t x y θ, Vicon) and the odometry-calibration graph built from them (docs/calibration.md):
// per robot a chain of keyframes every keyframe_s, an EDGE_SE2 from the Vicon poses between
// consecutive keyframes and an EDGE_SE2_ODOM_DIFFERENTIAL_CALIB carrying the time-averaged
// commands as wheel velocities v_l,r = v ∓ ω b₀/2 over keyframe_s, with one
// VERTEX_ODOM_DIFFERENTIAL (1, 1, b₀) per robot: id 1000000 + robot; poses robot·100000 + k.
#pragma once

#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "slamkit/core/pose_graph.h"

namespace slamkit {

struct MrclamSample {
  double t, a, b, c;  ///< odometry: t v ω (c unused); ground truth: t x y θ
};

struct MrclamRobotLog {
  int robot = 1;
  std::vector<MrclamSample> odometry, groundtruth;
};

/// One log file: `columns` = 3 (odometry: t v ω) or 4 (ground truth: t x y θ), '#' comments.
/// Throws InputError naming `source`, line and field on malformed rows, stamps going backwards,
/// or fewer than 2 samples.
std::vector<MrclamSample> read_mrclam_samples(std::istream& in, const std::string& source, int columns);
/// Writes samples as read_mrclam_samples reads them back (shortest round-trip numbers).
void write_mrclam_samples(std::ostream& out, const std::vector<MrclamSample>& samples, int columns);

/// Reads RobotN_Odometry.dat and RobotN_Groundtruth.dat of `dir`. Throws InputError naming file,
/// line and field on malformed rows, stamps going backwards, or fewer than 2 samples.
MrclamRobotLog read_mrclam_robot(const std::string& dir, int robot);

/// The Vicon pose at time t (linear interpolation, the angle through its wrapped difference).
SE2 mrclam_groundtruth_at(const MrclamRobotLog& log, double t);

struct OdometryCalibrationGraphOptions {
  double keyframe_s = 2.0;          ///< shorter intervals bias the ω scale low (docs/calibration.md)
  double nominal_baseline = 0.25;   ///< b₀, metres
  double from = 0.0, to = 1.0;      ///< the fraction of each robot's common time span to use
  double lag_s = 0.0;               ///< the motion follows the commands by this much
  Eigen::Vector3d odometry_sigma{0.02, 0.02, 0.05};  ///< initial information of the command edges
  Eigen::Vector3d vicon_sigma{0.01, 0.01, 0.02};
};

struct OdometryCalibrationGraph {
  PoseGraph graph;
  std::vector<std::pair<std::size_t, std::size_t>> edge_ranges;  ///< per robot: [first, last) edge
  std::vector<std::vector<SE2>> vicon;                            ///< per robot: keyframe poses
  struct ClosedForm {
    double v_scale, omega_scale;  ///< Σ|Δp|/Σ|v dt| and Σ Δθ ω dt / Σ (ω dt)²
  };
  std::vector<ClosedForm> closed_form;
};

OdometryCalibrationGraph build_odometry_calibration_graph(const std::vector<MrclamRobotLog>& logs,
                                                          const OdometryCalibrationGraphOptions& options = {});

/// Id of robot r's VERTEX_ODOM_DIFFERENTIAL.
inline std::int64_t mrclam_odometry_vertex(int robot) { return 1000000 + robot; }

}  // namespace slamkit
