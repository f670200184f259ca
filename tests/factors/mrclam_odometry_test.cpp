// MRCLAM logs and the odometry-calibration graph on real data (Dataset 7, robots 1–3, the
// first third of the run): the graph reads back through g2o, and the commanded-velocity scale
// factors come out observable, near the closed-form distance and rotation ratios.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/factors/pose_graph_optimizer.h"
#include "slamkit/io/mrclam_odometry.h"
#include "slamkit/io/pose_graph_io.h"
#include "testing/data.h"

namespace slamkit {
namespace {

TEST(MrclamOdometry, CommandScaleFactorsOnDataset7) {
  SLAMKIT_REQUIRE_DATA(dir, "landmark/MRCLAM_Dataset7");
  std::vector<MrclamRobotLog> logs;
  for (int robot = 1; robot <= 3; ++robot) logs.push_back(read_mrclam_robot(dir.string(), robot));
  OdometryCalibrationGraphOptions o;
  o.to = 1.0 / 3.0;
  OdometryCalibrationGraph og = build_odometry_calibration_graph(logs, o);
  EXPECT_EQ(og.graph.calibration.vertices.size(), 3u);
  EXPECT_EQ(count_connected_components(og.graph), 3u);
  // The tags round-trip.
  const std::string text = pose_graph_to_string(og.graph, PoseGraphFormat::kG2o);
  std::istringstream in(text);
  const PoseGraph back = read_pose_graph(in, "mrclam.g2o");
  EXPECT_EQ(pose_graph_to_string(back, PoseGraphFormat::kG2o), text);

  PoseGraphOptimizerOptions opt;
  opt.init = InitMethod::kNone;
  const PoseGraphResult r = optimize_pose_graph(og.graph, opt);
  EXPECT_TRUE(r.summary.success());
  EXPECT_LT(r.final_chi2, r.input_chi2);
  EXPECT_TRUE(r.calibration.warnings.empty());
  ASSERT_EQ(r.calibration.parameters.size(), 9u);
  for (int robot = 1; robot <= 3; ++robot) {
    const auto& P = r.calibration.parameters;
    const std::size_t i = static_cast<std::size_t>(3 * (robot - 1));
    const double v_scale = (P[i].value + P[i + 1].value) / 2;
    const double omega_scale = v_scale * o.nominal_baseline / P[i + 2].value;
    const auto& cf = og.closed_form[static_cast<std::size_t>(robot - 1)];
    EXPECT_NEAR(v_scale, cf.v_scale, 0.05) << "robot " << robot;
    EXPECT_NEAR(omega_scale, cf.omega_scale, 0.05) << "robot " << robot;
    EXPECT_GT(v_scale, 0.75);
    EXPECT_LT(v_scale, 1.0);
    for (std::size_t k = i; k < i + 3; ++k) EXPECT_TRUE(P[k].observable && P[k].sigma > 0) << P[k].name;
  }
}

TEST(MrclamOdometry, BadLogNamesFileLineAndField) {
  const std::string dir = ::testing::TempDir() + "/mrclam_bad";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/Robot1_Odometry.dat") << "# header\n1.0 0.1 0.2\n2.0 0.1 x\n";
  std::ofstream(dir + "/Robot1_Groundtruth.dat") << "1.0 0 0 0\n2.0 1 0 0\n";
  try {
    read_mrclam_robot(dir, 1);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "omega");
  }
  std::ofstream(dir + "/Robot1_Odometry.dat") << "2.0 0.1 0.2\n1.0 0.1 0.2\n";
  EXPECT_THROW(read_mrclam_robot(dir, 1), InputError);
}

}  // namespace
}  // namespace slamkit
