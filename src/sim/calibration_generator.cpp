#include "slamkit/sim/calibration_generator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <sstream>

#include "sim_spec.h"
#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_calibration.h"

namespace slamkit {
namespace {

struct Rng {
  std::mt19937 engine;
  double normal(double sigma) { return sigma * std::normal_distribution<double>(0.0, 1.0)(engine); }
  double uniform(double half_width) { return std::uniform_real_distribution<double>(-half_width, half_width)(engine); }
};

Eigen::VectorXd identity_k() {
  Eigen::VectorXd k(9);
  k << 1, 0, 0, 0, 1, 0, 0, 0, 1;
  return k;
}

struct Command {
  double v, omega;
};

constexpr double kDt = 0.5;  // seconds per step

// calib2d route: laps of two squares, the first turning left on arcs, the second turning right
// in place; or a straight line.
std::vector<Command> route(const CalibrationSimOptions& o) {
  const double v = o.step / kDt;
  std::vector<Command> c;
  auto straight = [&](int n) { c.insert(c.end(), n, Command{v, 0.0}); };
  if (o.path == "line") {
    straight(o.laps * 172);
    return c;
  }
  for (int lap = 0; lap < o.laps; ++lap) {
    for (int side = 0; side < 4; ++side) {
      straight(16);
      c.insert(c.end(), 6, Command{v, (kPi / 2) / (6 * kDt)});  // left arc
    }
    for (int side = 0; side < 4; ++side) {
      straight(16);
      c.insert(c.end(), 5, Command{0.0, -(kPi / 2) / (5 * kDt)});  // right turn in place
    }
  }
  return c;
}

Eigen::Matrix3d diag3(double st, double sr) {
  return Eigen::Vector3d(1 / (st * st), 1 / (st * st), 1 / (sr * sr)).asDiagonal();
}

void add_vertex2(PoseGraph& g, std::int64_t id, const SE2& x) {
  GraphVertex v;
  v.id = id;
  v.kind = VertexKind::kPose2;
  v.pose2 = x;
  g.add_vertex(v);
}

PoseGraph calib2d(const CalibrationSimOptions& o, CalibrationTruth* truth, PoseGraph* gt) {
  Rng rng{std::mt19937(o.seed)};
  const Eigen::Vector3d K_nominal(1.0, 1.0, o.nominal_baseline);
  const Eigen::Vector3d K_true(1.0 + rng.uniform(o.bias), 1.0 + rng.uniform(o.bias),
                               o.nominal_baseline * (1.0 + rng.uniform(o.bias)));
  const Eigen::Vector3d S_nominal(0.2, 0.0, 0.0);
  const Eigen::Vector3d S_true(0.2 + rng.uniform(0.05), rng.uniform(0.05), rng.uniform(0.1));
  const SE2 S = to_se2(S_true);
  const std::vector<Command> commands = route(o);
  const int n = static_cast<int>(commands.size()) + 1;
  const std::int64_t offset_id = n, odometry_id = n + 1;

  std::vector<SE2> x_true{SE2()}, x_dead{SE2()};
  std::vector<Eigen::Vector3d> raw;  // (v_l, v_r, dt) as the encoders report them
  for (const Command& c : commands) {
    const double vl = c.v - c.omega * K_true[2] / 2, vr = c.v + c.omega * K_true[2] / 2;
    raw.emplace_back(vl / K_true[0], vr / K_true[1], kDt);
    const SE2 u = to_se2(differential_drive_motion(K_true, raw.back()[0], raw.back()[1], kDt));
    x_true.push_back(x_true.back() * u.plus(Eigen::Vector3d(rng.normal(o.odometry_sigma_t), rng.normal(o.odometry_sigma_t),
                                                             rng.normal(o.odometry_sigma_r))));
    x_dead.push_back(x_dead.back() * to_se2(differential_drive_motion(K_nominal, raw.back()[0], raw.back()[1], kDt)));
  }
  PoseGraph g;
  g.source = o.path == "line" ? "sim:calib2d?path=line" : "sim:calib2d";
  g.format = "g2o";
  for (int i = 0; i < n; ++i) add_vertex2(g, i, x_dead[static_cast<std::size_t>(i)]);
  g.calibration.vertices.push_back({offset_id, CalibrationKind::kOffset2, S_nominal, true, 0});
  const bool linear = o.odometry == "linear";
  if (linear) g.calibration.vertices.push_back({odometry_id, CalibrationKind::kOdomLinear, identity_k(), true, 0});
  else g.calibration.vertices.push_back({odometry_id, CalibrationKind::kOdomDifferential, K_nominal, true, 0});

  auto scan_edge = [&](int i, int j) {
    GraphEdge e;
    e.from = i, e.to = j, e.kind = EdgeKind::kPose2Pose2;
    CalibratedMeasurement c;
    c.kind = CalibratedEdgeKind::kSensorOffset2;
    c.param_a = c.param_b = offset_id;
    const SE2 z = (x_true[static_cast<std::size_t>(i)] * S).between(x_true[static_cast<std::size_t>(j)] * S);
    c.sensor2 = z.plus(Eigen::Vector3d(rng.normal(o.scan_sigma_t), rng.normal(o.scan_sigma_t), rng.normal(o.scan_sigma_r)));
    e.calibrated = c;
    e.information = diag3(o.scan_sigma_t, o.scan_sigma_r);
    g.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) {
    GraphEdge e;
    e.from = i, e.to = i + 1, e.kind = EdgeKind::kPose2Pose2;
    CalibratedMeasurement c;
    c.kind = linear ? CalibratedEdgeKind::kOdomLinear : CalibratedEdgeKind::kOdomDifferential;
    c.param_a = c.param_b = odometry_id;
    c.odometry = raw[static_cast<std::size_t>(i)];
    // Linear model: the raw increment is the nominal dead-reckoning step (Δx, Δy, Δθ).
    if (linear) c.odometry = differential_drive_motion(K_nominal, c.odometry[0], c.odometry[1], c.odometry[2]);
    e.calibrated = c;
    e.information = diag3(o.odometry_sigma_t, o.odometry_sigma_r);
    g.edges.push_back(e);
    scan_edge(i, i + 1);
  }
  // Loop closures to earlier laps: near in position and heading, every other pose. Candidates
  // come from a grid of cells a hair wider than loop_radius (the 3×3 cells around a pose hold
  // every pose within the radius, rounding included) and are visited in increasing i, as the scan
  // over all earlier poses did: the same graph, in time linear in poses + closures.
  if (o.loop_radius > 0.0) {
    const double cell = o.loop_radius * (1.0 + 1e-9);
    auto cell_of = [&](int i) {
      const Eigen::Vector2d& p = x_true[static_cast<std::size_t>(i)].translation();
      return std::make_pair(static_cast<std::int64_t>(std::floor(p.x() / cell)), static_cast<std::int64_t>(std::floor(p.y() / cell)));
    };
    std::map<std::pair<std::int64_t, std::int64_t>, std::vector<int>> grid;  // cell -> poses, increasing
    std::vector<int> candidates;
    int next_in_grid = 0;  // poses i < next_in_grid are in the grid; a pose is a candidate once i + 60 < j
    for (int j = 0; j < n; j += 2) {
      for (; next_in_grid + 60 < j; ++next_in_grid) grid[cell_of(next_in_grid)].push_back(next_in_grid);
      const auto [cx, cy] = cell_of(j);
      candidates.clear();
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy) {
          const auto it = grid.find({cx + dx, cy + dy});
          if (it != grid.end()) candidates.insert(candidates.end(), it->second.begin(), it->second.end());
        }
      std::sort(candidates.begin(), candidates.end());
      for (int i : candidates) {
        const SE2 d = x_true[static_cast<std::size_t>(i)].between(x_true[static_cast<std::size_t>(j)]);
        if (d.translation().norm() < o.loop_radius && std::abs(d.theta()) < 0.5) scan_edge(i, j);
      }
    }
  }
  update_calibrated_measurements(g);
  if (truth) {
    const std::string s = "offset[" + std::to_string(offset_id) + "].", k = "odometry[" + std::to_string(odometry_id) + "].";
    *truth = {{s + "x", S_true[0]}, {s + "y", S_true[1]}, {s + "theta", S_true[2]}};
    if (!linear) truth->insert(truth->end(), {{k + "k_left", K_true[0]}, {k + "k_right", K_true[1]}, {k + "baseline", K_true[2]}});
  }
  if (gt) {
    *gt = g;
    for (int i = 0; i < n; ++i) gt->vertex_at(static_cast<std::size_t>(i)).pose2 = x_true[static_cast<std::size_t>(i)];
    gt->calibration.vertices[0].value = S_true;
    if (!linear) gt->calibration.vertices[1].value = K_true;
    update_calibrated_measurements(*gt);
  }
  return g;
}

PoseGraph calib3d(const CalibrationSimOptions& o, CalibrationTruth* truth, PoseGraph* gt) {
  Rng rng{std::mt19937(o.seed)};
  constexpr int kPerLap = 120;
  const int n = o.laps * kPerLap;
  const SE3 S_nominal(SO3(), Eigen::Vector3d(0.1, 0.0, 0.2));
  const Eigen::Vector3d phi_true(rng.uniform(0.1), rng.uniform(0.1), rng.uniform(0.1));
  const SE3 S(SO3::exp(phi_true), S_nominal.translation() + Eigen::Vector3d(rng.uniform(0.05), rng.uniform(0.05), rng.uniform(0.05)));
  std::vector<SE3> x_true;
  for (int k = 0; k < n; ++k) {
    const double psi = 2 * kPi * k / kPerLap, lap = static_cast<double>(k / kPerLap);
    const SO3 R = SO3::exp(Eigen::Vector3d(0, 0, psi + kPi / 2)) *
                  SO3::exp(Eigen::Vector3d(0.6 * std::sin(2 * psi + 0.7 * lap), 0, 0)) *
                  SO3::exp(Eigen::Vector3d(0, 0.5 * std::cos(3 * psi + 0.4 * lap), 0));
    x_true.emplace_back(R, Eigen::Vector3d(5 * std::cos(psi), 5 * std::sin(psi), 0.8 * std::sin(3 * psi) + 0.1 * lap));
  }
  auto noisy = [&](const SE3& z) {
    SE3::Tangent t;
    t << rng.normal(o.odometry_sigma_t), rng.normal(o.odometry_sigma_t), rng.normal(o.odometry_sigma_t),
        rng.normal(o.odometry_sigma_r), rng.normal(o.odometry_sigma_r), rng.normal(o.odometry_sigma_r);
    return z.plus(t);
  };
  auto info6 = [](double st, double sr) {
    Eigen::Matrix<double, 6, 1> d;
    d << 1 / (st * st), 1 / (st * st), 1 / (st * st), 4 / (sr * sr), 4 / (sr * sr), 4 / (sr * sr);  // q.vec ≈ φ/2
    return Eigen::MatrixXd(d.asDiagonal());
  };
  PoseGraph g;
  g.source = "sim:calib3d";
  g.format = "g2o";
  g.sensor_offsets[0] = S_nominal;
  g.calibration.estimate_offset_parameters = true;
  std::vector<SE3> x_dead{x_true[0]};
  for (int i = 0; i + 1 < n; ++i) {
    GraphEdge e;
    e.from = i, e.to = i + 1, e.kind = EdgeKind::kPose3Pose3;
    e.pose3 = noisy(x_true[static_cast<std::size_t>(i)].between(x_true[static_cast<std::size_t>(i + 1)]));
    e.information = info6(o.odometry_sigma_t, o.odometry_sigma_r);
    g.edges.push_back(e);
    x_dead.push_back(x_dead.back() * e.pose3);
  }
  for (int i = 0; i < n; ++i) {
    GraphVertex v;
    v.id = i, v.kind = VertexKind::kPose3, v.pose3 = x_dead[static_cast<std::size_t>(i)];
    g.add_vertex(v);
  }
  auto sensor_edge = [&](int i, int j) {
    GraphEdge e;
    e.from = i, e.to = j, e.kind = EdgeKind::kPose3Pose3;
    CalibratedMeasurement c;
    c.kind = CalibratedEdgeKind::kOffsetParams3;
    c.param_a = c.param_b = 0;
    SE3::Tangent t;
    t << rng.normal(o.scan_sigma_t), rng.normal(o.scan_sigma_t), rng.normal(o.scan_sigma_t), rng.normal(o.scan_sigma_r),
        rng.normal(o.scan_sigma_r), rng.normal(o.scan_sigma_r);
    c.sensor3 = (x_true[static_cast<std::size_t>(i)] * S).between(x_true[static_cast<std::size_t>(j)] * S).plus(t);
    e.calibrated = c;
    e.information = info6(o.scan_sigma_t, o.scan_sigma_r);
    g.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) sensor_edge(i, i + 1);
  for (int i = 0; i + 12 < n; i += 3) sensor_edge(i, i + 12);          // over a window of 12 steps
  for (int j = kPerLap; j < n; j += 2) sensor_edge(j - kPerLap, j);  // the same place one lap earlier
  update_calibrated_measurements(g);
  if (truth) {
    const Eigen::Vector3d& t = S.translation();
    const std::string p = "params_se3offset[0].";
    *truth = {{p + "x", t.x()}, {p + "y", t.y()}, {p + "z", t.z()},
              {p + "rx", phi_true.x()}, {p + "ry", phi_true.y()}, {p + "rz", phi_true.z()}};
  }
  if (gt) {
    *gt = g;
    for (int i = 0; i < n; ++i) gt->vertex_at(static_cast<std::size_t>(i)).pose3 = x_true[static_cast<std::size_t>(i)];
    gt->sensor_offsets[0] = S;
    update_calibrated_measurements(*gt);
  }
  return g;
}

}  // namespace

PoseGraph generate_calibration_problem(const CalibrationSimOptions& o, CalibrationTruth* truth, PoseGraph* ground_truth) {
  if (o.laps < 1 || o.laps > 1000) throw InputError("", 0, "laps", "laps must be in [1, 1000]");
  if (!(o.step > 0) || !(o.bias >= 0 && o.bias < 0.5) || !(o.nominal_baseline > 0))
    throw InputError("", 0, "step", "step and baseline must be positive, bias in [0, 0.5)");
  if (!(o.odometry_sigma_t > 0 && o.odometry_sigma_r > 0 && o.scan_sigma_t > 0 && o.scan_sigma_r > 0))
    throw InputError("", 0, "sigma", "noise sigmas must be positive");
  if (o.world == "calib2d") {
    if (o.path != "figure" && o.path != "line") throw InputError("", 0, "path", "path must be figure or line");
    if (o.odometry != "differential" && o.odometry != "linear")
      throw InputError("", 0, "odometry", "odometry must be differential or linear");
    return calib2d(o, truth, ground_truth);
  }
  if (o.world == "calib3d") return calib3d(o, truth, ground_truth);
  throw InputError("", 0, "world", "unknown calibration world '" + o.world + "' (calib2d, calib3d)");
}

bool parse_calibration_sim_spec(const std::string& spec, CalibrationSimOptions* options) {
  using namespace sim_detail;
  if (spec.rfind("sim:calib2d", 0) != 0 && spec.rfind("sim:calib3d", 0) != 0) return false;
  const SpecParts parts = split_spec(spec);
  if (parts.world != "calib2d" && parts.world != "calib3d") return false;
  CalibrationSimOptions o;
  o.world = parts.world;
  const bool planar = o.world == "calib2d";
  if (!planar) o.laps = 3;
  for (const auto& [key, value] : parts.params) {
    if (key == "seed") o.seed = static_cast<std::uint32_t>(spec_integer(spec, key, value, 0, 0xffffffffLL));
    else if (key == "laps") o.laps = static_cast<int>(spec_integer(spec, key, value, 1, 1000));
    else if (key == "bias") o.bias = spec_number(spec, key, value, 0.0, 0.5);
    else if (key == "path" && planar && (value == "figure" || value == "line")) o.path = value;
    else if (key == "odometry" && planar && (value == "differential" || value == "linear")) o.odometry = value;
    else if ((key == "path" || key == "odometry") && planar)
      throw InputError(spec, 0, key, "'" + value + "' is not one of " +
                                         (key == "path" ? "figure, line" : "differential, linear"));
    else throw InputError(spec, 0, key, std::string("unknown parameter for ") + o.world +
                                            (planar ? " (seed, laps, bias, path, odometry)" : " (seed, laps, bias)"));
  }
  *options = o;
  return true;
}

std::string to_calibration_sim_spec(const CalibrationSimOptions& o) {
  std::string spec = "sim:" + o.world + "?seed=" + std::to_string(o.seed) + "&laps=" + std::to_string(o.laps) +
                     "&bias=" + sim_detail::spec_text(o.bias);
  if (o.world == "calib2d") spec += "&path=" + o.path + "&odometry=" + o.odometry;
  return spec;
}

}  // namespace slamkit
