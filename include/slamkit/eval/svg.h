// SvgWriter: a minimal SVG 1.1 document builder for slamkit's plots (no dependencies, no
// scripts, no external resources), plus the colours the plots use.
//
// Coordinates are user units (pixels at 100 % zoom), y pointing down. Text is XML-escaped.
// Numbers are written with one decimal, enough for screen output and compact files.
// A finished document (str()) can be saved as a .svg file or inlined into HTML as is.
// Not thread-safe; one writer per document.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace slamkit {

/// An sRGB colour.
struct Rgb {
  unsigned char r = 0, g = 0, b = 0;
  std::string hex() const;  ///< "#rrggbb"
};

/// Perceptually uniform colour map (viridis, interpolated from 9 anchors), t clamped to [0, 1].
Rgb viridis(double t);
/// k-th colour of a 10-colour categorical palette (cycled).
Rgb palette(std::size_t k);

/// Escapes & < > " ' for XML text and attribute values.
std::string xml_escape(std::string_view text);

using Point2 = std::pair<double, double>;

class SvgWriter {
 public:
  struct Stroke {
    std::string color = "#000000";
    double width = 1.0;
    std::string dash;        ///< e.g. "6 4"; empty: solid
    double opacity = 1.0;
  };
  struct Text {
    double size = 12.0;
    std::string anchor = "start";  ///< start | middle | end
    std::string color = "#222222";
    bool bold = false;
    double rotate = 0.0;  ///< degrees, about the anchor point
  };

  SvgWriter(double width, double height);

  double width() const { return width_; }
  double height() const { return height_; }

  void rect(double x, double y, double w, double h, std::string_view fill, const Stroke* stroke = nullptr,
            double fill_opacity = 1.0);
  void line(double x1, double y1, double x2, double y2, const Stroke& stroke);
  /// A polyline; points closer than min_step pixels to the previously kept one are skipped
  /// (the last point is always kept), which keeps long trajectories compact.
  void polyline(const std::vector<Point2>& points, const Stroke& stroke, double min_step = 0.5);
  void circle(double cx, double cy, double r, std::string_view fill, const Stroke* stroke = nullptr);
  void text(double x, double y, std::string_view content, const Text& style);
  /// Embeds another finished document at (x, y) as a nested <svg>.
  void embed(const SvgWriter& child, double x, double y);
  /// Opens / closes a <g> with a class attribute (for styling and tests).
  void begin_group(std::string_view css_class);
  void end_group();

  /// The complete document "<svg ...>...</svg>".
  std::string str() const;

 private:
  double width_, height_;
  std::string body_;
  int open_groups_ = 0;
};

}  // namespace slamkit
