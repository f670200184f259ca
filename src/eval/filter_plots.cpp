#include "slamkit/eval/filter_plots.h"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "slamkit/eval/plot.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {

namespace {
Plot::Series series(std::string label, std::vector<double> x, std::vector<double> y, Rgb color, double width,
                    std::string dash = "") {
  Plot::Series s;
  s.label = std::move(label);
  s.x = std::move(x);
  s.y = std::move(y);
  s.color = color;
  s.width = width;
  s.dash = std::move(dash);
  return s;
}

// Points of the 3σ ellipse of a 2×2 covariance around c.
void ellipse(const Eigen::Vector2d& c, const Eigen::Matrix2d& P, std::vector<double>* x, std::vector<double>* y) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 * (P + P.transpose()));
  const Eigen::Matrix2d A = es.eigenvectors() * es.eigenvalues().cwiseMax(0).cwiseSqrt().asDiagonal() * 3.0;
  for (int i = 0; i <= 36; ++i) {
    const double a = 2 * kPi * i / 36;
    const Eigen::Vector2d p = c + A * Eigen::Vector2d(std::cos(a), std::sin(a));
    x->push_back(p.x());
    y->push_back(p.y());
  }
}
}  // namespace

SvgWriter plot_filter_map(const FilterRunResult& run, const std::vector<Eigen::Vector2d>& truth_map,
                          const std::string& title, double width, double height) {
  Plot p(title, "x [m]", "y [m]");
  p.set_equal_aspect(true);
  Plot::Series truth = series("true path", {}, {}, Rgb{90, 90, 90}, 1.5, "6 4");
  Plot::Series est = series("estimate", {}, {}, palette(0), 1.8);
  for (std::size_t k = 0; k < run.truth.size(); ++k) {
    truth.x.push_back(run.truth[k].x());
    truth.y.push_back(run.truth[k].y());
    est.x.push_back(run.estimate[k].x());
    est.y.push_back(run.estimate[k].y());
  }
  p.add_series(truth);
  p.add_series(est);
  Plot::Series lm_true = series("true landmarks", {}, {}, Rgb{40, 40, 40}, 0.0);
  lm_true.points = true;
  for (const auto& m : truth_map) lm_true.x.push_back(m.x()), lm_true.y.push_back(m.y());
  lm_true.opacity = 0.7;
  if (!truth_map.empty()) p.add_series(lm_true);
  bool first = true;
  for (const auto& m : run.final_map) {
    Plot::Series e = series(first ? "landmark 3σ" : "", {}, {}, palette(3), 1.0);
    ellipse(m.mean, m.covariance, &e.x, &e.y);
    p.add_series(std::move(e));
    first = false;
  }
  if (!run.covariance.empty()) {
    Plot::Series e = series("final pose 3σ", {}, {}, palette(1), 1.4);
    ellipse(run.estimate.back().head<2>(), run.covariance.back().topLeftCorner<2, 2>(), &e.x, &e.y);
    p.add_series(std::move(e));
  }
  return p.render(width, height);
}

SvgWriter plot_filter_errors(const FilterRunResult& run, const std::string& title, double width, double height) {
  SvgWriter svg(width, height);
  const char* names[3] = {"x error [m]", "y error [m]", "heading error [deg]"};
  const double panel = height / 3;
  for (int c = 0; c < 3; ++c) {
    Plot p(c == 0 ? title : "", "time [s]", names[c]);
    Plot::Series e = series("error", {}, {}, palette(0), 1.4);
    Plot::Series hi = series("±3σ", {}, {}, palette(3), 1.2, "5 3"), lo = series("", {}, {}, palette(3), 1.2, "5 3");
    const double scale = c == 2 ? 180 / kPi : 1.0;
    for (std::size_t k = 0; k < run.time.size(); ++k) {
      double err = run.estimate[k](c) - run.truth[k](c);
      if (c == 2) err = wrap_angle(err);
      const double s = 3 * std::sqrt(std::max(0.0, run.covariance[k](c, c)));
      e.x.push_back(run.time[k]);
      e.y.push_back(err * scale);
      hi.x.push_back(run.time[k]);
      hi.y.push_back(s * scale);
      lo.x.push_back(run.time[k]);
      lo.y.push_back(-s * scale);
    }
    p.add_series(hi);
    p.add_series(lo);
    p.add_series(e);
    svg.embed(p.render(width, panel), 0, c * panel);
  }
  return svg;
}

SvgWriter plot_anees(const std::vector<std::pair<std::string, const ConsistencySummary*>>& filters,
                     const std::string& title, double width, double height) {
  Plot p(title, "time [s]", "ANEES (pose, 3 dof)");
  p.set_log_y(true);
  if (!filters.empty()) {
    const ConsistencySummary& s = *filters.front().second;
    char label[96];
    std::snprintf(label, sizeof label, "%.0f%% bounds, N = %d [%.3f, %.3f]", 100 * s.confidence, s.runs,
                  s.anees_lo, s.anees_hi);
    p.add_band(s.anees_lo, s.anees_hi, label, Rgb{60, 160, 60}, 0.18);
    p.add_hline(3.0, "n = 3", Rgb{60, 120, 60});
  }
  for (std::size_t i = 0; i < filters.size(); ++i)
    p.add_series(series(filters[i].first, filters[i].second->time, filters[i].second->anees, palette(i), 1.4));
  return p.render(width, height);
}

SvgWriter plot_rmse(const std::vector<std::pair<std::string, const ConsistencySummary*>>& filters,
                    const std::string& title, double width, double height) {
  Plot p(title, "time [s]", "position RMSE over runs [m]");
  p.set_y_from_zero(true);
  for (std::size_t i = 0; i < filters.size(); ++i)
    p.add_series(series(filters[i].first, filters[i].second->time, filters[i].second->rmse_position, palette(i), 1.4));
  return p.render(width, height);
}

SvgWriter plot_time_per_step(const std::vector<TimingSeries>& lines, const std::string& title, double width,
                             double height) {
  Plot p(title, "landmarks in the map (log scale)", "time per step [ms] (log scale)");
  p.set_log_x(true);
  p.set_log_y(true);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    Plot::Series s = series(lines[i].label, lines[i].landmarks, lines[i].ms, palette(i), 1.6);
    s.points = lines[i].ms.size() <= 60;
    p.add_series(std::move(s));
  }
  return p.render(width, height);
}

SvgWriter filter_dashboard(const std::string& label, const FilterRunResult& run, const ConsistencySummary& summary,
                           const std::vector<Eigen::Vector2d>& true_landmarks) {
  const double w = 620, h = 520;
  SvgWriter svg(2 * w, 2 * h);
  svg.embed(plot_filter_map(run, true_landmarks, label + ": trajectory and map (seed " + std::to_string(run.seed) + ")", w, h), 0, 0);
  svg.embed(plot_filter_errors(run, label + ": pose error and ±3σ (seed " + std::to_string(run.seed) + ")", w, h), w, 0);
  svg.embed(plot_anees({{label, &summary}}, label + ": ANEES over " + std::to_string(summary.runs) + " runs", w, h), 0, h);
  svg.embed(plot_rmse({{label, &summary}}, label + ": position RMSE over runs", w, h), w, h);
  return svg;
}

}  // namespace slamkit
