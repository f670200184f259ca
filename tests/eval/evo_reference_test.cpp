// Acceptance: slamkit's ATE/RPE reproduce evo's stored results on KITTI 00 (ORB-SLAM vs
// ground truth): every statistic of stats.json and every per-pair error of error_array.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "npy_reader.h"
#include "slamkit/eval/evaluation.h"
#include "slamkit/io/trajectory_io.h"
#include "testing/data.h"

namespace slamkit {
namespace {

constexpr double kRelTol = 1e-6;  // acceptance tolerance (relative)

::testing::AssertionResult near_rel(double ours, double evo, double tol = kRelTol) {
  const double rel = std::abs(ours - evo) / std::max(std::abs(evo), 1e-300);
  if (rel <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "ours " << ours << " evo " << evo << " relative error " << rel;
}

std::filesystem::path evo_result(const char* name) {
  return std::filesystem::path(SLAMKIT_EVO_REFERENCE_DIR) / name;
}

void expect_stats_match(const ErrorStatistics& s, const std::filesystem::path& stats_json) {
  std::ifstream in(stats_json);
  ASSERT_TRUE(in) << stats_json << " missing: re-run cmake to unpack evo's results";
  const nlohmann::json j = nlohmann::json::parse(in);
  for (const char* key : {"rmse", "mean", "median", "std", "min", "max", "sse"}) ASSERT_TRUE(j.contains(key)) << key;
  EXPECT_TRUE(near_rel(s.rmse, j["rmse"].get<double>())) << "rmse";
  EXPECT_TRUE(near_rel(s.mean, j["mean"].get<double>())) << "mean";
  EXPECT_TRUE(near_rel(s.median, j["median"].get<double>())) << "median";
  EXPECT_TRUE(near_rel(s.std, j["std"].get<double>())) << "std";
  EXPECT_TRUE(near_rel(s.min, j["min"].get<double>())) << "min";
  EXPECT_TRUE(near_rel(s.max, j["max"].get<double>())) << "max";
  EXPECT_TRUE(near_rel(s.sse, j["sse"].get<double>())) << "sse";
}

void expect_errors_match(const std::vector<double>& ours, const std::filesystem::path& npy) {
  const std::vector<double> evo = testing::read_npy_f8(npy.string());
  ASSERT_EQ(ours.size(), evo.size());
  double worst = 0.0;
  for (std::size_t k = 0; k < evo.size(); ++k) worst = std::max(worst, std::abs(ours[k] - evo[k]));
  EXPECT_LT(worst, 1e-9) << "largest per-pair difference [m]";
}

class KittiOrb : public ::testing::Test {
 protected:
  void SetUp() override {
    SLAMKIT_REQUIRE_DATA(gt, "vio/eval_reference/KITTI_00_gt.txt");
    SLAMKIT_REQUIRE_DATA(orb, "vio/eval_reference/KITTI_00_ORB.txt");
    ref_ = read_trajectory(gt.string(), TrajectoryFormat::kKitti);
    est_ = read_trajectory(orb.string(), TrajectoryFormat::kKitti);
  }
  Trajectory ref_, est_;
};

// evo_ape kitti KITTI_00_gt.txt KITTI_00_ORB.txt -a
TEST_F(KittiOrb, ApeSe3MatchesEvo) {
  EvalOptions opt;
  opt.kind = MetricKind::kAte;
  opt.align = AlignmentMode::kSe3;
  const EvalResult r = evaluate(est_, ref_, opt);
  EXPECT_TRUE(r.association.by_index);
  EXPECT_EQ(r.stats.count, 4541u);
  // The README's figures, then evo's files themselves.
  EXPECT_TRUE(near_rel(r.stats.rmse, 1.3034497145650266));
  EXPECT_TRUE(near_rel(r.stats.mean, 1.1569971285389768));
  EXPECT_TRUE(near_rel(r.stats.median, 1.065624769555848));
  EXPECT_TRUE(near_rel(r.stats.std, 0.6002822693968323));
  EXPECT_TRUE(near_rel(r.stats.min, 0.06931322021483087));
  EXPECT_TRUE(near_rel(r.stats.max, 3.587949120678954));
  EXPECT_TRUE(near_rel(r.stats.sse, 7715.073440292808));
  expect_stats_match(r.stats, evo_result("orb_ape/stats.json"));
  expect_errors_match(r.errors.errors, evo_result("orb_ape/error_array.npz"));
}

// evo_rpe kitti KITTI_00_gt.txt KITTI_00_ORB.txt --delta 10 --delta_unit m
TEST_F(KittiOrb, Rpe10MetresConsecutiveMatchesEvo) {
  EvalOptions opt;
  opt.kind = MetricKind::kRpe;
  opt.align = AlignmentMode::kNone;
  opt.rpe.delta = 10.0;
  opt.rpe.delta_unit = DeltaUnit::kMeters;
  const EvalResult r = evaluate(est_, ref_, opt);
  EXPECT_EQ(r.stats.count, 353u);
  EXPECT_TRUE(near_rel(r.stats.rmse, 0.22626134329310163));
  EXPECT_TRUE(near_rel(r.stats.mean, 0.16901737200653275));
  EXPECT_TRUE(near_rel(r.stats.median, 0.13848432516645606));
  EXPECT_TRUE(near_rel(r.stats.max, 1.2722090778658726));
  EXPECT_TRUE(near_rel(r.stats.min, 0.025322719660754993));
  expect_stats_match(r.stats, evo_result("orb_rpe/stats.json"));
  expect_errors_match(r.errors.errors, evo_result("orb_rpe/error_array.npz"));
}

// RPE does not depend on a rigid alignment: E_ij is invariant under P ↦ S P.
TEST_F(KittiOrb, RpeIsInvariantToRigidAlignment) {
  EvalOptions opt;
  opt.kind = MetricKind::kRpe;
  opt.rpe.delta = 10.0;
  opt.rpe.delta_unit = DeltaUnit::kMeters;
  const EvalResult plain = evaluate(est_, ref_, opt);
  opt.align = AlignmentMode::kSe3;
  const EvalResult aligned = evaluate(est_, ref_, opt);
  ASSERT_EQ(plain.pairs, aligned.pairs);
  EXPECT_NEAR(plain.stats.rmse, aligned.stats.rmse, 1e-9);
}

}  // namespace
}  // namespace slamkit
