#include "slamkit/solvers/pose_graph_init.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace slamkit {
namespace {

// Exact measurements: every initializer that solves for the poses must recover the truth.
PoseGraph noise_free(const std::string& world, PoseGraph* truth) {
  PoseGraphSimOptions o;
  o.world = world;
  o.num_poses = 600;
  o.rings = 10;
  o.poses_per_ring = 16;
  o.translation_sigma = 1e-12;
  o.rotation_sigma = 1e-12;
  return generate_pose_graph(o, truth);
}

double max_pose_error(const PoseGraph& a, const PoseGraph& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < a.vertices().size(); ++i) {
    const GraphVertex &u = a.vertices()[i], &v = b.vertices()[i];
    const double e = u.kind == VertexKind::kPose2 ? (u.pose2.matrix() - v.pose2.matrix()).norm()
                                                  : (u.pose3.matrix() - v.pose3.matrix()).norm();
    worst = std::max(worst, e);
  }
  return worst;
}

TEST(PoseGraphInit, RecoversNoiseFreeGraphsExactly) {
  for (const std::string world : {"manhattan", "sphere"}) {
    PoseGraph truth;
    PoseGraph g = noise_free(world, &truth);
    for (std::size_t i = 1; i < g.vertices().size(); ++i) {  // scramble the estimates
      g.vertex_at(i).pose2 = SE2(5, -3, 1);
      g.vertex_at(i).pose3 = SE3(SO3::exp(Eigen::Vector3d(1, 2, 3)), Eigen::Vector3d(7, 8, 9));
    }
    for (InitMethod m : {InitMethod::kOdometry, InitMethod::kSpanningTree, InitMethod::kAuto}) {
      PoseGraph h = g;
      const InitSummary s = initialize_pose_graph(h, m, gauge_vertices(h));
      EXPECT_LT(max_pose_error(h, truth), 1e-6) << world << " " << to_string(m);
      if (m == InitMethod::kAuto) EXPECT_EQ(s.used, world == "sphere" ? InitMethod::kChordal : InitMethod::kLinear);
    }
  }
}

TEST(PoseGraphInit, LinearAndChordalBeatOdometryOnNoisyGraphs) {
  for (const std::string world : {"manhattan", "sphere"}) {
    PoseGraphSimOptions o;
    o.world = world;
    o.num_poses = 1500;
    o.rings = 20;
    o.poses_per_ring = 30;
    o.rotation_sigma = 0.05;
    PoseGraph g = generate_pose_graph(o);
    PoseGraph odo = g;
    initialize_pose_graph(odo, InitMethod::kOdometry, gauge_vertices(odo));
    initialize_pose_graph(g, InitMethod::kAuto, gauge_vertices(g));
    EXPECT_LT(total_chi2(g), 0.2 * total_chi2(odo)) << world;
  }
}

// ∇ over the non-gauge positions of Σ_e ‖R_zᵀ(R_aᵀ(p_b − p_a) − t_z)‖²_{Ω_xy} at the graph's
// estimates (θ held), relative to the largest per-edge term: LAGO's position step minimizes it.
double relative_position_gradient(const PoseGraph& g, const std::vector<std::int64_t>& gauge) {
  std::vector<Eigen::Vector2d> grad(g.vertices().size(), Eigen::Vector2d::Zero());
  double scale = 0.0;
  for (const GraphEdge& e : g.edges) {
    const std::size_t a = *g.index_of(e.from), b = *g.index_of(e.to);
    const SE2& Xa = g.vertices()[a].pose2;
    const SE2& Xb = g.vertices()[b].pose2;
    const Eigen::Matrix2d M = Xa.rotation().matrix() * e.pose2.rotation().matrix();
    const Eigen::Vector2d r = M.transpose() * (Xb.translation() - Xa.translation()) -
                              e.pose2.rotation().matrix().transpose() * e.pose2.translation();
    const Eigen::Vector2d gb = M * (e.information.topLeftCorner<2, 2>() * r);
    grad[b] += gb;
    grad[a] -= gb;
    scale = std::max(scale, (M * e.information.topLeftCorner<2, 2>()).norm() * e.pose2.translation().norm());
  }
  double worst = 0.0;
  for (std::size_t i = 0; i < grad.size(); ++i) {
    if (std::find(gauge.begin(), gauge.end(), g.vertices()[i].id) != gauge.end()) continue;
    worst = std::max(worst, grad[i].norm());
  }
  return worst / scale;
}

TEST(PoseGraphInit, LinearPositionsSolveTheirLeastSquaresProblemIsotropicOrNot) {
  // Generated graphs have isotropic Ω_xy (the θ system's analysis solves the positions); a
  // rotated, stretched Ω_xy takes the 2×2-block system. Both must give the exact minimizer.
  PoseGraphSimOptions o;
  o.world = "manhattan";
  o.num_poses = 800;
  o.rings = 12;
  o.poses_per_ring = 20;
  o.rotation_sigma = 0.05;
  for (bool isotropic : {true, false}) {
    PoseGraph g = generate_pose_graph(o);
    if (!isotropic) {
      for (GraphEdge& e : g.edges) {
        Eigen::Matrix2d S;
        S << 4.0, 1.5, 1.5, 1.0;  // SPD, anisotropic, correlated
        e.information.topLeftCorner<2, 2>() = e.information(0, 0) * S;
      }
    }
    const auto gauge = gauge_vertices(g);
    initialize_pose_graph(g, InitMethod::kLinear, gauge);
    EXPECT_LT(relative_position_gradient(g, gauge), 1e-9) << (isotropic ? "isotropic" : "anisotropic");
    // Scrambled positions are far from the minimizer: the check can fail.
    PoseGraph scrambled = g;
    for (std::size_t i = 1; i < scrambled.vertices().size(); ++i)
      scrambled.vertex_at(i).pose2 = SE2(SO2(scrambled.vertices()[i].pose2.theta()),
                                         scrambled.vertices()[i].pose2.translation() + Eigen::Vector2d(0.1 * (i % 7), 0.0));
    EXPECT_GT(relative_position_gradient(scrambled, gauge), 1e-3);
  }
}

TEST(PoseGraphInit, RejectsMethodsOfTheWrongDimension) {
  PoseGraph truth;
  PoseGraph g = noise_free("manhattan", &truth);
  EXPECT_THROW(initialize_pose_graph(g, InitMethod::kChordal, gauge_vertices(g)), InputError);
  EXPECT_THROW(parse_init_method("magic"), InputError);
}

// Found through the Python bindings: an unknown gauge id crashed the initializer.
TEST(PoseGraphInit, RejectsUnknownOrMissingGaugeVertices) {
  PoseGraph truth;
  PoseGraph g = noise_free("manhattan", &truth);
  for (InitMethod m : {InitMethod::kOdometry, InitMethod::kSpanningTree, InitMethod::kLinear}) {
    try {
      initialize_pose_graph(g, m, {123456789});
      ADD_FAILURE() << "unknown gauge vertex accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "gauge");
      EXPECT_NE(std::string(e.what()).find("123456789"), std::string::npos) << e.what();
    }
    EXPECT_THROW(initialize_pose_graph(g, m, {}), InputError);
  }
}

}  // namespace
}  // namespace slamkit
