// The `slamkit info` and `slamkit convert` commands, run as a user would (the built binary).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "slamkit/core/pose_graph_error.h"
#include "slamkit/io/pose_graph_io.h"
#include "testing/cli.h"
#include "testing/data.h"

namespace slamkit {
namespace {

namespace fs = std::filesystem;

using testing::CliRun;
using testing::contains;
using testing::slurp;

fs::path scratch() { return testing::cli_scratch("slamkit_cli_test_"); }
CliRun slamkit(const std::string& args) { return testing::run_slamkit(args, scratch()); }

TEST(CliInfo, ReportsCubicleCountsHealthAndChi2AsJson) {
  SLAMKIT_REQUIRE_DATA(cubicle, "posegraph/3d/cubicle.g2o");
  const fs::path json = scratch() / "cubicle.json";
  const CliRun r = slamkit("info " + cubicle.string() + " --json " + json.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["format"], "g2o");
  EXPECT_EQ(j["dimension"], 3);
  EXPECT_EQ(j["vertices"], 5750);
  EXPECT_EQ(j["poses"], 5750);
  EXPECT_EQ(j["landmarks"], 0);
  EXPECT_EQ(j["edges"], 16869);
  EXPECT_EQ(j["odometry_edges"].get<int>() + j["loop_closures"].get<int>(), 16869);
  EXPECT_EQ(j["components"], 1);
  EXPECT_EQ(j["indefinite_information_edges"], 5021);
  EXPECT_EQ(j["singular_information_edges"], 0);
  EXPECT_GT(j["first_bad_information_line"].get<int>(), 0);
  EXPECT_DOUBLE_EQ(j["initial_chi2"].get<double>(), total_chi2(read_pose_graph(cubicle.string())));
  EXPECT_GT(j["load_time_s"].get<double>(), 0.0);
  // The human summary is printed too.
  EXPECT_TRUE(contains(r.out, "5021 indefinite")) << r.out;
  EXPECT_TRUE(contains(r.out, "--repair-information")) << r.out;

  const CliRun repaired = slamkit("info " + cubicle.string() + " --repair-information --json -");
  ASSERT_EQ(repaired.exit_code, 0) << repaired.err;
  const nlohmann::json k = nlohmann::json::parse(repaired.out);  // stdout holds only JSON
  EXPECT_EQ(k["repaired_information_edges"], 5021);
  EXPECT_EQ(k["indefinite_information_edges"], 5021);  // as read
}

TEST(CliInfo, CountsEquivalencesAndEdgesOnlyEstimates) {
  SLAMKIT_REQUIRE_DATA(w100, "posegraph/2d/toro/w100.graph");
  SLAMKIT_REQUIRE_DATA(sphere, "posegraph/3d/gtsam_txt/sphere2500.txt");
  CliRun r = slamkit("info " + w100.string() + " --json -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["format"], "toro");
  EXPECT_EQ(j["equivalences"], 40);
  EXPECT_EQ(j["vertices"], 100);
  r = slamkit("info " + sphere.string() + " --json -");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["format"], "gtsam");
  EXPECT_EQ(j["edges_only"], true);
  EXPECT_EQ(j["estimates_from_odometry"], 2500);
  EXPECT_EQ(j["odometry_edges"], 2499);
}

TEST(CliInfo, BadInputGivesFileLineFieldAndExitCode1) {
  const fs::path bad = scratch() / "bad.g2o";
  std::ofstream(bad) << "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 0 0 0\nEDGE_SE2 0 1 1 0 0 1 0 0 nan 0 1\n";
  CliRun r = slamkit("info " + bad.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, bad.string() + ":3: field 'I22': not finite")) << r.err;

  r = slamkit("info " + (scratch() / "missing.g2o").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, "cannot open")) << r.err;

  r = slamkit("info " + bad.string() + " --format bal");
  EXPECT_EQ(r.exit_code, 2);  // usage error

  const fs::path tagged = scratch() / "tagged.g2o";
  std::ofstream(tagged) << "VERTEX_SE2 0 0 0 0\nVERTEX_CAM 1 2\n";
  r = slamkit("info " + tagged.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, ":2: field 'tag': unknown tag 'VERTEX_CAM'")) << r.err;
  r = slamkit("info " + tagged.string() + " --allow-unknown-tags");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "warning: " + tagged.string() + ":2: unknown tag")) << r.err;
}

TEST(CliConvert, ConvertsByExtensionAndWarnsAboutDroppedElements) {
  SLAMKIT_REQUIRE_DATA(w100, "posegraph/2d/toro/w100.graph");
  const fs::path out = scratch() / "w100.g2o";
  CliRun r = slamkit("convert " + w100.string() + " " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(contains(r.err, "40 vertex equivalences dropped")) << r.err;
  const PoseGraph in = read_pose_graph(w100.string());
  const PoseGraph back = read_pose_graph(out.string());
  EXPECT_EQ(back.format, "g2o");
  EXPECT_NEAR(total_chi2(back) / total_chi2(in), 1.0, 1e-12);

  // --to overrides the extension; --from forces the reader.
  const fs::path toro = scratch() / "w100.out";
  r = slamkit("convert " + out.string() + " " + toro.string() + " --to toro --from g2o");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  PoseGraphReadOptions as_toro;
  as_toro.format = PoseGraphFormat::kToro;
  EXPECT_EQ(read_pose_graph(toro.string(), as_toro).edges.size(), 300u);
}

TEST(CliConvert, ImpossibleConversionsFailWithoutWriting) {
  SLAMKIT_REQUIRE_DATA(intel, "posegraph/2d/intel.g2o");
  const fs::path txt = scratch() / "intel.txt";
  fs::remove(txt);
  CliRun r = slamkit("convert " + intel.string() + " " + txt.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, "3D pose graphs only")) << r.err;
  EXPECT_FALSE(fs::exists(txt));

  const fs::path landmarks = scratch() / "landmarks.g2o";
  std::ofstream(landmarks) << "VERTEX_SE2 0 0 0 0\nVERTEX_XY 1 1 1\nEDGE_SE2_XY 0 1 1 1 1 0 1\n";
  r = slamkit("convert " + landmarks.string() + " " + (scratch() / "l.graph").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, "TORO has no tag for point2")) << r.err;

  r = slamkit("convert " + intel.string() + " " + (scratch() / "intel.unknown").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.err, "--to")) << r.err;
}

}  // namespace
}  // namespace slamkit
