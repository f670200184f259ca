// SVG writer, Plot/BarChart and the evaluation figures: well-formed markup (balanced tags,
// escaped text), the elements each figure must contain, ticks, colour maps, log axes.
#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "slamkit/eval/eval_plots.h"
#include "slamkit/eval/plot.h"
#include "slamkit/eval/svg.h"
#include "testing/text.h"

namespace slamkit {
namespace {

constexpr auto* count = &slamkit::testing::count_occurrences;

/// Every opened element is closed (self-closing or by its end tag), in order.
::testing::AssertionResult well_formed(const std::string& svg) {
  std::vector<std::string> stack;
  const std::regex tag("<(/?)([a-zA-Z]+)[^>]*?(/?)>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), tag); it != std::sregex_iterator(); ++it) {
    const std::string name = (*it)[2];
    if ((*it)[1] == "/") {
      if (stack.empty() || stack.back() != name) return ::testing::AssertionFailure() << "unbalanced </" << name << ">";
      stack.pop_back();
    } else if ((*it)[3] != "/") {
      stack.push_back(name);
    }
  }
  if (!stack.empty()) return ::testing::AssertionFailure() << "unclosed <" << stack.back() << ">";
  return ::testing::AssertionSuccess();
}

TEST(Svg, EscapesTextAndDecimatesPolylines) {
  SvgWriter svg(100, 50);
  svg.text(1, 2, "a<b & \"c\"", {});
  std::vector<Point2> pts;
  for (int k = 0; k <= 1000; ++k) pts.push_back({0.01 * k, 0.0});  // 10 px in 0.01 px steps
  svg.polyline(pts, {"#ff0000", 1.0, "", 1.0});
  const std::string s = svg.str();
  EXPECT_NE(s.find("a&lt;b &amp; &quot;c&quot;"), std::string::npos);
  EXPECT_EQ(s.find("a<b"), std::string::npos);
  const std::smatch m = [&] {
    std::smatch r;
    std::regex_search(s, r, std::regex("points=\"([^\"]*)\""));
    return r;
  }();
  ASSERT_FALSE(m.empty());
  EXPECT_LE(count(m[1], ","), 22u);  // ~0.5 px apart, plus the last point
  EXPECT_NE(std::string(m[1]).find("10,0"), std::string::npos);
  EXPECT_TRUE(well_formed(s));
}

TEST(Svg, ColoursAndTicks) {
  EXPECT_EQ(viridis(0.0).hex(), "#440154");
  EXPECT_EQ(viridis(1.0).hex(), "#fde725");
  EXPECT_EQ(viridis(-3.0).hex(), "#440154");
  EXPECT_NE(palette(0).hex(), palette(1).hex());
  EXPECT_EQ(palette(0).hex(), palette(10).hex());
  EXPECT_EQ(nice_ticks(0.0, 1.0, 5), (std::vector<double>{0.0, 0.2, 0.4, 0.6, 0.8, 1.0}));
  EXPECT_EQ(nice_ticks(-3.2, 7.9, 5), (std::vector<double>{-2, 0, 2, 4, 6}));
  EXPECT_TRUE(nice_ticks(1.0, 1.0, 5).empty());
  EXPECT_EQ(tick_label(0.25, 0.05), "0.25");
  EXPECT_EQ(tick_label(200, 50), "200");
  EXPECT_EQ(tick_label(-0.0, 0.1), "0.0");
  const Histogram h = make_histogram({0.1, 0.2, 0.25, 0.9, 1.0}, 4, 0.0, 1.0);
  EXPECT_EQ(h.counts, (std::vector<double>{2, 1, 0, 2}));  // [0, .25) [.25, .5) [.5, .75) [.75, 1]
  EXPECT_EQ(h.edges.size(), 5u);
}

TEST(Plot, DrawsEveryElementKind) {
  Plot p("title & more", "x", "y");
  p.set_log_y(true);
  p.add_series({"line", {1, 2, 3, 4}, {10, 100, -1, 1000}, palette(0), 1.5, "", 1.0, true});  // -1 splits the line
  p.add_hline(50, "h", palette(1));
  p.add_band(20, 40, "band", palette(2));
  p.add_marker(2, 100, "m", palette(3));
  const std::string s = p.render(500, 300).str();
  EXPECT_TRUE(well_formed(s));
  EXPECT_NE(s.find("title &amp; more"), std::string::npos);
  EXPECT_NE(s.find(">1000<"), std::string::npos);  // decade ticks
  EXPECT_NE(s.find(">100<"), std::string::npos);
  EXPECT_EQ(count(s, "<polyline"), 1u);  // the run 1–2; 4 stands alone (a dot)
  EXPECT_GE(count(s, "<circle"), 4u);
  Plot empty("none", "x", "y");
  EXPECT_NE(empty.render(300, 200).str().find("no data"), std::string::npos);
}

TEST(Plot, LogXAxisHasDecadeTicksAndDropsNonPositiveX) {
  Plot p("convergence", "time [s]", "chi2");
  p.set_log_x(true);
  p.set_log_y(true);
  Plot::Series s;
  s.label = "solver";
  s.x = {0.0, 0.001, 0.01, 0.1, 2.0};  // t = 0 cannot be drawn on a log axis
  s.y = {1e6, 1e4, 1e3, 200, 150};
  p.add_series(s);
  const std::string svg = p.render(600, 400).str();
  for (const char* tick : {">0.001<", ">0.01<", ">0.1<", ">1<"}) EXPECT_NE(svg.find(tick), std::string::npos) << tick;
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
  // The linear axis (the default) keeps t = 0 and its linear ticks.
  Plot lin("convergence", "time [s]", "chi2");
  lin.add_series(s);
  EXPECT_NE(lin.render(600, 400).str().find(">0.0<"), std::string::npos);
}

TEST(Plot, ColouredPathHasAColourBarAndFewPolylines) {
  Plot p("path", "x [m]", "y [m]");
  p.set_equal_aspect(true);
  std::vector<double> x, y, v;
  for (int k = 0; k < 2000; ++k) x.push_back(std::cos(0.01 * k)), y.push_back(std::sin(0.01 * k)), v.push_back(k);
  p.add_colored_path(x, y, v, "error [m]");
  const std::string s = p.render(600, 500).str();
  EXPECT_TRUE(well_formed(s));
  EXPECT_NE(s.find("class=\"colorbar\""), std::string::npos);
  EXPECT_NE(s.find("error [m]"), std::string::npos);
  const std::size_t n = count(s, "<polyline");
  EXPECT_GE(n, 40u);   // one per colour level used
  EXPECT_LE(n, 48u);   // merged, not one per segment
}

TEST(BarChart, BarsAndLabels) {
  BarChart b("stats", "error [m]", {"run one", "run two"}, {"rmse", "mean"});
  b.set_values({{1.0, 0.5}, {2.0, std::nan("")}});
  const std::string s = b.render(500, 300).str();
  EXPECT_TRUE(well_formed(s));
  EXPECT_NE(s.find("run two"), std::string::npos);
  EXPECT_EQ(count(s, "fill=\"" + palette(0).hex() + "\""), 3u);  // 2 bars + legend
}

EvalRunData sample_run(const std::string& kind, bool timestamps) {
  EvalRunData d;
  d.kind = kind;
  d.label = "run <1>";
  d.title = "APE w.r.t. translation part (m)";
  d.unit = "m";
  d.reference = "gt.txt";
  d.has_timestamps = timestamps;
  for (int k = 0; k < 300; ++k) {
    const double s = 0.05 * k;
    d.ref_xyz.emplace_back(10 * std::cos(s), 6 * std::sin(s), 0.2 * s);
    d.est_xyz.emplace_back(10 * std::cos(s) + 0.1 * std::sin(5 * s), 6 * std::sin(s), 0.2 * s + 0.05);
    d.index.push_back(static_cast<std::size_t>(k));
    d.time.push_back(1000.0 + s);
    d.error.push_back(0.1 + 0.05 * std::sin(3 * s));
  }
  d.stats.rmse = 0.11, d.stats.mean = 0.1, d.stats.median = 0.1, d.stats.std = 0.035, d.stats.count = 300;
  return d;
}

TEST(EvalPlots, FigureHasAllPanels) {
  const EvalRunData run = sample_run("ate", true);
  const std::string s = eval_figure(run).str();
  EXPECT_TRUE(well_formed(s));
  EXPECT_EQ(count(s, "<svg"), 6u);  // the page and five panels
  EXPECT_NE(s.find("Top view (x–y)"), std::string::npos);
  EXPECT_NE(s.find("Side view (x–z)"), std::string::npos);
  EXPECT_NE(s.find("along the path"), std::string::npos);
  EXPECT_NE(s.find("Distribution of APE"), std::string::npos);
  EXPECT_NE(s.find("time [s]"), std::string::npos);
  EXPECT_NE(s.find("run &lt;1&gt;"), std::string::npos);
  EXPECT_NE(s.find("class=\"colorbar\""), std::string::npos);
}

TEST(EvalPlots, IndexAxisWithoutTimestampsAndSeveralRuns) {
  const EvalRunData a = sample_run("rpe", false), b = sample_run("rpe", false);
  const std::string s = plot_error_over_time({&a, &b}, 800, 300).str();
  EXPECT_NE(s.find(">index<"), std::string::npos);
  EXPECT_NE(s.find(palette(1).hex()), std::string::npos);
  EXPECT_EQ(s.find(">rmse<"), std::string::npos);  // statistics lines only for a single run
  EXPECT_NE(plot_error_histogram({&a, &b}, 500, 300).str().find("Distribution of RPE"), std::string::npos);
}

}  // namespace
}  // namespace slamkit
