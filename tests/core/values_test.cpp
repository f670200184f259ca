#include "slamkit/core/values.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <utility>

#include "slamkit/geometry/se2.h"

namespace slamkit {
namespace {

// Copies share the key index until one inserts; each copy then sees only its own variables,
// and parameters are never shared.
TEST(Values, CopiesAreIndependent) {
  Values a;
  a.insert(1, SE2(1.0, 2.0, 0.3));
  a.insert(2, Eigen::Vector2d(4.0, 5.0));
  Values b = a;
  b.insert(3, Eigen::Vector2d(6.0, 7.0));
  EXPECT_TRUE(b.exists(3));
  EXPECT_FALSE(a.exists(3));
  EXPECT_THROW(a.index_of(3), InputError);
  a.insert(4, SE2(0.0, 0.0, 0.1));
  EXPECT_FALSE(b.exists(4));
  EXPECT_EQ(a.index_of(4), 2u);
  EXPECT_EQ(b.index_of(3), 2u);
  b.update(1, SE2(9.0, 9.0, 0.0));
  EXPECT_DOUBLE_EQ(a.at<SE2>(1).translation().x(), 1.0);
  EXPECT_DOUBLE_EQ(b.at<SE2>(1).translation().x(), 9.0);
  EXPECT_THROW(a.insert(2, Eigen::Vector2d(0.0, 0.0)), InputError);  // twice
  EXPECT_THROW(a.at<SE2>(2), InputError);                           // wrong type

  Values moved = std::move(a);
  EXPECT_TRUE(moved.exists(4));
  Values fresh;  // an empty and a moved-from Values answer and accept inserts
  EXPECT_FALSE(fresh.exists(1));
  a = Values();
  a.insert(7, Eigen::Vector2d(1.0, 1.0));
  EXPECT_EQ(a.index_of(7), 0u);
  std::swap(moved, b);
  EXPECT_TRUE(moved.exists(3));
  EXPECT_TRUE(b.exists(4));
}

}  // namespace
}  // namespace slamkit
