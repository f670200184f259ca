// The optimizer on the standard pose-graph datasets: the default configuration reaches the
// best known chi2 (issue figures), and every algorithm agrees on the easy files.
#include <gtest/gtest.h>

#include "slamkit/core/jacobian_check.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/io/pose_graph_io.h"
#include "testing/data.h"

namespace slamkit {
namespace {

struct Reference {
  const char* file;
  double accept_chi2;  // best known · (1 + 1e-4), or the bound
};

// Best known chi2 (g2o definition) from the issue; M3500b: at most g2o's lowest (Dogleg after its
// spanning-tree guess, 3624.44), which the default reaches by its second-initializer rule.
const Reference kReferences[] = {
    {"posegraph/2d/input_INTEL_g2o.g2o", 215.83 * (1 + 1e-4)},
    {"posegraph/2d/intel.g2o", 45.0047 * (1 + 1e-4)},
    {"posegraph/2d/input_MITb_g2o.g2o", 41.1633 * (1 + 1e-4)},
    {"posegraph/2d/input_M3500_g2o.g2o", 137.913 * (1 + 1e-4)},
    {"posegraph/2d/input_M3500b_g2o.g2o", 3624.44 * (1 + 1e-4)},
    {"posegraph/2d/city10000.g2o", 511.985 * (1 + 1e-4)},
    {"posegraph/2d/derived/manhattan_odominit.g2o", 3549.04 * (1 + 1e-4)},
    {"posegraph/2d/derived/CSAIL_P_toro.g2o", 40.5551 * (1 + 1e-4)},
    {"posegraph/3d/sphere2500.g2o", 727.149 * (1 + 1e-4)},
    {"posegraph/3d/torus3D.g2o", 14574.7 * (1 + 1e-4)},
    {"posegraph/3d/parking-garage.g2o", 1.23868 * (1 + 1e-4)},
    {"posegraph/3d/derived/cubicle_psd.g2o", 2379.91 * (1 + 1e-4)},
};

class DatasetOptimum : public ::testing::TestWithParam<Reference> {};

TEST_P(DatasetOptimum, DefaultsReachTheBestKnownChi2) {
  SLAMKIT_REQUIRE_DATA(file, GetParam().file);
  PoseGraph g = read_pose_graph(file.string());
  const PoseGraphResult r = optimize_pose_graph(g);
  EXPECT_TRUE(r.summary.success()) << r.summary.report();
  EXPECT_LE(r.final_chi2, GetParam().accept_chi2) << r.summary.report();
  EXPECT_GT(r.final_chi2, 0.0);
}

INSTANTIATE_TEST_SUITE_P(StandardFiles, DatasetOptimum, ::testing::ValuesIn(kReferences),
                         [](const ::testing::TestParamInfo<Reference>& info) {
                           std::string name = info.param.file;
                           name = name.substr(name.find_last_of('/') + 1);
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// The second-initializer rule fires only where the guess is worse than the noise allows.
TEST(DefaultInitialization, SecondGuessOnlyWhenChi2PerDofAfterInitExceedsOne) {
  for (const char* f : {"posegraph/2d/input_M3500_g2o.g2o", "posegraph/2d/input_M3500b_g2o.g2o"}) {
    SLAMKIT_REQUIRE_DATA(file, f);
    PoseGraph g = read_pose_graph(file.string());
    const PoseGraphResult r = optimize_pose_graph(g);
    const double dof = r.summary.num_residuals - r.summary.tangent_dim;
    bool retried = false;
    for (const std::string& n : r.notes) retried = retried || n.find("spanning-tree guess") != std::string::npos;
    const bool m3500b = std::string(f).find("M3500b") != std::string::npos;
    EXPECT_EQ(retried, m3500b) << f;
    if (!m3500b) EXPECT_LT(r.chi2_after_init, dof) << f;  // LAGO's guess is consistent with the noise
    if (m3500b) EXPECT_EQ(r.init.used, InitMethod::kSpanningTree);  // and it ends lower than LAGO's basin
  }
}

// intel.g2o comes with estimates at χ²/dof 0.23: the default starts from them and reaches the
// same minimum as after LAGO; M3500's odometry start (χ²/dof 438) is initialized.
TEST(DefaultInitialization, FileEstimatesThatFitTheNoiseNeedNoInitialization) {
  for (const char* f : {"posegraph/2d/intel.g2o", "posegraph/2d/input_M3500_g2o.g2o"}) {
    SLAMKIT_REQUIRE_DATA(file, f);
    const PoseGraph original = read_pose_graph(file.string());
    PoseGraph g = original;
    const PoseGraphResult r = optimize_pose_graph(g);
    const bool fits = std::string(f).find("intel") != std::string::npos;
    EXPECT_EQ(r.init.used, fits ? InitMethod::kNone : InitMethod::kLinear) << f;
    PoseGraph h = original;
    PoseGraphOptimizerOptions lago;
    lago.init = InitMethod::kLinear;
    EXPECT_NEAR(r.final_chi2, optimize_pose_graph(h, lago).final_chi2, 1e-7 * r.final_chi2) << f;
  }
}

// Large enough that evaluation, assembly and retraction run in parallel (small graphs stay on
// the calling thread): the result must not depend on the thread count.
TEST(DatasetThreads, ResultIsBitIdenticalForAnyThreadCount) {
  for (const char* f : {"posegraph/2d/input_M3500_g2o.g2o", "posegraph/3d/sphere2500.g2o"}) {
    SLAMKIT_REQUIRE_DATA(file, f);
    const PoseGraph original = read_pose_graph(file.string());
    std::vector<PoseGraph> results;
    std::vector<double> chi2;
    for (int threads : {1, 3}) {
      PoseGraph g = original;
      PoseGraphOptimizerOptions o;
      o.optimizer.num_threads = threads;
      chi2.push_back(optimize_pose_graph(g, o).final_chi2);
      results.push_back(std::move(g));
    }
    EXPECT_EQ(chi2[0], chi2[1]) << f;
    for (std::size_t i = 0; i < original.vertices().size(); ++i) {
      const GraphVertex &a = results[0].vertices()[i], &b = results[1].vertices()[i];
      if (a.kind == VertexKind::kPose2) {
        ASSERT_EQ(a.pose2.theta(), b.pose2.theta()) << f << " vertex " << a.id;
        ASSERT_EQ(a.pose2.translation(), b.pose2.translation()) << f << " vertex " << a.id;
      } else {
        ASSERT_EQ(a.pose3.rotation().quaternion().coeffs(), b.pose3.rotation().quaternion().coeffs()) << f;
        ASSERT_EQ(a.pose3.translation(), b.pose3.translation()) << f << " vertex " << a.id;
      }
    }
  }
}

class AlgorithmsAgreeOnDatasets : public ::testing::TestWithParam<const char*> {};

TEST_P(AlgorithmsAgreeOnDatasets, SameOptimumToOnePartPerMillion) {
  SLAMKIT_REQUIRE_DATA(file, GetParam());
  const PoseGraph original = read_pose_graph(file.string());
  std::vector<double> finals;
  for (Algorithm a : {Algorithm::kGaussNewton, Algorithm::kLevenbergMarquardt, Algorithm::kTrustRegionLM,
                      Algorithm::kDogleg}) {
    PoseGraph g = original;
    PoseGraphOptimizerOptions o;
    o.optimizer.algorithm = a;
    o.optimizer.function_tolerance = 1e-10;
    const PoseGraphResult r = optimize_pose_graph(g, o);
    EXPECT_TRUE(r.summary.success()) << to_string(a) << "\n" << r.summary.report();
    finals.push_back(r.final_chi2);
  }
  for (std::size_t k = 1; k < finals.size(); ++k)
    EXPECT_NEAR(finals[k], finals[0], 1e-6 * finals[0]) << "algorithm " << k;
}

INSTANTIATE_TEST_SUITE_P(EasyFiles, AlgorithmsAgreeOnDatasets,
                         ::testing::Values("posegraph/2d/input_M3500_g2o.g2o", "posegraph/3d/sphere2500.g2o",
                                           "posegraph/3d/parking-garage.g2o"));

TEST(DatasetJacobians, BetweenFactorsOnRealGraphsMatchNumeric) {
  for (const char* f : {"posegraph/3d/parking-garage.g2o", "posegraph/2d/input_INTEL_g2o.g2o"}) {
    SLAMKIT_REQUIRE_DATA(file, f);
    const PoseGraph g = read_pose_graph(file.string());
    const PoseGraphProblem p = build_pose_graph_problem(g);
    const JacobianCheckResult r = check_jacobians(p.graph, p.values, 1e-5);
    EXPECT_TRUE(r.ok) << f << ": " << r.message();
  }
}

TEST(DatasetErrors, IndefiniteInformationIsRefusedWithLineAndHint) {
  SLAMKIT_REQUIRE_DATA(file, "posegraph/3d/cubicle.g2o");
  PoseGraph g = read_pose_graph(file.string());
  try {
    optimize_pose_graph(g);
    FAIL() << "cubicle.g2o has indefinite information matrices";
  } catch (const InputError& e) {
    EXPECT_GT(e.line(), 0);
    EXPECT_EQ(e.field(), "information");
    EXPECT_NE(std::string(e.what()).find("--repair-information"), std::string::npos);
  }
}

}  // namespace
}  // namespace slamkit
