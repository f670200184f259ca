// Statistics as numpy/evo define them (population std, median of even counts averaged).
#include "slamkit/eval/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace slamkit {
namespace {

TEST(Statistics, OddCount) {
  const ErrorStatistics s = compute_statistics({3.0, 1.0, 2.0});
  EXPECT_EQ(s.count, 3u);
  EXPECT_DOUBLE_EQ(s.mean, 2.0);
  EXPECT_DOUBLE_EQ(s.median, 2.0);
  EXPECT_DOUBLE_EQ(s.min, 1.0);
  EXPECT_DOUBLE_EQ(s.max, 3.0);
  EXPECT_DOUBLE_EQ(s.sse, 14.0);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(14.0 / 3.0));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(2.0 / 3.0));  // ddof = 0
}

TEST(Statistics, EvenCountMedianAveragesTheMiddlePair) {
  const ErrorStatistics s = compute_statistics({4.0, 1.0, 10.0, 2.0});
  EXPECT_DOUBLE_EQ(s.median, 3.0);
  EXPECT_DOUBLE_EQ(s.mean, 4.25);
  EXPECT_DOUBLE_EQ(s.std, std::sqrt((0.25 * 0.25 + 3.25 * 3.25 + 5.75 * 5.75 + 2.25 * 2.25) / 4.0));
}

TEST(Statistics, RmseSquaredIsMeanSquaredPlusVariance) {
  std::vector<double> e;
  for (int k = 0; k < 1000; ++k) e.push_back(std::abs(std::sin(0.37 * k)) * 2.0);
  const ErrorStatistics s = compute_statistics(e);
  EXPECT_NEAR(s.rmse * s.rmse, s.mean * s.mean + s.std * s.std, 1e-12);
  EXPECT_NEAR(s.sse, s.rmse * s.rmse * 1000.0, 1e-9);
}

TEST(Statistics, SingleValueAndInvalidInput) {
  const ErrorStatistics s = compute_statistics({0.5});
  EXPECT_EQ(s.median, 0.5);
  EXPECT_EQ(s.std, 0.0);
  EXPECT_THROW(compute_statistics({}), std::invalid_argument);
  EXPECT_THROW(compute_statistics({1.0, std::nan("")}), std::invalid_argument);
}

}  // namespace
}  // namespace slamkit
