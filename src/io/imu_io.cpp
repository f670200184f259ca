#include "slamkit/io/imu_io.h"

#include <cctype>
#include <fstream>

#include "slamkit/core/error.h"
#include "slamkit/io/text_reader.h"

namespace slamkit {

std::vector<ImuMeasurement> read_imu_csv(std::istream& in, const std::string& source) {
  TextReader::Options opt;
  opt.delimiter = ',';
  TextReader r(in, source, opt);
  std::vector<ImuMeasurement> out;
  bool first = true;
  while (r.next_line()) {
    const bool header = first && !r.field(0).empty() && std::isalpha(static_cast<unsigned char>(r.field(0)[0]));
    first = false;
    if (header) continue;
    r.expect_fields(7, "IMU row (t_ns, w_x, w_y, w_z, a_x, a_y, a_z)");
    ImuMeasurement m;
    const std::int64_t ns = r.integer(0, "timestamp");
    m.stamp_ns = ns;
    m.stamp = static_cast<double>(ns) / 1e9;
    m.gyro = Eigen::Vector3d(r.number(1, "w_x"), r.number(2, "w_y"), r.number(3, "w_z"));
    m.accel = Eigen::Vector3d(r.number(4, "a_x"), r.number(5, "a_y"), r.number(6, "a_z"));
    if (!out.empty() && ns <= *out.back().stamp_ns)
      r.fail("timestamp", "IMU stamps must increase (" + std::to_string(ns) + " after " +
                              std::to_string(*out.back().stamp_ns) + ")");
    out.push_back(m);
  }
  return out;
}

std::vector<ImuMeasurement> read_imu_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  std::vector<ImuMeasurement> out = read_imu_csv(in, path);
  if (out.empty()) throw InputError(path, 0, "", "no IMU samples found");
  return out;
}

}  // namespace slamkit
