#include "slamkit/eval/eval_plots.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "slamkit/eval/plot.h"

namespace slamkit {

namespace {

const Rgb kReferenceColor{90, 90, 90};
const char* kAxisNames[3] = {"x", "y", "z"};

/// Axes (a, b) of a view: top = the two axes of largest spread (in index order);
/// side = the largest against the smallest.
std::array<int, 2> view_axes(const std::vector<Eigen::Vector3d>& ref, TrajectoryView view) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& p : ref) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  std::array<int, 3> order = {0, 1, 2};
  const Eigen::Vector3d span = ref.empty() ? Eigen::Vector3d(2, 1, 0) : Eigen::Vector3d(hi - lo);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return span(a) > span(b); });
  if (view == TrajectoryView::kTop) return {std::min(order[0], order[1]), std::max(order[0], order[1])};
  return {order[0], order[2]};
}

std::string axis_label(int a) { return std::string(kAxisNames[a]) + " [m]"; }

std::string unit_suffix(const EvalRunData& run) { return run.unit.empty() ? "" : " [" + run.unit + "]"; }

std::string error_name(const EvalRunData& run) { return (run.kind == "ate" ? "APE" : "RPE") + unit_suffix(run); }

std::vector<double> relative_time(const EvalRunData& run) {
  std::vector<double> t = run.time;
  if (run.has_timestamps && !t.empty()) {
    const double t0 = t.front();
    for (double& v : t) v -= t0;
  }
  return t;
}

Plot::Series path_series(const std::vector<Eigen::Vector3d>& p, std::array<int, 2> ax, std::string label, Rgb color,
                         double width, std::string dash) {
  Plot::Series s;
  s.label = std::move(label);
  s.color = color;
  s.width = width;
  s.dash = std::move(dash);
  for (const auto& v : p) s.x.push_back(v(ax[0])), s.y.push_back(v(ax[1]));
  return s;
}

std::string fmt_stat(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

SvgWriter plot_trajectories(const std::vector<const EvalRunData*>& runs, TrajectoryView view, double width,
                            double height) {
  const std::vector<Eigen::Vector3d> empty;
  const auto& ref = runs.empty() ? empty : runs.front()->ref_xyz;
  const std::array<int, 2> ax = view_axes(ref, view);
  const std::string name = view == TrajectoryView::kTop ? "Top view" : "Side view";
  Plot plot(name + " (" + kAxisNames[ax[0]] + "–" + kAxisNames[ax[1]] + ")", axis_label(ax[0]), axis_label(ax[1]));
  plot.set_equal_aspect(true);
  plot.add_series(path_series(ref, ax, "reference", kReferenceColor, 1.6, "6 4"));
  for (std::size_t k = 0; k < runs.size(); ++k)
    plot.add_series(path_series(runs[k]->est_xyz, ax, runs[k]->label, palette(k), 1.6, ""));
  if (!ref.empty()) plot.add_marker(ref.front()(ax[0]), ref.front()(ax[1]), "start", Rgb{20, 20, 20});
  return plot.render(width, height);
}

SvgWriter plot_error_over_time(const std::vector<const EvalRunData*>& runs, double width, double height) {
  const bool timed = !runs.empty() && std::all_of(runs.begin(), runs.end(), [](auto* r) { return r->has_timestamps; });
  const std::string y = runs.empty() ? "error" : error_name(*runs.front());
  Plot plot(runs.size() == 1 ? runs.front()->title : y + " over " + (timed ? "time" : "index"),
            timed ? "time [s]" : "index", y);
  plot.set_y_from_zero(true);
  if (runs.size() == 1) {
    const EvalRunData& r = *runs.front();
    plot.add_band(r.stats.mean - r.stats.std, r.stats.mean + r.stats.std, "std", Rgb{120, 120, 120}, 0.12);
  }
  for (std::size_t k = 0; k < runs.size(); ++k) {
    Plot::Series s;
    s.label = runs[k]->label;
    s.x = relative_time(*runs[k]);
    s.y = runs[k]->error;
    s.color = palette(k);
    s.width = runs.size() == 1 ? 1.3 : 1.2;
    s.opacity = runs.size() == 1 ? 1.0 : 0.85;
    plot.add_series(std::move(s));
  }
  if (runs.size() == 1) {
    const EvalRunData& r = *runs.front();
    plot.add_hline(r.stats.rmse, "rmse", Rgb{214, 39, 40}, "");
    plot.add_hline(r.stats.median, "median", Rgb{44, 160, 44}, "6 4");
    plot.add_hline(r.stats.mean, "mean", Rgb{148, 103, 189}, "2 3");
  }
  return plot.render(width, height);
}

SvgWriter plot_error_along_path(const EvalRunData& run, double width, double height) {
  const std::array<int, 2> ax = view_axes(run.ref_xyz, TrajectoryView::kTop);
  Plot plot(error_name(run) + " along the path: " + run.label, axis_label(ax[0]), axis_label(ax[1]));
  plot.set_equal_aspect(true);
  plot.add_series(path_series(run.ref_xyz, ax, "reference", Rgb{160, 160, 160}, 1.3, "5 4"));
  // Points at which errors are defined, in path order, coloured by their error.
  std::vector<double> x, y, v;
  for (std::size_t k = 0; k < run.index.size(); ++k) {
    const Eigen::Vector3d& p = run.est_xyz[run.index[k]];
    x.push_back(p(ax[0]));
    y.push_back(p(ax[1]));
    v.push_back(run.error[k]);
  }
  plot.add_colored_path(std::move(x), std::move(y), std::move(v), error_name(run));
  return plot.render(width, height);
}

SvgWriter plot_error_histogram(const std::vector<const EvalRunData*>& runs, double width, double height) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  std::size_t n_max = 0;
  for (const auto* r : runs) {
    for (double e : r->error)
      if (std::isfinite(e)) lo = std::min(lo, e), hi = std::max(hi, e);
    n_max = std::max(n_max, r->error.size());
  }
  const std::string x = runs.empty() ? "error" : error_name(*runs.front());
  Plot plot("Distribution of " + (runs.empty() ? std::string("errors") : runs.front()->kind == "ate" ? "APE" : "RPE"),
            x, "pairs");
  const int bins = std::clamp(static_cast<int>(std::sqrt(static_cast<double>(n_max))), 8, 60);
  lo = std::min(lo, 0.0);
  for (std::size_t k = 0; k < runs.size(); ++k)
    plot.add_histogram(make_histogram(runs[k]->error, bins, lo, hi), runs[k]->label, palette(k),
                       runs.size() == 1 ? 0.75 : 0.45);
  return plot.render(width, height);
}

SvgWriter eval_figure(const EvalRunData& run) {
  const double w = 1200, cell = 600;
  const double header = 64, h1 = 470, h2 = 330;
  SvgWriter svg(w, header + 2 * h1 + h2);
  svg.rect(0, 0, svg.width(), svg.height(), "#ffffff");
  svg.text(16, 26, run.title, {15.0, "start", "#111111", true, 0.0});
  std::string line = run.label + " vs " + run.reference + " · pairs " + std::to_string(run.stats.count) +
                     " · rmse " + fmt_stat(run.stats.rmse) + " · mean " + fmt_stat(run.stats.mean) + " · median " +
                     fmt_stat(run.stats.median) + " · std " + fmt_stat(run.stats.std) + " · min " +
                     fmt_stat(run.stats.min) + " · max " + fmt_stat(run.stats.max) +
                     (run.unit.empty() ? "" : " " + run.unit);
  if (run.align == "sim3" || run.align == "scale") line += " · scale " + fmt_stat(run.scale);
  svg.text(16, 48, line, {12.0, "start", "#333333", false, 0.0});
  const std::vector<const EvalRunData*> one = {&run};
  svg.embed(plot_trajectories(one, TrajectoryView::kTop, cell, h1), 0, header);
  svg.embed(plot_error_along_path(run, cell, h1), cell, header);
  svg.embed(plot_trajectories(one, TrajectoryView::kSide, cell, h1), 0, header + h1);
  svg.embed(plot_error_histogram(one, cell, h1), cell, header + h1);
  svg.embed(plot_error_over_time(one, w, h2), 0, header + 2 * h1);
  return svg;
}

}  // namespace slamkit
