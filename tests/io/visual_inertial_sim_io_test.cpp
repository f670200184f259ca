// Visual-inertial simulation files: write → read → write is byte-identical and keeps every
// value; malformed files give InputError naming the line and the field.
#include "slamkit/io/visual_inertial_sim_io.h"

#include <gtest/gtest.h>

#include <sstream>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

VisualInertialSim small_run(DynamicLevel level = DynamicLevel::kHigh) {
  Trajectory path;
  for (double t = 0.0; t <= 3.0; t += 0.01)
    path.push_back(t, SE3(SO3::exp(Eigen::Vector3d(0, 0, 0.5 * t)), Eigen::Vector3d(std::cos(t), std::sin(t), 1.4)));
  VisualInertialSimOptions o;
  o.dynamic = level;
  o.duration = 1.0;
  o.seed = 4;
  o.landmark_density = 2.0;
  o.mask_radius_px = 300;
  const auto cam = make_camera_model("equidistant", {190.97, 190.97, 254.93, 256.90, 0.0035, 0.0007, -0.002, 0.0002}, 512, 512);
  VisualInertialSim sim = simulate_visual_inertial(BSplineTrajectory::fit(path), cam,
                                                   SE3(SO3::exp(Eigen::Vector3d(M_PI / 2, 0, 0)), Eigen::Vector3d(0.05, -0.05, -0.07)), o);
  sim.source = "test run";
  return sim;
}

std::string text_of(const VisualInertialSim& sim) {
  std::ostringstream out;
  write_visual_inertial_sim(out, sim);
  return out.str();
}

VisualInertialSim parse(const std::string& text) {
  std::istringstream in(text);
  return read_visual_inertial_sim(in, "run.vis");
}

TEST(VisualInertialSimIo, RoundTripIsExact) {
  const VisualInertialSim sim = small_run();
  ASSERT_FALSE(sim.groups.empty());
  // Values survive exactly except the renormalized T_cam_imu quaternion (1 ulp); the text of
  // a file once read is a fixed point of read → write.
  const std::string text = text_of(sim);
  const VisualInertialSim back = parse(text);
  EXPECT_EQ(text_of(parse(text_of(back))), text_of(back));
  EXPECT_TRUE(back.T_cam_imu.rotation().quaternion().coeffs().isApprox(sim.T_cam_imu.rotation().quaternion().coeffs(), 1e-15));
  EXPECT_EQ(back.imu_truth[5].q_world_imu.coeffs(), sim.imu_truth[5].q_world_imu.coeffs());
  EXPECT_EQ(back.source, "test_run");
  EXPECT_EQ(back.seed, 4u);
  EXPECT_EQ(back.dynamic, DynamicLevel::kHigh);
  EXPECT_EQ(back.camera->intrinsics(), sim.camera->intrinsics());
  EXPECT_EQ(back.mask_radius_px, 300.0);
  EXPECT_EQ(back.T_cam_imu.translation(), sim.T_cam_imu.translation());
  ASSERT_EQ(back.imu.size(), sim.imu.size());
  EXPECT_EQ(back.imu[17].accel, sim.imu[17].accel);
  EXPECT_EQ(back.imu_truth[17].b_a, sim.imu_truth[17].b_a);
  EXPECT_EQ(back.imu_truth[17].p_world, sim.imu_truth[17].p_world);
  ASSERT_EQ(back.frames.size(), sim.frames.size());
  ASSERT_EQ(back.landmarks.size(), sim.landmarks.size());
  ASSERT_EQ(back.groups.size(), sim.groups.size());
  EXPECT_EQ(back.groups[0].start, sim.groups[0].start);
  for (std::size_t f = 0; f < sim.frames.size(); ++f) {
    EXPECT_EQ(back.frames[f].imu_index, sim.frames[f].imu_index);
    EXPECT_EQ(back.frames[f].truth.v_world, sim.frames[f].truth.v_world);
    ASSERT_EQ(back.frames[f].observations.size(), sim.frames[f].observations.size());
    for (std::size_t i = 0; i < sim.frames[f].observations.size(); ++i) {
      EXPECT_EQ(back.frames[f].observations[i].uv, sim.frames[f].observations[i].uv);
      EXPECT_EQ(back.frames[f].observations[i].dynamic, sim.frames[f].observations[i].dynamic);
    }
  }
}

// Replaces the first line that starts with `prefix` by `line` ("" deletes it).
std::string edit(const std::string& text, const std::string& prefix, const std::string& line, int* number = nullptr) {
  std::istringstream in(text);
  std::string out, l;
  bool done = false;
  int n = 0;
  while (std::getline(in, l)) {
    ++n;
    if (!done && l.rfind(prefix, 0) == 0) {
      done = true;
      if (number) *number = n;
      if (!line.empty()) out += line + "\n";
      continue;
    }
    out += l + "\n";
  }
  EXPECT_TRUE(done) << prefix;
  return out;
}

std::string error_of(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(VisualInertialSimIo, MalformedFilesNameLineAndField) {
  const std::string good = text_of(small_run());
  int line = 0;
  EXPECT_EQ(error_of(""), "run.vis: field 'header': empty file (expected '# slamkit visual-inertial simulation 1')");
  EXPECT_EQ(error_of(edit(good, "# slamkit", "# slamkit visual-inertial simulation 2")),
            "run.vis:1: field 'header': first line must be '# slamkit visual-inertial simulation 1'");
  EXPECT_EQ(error_of(edit(good, "imu_rate", "")), "run.vis:11: field 'imu_rate': missing header record before the data");
  EXPECT_EQ(error_of(edit(good, "imu_rate", "imu_rate 200\nimu_rate 100")), "run.vis:10: field 'imu_rate': repeated header record");
  EXPECT_EQ(error_of(edit(good, "camera", "camera fov 512 512 1 1 1 1")),
            "run.vis:5: field 'camera': unknown camera model 'fov' (pinhole, radtan, equidistant)");
  EXPECT_EQ(error_of(edit(good, "T_cam_imu", "T_cam_imu 0 0 0 2 0 0 0")), "run.vis:7: field 'qw': quaternion is not unit (norm 2.000000)");
  EXPECT_NE(error_of(edit(good, "imu ", "imu 0 nan 0 0 0 0 0", &line)).find(":" + std::to_string(line) + ": field 'gyro_x'"),
            std::string::npos);
  EXPECT_NE(error_of(edit(good, "truth ", "", &line)).find(":" + std::to_string(line) + ": field 'truth': an imu line must be followed"),
            std::string::npos);
  EXPECT_NE(error_of(edit(good, "obs ", "", &line)).find("expects"), std::string::npos);
  const std::string frame0 = "frame 0.0001 " + std::to_string(parse(good).frames[0].observations.size());
  EXPECT_NE(error_of(edit(good, "frame ", frame0, &line)).find(":" + std::to_string(line) + ": field 't': frame time is not"),
            std::string::npos);
  EXPECT_NE(error_of(edit(good, "obs ", "obs 0 999999 1 1 s", &line)).find(":" + std::to_string(line) + ": field 'landmark': unknown"),
            std::string::npos);
  EXPECT_NE(error_of(edit(good, "landmark 0 ", "landmark 5 -1 0 0 0", &line)).find(":" + std::to_string(line) + ": field 'id'"),
            std::string::npos);
  EXPECT_NE(error_of(edit(good, "landmark 0 ", "landmark 0 -1 0 0", &line)).find(":" + std::to_string(line) + ": landmark needs 6 fields, line has 5"),
            std::string::npos);
  EXPECT_NE(error_of(edit(good, "frame ", "bogus 1 2", &line)).find(":" + std::to_string(line) + ": field 'record': unknown record 'bogus'"),
            std::string::npos);
  // Relabel the first static observation as dynamic.
  {
    std::string bad = good;
    const auto at = bad.find(" s\n");
    bad.replace(at, 3, " d\n");
    EXPECT_NE(error_of(bad).find("label disagrees"), std::string::npos);
  }
}

TEST(VisualInertialSimIo, FuzzSeedIsAValidRun) {
  const VisualInertialSim sim = read_visual_inertial_sim(std::string(SLAMKIT_SOURCE_DIR) + "/tests/fuzz/seeds/vi_sim/small.vis");
  ASSERT_EQ(sim.frames.size(), 1u);
  EXPECT_EQ(sim.frames[0].imu_index, 0u);
  EXPECT_EQ(sim.frames[0].observations.size(), 2u);
  EXPECT_TRUE(sim.frames[0].observations[1].dynamic);
  EXPECT_EQ(sim.groups.size(), 1u);
}

TEST(VisualInertialSimIo, WriterRejectsNonFiniteValues) {
  VisualInertialSim sim = small_run(DynamicLevel::kNone);
  sim.imu[3].gyro.x() = NAN;
  std::ostringstream out;
  EXPECT_THROW(write_visual_inertial_sim(out, sim), std::invalid_argument);
}

}  // namespace
}  // namespace slamkit
