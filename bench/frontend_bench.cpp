// Speed of the DVI front end per 512x512 frame: tracking (detection, sub-pixel refinement, KLT
// forward and backward) + classification (undistortion, F by RANSAC, epipolar distances), on
//   synthetic  a textured image panning 1.5 px/frame with a square patch moving on its own,
//              seen through the TUM-VI fisheye model (200 frames, no data needed)
//   vtest      the central 512x512 crop of vtest.avi (static camera, people walking), if found
// Each also with the epipolar re-search of the dynamic flags on (feature_epipolar_search.h), timed
// inside the classification.
// Writes bench/results/frontend.json (or the path given as the first argument).
// Run: build/bench/frontend_bench [OUT.json]   (SLAMKIT_DATA: the datasets folder)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>  // getloadavg
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <time.h>
#include <unistd.h>

#include "slamkit/geometry/camera_models.h"
#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/feature_epipolar_search.h"
#include "slamkit/vio/feature_tracker.h"
#include "slamkit/vio/frontend_io.h"

using namespace slamkit;

namespace {

struct Timing {
  std::vector<double> track_ms, classify_ms, cpu_ms;  // wall clock; process CPU time of both steps
  double mean_features = 0;
  long dynamic = 0, refound = 0;  // dynamic flags after the test (and the re-search), flags withdrawn by it
  nlohmann::json json() const {
    auto stats = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      double s = 0;
      for (double x : v) s += x;
      return nlohmann::json{{"mean", s / v.size()}, {"median", v[v.size() / 2]}, {"max", v.back()}};
    };
    std::vector<double> total(track_ms.size());
    for (std::size_t i = 0; i < total.size(); ++i) total[i] = track_ms[i] + classify_ms[i];
    return {{"frames", track_ms.size()}, {"tracking_ms", stats(track_ms)}, {"classification_ms", stats(classify_ms)},
            {"total_ms", stats(total)}, {"total_cpu_ms", stats(cpu_ms)}, {"features_per_frame", mean_features},
            {"dynamic_flags", dynamic}, {"refound_epipolar", refound}};
  }
};

double cpu_ms() {  // all threads of the process (OpenCV may use a pool)
  timespec t;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

double now_ms() {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

Timing run(const std::vector<GrayImage>& frames, std::shared_ptr<const CameraModel> camera, bool search) {
  FeatureTracker tracker;
  DynamicFeatureFilter filter({}, camera);
  EpipolarSearchOptions so;
  so.enabled = search;
  Timing t;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const double c0 = cpu_ms(), t0 = now_ms();
    const TrackingResult r = tracker.track(frames[k]);
    const double t1 = now_ms();
    std::vector<Eigen::Vector2d> a, b;
    r.matches(&a, &b);
    Classification c = filter.classify(a, b);
    if (search && k > 0) t.refound += search_along_epipolar(frames[k - 1], frames[k], a, &b, filter, &c, so).refound_count;
    const double t2 = now_ms(), c2 = cpu_ms();
    if (k == 0) continue;  // the first frame only detects
    t.dynamic += c.n_dynamic;
    t.track_ms.push_back(t1 - t0), t.classify_ms.push_back(t2 - t1), t.cpu_ms.push_back(c2 - c0);
    t.mean_features += double(r.features.size()) / (frames.size() - 1);
  }
  return t;
}

// Random rectangles (area-sampled) panned by (1.5 k, 0.4 k) px; a 90x160 patch moves its own way.
std::vector<GrayImage> synthetic_frames(int n) {
  const int size = 512;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> pos(-40.0, size + 240.0), side(8.0, 40.0), amp(-60.0, 60.0);
  std::vector<Eigen::Vector4d> rects(1500);
  std::vector<double> a(rects.size());
  for (std::size_t i = 0; i < rects.size(); ++i) {
    const double x = pos(rng), y = pos(rng);
    rects[i] = Eigen::Vector4d(x, y, x + side(rng), y + side(rng)), a[i] = amp(rng);
  }
  auto ov = [](double a0, double a1, double p) { return std::max(0.0, std::min(a1, p + 1.0) - std::max(a0, p)); };
  std::vector<GrayImage> frames;
  for (int k = 0; k < n; ++k) {
    std::vector<double> acc(std::size_t(size) * size, 128.0);
    const double sx = -1.5 * k, sy = -0.4 * k;
    for (std::size_t i = 0; i < rects.size(); ++i) {
      const Eigen::Vector4d b = rects[i] + Eigen::Vector4d(sx, sy, sx, sy);
      for (int y = std::max(0, int(b[1]) - 1); y < std::min(size, int(b[3]) + 2); ++y)
        for (int x = std::max(0, int(b[0]) - 1); x < std::min(size, int(b[2]) + 2); ++x)
          acc[std::size_t(y) * size + x] += a[i] * ov(b[0], b[2], x) * ov(b[1], b[3], y);
    }
    GrayImage g(size, size);
    for (std::size_t i = 0; i < acc.size(); ++i) g.pixels[i] = std::uint8_t(std::clamp(acc[i], 0.0, 255.0));
    // The moving patch: a copy of another part of the texture, sliding down 3 px/frame.
    const int px = 300, py = 40 + (3 * k) % 300;
    for (int y = 0; y < 160 && py + y < size; ++y)
      for (int x = 0; x < 90; ++x) g.at(px + x, py + y) = g.at(20 + x, 300 + y / 2);
    frames.push_back(std::move(g));
  }
  return frames;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2 || (argc == 2 && argv[1][0] == '-')) {  // e.g. --help: not an output path
    std::fprintf(stderr, "usage: frontend_bench [OUT.json]   (default bench/results/frontend.json)\n");
    return 2;
  }
  const std::string out = argc > 1 ? argv[1] : std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/frontend.json";
  const auto fisheye = make_camera_model(
      "equidistant", {190.978, 190.973, 254.932, 256.897, 0.00348239, 0.000715035, -0.00205324, 0.000202937}, 512, 512);
  nlohmann::json j;
  j["description"] = "DVI front end per 512x512 frame: tracking (goodFeaturesToTrack + cornerSubPix + KLT forward/backward + RLOF refinement, the default since session 34) "
                     "+ classification (undistortion + F RANSAC + epipolar distance); 150 features; one calling thread (OpenCV may use its pool; total_cpu_ms counts all threads)";
  double load[1] = {0};
  if (getloadavg(load, 1) == 1) j["load_average_1min"] = load[0];
  j["cores"] = sysconf(_SC_NPROCESSORS_ONLN);
  const std::vector<GrayImage> synthetic = synthetic_frames(200);
  j["synthetic"] = run(synthetic, fisheye, false).json();
  std::printf("synthetic 512x512: %s\n", j["synthetic"].dump().c_str());
  j["synthetic_epipolar_search"] = run(synthetic, fisheye, true).json();
  std::printf("synthetic 512x512, epipolar re-search: %s\n", j["synthetic_epipolar_search"].dump().c_str());
  const char* env = std::getenv("SLAMKIT_DATA");
  const std::filesystem::path video =
      std::filesystem::path(env && *env ? env : std::string(SLAMKIT_SOURCE_DIR) + "/../shared/datasets") / "vio/dynamic_video/vtest.avi";
  if (std::filesystem::exists(video)) {
    FrameSource source({video.string()});
    std::vector<GrayImage> frames;
    GrayImage g;
    while (source.next(&g, nullptr)) {  // central 512x512 crop
      GrayImage c(512, 512);
      const int x0 = (g.width - 512) / 2, y0 = (g.height - 512) / 2;
      for (int y = 0; y < 512; ++y)
        for (int x = 0; x < 512; ++x) c.at(x, y) = g.at(x0 + x, y0 + y);
      frames.push_back(std::move(c));
    }
    j["vtest_crop"] = run(frames, nullptr, false).json();
    std::printf("vtest.avi 512x512 crop: %s\n", j["vtest_crop"].dump().c_str());
  } else {
    std::printf("vtest.avi not found at %s: skipped\n", video.c_str());
  }
  std::ofstream(out) << j.dump(2) << "\n";
  std::printf("wrote %s\n", out.c_str());
}
