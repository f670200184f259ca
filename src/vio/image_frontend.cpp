// The DVI front end on images with the long-baseline epipolar test (see the header).
#include "slamkit/vio/image_frontend.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace slamkit {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

ImageFrontend::ImageFrontend(ImageFrontendOptions options, std::shared_ptr<const CameraModel> camera, GrayImage mask)
    : options_(options), tracker_(options.tracker, std::move(mask)), filter_(options.filter, std::move(camera)) {
  if (options_.baseline_frames < 1) throw std::invalid_argument("ImageFrontend: baseline_frames must be >= 1");
}

FrontendFrameResult ImageFrontend::process(const GrayImage& frame) {
  FrontendFrameResult out;
  const auto t0 = std::chrono::steady_clock::now();
  out.tracking = tracker_.track(frame);
  out.tracking_ms = ms_since(t0);
  const auto t1 = std::chrono::steady_clock::now();
  const int k = options_.baseline_frames;
  const std::vector<TrackedFeature>& tracked = out.tracking.features;
  out.features.resize(tracked.size());
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    out.features[i].id = tracked[i].id;
    out.features[i].uv = tracked[i].uv;
  }
  // Baseline of each feature: min(age, k, frames seen so far).
  const int available = static_cast<int>(history_.size());
  std::vector<int> baseline(tracked.size());
  int longest = 0;
  for (std::size_t i = 0; i < tracked.size(); ++i) {
    const int b = std::min({tracked[i].age, k, available});
    baseline[i] = b >= k ? k : std::min(b, 1);  // two RANSACs per frame at most: k and 1
    longest = std::max(longest, baseline[i]);
  }
  for (int b = longest; b >= 1; b = b > 1 ? 1 : 0) {
    const auto& then = history_[b - 1];
    std::vector<Eigen::Vector2d> p1, p2;
    std::vector<std::size_t> index;  // feature of each match
    for (std::size_t i = 0; i < tracked.size(); ++i) {
      if (tracked[i].age < b) continue;
      const auto it = then.find(tracked[i].id);
      if (it == then.end()) continue;  // cannot happen while ids persist; kept safe
      p1.push_back(it->second), p2.push_back(tracked[i].uv), index.push_back(i);
    }
    bool any = false;
    for (std::size_t m = 0; m < index.size() && !any; ++m) any = baseline[index[m]] == b;
    if (!any) continue;
    const Classification c = filter_.classify(p1, p2);
    if (b == longest) out.status = c.status;
    for (std::size_t m = 0; m < index.size(); ++m) {
      FrontendFeature& f = out.features[index[m]];
      if (baseline[index[m]] != b) continue;
      f.motion = c.flags[m];
      f.baseline = b;
    }
  }
  // Sticky flags, bookkeeping of the current ids only.
  std::unordered_set<std::int64_t> still;
  for (FrontendFeature& f : out.features) {
    if (options_.sticky_dynamic && flagged_dynamic_.count(f.id)) f.motion = FeatureMotion::kDynamic;
    if (f.motion == FeatureMotion::kDynamic) still.insert(f.id);
    if (f.motion == FeatureMotion::kStatic) ++out.n_static;
    else if (f.motion == FeatureMotion::kDynamic) ++out.n_dynamic;
    else ++out.n_unknown;
  }
  flagged_dynamic_.swap(still);
  const int classified = out.n_static + out.n_dynamic;
  out.static_ratio = classified > 0 ? static_cast<double>(out.n_static) / classified : 1.0;
  // History: this frame becomes t − 1.
  std::unordered_map<std::int64_t, Eigen::Vector2d> now;
  now.reserve(tracked.size());
  for (const TrackedFeature& f : tracked) now.emplace(f.id, f.uv);
  history_.push_front(std::move(now));
  while (static_cast<int>(history_.size()) > k) history_.pop_back();
  out.classification_ms = ms_since(t1);
  return out;
}

GrayImage circular_mask(int width, int height, double cx, double cy, double radius_px, double margin_px) {
  if (radius_px <= 0.0) return {};
  GrayImage mask(width, height, 0);
  const double r = radius_px - margin_px;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (std::hypot(x - cx, y - cy) <= r) mask.at(x, y) = 255;
  return mask;
}

}  // namespace slamkit
