// GrayImage as an OpenCV matrix, for the vio sources that call OpenCV (private: the public headers
// stay free of OpenCV).
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>

#include "slamkit/vio/gray_image.h"

namespace slamkit {

/// A view of the pixels, no copy; OpenCV only reads it.
inline cv::Mat wrap(const GrayImage& image) {
  return cv::Mat(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.pixels.data()));
}

/// Non-empty, with width × height pixels.
inline bool valid(const GrayImage& g) { return !g.empty() && g.pixels.size() == std::size_t(g.width) * g.height; }

}  // namespace slamkit
