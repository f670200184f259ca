// GrayImage: a plain 8-bit single-channel image (row-major, no padding), the exchange type
// between the image renderer (sim, no OpenCV) and PNG input/output (vio/image_io.h).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace slamkit {

struct GrayImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  ///< pixels[y * width + x]

  GrayImage() = default;
  /// Throws std::invalid_argument for a negative size.
  GrayImage(int w, int h, std::uint8_t fill = 0) : width(w), height(h) {
    if (w < 0 || h < 0) throw std::invalid_argument("GrayImage: negative size");
    pixels.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill);
  }
  bool empty() const { return pixels.empty(); }
  std::uint8_t& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  std::uint8_t at(int x, int y) const { return pixels[static_cast<std::size_t>(y) * width + x]; }
  std::uint8_t* row(int y) { return pixels.data() + static_cast<std::size_t>(y) * width; }
  const std::uint8_t* row(int y) const { return pixels.data() + static_cast<std::size_t>(y) * width; }
  bool operator==(const GrayImage& o) const { return width == o.width && height == o.height && pixels == o.pixels; }
  bool operator!=(const GrayImage& o) const { return !(*this == o); }
};

}  // namespace slamkit
