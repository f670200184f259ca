// The IMU CSV reader: the ASL layout, and clear errors on bad input.
#include <gtest/gtest.h>

#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/io/imu_io.h"

namespace slamkit {
namespace {

std::string error_of(const std::string& text) {
  std::istringstream in(text);
  try {
    read_imu_csv(in, "imu.csv");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ImuIo, ReadsTheAslLayout) {
  std::istringstream in(
      "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n"
      "1000000000,0.1,0.2,0.3,9.8,0.1,-0.2\n"
      "1005000000,0.1,0.2,0.3,9.8,0.1,-0.2\n");
  const std::vector<ImuMeasurement> m = read_imu_csv(in, "imu.csv");
  ASSERT_EQ(m.size(), 2u);
  EXPECT_DOUBLE_EQ(m[1].stamp, 1.005);
  EXPECT_EQ(*m[1].stamp_ns, 1005000000);
  EXPECT_DOUBLE_EQ(m[0].gyro.z(), 0.3);
  EXPECT_DOUBLE_EQ(m[0].accel.x(), 9.8);
}

TEST(ImuIo, BadInputNamesFileLineAndField) {
  EXPECT_NE(error_of("1,0,0,0,0,0\n").find("imu.csv:1"), std::string::npos);
  EXPECT_NE(error_of("1,0,0,0,0,0,x\n").find("a_z"), std::string::npos);
  EXPECT_NE(error_of("1,0,0,0,0,0,nan\n").find("imu.csv:1"), std::string::npos);
  const std::string out_of_order = error_of("2,0,0,0,0,0,0\n1,0,0,0,0,0,0\n");
  EXPECT_NE(out_of_order.find("imu.csv:2"), std::string::npos) << out_of_order;
  EXPECT_NE(out_of_order.find("timestamp"), std::string::npos) << out_of_order;
  EXPECT_THROW(read_imu_csv("/nonexistent/imu.csv"), InputError);
}

}  // namespace
}  // namespace slamkit
