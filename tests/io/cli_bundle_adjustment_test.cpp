// `slamkit optimize --format bal` as a user runs it: progress, JSON with ½Σ‖r‖² costs, BAL and
// PLY output that read back, every linear solver, and clear errors on bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "slamkit/io/bal_io.h"
#include "testing/cli.h"
#include "testing/data.h"

namespace slamkit {
namespace {

namespace fs = std::filesystem;

using testing::CliRun;
using testing::contains;
using testing::slurp;

fs::path scratch() { return testing::cli_scratch("slamkit_ba_cli_test_"); }
CliRun slamkit(const std::string& args) { return testing::run_slamkit(args, scratch()); }

TEST(CliBundleAdjustment, SimulatedProblemWithEveryLinearSolver) {
  const fs::path dir = scratch();
  double cost = -1.0;
  for (const char* linear : {"schur-dense", "schur-cholesky", "schur-pcg", "auto"}) {
    const fs::path json = dir / (std::string(linear) + ".json");
    const CliRun r = slamkit("optimize 'sim:ba?cameras=6&points=150&seed=2' --linear " + std::string(linear) +
                             " --json " + json.string() + " -o " + (dir / "out.bal").string() + " --ply " +
                             (dir / "out.ply").string());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.out, "bundle adjustment, 6 cameras, 150 points")) << r.out;
    EXPECT_TRUE(contains(r.out, "Schur complement (150 blocks eliminated, reduced dim 54)")) << r.out;
    const nlohmann::json j = nlohmann::json::parse(slurp(json));
    EXPECT_NEAR(j["final_cost"].get<double>(), 0.5 * j["final_chi2"].get<double>(), 1e-9);
    EXPECT_LT(j["final_cost"].get<double>(), j["initial_cost"].get<double>());
    if (cost < 0) cost = j["final_cost"];
    EXPECT_NEAR(j["final_cost"].get<double>(), cost, 1e-3 * cost) << linear;
    // The BAL output holds the optimum: its cost is the reported final cost.
    const BalProblem out = read_bal((dir / "out.bal").string());
    EXPECT_NEAR(bal_cost(out), j["final_cost"].get<double>(), 1e-6 * cost);
    EXPECT_TRUE(contains(slurp(dir / "out.ply"), "element vertex 156"));
  }
}

TEST(CliBundleAdjustment, BadInputGivesAClearErrorAndNonZeroExit) {
  const fs::path dir = scratch();
  auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  const std::string good = "1 2 2\n0 0 1 1\n0 1 2 2\n0 0 0 0 0 -5 500 0 0\n0 0 -1\n1 1 -2\n";
  CliRun r = slamkit("optimize " + write("truncated.bal", good.substr(0, good.size() - 8)));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "truncated.bal:")) << r.err;
  EXPECT_TRUE(contains(r.err, "the file ends early")) << r.err;
  std::string nan = good;
  nan.replace(nan.find("500"), 3, "nan");
  r = slamkit("optimize " + write("nan.bal", nan));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "nan.bal:4: field 'camera 0 f'")) << r.err;
  r = slamkit("optimize " + write("missing.bal", "1 2 2\n0 0 1 1\n3 1 2 2\n0 0 0 0 0 -5 500 0 0\n0 0 -1\n1 1 -2\n"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "missing.bal:3: field 'observation 1 camera': camera index 3 out of range")) << r.err;
  // Points behind the camera: reported, and the run still ends with a finite cost.
  r = slamkit("optimize " + write("behind.bal", "1 2 2\n0 0 1 1\n0 1 2 2\n0 0 0 0 0 5 500 0 0\n0 0 -1\n1 1 -2\n") +
              " --format bal --json " + (dir / "behind.json").string());
  EXPECT_TRUE(contains(r.err, "behind every camera")) << r.err;
  if (r.exit_code == 0) {
    const nlohmann::json j = nlohmann::json::parse(slurp(dir / "behind.json"));
    EXPECT_TRUE(std::isfinite(j["final_cost"].get<double>()));
  }
  // A point on the camera's plane: the prediction is infinite, rejected before optimizing.
  r = slamkit("optimize " + write("plane.bal", "1 2 2\n0 0 1 1\n0 1 2 2\n0 0 0 0 0 0 500 0 0\n0 0 0\n1 1 -2\n") + " --format bal");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_TRUE(contains(r.err, "plane.bal:2: field 'observation 0'")) << r.err;
}

TEST(CliBundleAdjustment, RealProblemReachesCeresCost) {
  SLAMKIT_REQUIRE_DATA(file, "bal/problem-21-11315-pre.txt");
  const fs::path json = scratch() / "t21.json";
  const CliRun r = slamkit("optimize " + file.string() + " -q --json " + json.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_NEAR(j["initial_cost"].get<double>(), 4.413e6, 0.001e6);  // Ceres 2.1: 4.413e6 -> 3.0379e4
  EXPECT_LT(j["final_cost"].get<double>(), 3.0379e4 * 1.001);
  EXPECT_EQ(j["problem"], "bundle_adjustment");
}

TEST(CliBundleAdjustment, RobustKernel) {
  const fs::path json = scratch() / "huber.json";
  const CliRun r = slamkit("optimize 'sim:ba?cameras=5&points=100' -q --robust huber:1 --json " + json.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["robust"], "huber:1");
  EXPECT_LT(j["final_cost"].get<double>(), j["initial_cost"].get<double>());
}

}  // namespace
}  // namespace slamkit
