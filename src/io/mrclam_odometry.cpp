#include "slamkit/io/mrclam_odometry.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <fstream>
#include <istream>
#include <ostream>
#include <cmath>
#include <filesystem>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_calibration.h"
#include "slamkit/io/text_reader.h"

namespace slamkit {
namespace {

// Time-weighted mean of the commanded (v, ω) over [t0, t1); a command holds until the next one.
Eigen::Vector2d mean_command(const std::vector<MrclamSample>& odo, double t0, double t1, double lag) {
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  auto it = std::upper_bound(odo.begin(), odo.end(), t0 - lag, [](double x, const MrclamSample& s) { return x < s.t; });
  if (it != odo.begin()) --it;
  for (; it != odo.end() && it->t + lag < t1; ++it) {
    const double a = std::max(t0, it->t + lag), b = std::min(t1, it + 1 == odo.end() ? t1 : (it + 1)->t + lag);
    if (b > a) sum += (b - a) * Eigen::Vector2d(it->a, it->b);
  }
  return sum / (t1 - t0);
}

std::vector<MrclamSample> read_columns(const std::string& path, int columns) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  return read_mrclam_samples(in, path, columns);
}

}  // namespace

std::vector<MrclamSample> read_mrclam_samples(std::istream& in, const std::string& source, int columns) {
  if (columns != 3 && columns != 4) throw InputError(source, 0, "", "MRCLAM logs have 3 or 4 columns");
  TextReader r(in, source);
  std::vector<MrclamSample> out;
  static constexpr const char* kNames[2][4] = {{"time", "v", "omega", ""}, {"time", "x", "y", "theta"}};
  const auto& names = kNames[columns == 4 ? 1 : 0];
  while (r.next_line()) {
    if (static_cast<int>(r.num_fields()) != columns)
      r.fail("", "expected " + std::to_string(columns) + " columns, line has " + std::to_string(r.num_fields()));
    MrclamSample s{r.number(0, names[0]), r.number(1, names[1]), r.number(2, names[2]),
                   columns > 3 ? r.number(3, names[3]) : 0.0};
    if (!out.empty() && s.t < out.back().t) r.fail("time", "time stamps go backwards");
    out.push_back(s);
  }
  if (out.size() < 2) throw InputError(source, 0, "", "fewer than 2 samples");
  return out;
}

void write_mrclam_samples(std::ostream& out, const std::vector<MrclamSample>& samples, int columns) {
  auto text = [](double v) {
    std::array<char, 32> buf{};
    return std::string(buf.data(), std::to_chars(buf.data(), buf.data() + buf.size(), v).ptr);
  };
  for (const MrclamSample& s : samples) {
    out << text(s.t) << '\t' << text(s.a) << '\t' << text(s.b);
    if (columns == 4) out << '\t' << text(s.c);
    out << '\n';
  }
}

MrclamRobotLog read_mrclam_robot(const std::string& dir, int robot) {
  const std::filesystem::path d(dir);
  const std::string name = "Robot" + std::to_string(robot);
  MrclamRobotLog log;
  log.robot = robot;
  log.odometry = read_columns((d / (name + "_Odometry.dat")).string(), 3);
  log.groundtruth = read_columns((d / (name + "_Groundtruth.dat")).string(), 4);
  return log;
}

SE2 mrclam_groundtruth_at(const MrclamRobotLog& log, double t) {
  const auto& gt = log.groundtruth;
  auto it = std::lower_bound(gt.begin(), gt.end(), t, [](const MrclamSample& s, double x) { return s.t < x; });
  if (it == gt.begin()) return SE2(it->a, it->b, it->c);
  if (it == gt.end()) return SE2(gt.back().a, gt.back().b, gt.back().c);
  const MrclamSample& p = *(it - 1);
  const double w = (t - p.t) / std::max(1e-9, it->t - p.t);
  return SE2(p.a + w * (it->a - p.a), p.b + w * (it->b - p.b), p.c + w * wrap_angle(it->c - p.c));
}

OdometryCalibrationGraph build_odometry_calibration_graph(const std::vector<MrclamRobotLog>& logs,
                                                          const OdometryCalibrationGraphOptions& o) {
  if (!(o.keyframe_s > 0) || !(o.nominal_baseline > 0) || !(o.from >= 0 && o.from < o.to && o.to <= 1))
    throw InputError("", 0, "keyframe_s", "keyframe and baseline must be positive, 0 <= from < to <= 1");
  OdometryCalibrationGraph out;
  PoseGraph& g = out.graph;
  g.source = "MRCLAM";
  g.format = "g2o";
  const double dt = o.keyframe_s, b0 = o.nominal_baseline;
  const Eigen::Vector3d odo_info = o.odometry_sigma.cwiseAbs2().cwiseInverse();
  const Eigen::Vector3d vicon_info = o.vicon_sigma.cwiseAbs2().cwiseInverse();
  for (const MrclamRobotLog& log : logs) {
    const double ta0 = std::max(log.odometry.front().t + o.lag_s, log.groundtruth.front().t);
    const double ta1 = std::min(log.odometry.back().t + o.lag_s, log.groundtruth.back().t);
    const double t0 = ta0 + o.from * (ta1 - ta0), t1 = ta0 + o.to * (ta1 - ta0);
    const int n = static_cast<int>((t1 - t0) / dt);
    if (n < 2) throw InputError("", 0, "keyframe_s", "robot " + std::to_string(log.robot) + ": fewer than 2 keyframes");
    const std::int64_t base = static_cast<std::int64_t>(log.robot) * 100000;
    g.calibration.vertices.push_back(
        {mrclam_odometry_vertex(log.robot), CalibrationKind::kOdomDifferential, Eigen::Vector3d(1, 1, b0), true, 0});
    out.vicon.emplace_back();
    for (int k = 0; k <= n; ++k) {
      GraphVertex v;
      v.id = base + k;
      v.pose2 = mrclam_groundtruth_at(log, t0 + k * dt);
      g.add_vertex(v);
      out.vicon.back().push_back(v.pose2);
    }
    const std::size_t first = g.edges.size();
    double dist_vicon = 0, dist_cmd = 0, rot_num = 0, rot_den = 0;
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector2d c = mean_command(log.odometry, t0 + k * dt, t0 + (k + 1) * dt, o.lag_s);
      GraphEdge e;
      e.from = base + k, e.to = base + k + 1, e.kind = EdgeKind::kPose2Pose2;
      CalibratedMeasurement m;
      m.kind = CalibratedEdgeKind::kOdomDifferential;
      m.param_a = m.param_b = mrclam_odometry_vertex(log.robot);
      m.odometry = Eigen::Vector3d(c[0] - c[1] * b0 / 2, c[0] + c[1] * b0 / 2, dt);
      e.calibrated = m;
      e.information = odo_info.asDiagonal();
      g.edges.push_back(e);
      const SE2 dv = out.vicon.back()[static_cast<std::size_t>(k)].between(out.vicon.back()[static_cast<std::size_t>(k + 1)]);
      dist_vicon += dv.translation().norm();
      dist_cmd += std::abs(c[0]) * dt;
      rot_num += dv.theta() * c[1] * dt;
      rot_den += c[1] * c[1] * dt * dt;
    }
    for (int k = 0; k < n; ++k) {
      GraphEdge e;
      e.from = base + k, e.to = base + k + 1, e.kind = EdgeKind::kPose2Pose2;
      e.pose2 = out.vicon.back()[static_cast<std::size_t>(k)].between(out.vicon.back()[static_cast<std::size_t>(k + 1)]);
      e.information = vicon_info.asDiagonal();
      g.edges.push_back(e);
    }
    out.edge_ranges.emplace_back(first, g.edges.size());
    out.closed_form.push_back({dist_vicon / dist_cmd, rot_num / rot_den});
  }
  update_calibrated_measurements(g);
  return out;
}

}  // namespace slamkit
