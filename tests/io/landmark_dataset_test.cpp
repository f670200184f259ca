// Landmark datasets (MRCLAM Dataset 7, Victoria Park): strict single-file readers with
// file:line:field errors on tiny fixtures, the event merge (controls split at scans), and the
// real data (skipped visibly without SLAMKIT_DATA, failing under CI=true).
#include "slamkit/io/landmark_dataset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/filters/victoria_park_model.h"
#include "testing/data.h"

namespace slamkit {
namespace {

template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

std::vector<MrclamSighting> sightings(const std::string& text) {
  std::istringstream in(text);
  return read_mrclam_measurements(in, "m.dat");
}
std::vector<VictoriaScan> trees(const std::string& text) {
  std::istringstream in(text);
  return read_victoria_trees(in, "t.txt");
}

TEST(LandmarkDataset, MrclamMeasurementsStrict) {
  const auto s = sightings("# c\n# c\n1.5 61 1.68 0.03\n1.5\t27 2.0 -0.5\r\n2.0 5 3 0.1\n");
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[1].barcode, 27);
  EXPECT_DOUBLE_EQ(s[1].bearing, -0.5);
  EXPECT_EQ(error_of([] { sightings("1 61 1.0\n"); }).rfind("m.dat:1:", 0), 0u);
  EXPECT_NE(error_of([] { sightings("1 61 1 0\n2 6.5 1 0\n"); }).find("m.dat:2: field 'barcode'"), std::string::npos);
  EXPECT_NE(error_of([] { sightings("1 61 -1 0\n"); }).find("field 'range'"), std::string::npos);
  EXPECT_NE(error_of([] { sightings("1 61 1 nan\n"); }).find("field 'bearing'"), std::string::npos);
  EXPECT_NE(error_of([] { sightings("1 61 1 4\n"); }).find("field 'bearing'"), std::string::npos);
  EXPECT_NE(error_of([] { sightings("2 61 1 0\n1 61 1 0\n"); }).find("m.dat:2: field 'time'"), std::string::npos);
}

TEST(LandmarkDataset, MrclamBarcodesAndLandmarksStrict) {
  std::istringstream b("# x\n1 5\n6 63\n");
  const auto map = read_mrclam_barcodes(b, "b.dat");
  EXPECT_EQ(map.at(63), 6);
  EXPECT_EQ(map.at(5), 1);
  EXPECT_NE(error_of([] { std::istringstream in("1 5\n2 5\n"); read_mrclam_barcodes(in, "b.dat"); })
                .find("b.dat:2: field 'barcode': listed twice"), std::string::npos);
  EXPECT_NE(error_of([] { std::istringstream in("# only comments\n"); read_mrclam_barcodes(in, "b.dat"); })
                .find("no barcodes"), std::string::npos);
  std::istringstream l("6 0.5 -4.2 0.0001 0.0005\n7 1 2 0 0\n");
  const auto lm = read_mrclam_landmarks(l, "l.dat");
  ASSERT_EQ(lm.size(), 2u);
  EXPECT_EQ(lm[0].first, 6);
  EXPECT_DOUBLE_EQ(lm[0].second.y(), -4.2);
  EXPECT_NE(error_of([] { std::istringstream in("6 0.5 -4.2 0.0001\n"); read_mrclam_landmarks(in, "l.dat"); })
                .find("l.dat:1:"), std::string::npos);
  EXPECT_NE(error_of([] { std::istringstream in("6 0 0 0 0\n6 1 1 0 0\n"); read_mrclam_landmarks(in, "l.dat"); })
                .find("l.dat:2: field 'subject'"), std::string::npos);
}

TEST(LandmarkDataset, VictoriaReadersStrict) {
  const auto s = trees("# h\n1000 2 10 0.5 20 -0.25\n1200 0\n");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_DOUBLE_EQ(s[0].time, 1.0);
  ASSERT_EQ(s[0].trees.size(), 2u);
  EXPECT_EQ(s[0].trees[1].id, -1);
  EXPECT_DOUBLE_EQ(s[0].trees[1].range, 20);
  EXPECT_TRUE(s[1].trees.empty());
  EXPECT_NE(error_of([] { trees("1000 2 10 0.5\n"); }).find("t.txt:1: field 'n'"), std::string::npos);
  EXPECT_NE(error_of([] { trees("1000 -1\n"); }).find("t.txt:1: field 'n'"), std::string::npos);
  EXPECT_NE(error_of([] { trees("1000 1 0 0.5\n"); }).find("field 'range'"), std::string::npos);
  EXPECT_NE(error_of([] { trees("1000 1 1 0.5x\n"); }).find("field 'bearing'"), std::string::npos);
  EXPECT_NE(error_of([] { trees("\n1000 0\n900 0\n"); }).find("t.txt:3: field 'time'"), std::string::npos);
  auto odo = [](const std::string& text) {
    std::istringstream in(text);
    return read_victoria_odometry(in, "o.txt");
  };
  const auto o = odo("25 1.5 0.1\n50 2 -0.1\n");
  EXPECT_DOUBLE_EQ(o[1].time, 0.05);
  EXPECT_NE(error_of([&] { odo("25 1 2\n50 1 0\n"); }).find("o.txt:1: field 'steering'"), std::string::npos);
  EXPECT_NE(error_of([&] { odo("25 1 0\n"); }).find("fewer than 2"), std::string::npos);
  EXPECT_NE(error_of([&] { odo("25 1 0 4\n50 1 0\n"); }).find("o.txt:1:"), std::string::npos);
  std::vector<double> t;
  std::vector<Eigen::Vector2d> p;
  std::istringstream g("1000 1 2\n2000 3 inf\n");
  EXPECT_NE(error_of([&] { read_victoria_gps(g, "g.txt", &t, &p); }).find("g.txt:2: field 'y'"), std::string::npos);
}

TEST(LandmarkDataset, MergeSplitsControlsAtScans) {
  // Commands at 0, 1, 2 (last one only ends the stream); scans at -1 (dropped), 0.5, 1, 3 (dropped).
  const std::vector<std::pair<double, Eigen::Vector2d>> cmds = {
      {0.0, {1, 0.1}}, {1.0, {2, 0.2}}, {2.0, {3, 0.3}}};
  std::vector<std::pair<double, std::vector<RangeBearing>>> scans = {
      {-1.0, {RangeBearing{}}}, {0.5, {RangeBearing{1, 2, 0}}}, {1.0, {}}, {3.0, {RangeBearing{}, RangeBearing{}}}};
  int dropped = 0;
  const auto ev = merge_landmark_events(cmds, scans, &dropped);
  EXPECT_EQ(dropped, 3);
  ASSERT_EQ(ev.size(), 5u);  // c(0,0.5) s c(0.5,0.5) s c(1,1)
  EXPECT_FALSE(ev[0].is_scan);
  EXPECT_DOUBLE_EQ(ev[0].control.dt, 0.5);
  EXPECT_DOUBLE_EQ(ev[0].control.v, 1);
  EXPECT_TRUE(ev[1].is_scan);
  EXPECT_EQ(ev[1].observations.size(), 1u);
  EXPECT_DOUBLE_EQ(ev[2].time, 0.5);
  EXPECT_DOUBLE_EQ(ev[2].control.dt, 0.5);
  EXPECT_TRUE(ev[3].is_scan);
  EXPECT_DOUBLE_EQ(ev[4].control.v, 2);
  EXPECT_DOUBLE_EQ(ev[4].control.turn, 0.2);
  double total = 0;
  for (const auto& e : ev) total += e.is_scan ? 0 : e.control.dt;
  EXPECT_DOUBLE_EQ(total, 2.0);
}

// A tiny MRCLAM folder written by the test: barcodes, landmarks, one robot.
TEST(LandmarkDataset, MrclamFolderFixture) {
  const auto dir = std::filesystem::temp_directory_path() / "slamkit_mrclam_fixture";
  std::filesystem::create_directories(dir);
  auto write = [&](const std::string& name, const std::string& text) { std::ofstream(dir / name) << text; };
  write("Barcodes.dat", "# h\n1 5\n2 14\n6 63\n7 81\n");
  write("Landmark_Groundtruth.dat", "6 1 0 0 0\n7 0 1 0 0\n");
  write("Robot1_Odometry.dat", "10.0 0.1 0.0\n10.5 0.2 0.1\n11.0 0 0\n");
  write("Robot1_Groundtruth.dat", "9.0 0 0 0\n10.0 0.5 0.25 0.1\n12.0 1 1 0.2\n");
  write("Robot1_Measurement.dat", "9.5 63 1 0\n10.2 63 1 0\n10.2 14 2 0\n10.2 81 1.5 0.5\n10.7 99 1 0\n");
  const LandmarkDataset ds = read_mrclam_dataset(dir.string(), 1);
  EXPECT_EQ(ds.dropped_before_start, 1);
  EXPECT_EQ(ds.dropped_robot_sightings, 1);
  EXPECT_EQ(ds.dropped_unknown_barcodes, 1);
  EXPECT_EQ(ds.motion_model, "unicycle");
  EXPECT_NEAR(ds.initial_pose.x(), 0.5, 1e-12);
  EXPECT_NEAR(ds.initial_pose.z(), 0.1, 1e-12);
  int scans = 0;
  for (const auto& e : ds.events)
    if (e.is_scan) {
      ++scans;
      ASSERT_EQ(e.observations.size(), 2u);
      EXPECT_EQ(e.observations[0].id, 6);
      EXPECT_EQ(e.observations[1].id, 7);
    }
  EXPECT_EQ(scans, 1);
  EXPECT_EQ(ds.true_landmarks.size(), 2u);
  write("Robot1_Measurement.dat", "10.2 63 1 0\n10.3 63 x 0\n");
  EXPECT_NE(error_of([&] { read_mrclam_dataset(dir.string(), 1); }).find("Robot1_Measurement.dat:2: field 'range'"),
            std::string::npos);
  EXPECT_NE(error_of([&] { read_mrclam_dataset(dir.string(), 2); }).find("Robot2_Odometry.dat"), std::string::npos);
  EXPECT_NE(error_of([&] { read_mrclam_dataset(dir.string(), 0); }).find("robot"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(LandmarkDataset, RealMrclamDataset7) {
  SLAMKIT_REQUIRE_DATA(dir, "landmark/MRCLAM_Dataset7");
  const int expected_landmark_obs[3] = {2578, 3818, 4425};
  for (int robot = 1; robot <= 3; ++robot) {
    const LandmarkDataset ds = read_mrclam_dataset(dir.string(), robot);
    int obs = 0;
    double duration = 0;
    for (const auto& e : ds.events) {
      if (e.is_scan) {
        obs += static_cast<int>(e.observations.size());
        for (const auto& z : e.observations) EXPECT_TRUE(z.id >= 6 && z.id <= 20);
      } else {
        duration += e.control.dt;
      }
    }
    // The README's counts of landmark sightings, less those before the first odometry stamp.
    EXPECT_EQ(obs + ds.dropped_before_start, expected_landmark_obs[robot - 1]) << "robot " << robot;
    EXPECT_GT(duration, 800.0);
    EXPECT_EQ(ds.true_landmarks.size(), 15u);
    EXPECT_GT(ds.truth_poses.size(), 50000u);
    EXPECT_EQ(ds.dropped_unknown_barcodes, robot == 3 ? 9 : 0);
  }
}

TEST(LandmarkDataset, RealVictoriaPark) {
  SLAMKIT_REQUIRE_DATA(dir, "landmark/VictoriaPark");
  const LandmarkDataset ds = read_victoria_park(dir.string());
  int scans = 0, detections = 0;
  for (const auto& e : ds.events)
    if (e.is_scan) ++scans, detections += static_cast<int>(e.observations.size());
  EXPECT_EQ(scans + (ds.dropped_before_start > 0 ? 1 : 0), 7249);  // one scan precedes the first command
  EXPECT_EQ(detections + ds.dropped_before_start, 52974);
  EXPECT_EQ(ds.gps_times.size(), 4466u);
  EXPECT_EQ(ds.motion_model, "victoria_park");
  // Dead reckoning through the car model over the first minute stays finite.
  const VictoriaParkModel model(VictoriaParkGeometry{}, 0.5, 0.05);
  Eigen::Vector3d x = ds.initial_pose;
  for (const auto& e : ds.events) {
    if (e.time > ds.gps_times.front() + 60) break;
    if (!e.is_scan) x = model.predict(x, e.control);
  }
  ASSERT_TRUE(x.allFinite());
}

}  // namespace
}  // namespace slamkit
