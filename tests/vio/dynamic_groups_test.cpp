// The dynamic-group rule (vio/dynamic_groups.h): a flag is a moving object only with flagged neighbours.
#include "slamkit/vio/dynamic_groups.h"

#include <gtest/gtest.h>

#include <limits>

namespace slamkit {
namespace {

constexpr FeatureMotion S = FeatureMotion::kStatic, D = FeatureMotion::kDynamic, U = FeatureMotion::kUnknown;

std::vector<char> marks(const std::vector<Eigen::Vector2d>& uv, const std::vector<FeatureMotion>& flags,
                        const DynamicGroupOptions& options, double radius, int expected_count) {
  std::vector<char> isolated;
  EXPECT_EQ(mark_isolated_flags(uv, flags, options, radius, &isolated), expected_count);
  return isolated;
}

TEST(DynamicGroups, MarksOnlyTheIsolatedFlags) {
  // A group of three flags 40 px apart, one lone flag, statics and an unknown beside them.
  const std::vector<Eigen::Vector2d> uv = {{100, 100}, {140, 100}, {140, 140}, {400, 400}, {405, 400}, {395, 400}, {110, 100}};
  const std::vector<FeatureMotion> flags = {D, D, D, D, S, U, S};
  // Static and unknown neighbours do not count.
  EXPECT_EQ(marks(uv, flags, DynamicGroupOptions{}, 60.0, 1), (std::vector<char>{0, 0, 0, 1, 0, 0, 0}));
}

TEST(DynamicGroups, RadiusAndSupportAreTheRule) {
  const std::vector<Eigen::Vector2d> uv = {{0, 0}, {60, 0}, {200, 0}, {260.5, 0}};
  // The radius is closed: 60 px counts, 60.5 does not.
  EXPECT_EQ(marks(uv, {D, D, D, D}, DynamicGroupOptions{}, 60.0, 2), (std::vector<char>{0, 0, 1, 1}));
  // Two supporters needed: a pair is not a group, a chain of three is one only in its middle; the
  // neighbours are the flags before the rule, so the order does not matter.
  DynamicGroupOptions two;
  two.min_support = 2;
  EXPECT_EQ(marks({{0, 0}, {50, 0}, {100, 0}}, {D, D, D}, two, 60.0, 2), (std::vector<char>{1, 0, 1}));
  EXPECT_EQ(marks({{100, 0}, {50, 0}, {0, 0}}, {D, D, D}, two, 60.0, 2), (std::vector<char>{1, 0, 1}));
  // A wider radius makes the far pair one group with the near one.
  EXPECT_EQ(marks(uv, {D, D, D, D}, DynamicGroupOptions{}, 200.0, 0), (std::vector<char>{0, 0, 0, 0}));
}

TEST(DynamicGroups, ATurnedFlagNeedsTwoSupporters) {
  // A pair of flags 40 px apart and a group of three; the first flag of each was static before.
  const std::vector<Eigen::Vector2d> uv = {{0, 0}, {40, 0}, {300, 0}, {340, 0}, {300, 40}};
  const std::vector<FeatureMotion> flags = {D, D, D, D, D};
  const std::vector<char> turned = {1, 0, 1, 0, 0};
  std::vector<char> isolated;
  // The pair's turned flag has one supporter: isolated; its partner stands (the neighbours are the
  // flags before the rule). In the group the turned flag has two: it stands.
  EXPECT_EQ(mark_isolated_flags(uv, flags, DynamicGroupOptions{}, 60.0, &isolated, &turned), 1);
  EXPECT_EQ(isolated, (std::vector<char>{1, 0, 0, 0, 0}));
  // turned_min_support 0 (or ≤ min_support): the plain rule; min_support 0 turns both off.
  DynamicGroupOptions plain;
  plain.turned_min_support = 0;
  EXPECT_EQ(mark_isolated_flags(uv, flags, plain, 60.0, &isolated, &turned), 0);
  DynamicGroupOptions off;
  off.min_support = 0;
  EXPECT_EQ(mark_isolated_flags(uv, flags, off, 60.0, &isolated, &turned), 0);
  // Without turned marks every flag is plain; marks of the wrong size are an error.
  EXPECT_EQ(mark_isolated_flags(uv, flags, DynamicGroupOptions{}, 60.0, &isolated), 0);
  const std::vector<char> short_marks = {1};
  EXPECT_THROW(mark_isolated_flags(uv, flags, DynamicGroupOptions{}, 60.0, &isolated, &short_marks), std::invalid_argument);
  DynamicGroupOptions bad;
  bad.turned_min_support = -1;
  EXPECT_THROW(check_dynamic_group_options(bad), std::invalid_argument);
  bad.turned_min_support = 2, bad.turned_static_tests = 0;
  EXPECT_THROW(check_dynamic_group_options(bad), std::invalid_argument);
  bad.turned_static_tests = 17;  // a track keeps its last 16 tests
  EXPECT_THROW(check_dynamic_group_options(bad), std::invalid_argument);
}

TEST(DynamicGroups, OffNonFiniteAndBadInput) {
  const std::vector<Eigen::Vector2d> uv = {{0, 0}, {1, 0}, {std::numeric_limits<double>::quiet_NaN(), 0}};
  DynamicGroupOptions off;
  off.min_support = 0;
  EXPECT_EQ(marks(uv, {D, D, D}, off, 60.0, 0), (std::vector<char>{0, 0, 0}));
  // A NaN pixel neither supports nor is marked: the flag at (0, 0) has no support.
  EXPECT_EQ(marks(uv, {D, S, D}, DynamicGroupOptions{}, 60.0, 1), (std::vector<char>{1, 0, 0}));
  std::vector<char> isolated;
  EXPECT_THROW(mark_isolated_flags(uv, {D}, DynamicGroupOptions{}, 60.0, &isolated), std::invalid_argument);
  DynamicGroupOptions bad;
  bad.min_support = -1;
  EXPECT_THROW(check_dynamic_group_options(bad), std::invalid_argument);
  bad.min_support = 1, bad.radius_factor = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(check_dynamic_group_options(bad), std::invalid_argument);
  bad.radius_factor = 0.0;
  EXPECT_THROW(check_dynamic_group_options(bad), std::invalid_argument);
  EXPECT_NO_THROW(check_dynamic_group_options(DynamicGroupOptions{}));
}

}  // namespace
}  // namespace slamkit
