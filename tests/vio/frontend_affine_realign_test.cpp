// Affine re-alignment (vio/feature_affine_realign.h) on a synthetic image pair whose answer is
// known: the second image is the first stretched 6 % along x and shifted 5 px (x' = 1.06 x + 5,
// y' = y: a camera moving along x towards a slanted wall; every epipolar line is a row), except a
// textured square that moves 8 px down (a mover). A static feature whose track ended 2.5 px off
// its match must be moved back onto it and turn static; the mover must stay dynamic.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/feature_affine_realign.h"
#include "testing/rectangle_canvas.h"
#include "testing/row_epipolar_model.h"

namespace slamkit {
namespace {

constexpr int kSize = 200;
constexpr double kStretch = 1.06, kShift = 5.0;
constexpr int kMoverX = 150, kMoverY = 140, kMoverHalf = 24, kMoverDown = 8;

using Canvas = testing::RectangleCanvas;

// Frame 1 (second = false) or frame 2: the background warped by x' = kStretch x + kShift, the
// mover's square (a second texture, not stretched) moved by (kShift, kMoverDown).
GrayImage render(bool second) {
  static const Canvas background(450, kSize + 20, 5, 24), mover(60, 2 * kMoverHalf + 1, 9, 24);
  GrayImage g(kSize, kSize, 0);
  for (int y = 0; y < kSize; ++y)
    for (int x = 0; x < kSize; ++x) {
      const double dx = second ? kShift : 0.0, dy = second ? kMoverDown : 0.0;
      const double mx = x - dx - (kMoverX - kMoverHalf), my = y - dy - (kMoverY - kMoverHalf);
      const bool on_mover = mx >= 0 && my >= 0 && mx <= 2 * kMoverHalf && my <= 2 * kMoverHalf;
      const double bx = second ? (x - kShift) / kStretch : x;
      g.at(x, y) = Canvas::gray(on_mover ? mover.sample(mx, my) : background.sample(bx + 10, y + 10));
    }
  return g;
}

Eigen::Vector2d warp(const Eigen::Vector2d& p) { return {kStretch * p.x() + kShift, p.y()}; }

// The classification of a motion along x: every epipolar line is a row.
Classification along_x(const std::vector<FeatureMotion>& flags) { return testing::rows_as_epipolar_lines(flags, 2.5); }

AffineRealignOptions enabled() {
  AffineRealignOptions o;
  o.enabled = true;
  return o;
}

TEST(AffineRealign, MovesAStaticTrackErrorOntoItsMatchAndKeepsTheMoverDynamic) {
  const GrayImage a = render(false), b = render(true);
  const DynamicFeatureFilter filter;  // pinhole pixels, threshold 1 px
  const auto D = FeatureMotion::kDynamic, S = FeatureMotion::kStatic;
  // 0, 1: static, tracks 2.5 px below / 2 px above and 1 px left of the match; 2: the mover, tracked
  // correctly; 3: static, correctly tracked (not flagged: untouched); 4: static with a track error
  // but left out by `consider`.
  const std::vector<Eigen::Vector2d> prev = {{50, 60}, {90, 40}, {kMoverX, kMoverY}, {40, 150}, {100, 100}};
  std::vector<Eigen::Vector2d> cur = {warp(prev[0]) + Eigen::Vector2d(0, 2.5), warp(prev[1]) + Eigen::Vector2d(-1, -2),
                                      {kMoverX + kShift, kMoverY + kMoverDown}, warp(prev[3]),
                                      warp(prev[4]) + Eigen::Vector2d(0, 2.5)};
  const std::vector<Eigen::Vector2d> before = cur;
  Classification c = along_x({D, D, D, S, D});
  const std::vector<char> consider = {1, 1, 1, 1, 0};
  const AffineRealignResult r = realign_affine(a, b, prev, &cur, filter, &c, enabled(), &consider);
  EXPECT_EQ(r.tried, 3);
  for (int i : {0, 1}) {
    EXPECT_TRUE(r.realigned[i]) << i;
    EXPECT_TRUE(r.unflagged[i]) << i;
    EXPECT_EQ(c.flags[i], S) << i;
    EXPECT_LT((cur[i] - warp(prev[i])).norm(), 0.25) << i << ": " << cur[i].transpose();
    EXPECT_LT(c.distance_px[i], 0.25) << i;
  }
  EXPECT_EQ(c.flags[2], D);  // the mover: aligned on the mover, still 8 px off its row
  EXPECT_FALSE(r.unflagged[2]);
  EXPECT_GT(c.distance_px[2], 6.0);
  EXPECT_LT((cur[2] - Eigen::Vector2d(kMoverX + kShift, kMoverY + kMoverDown)).norm(), 0.5);
  EXPECT_EQ(cur[3], before[3]);
  EXPECT_EQ(c.flags[3], S);
  EXPECT_EQ(cur[4], before[4]);  // not considered
  EXPECT_EQ(c.flags[4], D);
  EXPECT_EQ(r.unflagged_count, 2);
  EXPECT_EQ(c.n_static, 3);
  EXPECT_EQ(c.n_dynamic, 2);
  EXPECT_DOUBLE_EQ(c.static_ratio, 3.0 / 5.0);
}

TEST(AffineRealign, RecoversADiagonalTrackError) {
  const GrayImage a = render(false), b = render(true);
  const DynamicFeatureFilter filter;
  const std::vector<Eigen::Vector2d> prev = {{70, 80}};
  std::vector<Eigen::Vector2d> cur = {warp(prev[0]) + Eigen::Vector2d(1.5, 3.0)};
  Classification c = along_x({FeatureMotion::kDynamic});
  const AffineRealignResult r = realign_affine(a, b, prev, &cur, filter, &c, enabled());
  ASSERT_TRUE(r.realigned[0]);
  EXPECT_LT((cur[0] - warp(prev[0])).norm(), 0.25);
  EXPECT_EQ(c.flags[0], FeatureMotion::kStatic);
}

TEST(AffineRealign, RefusesShiftsBeyondTheLimitAndFlatPatches) {
  const GrayImage a = render(false), b = render(true);
  const DynamicFeatureFilter filter;
  const std::vector<Eigen::Vector2d> prev = {{50, 60}};
  AffineRealignOptions o = enabled();
  o.max_shift_px = 1.5, o.search_margin_px = 8;  // the error is 2.5 px: not allowed to move that far
  std::vector<Eigen::Vector2d> cur = {warp(prev[0]) + Eigen::Vector2d(0, 2.5)};
  Classification c = along_x({FeatureMotion::kDynamic});
  AffineRealignResult r = realign_affine(a, b, prev, &cur, filter, &c, o);
  EXPECT_EQ(r.tried, 1);
  EXPECT_FALSE(r.realigned[0]);
  EXPECT_EQ(c.flags[0], FeatureMotion::kDynamic);
  // A flat image: nothing to align (ECC fails or correlation undefined): left as it was.
  const GrayImage flat(kSize, kSize, 100);
  cur = {warp(prev[0]) + Eigen::Vector2d(0, 2.5)};
  c = along_x({FeatureMotion::kDynamic});
  r = realign_affine(flat, flat, prev, &cur, filter, &c, enabled());
  EXPECT_FALSE(r.realigned[0]);
  EXPECT_EQ(c.flags[0], FeatureMotion::kDynamic);
}

TEST(AffineRealign, NothingChangesWithoutAnEpipolarModelAndBadInputThrows) {
  const GrayImage a = render(false), b = render(true);
  const DynamicFeatureFilter filter;
  const std::vector<Eigen::Vector2d> prev = {{50, 60}};
  std::vector<Eigen::Vector2d> cur = {warp(prev[0]) + Eigen::Vector2d(0, 2.5)};
  Classification c = along_x({FeatureMotion::kDynamic});
  c.status = ClassificationStatus::kStaticCamera;
  const AffineRealignResult r = realign_affine(a, b, prev, &cur, filter, &c, enabled());
  EXPECT_EQ(r.tried, 0);
  EXPECT_EQ(c.flags[0], FeatureMotion::kDynamic);
  c.status = ClassificationStatus::kEpipolar;
  std::vector<Eigen::Vector2d> two = {cur[0], cur[0]};
  EXPECT_THROW(realign_affine(a, b, prev, &two, filter, &c, enabled()), std::invalid_argument);
  EXPECT_THROW(realign_affine(a, GrayImage(10, 10, 0), prev, &cur, filter, &c, enabled()), std::invalid_argument);
  EXPECT_THROW(realign_affine(GrayImage{}, b, prev, &cur, filter, &c, enabled()), std::invalid_argument);
  AffineRealignOptions o = enabled();
  o.min_correlation = std::nan("");
  EXPECT_THROW(check_affine_realign_options(o), std::invalid_argument);
  o = enabled(), o.search_margin_px = 4, o.max_shift_px = 6.0;
  EXPECT_THROW(check_affine_realign_options(o), std::invalid_argument);
  o = enabled(), o.patch_half_px = 1;
  EXPECT_THROW(check_affine_realign_options(o), std::invalid_argument);
  o = enabled(), o.max_iterations = 0;
  EXPECT_THROW(check_affine_realign_options(o), std::invalid_argument);
}

}  // namespace
}  // namespace slamkit
