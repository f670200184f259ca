// Epipolar re-search (vio/feature_epipolar_search.h) on a synthetic image pair whose answer is
// known: the second image is the first shifted 5 px to the right (a camera translating along x:
// every epipolar line is the row y = const), except a textured square that also moves 10 px down
// (a mover). A static feature given a wrong track must be re-found at its true match on its row;
// the mover's correct track must stay dynamic. Also: the filter's distort/undistort round trip and
// epipolar_distance against classify() on a fisheye camera.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "slamkit/geometry/camera_models.h"
#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/feature_epipolar_search.h"
#include "testing/rectangle_canvas.h"
#include "testing/row_epipolar_model.h"

namespace slamkit {
namespace {

constexpr int kSize = 240;
constexpr int kShift = 5;                    // background flow (px, along x)
constexpr int kMoverX = 160, kMoverY = 150;  // mover's centre in the first image
constexpr int kMoverHalf = 24, kMoverDown = 10;

// Integer-grid texture of random filled rectangles (real corners), sampled at integer offsets so
// that the shifts are exact.
using Canvas = testing::RectangleCanvas;

// Frame 1 (moved = false) or frame 2: the background shifted by kShift, the mover's square (from
// a second texture) by (kShift, kMoverDown).
GrayImage render(bool moved) {
  static const Canvas background(500, kSize + 20, 7), mover(60, 2 * kMoverHalf + 1, 11);
  GrayImage g(kSize, kSize, 0);
  const int dx = moved ? kShift : 0, dy = moved ? kMoverDown : 0;
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const int mx = x - dx - (kMoverX - kMoverHalf), my = y - dy - (kMoverY - kMoverHalf);
      const bool on_mover = mx >= 0 && my >= 0 && mx <= 2 * kMoverHalf && my <= 2 * kMoverHalf;
      g.at(x, y) = Canvas::gray(on_mover ? mover.at(mx, my) : background.at(x - dx + 10, y + 10));
    }
  return g;
}

// The classification of a motion along x: every epipolar line is a row.
Classification translation_along_x(const std::vector<FeatureMotion>& flags) { return testing::rows_as_epipolar_lines(flags, 5.0); }

TEST(EpipolarSearch, RefindsAStaticTrackErrorAndKeepsTheMoverDynamic) {
  const GrayImage a = render(false), b = render(true);
  const DynamicFeatureFilter filter;  // pinhole pixels, threshold 1 px
  // 0: static, wrong track 7 px below and 3 px right of its match (60, 70) → (65, 70);
  // 1: the mover, correctly tracked; 2, 3: static, correctly tracked.
  const std::vector<Eigen::Vector2d> prev = {{60, 70}, {kMoverX, kMoverY}, {100, 40}, {50, 190}};
  std::vector<Eigen::Vector2d> cur = {{68, 77}, {kMoverX + kShift, kMoverY + kMoverDown}, {105, 40}, {55, 190}};
  Classification c = translation_along_x({FeatureMotion::kDynamic, FeatureMotion::kDynamic, FeatureMotion::kStatic,
                                          FeatureMotion::kStatic});
  EpipolarSearchOptions o;
  o.enabled = true;
  const EpipolarSearchResult r = search_along_epipolar(a, b, prev, &cur, filter, &c, o);
  EXPECT_EQ(r.tried, 2);
  EXPECT_EQ(r.refound_count, 1);
  ASSERT_TRUE(r.refound[0]);
  EXPECT_FALSE(r.refound[1]);
  EXPECT_NEAR(cur[0].x(), 65.0, 0.05);
  EXPECT_NEAR(cur[0].y(), 70.0, 0.05);
  EXPECT_EQ(c.flags[0], FeatureMotion::kStatic);
  EXPECT_LT(c.distance_px[0], 0.05);
  EXPECT_EQ(c.flags[1], FeatureMotion::kDynamic);
  EXPECT_EQ(cur[1], Eigen::Vector2d(kMoverX + kShift, kMoverY + kMoverDown));  // untouched
  EXPECT_EQ(c.n_static, 3);
  EXPECT_EQ(c.n_dynamic, 1);
  EXPECT_DOUBLE_EQ(c.static_ratio, 0.75);
}

// The 1-D search alone (no median-flow seed): the wrong track lies 12 px along its row from the
// true match, beyond the capture range of a one-level KLT from the row's nearest point, so only
// the seeds along the line re-find it.
TEST(EpipolarSearch, OneDimensionalSeedsFindAMatchAlongTheLine) {
  const GrayImage a = render(false), b = render(true);
  const DynamicFeatureFilter filter;
  const std::vector<Eigen::Vector2d> prev = {{70, 60}, {kMoverX, kMoverY}};
  EpipolarSearchOptions o;
  o.enabled = true, o.seed_median_flow = false, o.klt_pyramid_levels = 0, o.klt_window = 11;
  auto run = [&](double range, std::vector<Eigen::Vector2d>* cur) {
    *cur = {{75 + 24, 63}, {kMoverX + kShift, kMoverY + kMoverDown}};
    Classification c = translation_along_x({FeatureMotion::kDynamic, FeatureMotion::kDynamic});
    o.search_half_px = range;
    return search_along_epipolar(a, b, prev, cur, filter, &c, o);
  };
  std::vector<Eigen::Vector2d> cur;
  EXPECT_FALSE(run(0.0, &cur).refound[0]);
  const EpipolarSearchResult r = run(28.0, &cur);
  ASSERT_TRUE(r.refound[0]);
  EXPECT_NEAR(cur[0].x(), 75.0, 0.05);
  EXPECT_NEAR(cur[0].y(), 60.0, 0.05);
  EXPECT_FALSE(r.refound[1]);  // the mover, searched along its row as far, is not re-found
}

TEST(EpipolarSearch, ChangesNothingWithoutAnEpipolarModelOrOutsideTheMask) {
  const GrayImage a = render(false), b = render(true);
  const DynamicFeatureFilter filter;
  const std::vector<Eigen::Vector2d> prev = {{60, 70}};
  std::vector<Eigen::Vector2d> cur = {{68, 77}};
  EpipolarSearchOptions o;
  o.enabled = true;
  Classification c = translation_along_x({FeatureMotion::kDynamic});
  const std::vector<char> none = {0};
  EXPECT_EQ(search_along_epipolar(a, b, prev, &cur, filter, &c, o, &none).refound_count, 0);
  c.status = ClassificationStatus::kStaticCamera;
  EXPECT_EQ(search_along_epipolar(a, b, prev, &cur, filter, &c, o).refound_count, 0);
  EXPECT_EQ(cur[0], Eigen::Vector2d(68, 77));
  EXPECT_EQ(c.flags[0], FeatureMotion::kDynamic);
  EXPECT_THROW(search_along_epipolar(a, GrayImage(10, 10, 0), prev, &cur, filter, &c, o), std::invalid_argument);
  std::vector<Eigen::Vector2d> two = {{1, 1}, {2, 2}};
  EXPECT_THROW(search_along_epipolar(a, b, prev, &two, filter, &c, o), std::invalid_argument);
  o.seed_step_px = 0.0;
  EXPECT_THROW(search_along_epipolar(a, b, prev, &cur, filter, &c, o), std::invalid_argument);
}

// On a fisheye camera: distort(undistort(x)) = x, epipolar_distance reproduces classify()'s
// distance (virtual-pinhole F path), and epipolar_point lies on the line (distance ≈ 0).
TEST(EpipolarSearch, FilterGeometryOnAFisheyeCamera) {
  auto camera = std::make_shared<EquidistantCamera>(190.0, 190.0, 256.0, 256.0, 0.003, 0.01, -0.01, 0.002, 512, 512);
  DynamicFilterOptions fo;
  fo.spherical = false;
  const DynamicFeatureFilter filter(fo, camera);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> xy(-1.5, 1.5), depth(2.0, 8.0);
  const Eigen::Vector3d t(0.2, 0.05, 0.0);  // camera translation between the views
  std::vector<Eigen::Vector2d> p1, p2;
  while (p1.size() < 60) {
    const Eigen::Vector3d X(xy(rng), xy(rng), depth(rng));
    Eigen::Vector2d u, v;
    if (camera->project(X, &u) && camera->project(X - t, &v) && camera->in_image(u, 5) && camera->in_image(v, 5))
      p1.push_back(u), p2.push_back(v);
  }
  p2[0] += Eigen::Vector2d(0, 6);  // one mover
  const Classification c = filter.classify(p1, p2);
  ASSERT_EQ(c.status, ClassificationStatus::kEpipolar);
  EXPECT_EQ(c.flags[0], FeatureMotion::kDynamic);
  for (std::size_t i = 0; i < p1.size(); ++i) {
    Eigen::Vector2d v, back;
    ASSERT_TRUE(filter.undistort(p2[i], &v));
    ASSERT_TRUE(filter.distort(v, &back));
    EXPECT_NEAR((back - p2[i]).norm(), 0.0, 1e-6);
    EXPECT_NEAR(filter.epipolar_distance(c, p1[i], p2[i]), c.distance_px[i], 1e-9);
    Eigen::Vector2d on;
    ASSERT_TRUE(filter.epipolar_point(c, p1[i], p2[i], 3.0, &on));
    EXPECT_LT(filter.epipolar_distance(c, p1[i], on), 1e-4);
  }
}

}  // namespace
}  // namespace slamkit
