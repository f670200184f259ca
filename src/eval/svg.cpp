#include "slamkit/eval/svg.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace slamkit {

namespace {

/// One decimal, no trailing ".0", never "-0".
std::string num(double v) {
  if (!std::isfinite(v)) v = 0.0;
  char buf[32];
  const double r = std::round(v * 10.0) / 10.0;
  if (r == std::floor(r)) std::snprintf(buf, sizeof buf, "%.0f", r == 0.0 ? 0.0 : r);
  else std::snprintf(buf, sizeof buf, "%.1f", r);
  return buf;
}

/// Up to two decimals, trailing zeros trimmed (stroke widths, opacities).
std::string fine(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", std::isfinite(v) ? v : 0.0);
  std::string s(buf);
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

std::string stroke_attrs(const SvgWriter::Stroke& s) {
  std::string a = " stroke=\"" + xml_escape(s.color) + "\" stroke-width=\"" + fine(s.width) + "\"";
  if (!s.dash.empty()) a += " stroke-dasharray=\"" + xml_escape(s.dash) + "\"";
  if (s.opacity < 1.0) a += " stroke-opacity=\"" + fine(s.opacity) + "\"";
  return a;
}

}  // namespace

std::string Rgb::hex() const {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", r, g, b);
  return buf;
}

Rgb viridis(double t) {
  // Anchors of matplotlib's viridis at t = 0, 1/8, …, 1.
  static constexpr std::array<std::array<int, 3>, 9> kAnchors = {{{68, 1, 84},
                                                                  {71, 44, 122},
                                                                  {59, 81, 139},
                                                                  {44, 113, 142},
                                                                  {33, 144, 141},
                                                                  {39, 173, 129},
                                                                  {92, 200, 99},
                                                                  {170, 220, 50},
                                                                  {253, 231, 37}}};
  if (!std::isfinite(t)) t = 0.0;
  t = std::clamp(t, 0.0, 1.0) * 8.0;
  const int k = std::min(7, static_cast<int>(t));
  const double f = t - k;
  Rgb c;
  auto mix = [&](int ch) {
    return static_cast<unsigned char>(std::lround(kAnchors[k][ch] + f * (kAnchors[k + 1][ch] - kAnchors[k][ch])));
  };
  c.r = mix(0);
  c.g = mix(1);
  c.b = mix(2);
  return c;
}

Rgb palette(std::size_t k) {
  static constexpr std::array<std::array<unsigned char, 3>, 10> kColors = {{{31, 119, 180},
                                                                            {255, 127, 14},
                                                                            {44, 160, 44},
                                                                            {214, 39, 40},
                                                                            {148, 103, 189},
                                                                            {140, 86, 75},
                                                                            {227, 119, 194},
                                                                            {127, 127, 127},
                                                                            {188, 189, 34},
                                                                            {23, 190, 207}}};
  const auto& c = kColors[k % kColors.size()];
  return Rgb{c[0], c[1], c[2]};
}

std::string xml_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    switch (ch) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += ch;
    }
  }
  return out;
}

SvgWriter::SvgWriter(double width, double height) : width_(width), height_(height) {}

void SvgWriter::rect(double x, double y, double w, double h, std::string_view fill, const Stroke* stroke,
                     double fill_opacity) {
  body_ += "<rect x=\"" + num(x) + "\" y=\"" + num(y) + "\" width=\"" + num(std::max(0.0, w)) + "\" height=\"" +
           num(std::max(0.0, h)) + "\" fill=\"" + xml_escape(fill) + "\"";
  if (fill_opacity < 1.0) body_ += " fill-opacity=\"" + fine(fill_opacity) + "\"";
  if (stroke) body_ += stroke_attrs(*stroke);
  body_ += "/>\n";
}

void SvgWriter::line(double x1, double y1, double x2, double y2, const Stroke& stroke) {
  body_ += "<line x1=\"" + num(x1) + "\" y1=\"" + num(y1) + "\" x2=\"" + num(x2) + "\" y2=\"" + num(y2) + "\"" +
           stroke_attrs(stroke) + "/>\n";
}

void SvgWriter::polyline(const std::vector<Point2>& points, const Stroke& stroke, double min_step) {
  if (points.size() < 2) return;
  std::string pts;
  pts.reserve(points.size() * 12);
  Point2 last = points.front();
  pts += num(last.first) + "," + num(last.second);
  for (std::size_t k = 1; k < points.size(); ++k) {
    const Point2& p = points[k];
    const bool final_point = k + 1 == points.size();
    if (!final_point && std::hypot(p.first - last.first, p.second - last.second) < min_step) continue;
    pts += " " + num(p.first) + "," + num(p.second);
    last = p;
  }
  body_ += "<polyline fill=\"none\" stroke-linejoin=\"round\" stroke-linecap=\"round\"" + stroke_attrs(stroke) +
           " points=\"" + pts + "\"/>\n";
}

void SvgWriter::circle(double cx, double cy, double r, std::string_view fill, const Stroke* stroke) {
  body_ += "<circle cx=\"" + num(cx) + "\" cy=\"" + num(cy) + "\" r=\"" + num(r) + "\" fill=\"" + xml_escape(fill) +
           "\"" + (stroke ? stroke_attrs(*stroke) : std::string()) + "/>\n";
}

void SvgWriter::text(double x, double y, std::string_view content, const Text& style) {
  body_ += "<text x=\"" + num(x) + "\" y=\"" + num(y) + "\" font-size=\"" + num(style.size) + "\" text-anchor=\"" +
           xml_escape(style.anchor) + "\" fill=\"" + xml_escape(style.color) + "\"";
  if (style.bold) body_ += " font-weight=\"bold\"";
  if (style.rotate != 0.0) body_ += " transform=\"rotate(" + num(style.rotate) + " " + num(x) + " " + num(y) + ")\"";
  body_ += ">" + xml_escape(content) + "</text>\n";
}

void SvgWriter::embed(const SvgWriter& child, double x, double y) {
  std::string doc = child.str();
  // Turn the child's root element into a positioned nested <svg> (drop its xmlns).
  const std::string root = "<svg xmlns=\"http://www.w3.org/2000/svg\"";
  if (doc.compare(0, root.size(), root) == 0)
    doc = "<svg x=\"" + num(x) + "\" y=\"" + num(y) + "\"" + doc.substr(root.size());
  body_ += doc;
}

void SvgWriter::begin_group(std::string_view css_class) {
  body_ += "<g class=\"" + xml_escape(css_class) + "\">\n";
  ++open_groups_;
}

void SvgWriter::end_group() {
  if (open_groups_ == 0) return;
  body_ += "</g>\n";
  --open_groups_;
}

std::string SvgWriter::str() const {
  std::string out = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + num(width_) + "\" height=\"" +
                    num(height_) + "\" viewBox=\"0 0 " + num(width_) + " " + num(height_) +
                    "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n";
  out += body_;
  for (int k = 0; k < open_groups_; ++k) out += "</g>\n";
  out += "</svg>\n";
  return out;
}

}  // namespace slamkit
