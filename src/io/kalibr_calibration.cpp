#include "slamkit/io/kalibr_calibration.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "slamkit/core/error.h"
#include "yaml_subset.h"

namespace slamkit {
namespace {

using yaml_subset::Node;

struct Context {
  const std::string& source;
  std::string prefix;  ///< "cam0."
  [[noreturn]] void fail(const Node& n, const std::string& key, const std::string& message) const {
    throw InputError(source, n.line, prefix + key, message);
  }
  const Node& get(const Node& map, const std::string& key) const {
    const Node* n = map.find(key);
    if (!n) fail(map, key, "missing");
    return *n;
  }
  double number(const Node& n, const std::string& key) const {
    if (n.kind != Node::Kind::kScalar) fail(n, key, "expected a number");
    const std::string& s = n.scalar;
    double v = 0.0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !std::isfinite(v))
      fail(n, key, "not a finite number: '" + s.substr(0, 40) + "'");
    return v;
  }
  std::vector<double> numbers(const Node& n, const std::string& key, std::size_t count) const {
    if (n.kind != Node::Kind::kSequence) fail(n, key, "expected a list of " + std::to_string(count) + " numbers");
    if (n.items.size() != count)
      fail(n, key, "expected " + std::to_string(count) + " numbers, got " + std::to_string(n.items.size()));
    std::vector<double> v;
    for (const Node& item : n.items) v.push_back(number(item, key));
    return v;
  }
  std::string text(const Node& n, const std::string& key) const {
    if (n.kind != Node::Kind::kScalar) fail(n, key, "expected a name");
    return n.scalar;
  }
  // A 4×4 homogeneous transform as 4 rows of 4; the last row must be 0 0 0 1 and the
  // rotation orthonormal to 1e-3 (it is then projected onto SO(3)).
  SE3 transform(const Node& n, const std::string& key) const {
    if (n.kind != Node::Kind::kSequence || n.items.size() != 4) fail(n, key, "expected 4 rows of 4 numbers");
    Eigen::Matrix4d T;
    for (int r = 0; r < 4; ++r) {
      const std::vector<double> row = numbers(n.items[r], key, 4);
      for (int c = 0; c < 4; ++c) T(r, c) = row[c];
    }
    if ((T.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) fail(n, key, "last row must be [0, 0, 0, 1]");
    const Eigen::Matrix3d R = T.topLeftCorner<3, 3>();
    if ((R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-3 || R.determinant() < 0.0)
      fail(n, key, "the rotation block is not a rotation");
    return SE3::from_matrix(T.topRows<3>());
  }
};

std::ifstream open_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, "", std::string("cannot open file: ") + std::strerror(errno));
  return f;
}

CameraCalibration read_camera(const Node& cam, const std::string& name, const std::string& source) {
  const Context ctx{source, name + "."};
  if (cam.kind != Node::Kind::kMap) ctx.fail(cam, "", "expected a map of camera fields");
  CameraCalibration c;
  c.name = name;
  const std::string model = ctx.text(ctx.get(cam, "camera_model"), "camera_model");
  if (model != "pinhole") ctx.fail(ctx.get(cam, "camera_model"), "camera_model", "unsupported '" + model + "' (pinhole)");
  const Node& dist_node = ctx.get(cam, "distortion_model");
  c.distortion_model = ctx.text(dist_node, "distortion_model");
  std::size_t n_dist = 0;
  if (c.distortion_model == "radtan" || c.distortion_model == "equidistant") n_dist = 4;
  else if (c.distortion_model != "none")
    ctx.fail(dist_node, "distortion_model", "unsupported '" + c.distortion_model + "' (radtan, equidistant, none)");
  c.intrinsics = ctx.numbers(ctx.get(cam, "intrinsics"), "intrinsics", 4);
  if (n_dist > 0) {
    c.distortion = ctx.numbers(ctx.get(cam, "distortion_coeffs"), "distortion_coeffs", n_dist);
  } else if (const Node* d = cam.find("distortion_coeffs")) {
    c.distortion = ctx.numbers(*d, "distortion_coeffs", d->items.size());
    for (double v : c.distortion)
      if (v != 0.0) ctx.fail(*d, "distortion_coeffs", "must be zero for distortion_model none");
    c.distortion.clear();
  }
  const Node& res = ctx.get(cam, "resolution");
  const std::vector<double> wh = ctx.numbers(res, "resolution", 2);
  for (double v : wh)
    if (v < 1 || v > 100000 || v != std::floor(v)) ctx.fail(res, "resolution", "must be two positive integers");
  c.width = static_cast<int>(wh[0]), c.height = static_cast<int>(wh[1]);
  const Node* t_ci = cam.find("T_cam_imu");
  const Node* t_ic = cam.find("T_imu_cam");
  if (t_ci && t_ic) ctx.fail(*t_ic, "T_imu_cam", "give either T_cam_imu or T_imu_cam, not both");
  if (!t_ci && !t_ic) ctx.fail(cam, "T_cam_imu", "missing (neither T_cam_imu nor T_imu_cam)");
  c.T_cam_imu = t_ci ? ctx.transform(*t_ci, "T_cam_imu") : ctx.transform(*t_ic, "T_imu_cam").inverse();
  std::vector<double> all = c.intrinsics;
  all.insert(all.end(), c.distortion.begin(), c.distortion.end());
  try {
    c.model = make_camera_model(n_dist ? c.distortion_model : "pinhole", all, c.width, c.height);
  } catch (const std::invalid_argument& e) {
    ctx.fail(ctx.get(cam, "intrinsics"), "intrinsics", e.what());
  }
  return c;
}

}  // namespace

std::vector<CameraCalibration> read_kalibr_camchain(std::istream& in, const std::string& source) {
  const Node root = yaml_subset::parse(in, source);
  std::vector<CameraCalibration> cams;
  for (const auto& [key, node] : root.entries) {
    if (key.rfind("cam", 0) != 0) continue;
    cams.push_back(read_camera(node, key, source));
  }
  if (cams.empty()) throw InputError(source, 0, "cam0", "no camera ('camN:') in the file");
  return cams;
}

std::vector<CameraCalibration> read_kalibr_camchain(const std::string& path) {
  std::ifstream f = open_file(path);
  return read_kalibr_camchain(f, path);
}

ImuCalibration read_kalibr_imu(std::istream& in, const std::string& source) {
  const Node root = yaml_subset::parse(in, source);
  const Context top{source, ""};
  const Node& imu = top.get(root, "imu0");
  const Context ctx{source, "imu0."};
  if (imu.kind != Node::Kind::kMap) top.fail(imu, "imu0", "expected a map of IMU fields");
  ImuCalibration c;
  const auto positive = [&](const std::string& key) {
    const Node& n = ctx.get(imu, key);
    const double v = ctx.number(n, key);
    if (v <= 0.0) ctx.fail(n, key, "must be > 0");
    return v;
  };
  c.accelerometer_noise_density = positive("accelerometer_noise_density");
  c.accelerometer_random_walk = positive("accelerometer_random_walk");
  c.gyroscope_noise_density = positive("gyroscope_noise_density");
  c.gyroscope_random_walk = positive("gyroscope_random_walk");
  c.update_rate = positive("update_rate");
  return c;
}

ImuCalibration read_kalibr_imu(const std::string& path) {
  std::ifstream f = open_file(path);
  return read_kalibr_imu(f, path);
}

}  // namespace slamkit
