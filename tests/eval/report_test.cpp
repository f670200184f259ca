// The HTML report: self-contained (no scripts, no external resources), one table row per run,
// the plots of each section, strict handling of unknown kinds and malformed optimizer runs.
#include "slamkit/eval/report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "slamkit/core/error.h"
#include "slamkit/eval/run_json.h"
#include "testing/text.h"

namespace slamkit {
namespace {

constexpr auto* count = &slamkit::testing::count_occurrences;

nlohmann::json eval_doc(MetricKind kind, const std::string& label, double noise,
                        PoseRelation relation = PoseRelation::kTranslation) {
  Trajectory ref, est;
  for (int k = 0; k < 200; ++k) {
    const double s = 0.05 * k;
    const Eigen::Vector3d p(8 * std::cos(s), 5 * std::sin(s), 0.1 * s);
    ref.push_back(s, SE3(SO3::from_rpy(0, 0, s), p));
    est.push_back(s + 0.001, SE3(SO3::from_rpy(0, 0, s + noise), p + noise * Eigen::Vector3d(std::sin(7 * s), 0, 1)));
  }
  EvalOptions opt;
  opt.kind = kind;
  opt.align = AlignmentMode::kSe3;
  opt.relation = relation;
  return eval_result_to_json(evaluate(est, ref, opt), RunSource{label, "est.txt", "tum", "gt.txt", "tum", 200, 200});
}

nlohmann::json optimize_doc(const std::string& label, double final_cost) {
  nlohmann::json trace = nlohmann::json::array();
  double cost = 1e5;
  for (int k = 0; k <= 6; ++k, cost = std::max(final_cost, cost / 8))
    trace.push_back({{"iteration", k}, {"cost", cost}, {"gradient_norm", cost / 10}, {"time_s", 0.05 * (k + 1)}});
  return {{"kind", "optimize"}, {"label", label},       {"solver", "lm"},       {"init", "chordal"},
          {"initial_chi2", 2e5},  {"final_chi2", 2 * final_cost}, {"iterations", 6}, {"time_total_s", 0.35},
          {"termination", "function tolerance"}, {"trace", trace}};
}

TEST(Report, SelfContainedPageWithTablesAndPlots) {
  const std::vector<ReportInput> in = {{"a.json", eval_doc(MetricKind::kAte, "solver <A>", 0.02)},
                                       {"b.json", eval_doc(MetricKind::kAte, "solver B", 0.05)},
                                       {"c.json", eval_doc(MetricKind::kRpe, "solver B", 0.05)},
                                       {"d.json", optimize_doc("lm", 363.5)},
                                       {"e.json", optimize_doc("gn", 370.0)}};
  const std::string html = render_html_report(in, ReportOptions{"My & report", "slamkit test"});
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("<title>My &amp; report</title>"), std::string::npos);
  EXPECT_NE(html.find("solver &lt;A&gt;"), std::string::npos);
  EXPECT_EQ(html.find("solver <A>"), std::string::npos);
  // Self-contained: no scripts, no external resources (the SVG namespace URI is not fetched).
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);
  EXPECT_EQ(html.find("url("), std::string::npos);
  EXPECT_EQ(std::regex_search(html, std::regex("(src|href)=\"(https?:)?//")), false);
  // Sections, tables and plots.
  for (const char* id : {"id=\"ate\"", "id=\"rpe\"", "id=\"optimize\""}) EXPECT_NE(html.find(id), std::string::npos) << id;
  EXPECT_EQ(count(html, "<table"), 3u);
  EXPECT_EQ(count(html, "<tr>"), 3u + 2 + 1 + 2);  // header rows + one per run
  EXPECT_EQ(count(html, "<svg"), 7u + 6u + 2u);  // APE: 5 + 2 along the path; RPE: 5 + 1; optimization: 2
  EXPECT_GE(count(html, "<polyline"), 20u);
  EXPECT_NE(html.find("Cost per iteration"), std::string::npos);
  EXPECT_NE(html.find("class=\"best\""), std::string::npos);
}

TEST(Report, RunsWithDifferentUnitsGetTheirOwnSections) {
  const std::vector<ReportInput> in = {{"r.json", eval_doc(MetricKind::kRpe, "rpe", 0.05)},
                                       {"a.json", eval_doc(MetricKind::kAte, "trans", 0.05)},
                                       {"b.json", eval_doc(MetricKind::kAte, "angle", 0.05, PoseRelation::kAngleDeg)},
                                       {"c.json", eval_doc(MetricKind::kAte, "trans 2", 0.02)}};
  const std::string html = render_html_report(in, {});
  const std::size_t ate = html.find("<section id=\"ate\">"), ate1 = html.find("<section id=\"ate-1\">");
  const std::size_t rpe = html.find("<section id=\"rpe\">");
  ASSERT_NE(ate, std::string::npos);
  ASSERT_NE(ate1, std::string::npos);
  ASSERT_NE(rpe, std::string::npos);
  EXPECT_LT(ate, ate1);  // APE first, in order of appearance, then RPE
  EXPECT_LT(ate1, rpe);
  EXPECT_NE(html.find("Absolute pose error (APE / ATE), angle_deg [deg]"), std::string::npos);
  EXPECT_EQ(count(html, "<table"), 3u);
}

nlohmann::json simulate_doc(const std::string& output, const std::string& dynamic) {
  return {{"kind", "simulate"}, {"source", "room1"}, {"output", output}, {"seed", 3}, {"dynamic", dynamic},
          {"camera", {{"model", "equidistant"}}}, {"duration_s", 10.0}, {"frames", 200},
          {"features_per_frame", {{"mean", 148.5}, {"min", 120}}}, {"dynamic_share", 0.21},
          {"static_ratio", {{"mean", 0.79}, {"min", 0.41}}},
          {"landmarks", {{"static", 4000}, {"dynamic", 160}, {"groups", 4}}},
          {"spline_fit", {{"position_rmse_m", 0.0004}, {"rotation_rmse_deg", 0.02}}}};
}

TEST(Report, SimulatedRunsGetTheirTable) {
  const std::string h = render_html_report(
      {{"a.json", simulate_doc("high.vis", "high")}, {"b.json", simulate_doc("none.vis", "none")},
       {"c.json", eval_doc(MetricKind::kAte, "vio", 0.02)}},
      {});
  EXPECT_EQ(count(h, "id=\"simulations\""), 1);
  EXPECT_EQ(count(h, "href=\"#simulations\""), 1);
  EXPECT_NE(h.find("high.vis"), std::string::npos);
  EXPECT_NE(h.find("none.vis"), std::string::npos);
  EXPECT_NE(h.find("2 simulation"), std::string::npos);
  EXPECT_NE(h.find("<td>0.410</td>"), std::string::npos);  // M min
}

// `slamkit frontend --json` documents and the "frontend" object of `slamkit vio --images` runs.
TEST(Report, FrontEndRunsGetTheirTable) {
  const nlohmann::json front = {{"kind", "frontend"}, {"input", "aloeL.jpg aloeR.jpg"}, {"camera", "none"}, {"frames", 2},
                                {"static_ratio", {{"mean", 0.86}, {"min", 0.86}}}, {"share_dynamic", 0.14}, {"share_flagged", 0.205},
                                {"frames_too_few_matches", 0}, {"time_per_frame_ms", {{"mean", 12.5}, {"max", 12.5}}}};
  nlohmann::json vio = eval_doc(MetricKind::kAte, "vio room1 images", 0.02);
  vio["frontend"] = {{"kind", "frontend"}, {"image_source", "rendered in memory"}, {"frames", 600},
                     {"static_ratio", {{"mean", 0.93}, {"min", 0.52}}}, {"dynamic_precision", 0.912},
                     {"dynamic_recall", 0.834}, {"tracking_ms_per_frame", 9.0}, {"classification_ms_per_frame", 2.0},
                     {"image_ms_per_frame", 40.0}};
  const std::string h = render_html_report({{"a.json", front}, {"b.json", vio}}, {});
  EXPECT_EQ(count(h, "id=\"frontend\""), 1);
  EXPECT_EQ(count(h, "href=\"#frontend\""), 1);
  EXPECT_NE(h.find("2 front-end"), std::string::npos);
  EXPECT_NE(h.find("<td>14.0</td>"), std::string::npos);   // dynamic share [%]
  EXPECT_NE(h.find("<td>20.5</td>"), std::string::npos);   // flagged share [%] (isolated flags too)
  EXPECT_NE(h.find("<td>0.912</td>"), std::string::npos);  // precision
  EXPECT_NE(h.find("<td>11.0</td>"), std::string::npos);   // tracking + classification
  EXPECT_NE(h.find("rendered in memory"), std::string::npos);
  nlohmann::json bad = front;
  bad["static_ratio"].erase("mean");
  EXPECT_THROW(render_html_report({{"a.json", bad}}, {}), InputError);
}

TEST(Report, UnknownKindsAndMalformedRunsAreClearErrors) {
  auto expect_error = [](const nlohmann::json& doc, const std::string& field) {
    try {
      render_html_report({{"run.json", doc}}, {});
      ADD_FAILURE() << "accepted " << doc.dump().substr(0, 80);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "run.json");
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  expect_error({{"kind", "particle-cloud"}}, "kind");
  expect_error({{"kind", "filter"}}, "runs");  // a filter run (filter_report.h) without its fields
  expect_error({{"label", "x"}}, "kind");
  nlohmann::json sim = simulate_doc("x.vis", "low");
  sim["static_ratio"].erase("min");
  expect_error(sim, "static_ratio.min");
  sim = simulate_doc("x.vis", "low");
  sim["frames"] = "many";
  expect_error(sim, "frames");
  expect_error(nlohmann::json::array(), "kind");
  nlohmann::json opt = optimize_doc("lm", 1.0);
  opt.erase("trace");
  expect_error(opt, "trace");
  opt = optimize_doc("lm", 1.0);
  opt["trace"][2].erase("cost");
  expect_error(opt, "trace[2].cost");
  opt = optimize_doc("lm", 1.0);
  opt["final_chi2"] = "small";
  expect_error(opt, "final_chi2");
  nlohmann::json ate = eval_doc(MetricKind::kAte, "x", 0.1);
  ate["series"].erase("est_xyz");
  expect_error(ate, "series.est_xyz");
  EXPECT_THROW(render_html_report({}, {}), InputError);
}

TEST(Report, OptimizerRunParsing) {
  nlohmann::json doc = optimize_doc("", 10.0);
  doc.erase("label");
  doc["trace"][1].erase("time_s");
  const OptimizeRunData d = optimize_run_from_json(doc, "dir/lm_run.json");
  EXPECT_EQ(d.label, "lm_run.json");  // default: the file name
  EXPECT_EQ(d.trace.size(), 7u);
  EXPECT_FALSE(d.trace[1].time_s.has_value());
  EXPECT_DOUBLE_EQ(*d.trace[2].time_s, 0.15);
  EXPECT_EQ(*d.iterations, 6);
  EXPECT_EQ(d.termination, "function tolerance");
  // Optional fields may be absent.
  const OptimizeRunData m = optimize_run_from_json({{"kind", "optimize"}, {"trace", nlohmann::json::array()}}, "m.json");
  EXPECT_FALSE(m.final_chi2.has_value());
  EXPECT_TRUE(m.trace.empty());
}

}  // namespace
}  // namespace slamkit
