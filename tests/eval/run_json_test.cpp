// The eval JSON document: schema fields, statistics at top level, series that index into the
// aligned positions, and strict reading back (missing / mistyped fields name the field).
#include "slamkit/eval/run_json.h"

#include <gtest/gtest.h>

#include <cmath>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

Trajectory spiral(double scale, double offset) {
  Trajectory t;
  for (int k = 0; k < 80; ++k) {
    const double s = 0.1 * k;
    t.push_back(100.0 + s, SE3(SO3::from_rpy(0, 0, s), scale * Eigen::Vector3d(std::cos(s), std::sin(s), 0.1 * s + offset * std::sin(3 * s))));
  }
  return t;
}

EvalResult example(MetricKind kind) {
  EvalOptions opt;
  opt.kind = kind;
  opt.align = AlignmentMode::kSim3;
  opt.rpe.delta = 0.5;
  opt.rpe.delta_unit = DeltaUnit::kMeters;
  return evaluate(spiral(2.0, 0.05), spiral(1.0, 0.0), opt);
}

RunSource source() { return {"spiral", "est.txt", "tum", "ref.txt", "tum", 80, 80}; }

TEST(RunJson, AteDocumentHasTheSchema) {
  const EvalResult r = example(MetricKind::kAte);
  const nlohmann::json j = eval_result_to_json(r, source());
  EXPECT_EQ(j["kind"], "ate");
  EXPECT_EQ(j["label"], "spiral");
  for (const char* k : {"rmse", "mean", "median", "std", "min", "max", "sse", "pairs"}) EXPECT_TRUE(j.contains(k)) << k;
  EXPECT_EQ(j["rmse"].get<double>(), r.stats.rmse);
  EXPECT_EQ(j["pairs"].get<std::size_t>(), 80u);
  EXPECT_EQ(j["alignment"]["mode"], "sim3");
  EXPECT_NEAR(j["alignment"]["scale"].get<double>(), 0.5, 0.01);
  EXPECT_EQ(j["association"]["method"], "timestamps");
  EXPECT_EQ(j["options"]["align"], "sim3");
  EXPECT_FALSE(j["options"].contains("delta"));
  EXPECT_EQ(j["translation"]["unit"], "m");
  EXPECT_EQ(j["rotation"]["unit"], "deg");
  EXPECT_EQ(j["series"]["error"].size(), 80u);
  EXPECT_EQ(j["series"]["est_xyz"].size(), 80u);
  EXPECT_EQ(j["title"], "APE w.r.t. translation part (m) (with Sim(3) Umeyama alignment)");
}

TEST(RunJson, RpeDocumentRoundTripsIntoRunData) {
  const EvalResult r = example(MetricKind::kRpe);
  const nlohmann::json j = eval_result_to_json(r, source());
  EXPECT_EQ(j["options"]["delta_unit"], "m");
  EXPECT_EQ(j["series"]["pair_first"].size(), r.pairs.size());
  // Through text, as `slamkit report` reads it.
  const EvalRunData d = eval_run_from_json(nlohmann::json::parse(j.dump()), "run.json");
  EXPECT_EQ(d.kind, "rpe");
  EXPECT_EQ(d.stats.rmse, r.stats.rmse);
  EXPECT_EQ(d.stats.count, r.pairs.size());
  ASSERT_EQ(d.index.size(), r.pairs.size());
  for (std::size_t k = 0; k < r.pairs.size(); ++k) {
    EXPECT_EQ(d.index[k], r.pairs[k].second);
    EXPECT_EQ(d.error[k], r.errors.errors[k]);
    EXPECT_EQ(d.time[k], r.est[r.pairs[k].second].stamp);
  }
  EXPECT_EQ(d.est_xyz[5], r.est[5].T_world_body.translation());
  EXPECT_EQ(d.reference, "ref.txt");
  EXPECT_TRUE(d.has_timestamps);
  ASSERT_TRUE(d.rotation.has_value());
  EXPECT_EQ(d.rotation->rmse, r.rotation_stats.rmse);
}

TEST(RunJson, StrictReading) {
  const nlohmann::json good = eval_result_to_json(example(MetricKind::kAte), source());
  auto expect_field = [](const nlohmann::json& j, const std::string& field) {
    try {
      eval_run_from_json(j, "bad.json");
      ADD_FAILURE() << "accepted a document with a bad '" << field << "'";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
      EXPECT_EQ(e.file(), "bad.json");
    }
  };
  nlohmann::json j = good;
  j["kind"] = "optimize";
  expect_field(j, "kind");
  j = good;
  j.erase("rmse");
  expect_field(j, "rmse");
  j = good;
  j["series"]["error"][3] = "x";
  expect_field(j, "series.error");
  j = good;
  j["series"]["error"].erase(0);
  expect_field(j, "series");
  j = good;
  j["series"]["index"][0] = 1e6;
  expect_field(j, "series.index");
  j = good;
  j["series"]["est_xyz"][0] = {1, 2};
  expect_field(j, "series.est_xyz");
  j = good;
  j["translation"]["rmse"] = "1";
  expect_field(j, "translation.rmse");
  expect_field(nlohmann::json::array(), "");
}

}  // namespace
}  // namespace slamkit
