#include "slamkit/eval/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace slamkit {

namespace {

constexpr double kTitleSize = 13.0;
constexpr double kLabelSize = 11.5;
constexpr double kTickSize = 10.5;
constexpr double kLegendSize = 11.0;
constexpr double kCharWidth = 0.61;  // average glyph width of DejaVu Sans, in em
constexpr int kColorLevels = 48;     // quantization of colour-coded paths
const char* kAxisColor = "#444444";
const char* kGridColor = "#e6e6e6";

double text_width(const std::string& s, double size) { return kCharWidth * size * static_cast<double>(s.size()); }

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool valid() const { return lo <= hi; }
};

std::string compact_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  std::string s(buf);
  for (const char* from : {"e-0", "e+0", "e+"}) {
    const std::size_t p = s.find(from);
    if (p != std::string::npos) s.replace(p, std::string(from).size(), from[1] == '-' ? "e-" : "e");
  }
  return s;
}

}  // namespace

// ---- ticks and histograms --------------------------------------------------------------

std::vector<double> nice_ticks(double lo, double hi, int target) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi) || target < 1) return ticks;
  const double raw = (hi - lo) / target;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  const double m = norm < 1.5 ? 1.0 : norm < 3.0 ? 2.0 : norm < 7.0 ? 5.0 : 10.0;
  const double step = m * mag;
  // k · m / 10^e (one rounding) gives 0.6, not 0.6000000000000001, for decimal steps.
  const double inv = mag < 1.0 ? std::round(1.0 / mag) : 0.0;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1.0)
    ticks.push_back(k == 0.0 ? 0.0 : inv > 0.0 ? (k * m) / inv : k * step);
  return ticks;
}

std::string tick_label(double v, double step) {
  if (std::abs(v) >= 1e6 || (std::abs(v) > 0 && std::abs(v) < 1e-4)) return compact_number(v);
  const int decimals = step > 0 ? std::clamp(static_cast<int>(-std::floor(std::log10(step) + 1e-9)), 0, 8) : 0;
  if (std::abs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0.0;  // no "-0.0"
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

Histogram make_histogram(const std::vector<double>& values, int n_bins, double lo, double hi) {
  Histogram h;
  if (values.empty() || n_bins < 1 || !std::isfinite(lo) || !std::isfinite(hi)) return h;
  if (!(hi > lo)) {
    lo -= 0.5;
    hi += 0.5;
  }
  const double w = (hi - lo) / n_bins;
  for (int k = 0; k <= n_bins; ++k) h.edges.push_back(lo + k * w);
  h.counts.assign(static_cast<std::size_t>(n_bins), 0.0);
  for (double v : values) {
    if (!std::isfinite(v) || v < lo || v > hi) continue;
    const int k = std::min(n_bins - 1, static_cast<int>((v - lo) / w));
    h.counts[static_cast<std::size_t>(k)] += 1.0;
  }
  return h;
}

// ---- Plot ------------------------------------------------------------------------------

struct Plot::Frame {
  double left, top, width, height;  // plot area in pixels
  double x0, x1, y0, y1;            // data range (in log10 units on a log axis)
  bool log_y, log_x = false;
  bool has_y(double y) const { return std::isfinite(y) && (!log_y || y > 0.0); }
  bool has_x(double x) const { return std::isfinite(x) && (!log_x || x > 0.0); }
  double px(double x) const { return left + ((log_x ? std::log10(x) : x) - x0) / (x1 - x0) * width; }
  double py(double y) const { return top + height - ((log_y ? std::log10(y) : y) - y0) / (y1 - y0) * height; }
};

Plot::Plot(std::string title, std::string x_label, std::string y_label)
    : title_(std::move(title)), x_label_(std::move(x_label)), y_label_(std::move(y_label)) {}

void Plot::add_hline(double y, std::string label, Rgb color, std::string dash) {
  hlines_.push_back({y, std::move(label), color, std::move(dash)});
}

void Plot::add_band(double y0, double y1, std::string label, Rgb color, double opacity) {
  bands_.push_back({y0, y1, std::move(label), color, opacity});
}

void Plot::add_colored_path(std::vector<double> x, std::vector<double> y, std::vector<double> values,
                            std::string colorbar_label) {
  paths_.push_back({std::move(x), std::move(y), std::move(values), std::move(colorbar_label)});
}

void Plot::add_histogram(const Histogram& h, std::string label, Rgb color, double opacity) {
  bars_.push_back({h, std::move(label), color, opacity});
}

void Plot::add_marker(double x, double y, std::string label, Rgb color) {
  markers_.push_back({x, y, std::move(label), color});
}

SvgWriter Plot::render(double width, double height) const {
  SvgWriter svg(width, height);
  svg.rect(0, 0, width, height, "#ffffff");

  // Legend entries: (label, colour, dash, kind) with kind 0 line, 1 box, 2 dot.
  struct Entry {
    std::string label;
    std::string color;
    std::string dash;
    int kind;
    double opacity;
  };
  std::vector<Entry> legend;
  for (const auto& b : bands_) if (!b.label.empty()) legend.push_back({b.label, b.color.hex(), "", 1, b.opacity * 2});
  for (const auto& b : bars_) if (!b.label.empty()) legend.push_back({b.label, b.color.hex(), "", 1, b.opacity});
  for (const auto& s : series_) if (!s.label.empty()) legend.push_back({s.label, s.color.hex(), s.dash, 0, s.opacity});
  for (const auto& h : hlines_) if (!h.label.empty()) legend.push_back({h.label, h.color.hex(), h.dash, 0, 1.0});
  for (const auto& m : markers_) if (!m.label.empty()) legend.push_back({m.label, m.color.hex(), "", 2, 1.0});

  const bool colorbar = !paths_.empty();
  const double left = 64, right = 18 + (colorbar ? 78 : 0), bottom = 44;
  const double legend_width = width - left - right;
  std::vector<std::vector<std::pair<const Entry*, double>>> rows(1);  // entry, x offset
  double cursor = 0.0;
  for (const auto& e : legend) {
    const double w = 30.0 + text_width(e.label, kLegendSize) + 16.0;
    if (cursor > 0.0 && cursor + w > legend_width) {
      rows.emplace_back();
      cursor = 0.0;
    }
    rows.back().push_back({&e, cursor});
    cursor += w;
  }
  const double legend_rows = legend.empty() ? 0 : static_cast<double>(rows.size());
  const double top = (title_.empty() ? 12.0 : 32.0) + legend_rows * 17.0 + (legend.empty() ? 0.0 : 6.0);

  Frame f{left, top, std::max(10.0, width - left - right), std::max(10.0, height - top - bottom), 0, 1, 0, 1, log_y_,
          log_x_ && bars_.empty()};

  // Data ranges.
  Range xr, yr;
  auto add_y = [&](double y) {
    if (f.has_y(y)) yr.add(log_y_ ? std::log10(y) : y);
  };
  auto add_x = [&](double x) {
    if (f.has_x(x)) xr.add(f.log_x ? std::log10(x) : x);
  };
  for (const auto& s : series_)
    for (std::size_t k = 0; k < s.x.size() && k < s.y.size(); ++k)
      if (f.has_x(s.x[k]) && f.has_y(s.y[k])) add_x(s.x[k]), add_y(s.y[k]);
  for (const auto& p : paths_)
    for (std::size_t k = 0; k < p.x.size() && k < p.y.size(); ++k)
      if (f.has_x(p.x[k]) && f.has_y(p.y[k])) add_x(p.x[k]), add_y(p.y[k]);
  for (const auto& m : markers_) add_x(m.x), add_y(m.y);
  for (const auto& b : bars_) {
    for (double e : b.h.edges) xr.add(e);
    for (double c : b.h.counts) add_y(c);
    if (!log_y_) yr.add(0.0);
  }
  for (const auto& h : hlines_) add_y(h.y);
  for (const auto& b : bands_) add_y(b.y0), add_y(b.y1);
  if (y_from_zero_ && !log_y_) yr.add(0.0);
  const bool has_data = xr.valid() && yr.valid();
  if (!xr.valid()) xr.lo = 0, xr.hi = 1;
  if (!yr.valid()) yr.lo = 0, yr.hi = 1;
  auto widen = [](Range& r) {
    if (r.hi - r.lo <= 1e-12 * std::max(1.0, std::abs(r.hi))) {
      const double d = std::max(0.5, 0.1 * std::abs(r.hi));
      r.lo -= d;
      r.hi += d;
    }
  };
  widen(xr);
  widen(yr);
  const double xpad = bars_.empty() ? 0.04 * (xr.hi - xr.lo) : 0.0;
  const double ypad = 0.05 * (yr.hi - yr.lo);
  f.x0 = xr.lo - xpad;
  f.x1 = xr.hi + xpad;
  const bool floor_at_zero = !log_y_ && yr.lo == 0.0 && (y_from_zero_ || !bars_.empty());
  f.y0 = floor_at_zero ? 0.0 : yr.lo - ypad;
  f.y1 = yr.hi + ypad;
  if (equal_aspect_) {  // same data units per pixel on both axes
    const double s = std::max((f.x1 - f.x0) / f.width, (f.y1 - f.y0) / f.height);
    const double cx = 0.5 * (f.x0 + f.x1), cy = 0.5 * (f.y0 + f.y1);
    f.x0 = cx - 0.5 * s * f.width, f.x1 = cx + 0.5 * s * f.width;
    f.y0 = cy - 0.5 * s * f.height, f.y1 = cy + 0.5 * s * f.height;
  }

  // Grid, ticks and labels.
  const SvgWriter::Stroke grid{kGridColor, 1.0, "", 1.0};
  const SvgWriter::Stroke axis{kAxisColor, 1.0, "", 1.0};
  SvgWriter::Text tick_style{kTickSize, "middle", "#333333", false, 0.0};
  svg.begin_group("grid");
  std::vector<std::pair<double, std::string>> xticks;  // (data value, label)
  if (f.log_x) {  // decades
    for (double k = std::ceil(f.x0); k <= f.x1; k += 1.0) xticks.push_back({std::pow(10.0, k), compact_number(std::pow(10.0, k))});
  } else {
    const std::vector<double> xt = nice_ticks(f.x0, f.x1, std::max(2, static_cast<int>(f.width / 90)));
    const double xstep = xt.size() > 1 ? xt[1] - xt[0] : 1.0;
    for (double v : xt) xticks.push_back({v, tick_label(v, xstep)});
  }
  for (const auto& [v, label] : xticks) {
    const double x = f.px(v);
    svg.line(x, f.top, x, f.top + f.height, grid);
    svg.line(x, f.top + f.height, x, f.top + f.height + 4, axis);
    svg.text(x, f.top + f.height + 16, label, tick_style);
  }
  std::vector<std::pair<double, std::string>> yt;  // (axis units, label)
  const int ytarget = std::max(2, static_cast<int>(f.height / 55));
  if (log_y_) {
    for (double k = std::ceil(f.y0); k <= f.y1; k += 1.0)
      yt.push_back({k, k >= -2 && k <= 3 ? compact_number(std::pow(10.0, k)) : "1e" + std::to_string(static_cast<int>(k))});
    if (yt.size() < 2) {
      yt.clear();
      const std::vector<double> lin = nice_ticks(std::pow(10.0, f.y0), std::pow(10.0, f.y1), ytarget);
      for (double v : lin)
        if (v > 0) yt.push_back({std::log10(v), compact_number(v)});
    }
  } else {
    const std::vector<double> lin = nice_ticks(f.y0, f.y1, ytarget);
    const double ystep = lin.size() > 1 ? lin[1] - lin[0] : 1.0;
    for (double v : lin) yt.push_back({v, tick_label(v, ystep)});
  }
  tick_style.anchor = "end";
  for (const auto& [v, label] : yt) {
    const double y = f.top + f.height - (v - f.y0) / (f.y1 - f.y0) * f.height;
    svg.line(f.left, y, f.left + f.width, y, grid);
    svg.line(f.left - 4, y, f.left, y, axis);
    svg.text(f.left - 7, y + 3.5, label, tick_style);
  }
  svg.end_group();

  // Data.
  svg.begin_group("data");
  for (const auto& b : bands_) {
    if (!f.has_y(b.y0) || !f.has_y(b.y1)) continue;
    const double ya = std::clamp(f.py(std::max(b.y0, b.y1)), f.top, f.top + f.height);
    const double yb = std::clamp(f.py(std::min(b.y0, b.y1)), f.top, f.top + f.height);
    svg.rect(f.left, ya, f.width, yb - ya, b.color.hex(), nullptr, b.opacity);
  }
  for (const auto& b : bars_) {
    for (std::size_t k = 0; k < b.h.counts.size(); ++k) {
      if (!f.has_y(b.h.counts[k]) || b.h.counts[k] == 0.0) continue;
      const double x0 = f.px(b.h.edges[k]), x1 = f.px(b.h.edges[k + 1]);
      const double y = f.py(b.h.counts[k]);
      const double base = log_y_ ? f.top + f.height : f.py(0.0);
      SvgWriter::Stroke edge{b.color.hex(), 0.8, "", 1.0};
      svg.rect(x0, y, x1 - x0, base - y, b.color.hex(), &edge, b.opacity);
    }
  }
  auto draw_runs = [&](const std::vector<double>& x, const std::vector<double>& y, const SvgWriter::Stroke& st) {
    std::vector<Point2> run;
    auto flush = [&]() {
      if (run.size() == 1) svg.circle(run[0].first, run[0].second, st.width, st.color);
      if (run.size() >= 2) svg.polyline(run, st);
      run.clear();
    };
    for (std::size_t k = 0; k < std::min(x.size(), y.size()); ++k) {
      if (f.has_x(x[k]) && f.has_y(y[k])) run.push_back({f.px(x[k]), f.py(y[k])});
      else flush();
    }
    flush();
  };
  for (const auto& s : series_) {
    draw_runs(s.x, s.y, SvgWriter::Stroke{s.color.hex(), s.width, s.dash, s.opacity});
    if (!s.points) continue;
    for (std::size_t k = 0; k < std::min(s.x.size(), s.y.size()); ++k)
      if (f.has_x(s.x[k]) && f.has_y(s.y[k])) svg.circle(f.px(s.x[k]), f.py(s.y[k]), s.width + 1.2, s.color.hex());
  }
  double vmin = 0.0, vmax = 1.0;
  std::string colorbar_label;
  for (const auto& p : paths_) {
    Range vr;
    for (double v : p.values) vr.add(v);
    if (!vr.valid()) continue;
    vmin = vr.lo, vmax = vr.hi > vr.lo ? vr.hi : vr.lo + 1.0;
    colorbar_label = p.label;
    // Merge consecutive segments of the same colour level into one polyline.
    const std::size_t n = std::min({p.x.size(), p.y.size(), p.values.size()});
    int level = -1;
    std::vector<Point2> run;
    auto flush = [&]() {
      if (run.size() >= 2)
        svg.polyline(run, SvgWriter::Stroke{viridis((level + 0.5) / kColorLevels).hex(), 2.2, "", 1.0}, 0.8);
      run.clear();
    };
    for (std::size_t k = 1; k < n; ++k) {
      const bool ok = f.has_x(p.x[k - 1]) && f.has_x(p.x[k]) && f.has_y(p.y[k - 1]) && f.has_y(p.y[k]) &&
                      std::isfinite(p.values[k]);
      if (!ok) {
        flush();
        continue;
      }
      const int lv = std::clamp(static_cast<int>((p.values[k] - vmin) / (vmax - vmin) * kColorLevels), 0, kColorLevels - 1);
      if (lv != level) {
        const Point2 joint = run.empty() ? Point2{f.px(p.x[k - 1]), f.py(p.y[k - 1])} : run.back();
        flush();
        level = lv;
        run.push_back(joint);
      }
      run.push_back({f.px(p.x[k]), f.py(p.y[k])});
    }
    flush();
  }
  for (const auto& h : hlines_) {
    if (!f.has_y(h.y)) continue;
    svg.line(f.left, f.py(h.y), f.left + f.width, f.py(h.y), SvgWriter::Stroke{h.color.hex(), 1.4, h.dash, 1.0});
  }
  const SvgWriter::Stroke halo{"#ffffff", 1.5, "", 1.0};
  for (const auto& m : markers_)
    if (f.has_x(m.x) && f.has_y(m.y)) svg.circle(f.px(m.x), f.py(m.y), 4.5, m.color.hex(), &halo);
  svg.end_group();

  // Frame, title, axis labels, legend.
  svg.rect(f.left, f.top, f.width, f.height, "none", &axis);
  if (!has_data) svg.text(f.left + f.width / 2, f.top + f.height / 2, "no data", {kLabelSize, "middle", "#888888", false, 0});
  if (!title_.empty()) svg.text(f.left, 20, title_, {kTitleSize, "start", "#111111", true, 0.0});
  svg.text(f.left + f.width / 2, height - 8, x_label_, {kLabelSize, "middle", "#222222", false, 0.0});
  svg.text(15, f.top + f.height / 2, y_label_, {kLabelSize, "middle", "#222222", false, -90.0});
  svg.begin_group("legend");
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const double y = (title_.empty() ? 12.0 : 32.0) + 17.0 * static_cast<double>(r) + 6.0;
    for (const auto& [e, dx] : rows[r]) {
      const double x = f.left + dx;
      if (e->kind == 0) svg.line(x, y, x + 24, y, SvgWriter::Stroke{e->color, 2.2, e->dash, e->opacity});
      if (e->kind == 1) svg.rect(x + 4, y - 5.5, 16, 11, e->color, nullptr, std::min(1.0, e->opacity));
      if (e->kind == 2) svg.circle(x + 12, y, 4.5, e->color, &halo);
      svg.text(x + 30, y + 4, e->label, {kLegendSize, "start", "#222222", false, 0.0});
    }
  }
  svg.end_group();

  if (colorbar) {
    svg.begin_group("colorbar");
    const double bx = f.left + f.width + 18, bw = 14, by = f.top, bh = f.height;
    for (int k = 0; k < kColorLevels; ++k) {
      const double y = by + bh - (k + 1) * bh / kColorLevels;
      svg.rect(bx, y, bw, bh / kColorLevels + 0.6, viridis((k + 0.5) / kColorLevels).hex());
    }
    svg.rect(bx, by, bw, bh, "none", &axis);
    const std::vector<double> ct = nice_ticks(vmin, vmax, 5);
    const double cstep = ct.size() > 1 ? ct[1] - ct[0] : 1.0;
    for (double v : ct) {
      const double y = by + bh - (v - vmin) / (vmax - vmin) * bh;
      svg.line(bx + bw, y, bx + bw + 4, y, axis);
      svg.text(bx + bw + 7, y + 3.5, tick_label(v, cstep), {kTickSize, "start", "#333333", false, 0.0});
    }
    svg.text(width - 8, by + bh / 2, colorbar_label, {kLabelSize, "middle", "#222222", false, -90.0});
    svg.end_group();
  }
  return svg;
}

// ---- BarChart --------------------------------------------------------------------------

BarChart::BarChart(std::string title, std::string value_label, std::vector<std::string> categories,
                   std::vector<std::string> series_labels)
    : title_(std::move(title)),
      value_label_(std::move(value_label)),
      categories_(std::move(categories)),
      series_labels_(std::move(series_labels)) {}

SvgWriter BarChart::render(double width, double min_height) const {
  const double gap = 3.0, group_gap = 12.0, bottom = 40.0;
  const double header = category_colors_.empty() ? 56.0 : 34.0;  // title (+ legend)
  const std::size_t ns = std::max<std::size_t>(1, series_labels_.size());
  const double nc = static_cast<double>(std::max<std::size_t>(1, categories_.size()));
  // Bar thickness: 13 px, or thicker (up to 24 px) to fill min_height; the rest centres the bars.
  const double fill = ((min_height - header - bottom - group_gap) / nc - group_gap + gap) / static_cast<double>(ns) - gap;
  const double bar = std::clamp(fill, 13.0, 24.0);
  const double group_h = static_cast<double>(ns) * (bar + gap) - gap;
  double label_w = 40.0;
  for (const auto& c : categories_) label_w = std::max(label_w, text_width(c, kTickSize) + 12.0);
  const double left = std::min(label_w, 0.4 * width), right = category_colors_.empty() ? 64.0 : 96.0;
  const double plot_h = static_cast<double>(categories_.size()) * (group_h + group_gap) + group_gap;
  const double height = std::max(min_height, header + plot_h + bottom);
  const double top = header + 0.5 * (height - (header + plot_h + bottom));
  SvgWriter svg(width, height);
  svg.rect(0, 0, width, height, "#ffffff");
  double vmax = 0.0;
  for (const auto& row : values_)
    for (double v : row)
      if (std::isfinite(v)) vmax = std::max(vmax, v);
  if (vmax <= 0.0) vmax = 1.0;
  const std::vector<double> ticks = nice_ticks(0.0, vmax * 1.05, 5);
  const double xmax = ticks.empty() ? vmax : std::max(vmax, ticks.back());
  const double pw = width - left - right;
  auto px = [&](double v) { return left + v / xmax * pw; };
  const SvgWriter::Stroke grid{kGridColor, 1.0, "", 1.0}, axis{kAxisColor, 1.0, "", 1.0};
  const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : 1.0;
  for (double v : ticks) {
    svg.line(px(v), top, px(v), top + plot_h, grid);
    svg.text(px(v), top + plot_h + 16, tick_label(v, step), {kTickSize, "middle", "#333333", false, 0.0});
  }
  svg.begin_group("bars");
  for (std::size_t c = 0; c < categories_.size(); ++c) {
    const double gy = top + group_gap + static_cast<double>(c) * (group_h + group_gap);
    std::string name = categories_[c];
    const std::size_t max_chars = static_cast<std::size_t>(std::max(4.0, (left - 12.0) / (kCharWidth * kTickSize)));
    if (name.size() > max_chars) name = name.substr(0, max_chars - 1) + "…";
    svg.text(left - 8, gy + group_h / 2 + 4, name, {kTickSize, "end", "#222222", false, 0.0});
    for (std::size_t s = 0; s < ns && c < values_.size() && s < values_[c].size(); ++s) {
      const double v = values_[c][s];
      if (!std::isfinite(v)) continue;
      const double y = gy + static_cast<double>(s) * (bar + gap);
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.4g", v);
      std::string label = buf;
      Rgb color = palette(s);
      if (c < category_colors_.size()) {  // run colour, lighter for each further series
        const double w = std::min(0.75, 0.22 * static_cast<double>(s));
        const Rgb base = category_colors_[c];
        auto tint = [w](unsigned char ch) { return static_cast<unsigned char>(std::lround(ch + w * (255 - ch))); };
        color = Rgb{tint(base.r), tint(base.g), tint(base.b)};
        if (s < series_labels_.size()) label = series_labels_[s] + " " + label;
      }
      svg.rect(left, y, px(v) - left, bar, color.hex());
      svg.text(px(v) + 4, y + bar / 2 + 3.5, label, {kTickSize - 1, "start", "#333333", false, 0.0});
    }
  }
  svg.end_group();
  svg.line(left, top, left, top + plot_h, axis);
  svg.text(left, 20, title_, {kTitleSize, "start", "#111111", true, 0.0});
  svg.text(left + pw / 2, top + plot_h + 34, value_label_, {kLabelSize, "middle", "#222222", false, 0.0});
  double x = left;
  for (std::size_t s = 0; category_colors_.empty() && s < series_labels_.size(); ++s) {
    svg.rect(x, 34, 14, 10, palette(s).hex());
    svg.text(x + 19, 43, series_labels_[s], {kLegendSize, "start", "#222222", false, 0.0});
    x += 36 + text_width(series_labels_[s], kLegendSize);
  }
  return svg;
}

}  // namespace slamkit
