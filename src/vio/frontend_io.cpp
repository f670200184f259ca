// Frame sources, drawing and image/video writing of the front end (see the header).
#include "slamkit/vio/frontend_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "slamkit/core/error.h"
#include "slamkit/core/path_query.h"

namespace slamkit {

namespace fs = std::filesystem;

namespace {

bool is_image_file(const fs::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  for (const char* x : {".png", ".jpg", ".jpeg", ".bmp", ".pgm", ".ppm", ".tif", ".tiff"})
    if (e == x) return true;
  return false;
}

ColorImage to_color(const cv::Mat& bgr) {
  ColorImage c(bgr.cols, bgr.rows);
  bgr.copyTo(cv::Mat(bgr.rows, bgr.cols, CV_8UC3, c.pixels.data()));
  return c;
}

GrayImage to_gray(const cv::Mat& gray) {
  GrayImage g(gray.cols, gray.rows);
  gray.copyTo(cv::Mat(gray.rows, gray.cols, CV_8UC1, g.pixels.data()));
  return g;
}

// Any 8-bit image to a 3-channel BGR one (16-bit images are scaled down).
cv::Mat as_bgr8(const cv::Mat& in) {
  cv::Mat m = in;
  if (m.depth() == CV_16U) m.convertTo(m, CV_8U, 1.0 / 256.0);
  else if (m.depth() != CV_8U) m.convertTo(m, CV_8U);
  cv::Mat bgr;
  if (m.channels() == 1) cv::cvtColor(m, bgr, cv::COLOR_GRAY2BGR);
  else if (m.channels() == 4) cv::cvtColor(m, bgr, cv::COLOR_BGRA2BGR);
  else bgr = m;
  return bgr;
}

}  // namespace

struct FrameSource::Impl {
  std::string description;
  cv::VideoCapture video;
  bool is_video = false;
  std::vector<std::string> images;
  int index = 0;
  int width = 0, height = 0;
  std::string first_name;
};

FrameSource::FrameSource(const std::vector<std::string>& inputs) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  if (inputs.empty()) throw InputError("(frontend input)", 0, "input", "no video, image directory or images given");
  for (const std::string& in : inputs)
    if (!path_exists(in)) throw InputError(in, 0, "input", "no such file or directory");
  if (inputs.size() == 1 && is_directory_path(inputs[0])) {
    try {
      for (const auto& e : fs::directory_iterator(inputs[0]))
        if (e.is_regular_file() && is_image_file(e.path())) s.images.push_back(e.path().string());
    } catch (const fs::filesystem_error& e) {
      throw InputError(inputs[0], 0, "input", std::string("cannot list the directory: ") + e.code().message());
    }
    std::sort(s.images.begin(), s.images.end());
    if (s.images.empty()) throw InputError(inputs[0], 0, "input", "the directory holds no image files");
    s.description = "image directory " + inputs[0] + " (" + std::to_string(s.images.size()) + " images)";
  } else if (inputs.size() == 1 && !is_image_file(inputs[0])) {
    s.is_video = true;
    if (!s.video.open(inputs[0]) || !s.video.isOpened())
      throw InputError(inputs[0], 0, "input", "cannot open as a video (not a video file, or no decoder for its codec)");
    s.description = "video " + inputs[0];
  } else {
    for (const std::string& in : inputs) {
      if (is_directory_path(in)) throw InputError(in, 0, "input", "a directory among several inputs (give it alone)");
      s.images.push_back(in);
    }
    s.description = std::to_string(s.images.size()) + " image file(s)";
  }
  s.first_name = inputs[0];
}

FrameSource::~FrameSource() = default;
FrameSource::FrameSource(FrameSource&&) noexcept = default;

bool FrameSource::next(GrayImage* gray, ColorImage* color) {
  Impl& s = *impl_;
  cv::Mat frame;
  std::string name;
  if (s.is_video) {
    if (!s.video.read(frame) || frame.empty()) {
      if (s.index == 0) throw InputError(s.first_name, 0, "frame 0", "the video holds no decodable frame");
      return false;
    }
    name = s.first_name + " frame " + std::to_string(s.index);
  } else {
    if (s.index >= int(s.images.size())) return false;
    name = s.images[s.index];
    frame = cv::imread(name, cv::IMREAD_UNCHANGED);
    if (frame.empty()) throw InputError(name, 0, "image", "cannot be read as an image");
  }
  if (s.index == 0) s.width = frame.cols, s.height = frame.rows;
  else if (frame.cols != s.width || frame.rows != s.height)
    throw InputError(name, 0, "image size",
                     std::to_string(frame.cols) + "x" + std::to_string(frame.rows) + " differs from the first frame's " +
                         std::to_string(s.width) + "x" + std::to_string(s.height));
  const cv::Mat bgr = as_bgr8(frame);
  cv::Mat g;
  cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
  if (gray) *gray = to_gray(g);
  if (color) *color = to_color(bgr);
  ++s.index;
  return true;
}

bool FrameSource::is_video() const { return impl_->is_video; }

double FrameSource::fps() const {
  if (!impl_->is_video) return 0.0;
  const double f = impl_->video.get(cv::CAP_PROP_FPS);
  return std::isfinite(f) && f > 0.0 ? f : 10.0;
}

int FrameSource::frame_count() const {
  if (!impl_->is_video) return int(impl_->images.size());
  const double n = impl_->video.get(cv::CAP_PROP_FRAME_COUNT);
  return std::isfinite(n) && n > 0 ? int(n) : -1;
}

std::string FrameSource::frame_name(int index) const {
  if (!impl_->is_video && index >= 0 && index < int(impl_->images.size()))
    return fs::path(impl_->images[index]).stem().string();
  char b[32];
  std::snprintf(b, sizeof b, "frame_%06d", index);
  return b;
}

const std::string& FrameSource::description() const { return impl_->description; }

GrayImage read_gray_image(const std::string& path) {
  const cv::Mat m = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (m.empty()) throw InputError(path, 0, "image", path_exists(path) ? "cannot be read as an image" : "no such file");
  return to_gray(m);
}

void draw_features(ColorImage* image, const std::vector<TrackedFeature>& features, const std::vector<FeatureMotion>& flags,
                   const std::vector<char>* isolated) {
  cv::Mat m(image->height, image->width, CV_8UC3, image->pixels.data());
  const int r = std::max(3, std::min(image->width, image->height) / 120);
  for (std::size_t i = 0; i < features.size(); ++i) {
    const FeatureMotion f = i < flags.size() ? flags[i] : FeatureMotion::kUnknown;
    const bool alone = isolated && i < isolated->size() && (*isolated)[i];
    const cv::Scalar colour = f == FeatureMotion::kStatic    ? cv::Scalar(0, 220, 0)
                              : alone                        ? cv::Scalar(0, 128, 255)
                              : f == FeatureMotion::kDynamic ? cv::Scalar(0, 0, 255)
                                                             : cv::Scalar(0, 230, 255);
    const cv::Point p(int(std::lround(features[i].uv.x())), int(std::lround(features[i].uv.y())));
    if (features[i].age > 0)
      cv::line(m, cv::Point(int(std::lround(features[i].prev_uv.x())), int(std::lround(features[i].prev_uv.y()))), p, colour,
               1, cv::LINE_AA);
    cv::circle(m, p, r, colour, 2, cv::LINE_AA);
  }
}

void write_png(const std::string& path, const ColorImage& image) {
  const cv::Mat m(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data()));
  bool ok = false;
  try {
    ok = cv::imwrite(path, m);
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "png", std::string("cannot write: ") + e.what());
  }
  if (!ok) throw InputError(path, 0, "png", "cannot write");
}

struct VideoFileWriter::Impl {
  cv::VideoWriter writer;
  std::string path;
  int width = 0, height = 0;
};

VideoFileWriter::VideoFileWriter(const std::string& path, int width, int height, double fps)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path, impl_->width = width, impl_->height = height;
  if (!impl_->writer.open(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, cv::Size(width, height), true))
    throw InputError(path, 0, "video", "cannot open for writing (MJPG AVI)");
}

VideoFileWriter::~VideoFileWriter() = default;

void VideoFileWriter::write(const ColorImage& image) {
  if (image.width != impl_->width || image.height != impl_->height)
    throw InputError(impl_->path, 0, "video", "frame size differs from the video's");
  impl_->writer.write(cv::Mat(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.pixels.data())));
}

}  // namespace slamkit
