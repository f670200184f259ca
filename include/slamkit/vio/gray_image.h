// Plain image buffers of the vio front end, so that users of slamkit need no OpenCV headers
// (OpenCV is linked privately by slamkit_vio; the .cpp files wrap these buffers in cv::Mat
// without copying).
//   GrayImage   8-bit, one channel, row-major: pixel (x, y) at pixels[y·width + x] (sim/gray_image.h).
//   ColorImage  8-bit, three channels in B, G, R order (OpenCV's), row-major, interleaved.
//   LabelImage  16-bit per-pixel labels of a rendered frame: 0 static, > 0 the id of a moving object.
// Invariant: pixels.size() == width · height · channels.
#pragma once

#include <cstdint>
#include <vector>

#include "slamkit/sim/gray_image.h"  // GrayImage, shared with the image renderer

namespace slamkit {

struct ColorImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  ///< B, G, R per pixel
  ColorImage() = default;
  ColorImage(int w, int h) : width(w), height(h), pixels(std::size_t(w) * h * 3, 0) {}
  bool empty() const { return width <= 0 || height <= 0; }
};

struct LabelImage {
  int width = 0, height = 0;
  std::vector<std::uint16_t> labels;
  LabelImage() = default;
  LabelImage(int w, int h) : width(w), height(h), labels(std::size_t(w) * h, 0) {}
  std::uint16_t& at(int x, int y) { return labels[std::size_t(y) * width + x]; }
  std::uint16_t at(int x, int y) const { return labels[std::size_t(y) * width + x]; }
};

}  // namespace slamkit
