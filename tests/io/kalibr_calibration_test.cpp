// Kalibr camchain / IMU YAML readers: the real TUM-VI and EuRoC files give the README's
// numbers; malformed files give InputError naming the line and the field.
#include "slamkit/io/kalibr_calibration.h"

#include <gtest/gtest.h>

#include <sstream>

#include "slamkit/core/error.h"
#include "testing/data.h"

namespace slamkit {
namespace {

TEST(KalibrCalibration, TumViCamchainHasTheReadmeNumbers) {
  SLAMKIT_REQUIRE_DATA(file, "vio/tumvi/calib/openvins_kalibr_imucam_chain.yaml");
  const auto cams = read_kalibr_camchain(file.string());
  ASSERT_EQ(cams.size(), 2u);
  const CameraCalibration& c = cams[0];
  EXPECT_EQ(c.name, "cam0");
  EXPECT_EQ(c.distortion_model, "equidistant");
  EXPECT_EQ(c.width, 512);
  EXPECT_EQ(c.height, 512);
  EXPECT_DOUBLE_EQ(c.intrinsics[0], 190.97847715128717);
  EXPECT_DOUBLE_EQ(c.intrinsics[3], 256.8974428996504);
  EXPECT_DOUBLE_EQ(c.distortion[0], 0.0034823894022493434);
  EXPECT_DOUBLE_EQ(c.distortion[3], 0.00020293673591811182);
  EXPECT_NEAR(c.T_cam_imu.translation().x(), 0.04727988224914392, 1e-15);
  EXPECT_NEAR(c.T_cam_imu.rotation().matrix()(1, 2), -0.9993800792498829, 1e-6);
  // README: T_imu_cam0 has translation (0.04557, -0.07116, -0.04468).
  const Eigen::Vector3d t_imu_cam = c.T_cam_imu.inverse().translation();
  EXPECT_NEAR(t_imu_cam.x(), 0.04557, 1e-5);
  EXPECT_NEAR(t_imu_cam.y(), -0.07116, 1e-5);
  EXPECT_NEAR(t_imu_cam.z(), -0.04468, 1e-5);
  ASSERT_TRUE(c.model);
  EXPECT_EQ(c.model->model_name(), "equidistant");
  EXPECT_DOUBLE_EQ(cams[1].intrinsics[0], 190.44236969414825);
}

TEST(KalibrCalibration, EurocCamchainInvertsTImuCam) {
  SLAMKIT_REQUIRE_DATA(file, "vio/euroc/calib/openvins_kalibr_imucam_chain.yaml");
  const auto cams = read_kalibr_camchain(file.string());
  ASSERT_EQ(cams.size(), 2u);
  const CameraCalibration& c = cams[0];
  EXPECT_EQ(c.distortion_model, "radtan");
  EXPECT_EQ(c.width, 752);
  EXPECT_EQ(c.height, 480);
  EXPECT_DOUBLE_EQ(c.intrinsics[0], 458.654);
  EXPECT_DOUBLE_EQ(c.distortion[0], -0.28340811);
  EXPECT_DOUBLE_EQ(c.distortion[3], 1.76187114e-05);
  const SE3 T_imu_cam = c.T_cam_imu.inverse();
  EXPECT_NEAR(T_imu_cam.translation().x(), -0.0216401454975, 1e-12);
  EXPECT_NEAR(T_imu_cam.translation().z(), 0.00981073058949, 1e-12);
  EXPECT_NEAR(T_imu_cam.rotation().matrix()(1, 0), 0.999557249008, 1e-6);
  EXPECT_EQ(c.model->model_name(), "radtan");
}

TEST(KalibrCalibration, ImuNoiseOfBothDatasets) {
  SLAMKIT_REQUIRE_DATA(tumvi, "vio/tumvi/calib/openvins_kalibr_imu_chain.yaml");
  SLAMKIT_REQUIRE_DATA(euroc, "vio/euroc/calib/openvins_kalibr_imu_chain.yaml");
  const ImuCalibration t = read_kalibr_imu(tumvi.string());
  EXPECT_DOUBLE_EQ(t.gyroscope_noise_density, 0.00016);
  EXPECT_DOUBLE_EQ(t.gyroscope_random_walk, 2.2e-5);
  EXPECT_DOUBLE_EQ(t.accelerometer_noise_density, 0.0028);
  EXPECT_DOUBLE_EQ(t.accelerometer_random_walk, 0.00086);
  EXPECT_DOUBLE_EQ(t.update_rate, 200.0);
  const ImuCalibration e = read_kalibr_imu(euroc.string());
  EXPECT_DOUBLE_EQ(e.gyroscope_noise_density, 1.6968e-4);
  EXPECT_DOUBLE_EQ(e.accelerometer_random_walk, 3.0e-3);
}

const char* kGood = R"(%YAML:1.0
cam0:
  T_cam_imu:
    - [1, 0, 0, 0.1]
    - [0, 1, 0, 0]
    - [0, 0, 1, 0]
    - [0, 0, 0, 1]
  camera_model: pinhole
  distortion_coeffs: [0.01, 0, 0, 0]
  distortion_model: equidistant
  intrinsics: [200, 200, 256, 256]  # fu fv cu cv
  resolution: [512, 512]
)";

std::string error_of(const std::string& text) {
  std::istringstream in(text);
  try {
    read_kalibr_camchain(in, "chain.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

TEST(KalibrCalibration, SmallFileParses) {
  std::istringstream in(kGood);
  const auto cams = read_kalibr_camchain(in, "chain.yaml");
  ASSERT_EQ(cams.size(), 1u);
  EXPECT_DOUBLE_EQ(cams[0].T_cam_imu.translation().x(), 0.1);
  EXPECT_DOUBLE_EQ(cams[0].distortion[0], 0.01);
}

TEST(KalibrCalibration, ErrorsNameLineAndField) {
  EXPECT_EQ(error_of(replace(kGood, "  intrinsics: [200, 200, 256, 256]  # fu fv cu cv\n", "")),
            "chain.yaml:2: field 'cam0.intrinsics': missing");
  EXPECT_EQ(error_of(replace(kGood, "[200, 200, 256, 256]", "[200, 200, 256]")),
            "chain.yaml:11: field 'cam0.intrinsics': expected 4 numbers, got 3");
  EXPECT_EQ(error_of(replace(kGood, "[200, 200, 256, 256]", "[200, 2x0, 256, 256]")),
            "chain.yaml:11: field 'cam0.intrinsics': not a finite number: '2x0'");
  EXPECT_EQ(error_of(replace(kGood, "[200, 200, 256, 256]", "[200, nan, 256, 256]")),
            "chain.yaml:11: field 'cam0.intrinsics': not a finite number: 'nan'");
  EXPECT_EQ(error_of(replace(kGood, "equidistant", "fov")),
            "chain.yaml:10: field 'cam0.distortion_model': unsupported 'fov' (radtan, equidistant, none)");
  EXPECT_EQ(error_of(replace(kGood, "    - [0, 0, 0, 1]\n", "")),
            "chain.yaml:3: field 'cam0.T_cam_imu': expected 4 rows of 4 numbers");
  EXPECT_EQ(error_of(replace(kGood, "[0, 1, 0, 0]", "[0, 2, 0, 0]")),
            "chain.yaml:3: field 'cam0.T_cam_imu': the rotation block is not a rotation");
  EXPECT_EQ(error_of(replace(kGood, "T_cam_imu", "T_foo")),
            "chain.yaml:2: field 'cam0.T_cam_imu': missing (neither T_cam_imu nor T_imu_cam)");
  EXPECT_EQ(error_of(replace(kGood, "[512, 512]", "[512, -5]")),
            "chain.yaml:12: field 'cam0.resolution': must be two positive integers");
  EXPECT_EQ(error_of(replace(kGood, "[200, 200, 256, 256]", "[0, 200, 256, 256]")),
            "chain.yaml:11: field 'cam0.intrinsics': camera: fx must be > 0");
  EXPECT_EQ(error_of(replace(kGood, "  camera_model: pinhole\n", "\tcamera_model: pinhole\n")),
            "chain.yaml:8: tab in indentation");
  EXPECT_EQ(error_of(replace(kGood, "  camera_model: pinhole\n", "     camera_model: pinhole\n")),
            "chain.yaml:8: unexpected indentation");
  EXPECT_EQ(error_of(replace(kGood, "resolution: [512, 512]", "resolution: [512, 512")),
            "chain.yaml:12: unterminated '['");
  EXPECT_EQ(error_of(kGood + std::string("  resolution: [1, 1]\n")), "chain.yaml:13: duplicate key 'resolution'");
  EXPECT_EQ(error_of("imu0:\n  a: 1\n"), "chain.yaml: field 'cam0': no camera ('camN:') in the file");
  EXPECT_EQ(error_of(""), "chain.yaml: field 'cam0': no camera ('camN:') in the file");
}

TEST(KalibrCalibration, ImuErrors) {
  std::istringstream in("imu0:\n  accelerometer_noise_density: 0.1\n  accelerometer_random_walk: -1\n");
  try {
    read_kalibr_imu(in, "imu.yaml");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "imu.yaml:3: field 'imu0.accelerometer_random_walk': must be > 0");
  }
}

}  // namespace
}  // namespace slamkit
