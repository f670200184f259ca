// Plot: a 2-D chart rendered to SVG — axes with "nice" ticks (1, 2, 5 × 10^k; decades on a
// log axis), grid, title, axis labels, a legend strip above the plot area (it never hides
// data), line series, horizontal reference lines and bands, histograms, markers, and a path
// colour-coded by a value with a colour bar (viridis). Equal-aspect mode keeps metres equal
// on both axes for trajectory views. Non-finite points (and non-positive ones on a log axis)
// split lines instead of being drawn. Value type; render() is const and thread-safe.
//
// BarChart: horizontal grouped bars for comparing a few statistics across runs.
#pragma once

#include <string>
#include <vector>

#include "slamkit/eval/svg.h"

namespace slamkit {

/// Bin edges (n_bins + 1) and counts (n_bins) of values over [min, max] (empty input: empty).
struct Histogram {
  std::vector<double> edges;
  std::vector<double> counts;
};
Histogram make_histogram(const std::vector<double>& values, int n_bins, double lo, double hi);

class Plot {
 public:
  struct Series {
    std::string label;  ///< empty: not in the legend
    std::vector<double> x, y;
    Rgb color;
    double width = 1.5;
    std::string dash;
    double opacity = 1.0;
    bool points = false;  ///< also mark every data point (for short series)
  };

  Plot(std::string title, std::string x_label, std::string y_label);

  void set_log_y(bool on) { log_y_ = on; }
  /// Logarithmic x axis (decade ticks); points with x ≤ 0 are left out.
  void set_log_x(bool on) { log_x_ = on; }
  void set_equal_aspect(bool on) { equal_aspect_ = on; }
  /// Include y = 0 in the range (for error magnitudes).
  void set_y_from_zero(bool on) { y_from_zero_ = on; }

  void add_series(Series s) { series_.push_back(std::move(s)); }
  void add_hline(double y, std::string label, Rgb color, std::string dash = "6 4");
  void add_band(double y0, double y1, std::string label, Rgb color, double opacity = 0.15);
  /// Path (x, y) whose segment k → k+1 is coloured by values[k+1] on [min, max] of values.
  void add_colored_path(std::vector<double> x, std::vector<double> y, std::vector<double> values,
                        std::string colorbar_label);
  void add_histogram(const Histogram& h, std::string label, Rgb color, double opacity = 0.55);
  void add_marker(double x, double y, std::string label, Rgb color);

  SvgWriter render(double width, double height) const;

 private:
  struct HLine {
    double y;
    std::string label;
    Rgb color;
    std::string dash;
  };
  struct Band {
    double y0, y1;
    std::string label;
    Rgb color;
    double opacity;
  };
  struct ColoredPath {
    std::vector<double> x, y, values;
    std::string label;
  };
  struct Bars {
    Histogram h;
    std::string label;
    Rgb color;
    double opacity;
  };
  struct Marker {
    double x, y;
    std::string label;
    Rgb color;
  };
  struct Frame;  // pixel mapping, defined in plot.cpp

  std::string title_, x_label_, y_label_;
  bool log_y_ = false, log_x_ = false, equal_aspect_ = false, y_from_zero_ = false;
  std::vector<Series> series_;
  std::vector<HLine> hlines_;
  std::vector<Band> bands_;
  std::vector<ColoredPath> paths_;
  std::vector<Bars> bars_;
  std::vector<Marker> markers_;
};

class BarChart {
 public:
  /// groups: one per category (e.g. a run); series: one per statistic (e.g. rmse, mean).
  BarChart(std::string title, std::string value_label, std::vector<std::string> categories,
           std::vector<std::string> series_labels);
  /// values[category][series]
  void set_values(std::vector<std::vector<double>> values) { values_ = std::move(values); }
  /// Colour each category (e.g. with its run's colour); the series then differ in lightness
  /// and are named next to their values instead of in a legend.
  void set_category_colors(std::vector<Rgb> colors) { category_colors_ = std::move(colors); }
  /// The height follows from the number of categories; bars thicken to fill min_height.
  SvgWriter render(double width, double min_height = 0.0) const;

 private:
  std::string title_, value_label_;
  std::vector<std::string> categories_, series_labels_;
  std::vector<std::vector<double>> values_;
  std::vector<Rgb> category_colors_;
};

/// Tick positions covering [lo, hi] with about `target` steps of 1, 2 or 5 × 10^k.
std::vector<double> nice_ticks(double lo, double hi, int target);
/// Tick label for a value on a linear axis with the given tick step.
std::string tick_label(double v, double step);

}  // namespace slamkit
