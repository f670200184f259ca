#include "slamkit/sim/pose_graph_generator.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <random>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "sim_spec.h"
#include "slamkit/core/error.h"

namespace slamkit {
namespace {

struct Noise {
  std::mt19937 rng;
  std::normal_distribution<double> n{0.0, 1.0};
  double operator()(double sigma) { return sigma * n(rng); }
};

GraphVertex pose_vertex(std::int64_t id) {
  GraphVertex v;
  v.id = id;
  return v;
}

void add_edge2(PoseGraph& g, const std::vector<SE2>& truth, int a, int b, const PoseGraphSimOptions& o, Noise& noise) {
  GraphEdge e;
  e.from = a, e.to = b, e.kind = EdgeKind::kPose2Pose2;
  const SE2 z = truth[a].between(truth[b]);
  e.pose2 = z.plus(SE2::Tangent(noise(o.translation_sigma), noise(o.translation_sigma), noise(o.rotation_sigma)));
  e.information = Eigen::Vector3d(1.0 / (o.translation_sigma * o.translation_sigma),
                                  1.0 / (o.translation_sigma * o.translation_sigma),
                                  1.0 / (o.rotation_sigma * o.rotation_sigma))
                      .asDiagonal();
  g.edges.push_back(e);
}

void add_edge3(PoseGraph& g, const std::vector<SE3>& truth, int a, int b, const PoseGraphSimOptions& o, Noise& noise) {
  GraphEdge e;
  e.from = a, e.to = b, e.kind = EdgeKind::kPose3Pose3;
  const SE3 z = truth[a].between(truth[b]);
  SE3::Tangent n;
  for (int k = 0; k < 3; ++k) n[k] = noise(o.translation_sigma);
  for (int k = 3; k < 6; ++k) n[k] = noise(o.rotation_sigma);
  e.pose3 = z.plus(n);
  Eigen::Matrix<double, 6, 1> info;
  const double it = 1.0 / (o.translation_sigma * o.translation_sigma);
  const double ir = 4.0 / (o.rotation_sigma * o.rotation_sigma);  // q.vec ≈ φ/2
  info << it, it, it, ir, ir, ir;
  e.information = info.asDiagonal();
  g.edges.push_back(e);
}

PoseGraph manhattan(const PoseGraphSimOptions& o, PoseGraph* gt) {
  Noise noise{std::mt19937(o.seed)};
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<SE2> truth{SE2()};
  for (int i = 1; i < o.num_poses; ++i) {
    double turn = 0.0;
    if (u(noise.rng) < o.turn_probability) turn = u(noise.rng) < 0.5 ? kPi / 2 : -kPi / 2;
    truth.push_back(truth.back() * SE2(1.0, 0.0, turn));
  }
  PoseGraph g;
  g.source = "sim:manhattan";
  for (int i = 0; i < o.num_poses; ++i) g.add_vertex(pose_vertex(i));
  for (int i = 1; i < o.num_poses; ++i) g.vertex_at(i).has_estimate = false;
  for (int i = 0; i + 1 < o.num_poses; ++i) add_edge2(g, truth, i, i + 1, o, noise);
  // Loop closures: earlier poses (not the previous few) within loop_radius, found through a
  // grid of loop_radius cells (the 3×3 cells around a pose hold every pose within the radius),
  // so generation is linear in the size. Candidates are visited in increasing i, as a scan
  // over all earlier poses would, so the random draws and the graph do not depend on the grid.
  const double cell = o.loop_radius > 0.0 ? o.loop_radius : 1.0;
  auto cell_of = [&](const Eigen::Vector2d& p) {
    return std::make_pair(static_cast<std::int64_t>(std::floor(p.x() / cell)), static_cast<std::int64_t>(std::floor(p.y() / cell)));
  };
  auto cell_key = [](std::int64_t cx, std::int64_t cy) { return (cx * 73856093) ^ (cy * 19349663); };
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  std::vector<int> candidates;
  for (int j = 0; j < o.num_poses; ++j) {
    const auto [cx, cy] = cell_of(truth[j].translation());
    candidates.clear();
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy) {
        const auto it = grid.find(cell_key(cx + dx, cy + dy));
        if (it == grid.end()) continue;
        for (int i : it->second)
          if (i + 2 < j && cell_of(truth[i].translation()) == std::make_pair(cx + dx, cy + dy)) candidates.push_back(i);
      }
    std::sort(candidates.begin(), candidates.end());
    for (int i : candidates)
      if ((truth[i].translation() - truth[j].translation()).norm() < o.loop_radius && u(noise.rng) < o.loop_probability)
        add_edge2(g, truth, i, j, o, noise);
    grid[cell_key(cx, cy)].push_back(j);
  }
  complete_estimates_by_odometry(g);  // noisy odometry chain as the initial guess
  if (gt) {
    *gt = g;
    for (int i = 0; i < o.num_poses; ++i) gt->vertex_at(i).pose2 = truth[i];
  }
  return g;
}

PoseGraph sphere(const PoseGraphSimOptions& o, PoseGraph* gt) {
  Noise noise{std::mt19937(o.seed)};
  std::vector<SE3> truth;
  const int n = o.rings * o.poses_per_ring;
  for (int r = 0; r < o.rings; ++r) {
    const double polar = kPi * (r + 0.5) / o.rings - kPi / 2;  // latitude
    for (int k = 0; k < o.poses_per_ring; ++k) {
      const double azimuth = 2.0 * kPi * k / o.poses_per_ring;
      const SO3 R = SO3::exp(Eigen::Vector3d(0, 0, azimuth)) * SO3::exp(Eigen::Vector3d(0, -polar, 0));
      const Eigen::Vector3d p = o.radius * Eigen::Vector3d(std::cos(polar) * std::cos(azimuth),
                                                           std::cos(polar) * std::sin(azimuth), std::sin(polar));
      // Heading along the ring: the body x axis tangent to the circle of latitude.
      truth.emplace_back(R * SO3::exp(Eigen::Vector3d(0, 0, kPi / 2)), p);
    }
  }
  PoseGraph g;
  g.source = "sim:sphere";
  for (int i = 0; i < n; ++i) g.add_vertex([&] {
      GraphVertex v = pose_vertex(i);
      v.kind = VertexKind::kPose3;
      return v;
    }());
  g.vertex_at(0).pose3 = truth[0];  // the noisy chain starts at the true first pose
  for (int i = 1; i < n; ++i) g.vertex_at(i).has_estimate = false;
  for (int i = 0; i + 1 < n; ++i) add_edge3(g, truth, i, i + 1, o, noise);
  for (int r = 1; r < o.rings; ++r)
    for (int k = 0; k < o.poses_per_ring; ++k) {
      const int i = r * o.poses_per_ring + k;
      add_edge3(g, truth, i - o.poses_per_ring, i, o, noise);  // same azimuth, ring below
      if (k + 1 < o.poses_per_ring) add_edge3(g, truth, i - o.poses_per_ring + 1, i, o, noise);
    }
  complete_estimates_by_odometry(g);
  if (gt) {
    *gt = g;
    for (int i = 0; i < n; ++i) gt->vertex_at(i).pose3 = truth[i];
  }
  return g;
}

}  // namespace

PoseGraph generate_pose_graph(const PoseGraphSimOptions& o, PoseGraph* ground_truth) {
  if (o.translation_sigma <= 0.0 || o.rotation_sigma <= 0.0)
    throw InputError("", 0, "sigma", "noise sigmas must be positive");
  if (o.world == "manhattan") {
    if (o.num_poses < 2) throw InputError("", 0, "num_poses", "need at least 2 poses");
    return manhattan(o, ground_truth);
  }
  if (o.world == "sphere") {
    if (o.rings < 2 || o.poses_per_ring < 3) throw InputError("", 0, "rings", "need at least 2 rings of 3 poses");
    return sphere(o, ground_truth);
  }
  throw InputError("", 0, "world", "unknown simulated world '" + o.world + "' (manhattan, sphere)");
}

bool parse_sim_spec(const std::string& spec, PoseGraphSimOptions* options) {
  using namespace sim_detail;
  if (spec.rfind("sim:", 0) != 0) return false;
  const SpecParts parts = split_spec(spec);
  PoseGraphSimOptions o;
  o.world = parts.world;
  if (o.world != "manhattan" && o.world != "sphere")
    throw InputError(spec, 0, "world", "unknown simulated world '" + o.world + "' (sim:manhattan, sim:sphere)");
  const bool sphere = o.world == "sphere";
  if (sphere) o.translation_sigma = 0.1, o.rotation_sigma = 0.02;
  for (const auto& [key, value] : parts.params) {
    if (key == "seed") o.seed = static_cast<std::uint32_t>(spec_integer(spec, key, value, 0, 0xffffffffLL));
    else if (key == "poses" && !sphere) o.num_poses = static_cast<int>(spec_integer(spec, key, value, 2, kMaxSimPoses));
    else if (key == "rings" && sphere) o.rings = static_cast<int>(spec_integer(spec, key, value, 2, kMaxSimPoses / 3));
    else if (key == "per_ring" && sphere) o.poses_per_ring = static_cast<int>(spec_integer(spec, key, value, 3, kMaxSimPoses / 2));
    else throw InputError(spec, 0, key, std::string("unknown parameter for ") + o.world +
                                            (sphere ? " (seed, rings, per_ring)" : " (seed, poses)"));
  }
  if (static_cast<long long>(o.rings) * o.poses_per_ring > kMaxSimPoses)
    throw InputError(spec, 0, "rings", "rings × per_ring exceeds " + std::to_string(kMaxSimPoses) + " poses");
  *options = o;
  return true;
}

std::string to_sim_spec(const PoseGraphSimOptions& o) {
  std::string spec = "sim:" + o.world + "?seed=" + std::to_string(o.seed);
  if (o.world == "sphere") return spec + "&rings=" + std::to_string(o.rings) + "&per_ring=" + std::to_string(o.poses_per_ring);
  return spec + "&poses=" + std::to_string(o.num_poses);
}

}  // namespace slamkit
