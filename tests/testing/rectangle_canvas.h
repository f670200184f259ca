// A test texture of random filled rectangles (real corners) on a grey ground, sampled at integer
// pixels or bilinearly at any point (coordinates clamped to the canvas). Used by the front-end
// tests that build image pairs whose true matches are known.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace slamkit::testing {

struct RectangleCanvas {
  int size;
  std::vector<double> value;
  /// n rectangles of side 5..max_side with amplitudes in ±60 on a size × size canvas of 128.
  RectangleCanvas(int n, int s, unsigned seed, int max_side = 26) : size(s), value(std::size_t(s) * s, 128.0) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> pos(0, s - 1), side(5, max_side), a(-60, 60);
    for (int r = 0; r < n; ++r) {
      const int x0 = pos(rng), y0 = pos(rng), w = side(rng), h = side(rng), amp = a(rng);
      for (int y = y0; y < std::min(s, y0 + h); ++y)
        for (int x = x0; x < std::min(s, x0 + w); ++x) value[std::size_t(y) * s + x] += amp;
    }
  }
  double at(int x, int y) const { return value[std::size_t(std::clamp(y, 0, size - 1)) * size + std::clamp(x, 0, size - 1)]; }
  double sample(double x, double y) const {
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const double fx = x - x0, fy = y - y0;
    return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
  }
  /// A value as an 8-bit grey level (rounded, clamped to 0..255).
  static std::uint8_t gray(double v) { return static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L)); }
};

}  // namespace slamkit::testing
