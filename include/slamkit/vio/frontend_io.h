// Image input and output of the front end (OpenCV inside slamkit_vio, plain buffers outside):
//   FrameSource   frames of a video file (cv::VideoCapture), of every image in a directory
//                 (sorted by name; .png .jpg .jpeg .bmp .pgm .ppm .tif .tiff), or of a list of
//                 image files (e.g. aloeL.jpg aloeR.jpg), as gray and colour images
//   draw_features the features of a frame on its colour image: a circle per feature, green
//                 (static), red (dynamic), orange (isolated flag) or yellow (unknown), and its flow
//   write_png, VideoFileWriter (AVI, MJPG)
// Every failure (unreadable file, frames of different sizes, unwritable output) throws
// InputError naming the file.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/feature_tracker.h"
#include "slamkit/vio/gray_image.h"

namespace slamkit {

class FrameSource {
 public:
  /// One video file, one directory of images, or one or more image files.
  explicit FrameSource(const std::vector<std::string>& inputs);
  ~FrameSource();
  FrameSource(FrameSource&&) noexcept;
  /// The next frame; false at the end. Throws InputError on an unreadable image or a size change.
  bool next(GrayImage* gray, ColorImage* color);
  bool is_video() const;
  double fps() const;          ///< of the video (10 if it does not say), 0 for images
  int frame_count() const;     ///< known count (a video's may be an estimate), -1 if unknown
  std::string frame_name(int index) const;  ///< "frame_000012" or the image file's stem
  const std::string& description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A gray image from a file (e.g. a mask). Throws InputError if it cannot be read.
GrayImage read_gray_image(const std::string& path);

/// Draws the features (flags: one per feature, or empty = all unknown) onto image.
/// isolated (optional, indexed like flags): isolated dynamic flags (dynamic_groups.h), drawn orange.
void draw_features(ColorImage* image, const std::vector<TrackedFeature>& features, const std::vector<FeatureMotion>& flags,
                   const std::vector<char>* isolated = nullptr);

/// Writes a PNG; throws InputError if it cannot.
void write_png(const std::string& path, const ColorImage& image);

class VideoFileWriter {
 public:
  /// An AVI with the MJPG codec. Throws InputError if it cannot be opened.
  VideoFileWriter(const std::string& path, int width, int height, double fps);
  ~VideoFileWriter();
  void write(const ColorImage& image);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace slamkit
