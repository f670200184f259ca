// g2o calibration tags (src/io/g2o_calibration_format.cpp): the records as g2o writes them,
// bit-identical write → read → write of generated problems, and strict errors.
#include <gtest/gtest.h>

#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_calibration.h"
#include "slamkit/core/pose_graph_error.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/sim/calibration_generator.h"

namespace slamkit {
namespace {

PoseGraph parse(const std::string& text) {
  std::istringstream in(text);
  return read_pose_graph(in, "test.g2o");
}

void expect_error(const std::string& text, int line, const std::string& field) {
  try {
    parse(text);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

const char* kSclam =
    "VERTEX_SE2 0 0 0 0\n"
    "VERTEX_SE2 1 1 0 0.1\n"
    "VERTEX_SE2 2 2 0.1 0.2\n"
    "VERTEX_SE2 10 0.2 0 0\n"
    "VERTEX_ODOM_DIFFERENTIAL 11 1 1 0.5\n"
    "FIX 0\n"
    "EDGE_SE2_ODOM_DIFFERENTIAL_CALIB 0 1 11 0.9 1.1 1 100 0 0 100 0 1000\n"
    "EDGE_SE2_ODOM_DIFFERENTIAL_CALIB 1 2 11 1.0 1.0 1 100 0 0 100 0 1000\n"
    "EDGE_SE2_CALIB 0 1 10 1 0.1 0.1 100 0 0 100 0 1000\n"
    "EDGE_SE2_CALIB 1 2 10 1 0 0.1 100 0 0 100 0 1000\n";

TEST(G2oCalibration, ReadsSclam2dRecords) {
  const PoseGraph g = parse(kSclam);
  EXPECT_EQ(g.vertices().size(), 3u);  // the offset VERTEX_SE2 is a calibration vertex
  ASSERT_EQ(g.calibration.vertices.size(), 2u);
  const CalibrationVertex* s = g.calibration.find(10);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->kind, CalibrationKind::kOffset2);
  EXPECT_DOUBLE_EQ(s->value[0], 0.2);
  const CalibrationVertex* k = g.calibration.find(11);
  ASSERT_NE(k, nullptr);
  EXPECT_EQ(k->kind, CalibrationKind::kOdomDifferential);
  EXPECT_DOUBLE_EQ(k->value[2], 0.5);
  ASSERT_EQ(g.edges.size(), 4u);
  ASSERT_TRUE(g.edges[0].calibrated);
  EXPECT_DOUBLE_EQ(g.edges[0].calibrated->odometry[0], 0.9);
  // Effective measurement: U(K) = differential_drive_motion; S z S⁻¹ for the scan edges.
  const Eigen::Vector3d u = differential_drive_motion(Eigen::Vector3d(1, 1, 0.5), 0.9, 1.1, 1.0);
  EXPECT_NEAR(g.edges[0].pose2.x(), u[0], 1e-15);
  EXPECT_NEAR(g.edges[0].pose2.theta(), u[2], 1e-15);
  EXPECT_NEAR(u[2], 0.4, 1e-15);  // (1.1 − 0.9)/0.5
  // chi2 uses the calibrated error, not the effective measurement.
  EXPECT_GT(total_chi2(g), 0.0);
}

TEST(G2oCalibration, FixOfACalibrationVertexHoldsIt) {
  const PoseGraph g = parse(std::string(kSclam) + "FIX 11\n");
  EXPECT_FALSE(g.calibration.find(11)->estimate);
  EXPECT_TRUE(g.calibration.find(10)->estimate);
  EXPECT_EQ(g.fixed, std::vector<std::int64_t>{0});
}

TEST(G2oCalibration, OffsetEdgesWithParameters) {
  const PoseGraph g2 = parse(
      "PARAMS_SE2OFFSET 0 0.1 0.2 0.3\nVERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n"
      "EDGE_SE2_OFFSET 0 1 0 0 1 0 0 1 0 0 1 0 1\n");
  ASSERT_EQ(g2.calibration.offset_parameters2.count(0), 1u);
  EXPECT_EQ(g2.edges[0].calibrated->kind, CalibratedEdgeKind::kOffsetParams2);
  const PoseGraph g3 = parse(
      "PARAMS_SE3OFFSET 4 0.1 0.2 0.3 0 0 0 1\nVERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\nVERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
      "EDGE_SE3_OFFSET 0 1 4 4 1 0 0 0 0 0 1 1 0 0 0 0 0 1 0 0 0 0 1 0 0 0 1 0 0 1 0 1\n");
  EXPECT_EQ(g3.edges[0].calibrated->kind, CalibratedEdgeKind::kOffsetParams3);
  EXPECT_EQ(g3.edges[0].calibrated->param_a, 4);
}

TEST(G2oCalibration, GeneratedProblemsRoundTripBitIdentical) {
  for (const char* world : {"calib2d", "calib3d"}) {
    CalibrationSimOptions o;
    o.world = world;
    o.laps = 1;
    const PoseGraph g = generate_calibration_problem(o);
    const std::string text = pose_graph_to_string(g, PoseGraphFormat::kG2o);
    EXPECT_NE(text.find(std::string(world) == "calib2d" ? "EDGE_SE2_CALIB " : "EDGE_SE3_OFFSET "), std::string::npos);
    // Read graphs hold exact-unit quaternions (io's fixed point), so from the first read on
    // write → read → write reproduces every bit; 2D has no quaternions and is exact at once.
    const PoseGraph back = parse(text);
    const std::string text2 = pose_graph_to_string(back, PoseGraphFormat::kG2o);
    if (std::string(world) == "calib2d") EXPECT_EQ(text2, text);
    EXPECT_EQ(pose_graph_to_string(parse(text2), PoseGraphFormat::kG2o), text2) << world;
    EXPECT_EQ(back.edges.size(), g.edges.size());
    EXPECT_NEAR(total_chi2(back), total_chi2(g), 1e-9 * total_chi2(g));
  }
}

TEST(G2oCalibration, OtherFormatsWarnThatCalibrationIsDropped) {
  CalibrationSimOptions o;
  o.laps = 1;
  const PoseGraph g = generate_calibration_problem(o);
  std::vector<std::string> warnings;
  pose_graph_to_string(g, PoseGraphFormat::kToro, &warnings);
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings.back().find("calibration"), std::string::npos);
}

TEST(G2oCalibration, StrictErrorsNameLineAndField) {
  const std::string v = "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0\n";
  expect_error(v + "EDGE_SE2_CALIB 0 1 7 1 0 0 1 0 0 1 0 1\n", 3, "offset_id");  // no VERTEX_SE2 7
  expect_error(v + "VERTEX_ODOM_DIFFERENTIAL 5 1 1 0\n", 3, "baseline");
  expect_error(v + "VERTEX_ODOM_DIFFERENTIAL 5 1 1\n", 3, "baseline");  // short line
  expect_error(v + "VERTEX_ODOM_DIFFERENTIAL 5 1 1 0.5 2\n", 3, "extra");
  expect_error(v + "VERTEX_ODOM_DIFFERENTIAL 5 1 1 0.5\nEDGE_SE2_ODOM_DIFFERENTIAL_CALIB 0 1 5 1 1 nan 1 0 0 1 0 1\n", 4, "dt");
  expect_error(v + "VERTEX_SE2 5 0 0 0\nEDGE_SE2_ODOM_DIFFERENTIAL_CALIB 0 1 5 1 1 1 1 0 0 1 0 1\n", 4, "odometry_id");
  expect_error(v + "EDGE_SE2_OFFSET 0 1 0 0 1 0 0 1 0 0 1 0 1\n", 3, "param_from");  // no PARAMS_SE2OFFSET 0
  expect_error(v + "PARAMS_SE2OFFSET 0 0 0 0\nPARAMS_SE2OFFSET 0 0 0 0\n", 4, "id");
  expect_error(v + "VERTEX_ODOM_DIFFERENTIAL 1 1 1 0.5\n", 3, "id");  // id taken by a pose
  expect_error(v + "VERTEX_ODOM_DIFFERENTIAL 5 1 1 0.5\nVERTEX_SE2 5 0 0 0\n", 4, "id");  // and the other way round (fuzz)
  // A sensor-offset vertex cannot also be a pose endpoint.
  expect_error(v + "VERTEX_SE2 5 0 0 0\nEDGE_SE2_CALIB 0 1 5 1 0 0 1 0 0 1 0 1\nEDGE_SE2 1 5 1 0 0 1 0 0 1 0 1\n", 5, "to");
}

}  // namespace
}  // namespace slamkit
