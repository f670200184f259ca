// Trajectory readers/writers: field order and units of each format, strict errors with
// file:line:field, lossless round trips, format detection, and the real dataset files.
#include "slamkit/io/trajectory_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <typeinfo>

#include "slamkit/core/error.h"
#include "testing/data.h"

namespace slamkit {
namespace {

/// Expects `f` to throw InputError at `line` about `field`, with "source:line:" in what().
template <class F>
void expect_input_error(F f, int line, const std::string& field, const std::string& needle = "") {
  try {
    f();
    ADD_FAILURE() << "no InputError thrown";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find("mem.txt:" + std::to_string(line) + ":"), std::string::npos) << e.what();
    if (!needle.empty()) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  }
}

Trajectory parse(const std::string& text, TrajectoryFormat f) {
  std::istringstream in(text);
  return read_trajectory(in, "mem.txt", f);
}

std::string render(const Trajectory& t, TrajectoryFormat f) {
  std::ostringstream out;
  write_trajectory(out, t, f);
  return out.str();
}

TEST(TrajectoryIo, TumHasQuaternionWLastAndExactDecimalStamps) {
  const Trajectory t = parse("# comment\n1305031102.160407 1 2 3 0 0 0.7071067811865476 0.7071067811865476\n"
                             "\n1.5e9 0 0 0 0 0 0 1\n",
                             TrajectoryFormat::kTum);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_TRUE(t.has_timestamps());
  EXPECT_DOUBLE_EQ(t[0].stamp, 1305031102.160407);
  ASSERT_TRUE(t[0].stamp_ns.has_value());
  EXPECT_EQ(*t[0].stamp_ns, 1305031102160407000);
  EXPECT_FALSE(t[1].stamp_ns.has_value());  // exponent notation: no exact ns
  EXPECT_EQ(t[0].T_world_body.translation(), Eigen::Vector3d(1, 2, 3));
  // 90° about z: x ↦ y.
  EXPECT_LT((t[0].T_world_body.rotation().act(Eigen::Vector3d::UnitX()) - Eigen::Vector3d::UnitY()).norm(), 1e-12);
}

TEST(TrajectoryIo, EurocHasNanosecondsQuaternionWFirstAndState) {
  const std::string csv =
      "#timestamp [ns],p_x,p_y,p_z,q_w,q_x,q_y,q_z,v_x,v_y,v_z,bw_x,bw_y,bw_z,ba_x,ba_y,ba_z\n"
      "1403715524907143168,0.5,2.0,0.97,0.7071067811865476,0,0,0.7071067811865476,0.1,0.2,0.3,0.01,0.02,0.03,"
      "-0.1,0.2,0.3\n"
      "1403715524912143104, 0.6 , 2.0, 0.97, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0\n";
  const Trajectory t = parse(csv, TrajectoryFormat::kEuroc);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(*t[0].stamp_ns, 1403715524907143168);
  EXPECT_NEAR(t[0].stamp, 1403715524.907143168, 1e-6);
  EXPECT_LT((t[0].T_world_body.rotation().act(Eigen::Vector3d::UnitX()) - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_TRUE(t.has_velocities());
  EXPECT_TRUE(t.has_biases());
  EXPECT_EQ(*t[0].v_world, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(t[0].bias->gyro, Eigen::Vector3d(0.01, 0.02, 0.03));
  EXPECT_EQ(t[0].bias->accel, Eigen::Vector3d(-0.1, 0.2, 0.3));
  EXPECT_DOUBLE_EQ(t[1].T_world_body.translation().x(), 0.6);
  // Pose-only rows (TUM-VI) and a header without '#'.
  const Trajectory p = parse("timestamp,x,y,z,qw,qx,qy,qz\n10,1,2,3,1,0,0,0\n20,1,2,3,1,0,0,0\n", TrajectoryFormat::kEuroc);
  EXPECT_EQ(p.size(), 2u);
  EXPECT_FALSE(p.has_velocities());
}

TEST(TrajectoryIo, KittiIsMatchedByIndexAndKeepsTheMatrixAsRead) {
  const Trajectory t = parse("1 0 0 1 0 1 0 2 0 0 1 3\n0 -1 0 4 1 0 0 5 0 0 0.99999994 6\n", TrajectoryFormat::kKitti);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_FALSE(t.has_timestamps());
  EXPECT_EQ(t[1].stamp, 1.0);
  EXPECT_EQ(t[1].T_world_body.translation(), Eigen::Vector3d(4, 5, 6));
  ASSERT_TRUE(t[1].source_rotation.has_value());
  EXPECT_EQ((*t[1].source_rotation)(2, 2), 0.99999994);
  EXPECT_NEAR(t[1].T_world_body.rotation().matrix().determinant(), 1.0, 1e-12);
}

TEST(TrajectoryIo, SlamkitFormatCarriesMetadataAndState) {
  const std::string text =
      "# slamkit trajectory 1\n# meta estimator=vio sliding window\n# meta dataset = V1_02\n# t x y z ...\n"
      "1.25 1 2 3 0 0 0 1 0.5 0 0\n2.5 1 2 3 0 0 0 1 0.5 0 0\n";
  const Trajectory t = parse(text, TrajectoryFormat::kSlamkit);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.metadata.at("estimator"), "vio sliding window");
  EXPECT_EQ(t.metadata.at("dataset"), "V1_02");
  EXPECT_TRUE(t.has_velocities());
  EXPECT_FALSE(t.has_biases());
  EXPECT_EQ(*t[0].stamp_ns, 1250000000);
}

TEST(TrajectoryIo, StrictErrorsNameFileLineAndField) {
  using F = TrajectoryFormat;
  expect_input_error([] { parse("1 2 3 4 5 6 7\n", F::kTum); }, 1, "", "needs 8 fields");
  expect_input_error([] { parse("# c\n1 2 3 x 0 0 0 1\n", F::kTum); }, 2, "tz", "not a number");
  expect_input_error([] { parse("2 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", F::kTum); }, 2, "timestamp", "back in time");
  expect_input_error([] { parse("1 0 0 0 0 0 0 0.5\n", F::kTum); }, 1, "quaternion", "norm");
  expect_input_error([] { parse("1 0 0 0 0 0 0 nan\n", F::kTum); }, 1, "qw");
  expect_input_error([] { parse("#h\n1.5,0,0,0,1,0,0,0\n", F::kEuroc); }, 2, "timestamp", "not an integer");
  expect_input_error([] { parse("1,0,0,0,1,0,0,0,1\n", F::kEuroc); }, 1, "", "8 or 11 or 17");
  expect_input_error([] { parse("1 0 0 0 0 1 0 0 0 0 1\n", F::kKitti); }, 1, "", "needs 12 fields");
  expect_input_error([] { parse("2 0 0 0 0 1 0 0 0 0 1 0\n", F::kKitti); }, 1, "rotation", "not a rotation");
  expect_input_error([] { parse("-1 0 0 0 0 1 0 0 0 0 1 0\n", F::kKitti); }, 1, "rotation");
  expect_input_error([] { parse("1 0 0 0 0 0 0 1\n", F::kSlamkit); }, 1, "header");
  expect_input_error([] { parse("# slamkit trajectory 1\n# meta novalue\n", F::kSlamkit); }, 2, "meta");
  expect_input_error([] { parse("# slamkit trajectory 1\n1 0 0 0 0 0 0 1 0\n", F::kSlamkit); }, 2, "");
  EXPECT_THROW(parse_trajectory_format("g2o"), InputError);
  EXPECT_THROW(read_trajectory("/nonexistent/file.txt", F::kTum), InputError);
}

std::filesystem::path temp_file(const std::string& name, const std::string& content) {
  const auto p = std::filesystem::temp_directory_path() / ("slamkit_io_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << content;
  return p;
}

TEST(TrajectoryIo, EmptyFileIsAnErrorAndFormatsAreDetected) {
  const auto empty = temp_file("empty.txt", "# only a comment\n");
  EXPECT_THROW(read_trajectory(empty.string(), TrajectoryFormat::kTum), InputError);
  const auto tum = temp_file("a.txt", "# c\n1 0 0 0 0 0 0 1\n");
  const auto kitti = temp_file("b.txt", "1 0 0 0 0 1 0 0 0 0 1 0\n");
  const auto csv = temp_file("c.csv", "#t\n1,0,0,0,1,0,0,0\n");
  const auto own = temp_file("d.txt", "\n# slamkit trajectory 1\n1 0 0 0 0 0 0 1\n");
  EXPECT_EQ(detect_trajectory_format(tum.string()), TrajectoryFormat::kTum);
  EXPECT_EQ(detect_trajectory_format(kitti.string()), TrajectoryFormat::kKitti);
  EXPECT_EQ(detect_trajectory_format(csv.string()), TrajectoryFormat::kEuroc);
  EXPECT_EQ(detect_trajectory_format(own.string()), TrajectoryFormat::kSlamkit);
  EXPECT_EQ(read_trajectory(own.string()).size(), 1u);
  for (const auto& p : {empty, tum, kitti, csv, own}) std::filesystem::remove(p);
}

Trajectory random_trajectory(std::size_t n, bool state, std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 3.0);
  Trajectory t;
  std::int64_t ns = 1403715524907143168;
  for (std::size_t k = 0; k < n; ++k) {
    TrajectorySample s;
    ns += 5000000 + static_cast<std::int64_t>(k % 7);
    s.stamp_ns = ns;
    s.stamp = static_cast<double>(ns) * 1e-9;
    s.T_world_body = SE3(SO3(Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng))), Eigen::Vector3d(g(rng), g(rng), g(rng)));
    if (state) {
      s.v_world = Eigen::Vector3d(g(rng), g(rng), g(rng));
      s.bias = ImuBias{Eigen::Vector3d(g(rng), g(rng), g(rng)) * 1e-3, Eigen::Vector3d(g(rng), g(rng), g(rng)) * 1e-2};
    }
    t.push_back(s);
  }
  return t;
}

void expect_same_poses(const Trajectory& a, const Trajectory& b, bool exact_rotation) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].T_world_body.translation(), b[k].T_world_body.translation());
    const Eigen::Quaterniond qa = a[k].T_world_body.rotation().quaternion(), qb = b[k].T_world_body.rotation().quaternion();
    // Reading re-normalizes the quaternion, which may move its last bit.
    if (exact_rotation) EXPECT_LE((qa.coeffs() - qb.coeffs()).cwiseAbs().maxCoeff(), 4e-16) << k;
    else EXPECT_LT(qa.angularDistance(qb), 1e-14) << k;
  }
}

TEST(TrajectoryIo, RoundTripsAreLossless) {
  std::mt19937 rng(3);
  const Trajectory t = random_trajectory(50, true, rng);
  for (TrajectoryFormat f : {TrajectoryFormat::kTum, TrajectoryFormat::kEuroc, TrajectoryFormat::kSlamkit}) {
    SCOPED_TRACE(to_string(f));
    const Trajectory back = parse(render(t, f), f);
    expect_same_poses(t, back, true);
    for (std::size_t k = 0; k < t.size(); ++k) {
      EXPECT_EQ(t[k].stamp_ns, back[k].stamp_ns);  // exact
      EXPECT_NEAR(t[k].stamp, back[k].stamp, 1e-6);  // the double nearest to the text: may differ by an ulp
    }
    if (f != TrajectoryFormat::kTum) {
      ASSERT_TRUE(back.has_velocities() && back.has_biases());
      for (std::size_t k = 0; k < t.size(); ++k) {
        EXPECT_EQ(*t[k].v_world, *back[k].v_world);
        EXPECT_EQ(t[k].bias->gyro, back[k].bias->gyro);
        EXPECT_EQ(t[k].bias->accel, back[k].bias->accel);
      }
    }
  }
  // KITTI: no stamps; the rotation goes through a matrix.
  const Trajectory kitti = parse(render(t, TrajectoryFormat::kKitti), TrajectoryFormat::kKitti);
  expect_same_poses(t, kitti, false);
  // and KITTI → KITTI reproduces the text exactly (the matrix as read is written back).
  const std::string text = render(kitti, TrajectoryFormat::kKitti);
  EXPECT_EQ(render(parse(text, TrajectoryFormat::kKitti), TrajectoryFormat::kKitti), text);
  // Metadata survives the slamkit format.
  Trajectory m = t;
  m.metadata["estimator"] = "lm";
  m.metadata["dataset"] = "sphere";
  EXPECT_EQ(parse(render(m, TrajectoryFormat::kSlamkit), TrajectoryFormat::kSlamkit).metadata, m.metadata);
  m.metadata["bad"] = "two\nlines";
  EXPECT_THROW(render(m, TrajectoryFormat::kSlamkit), InputError);
}

// Fuzz finding: the reader took control characters inside a metadata key or value, which the
// writer then refused. Reader and writer now share one rule: what reads, writes and reads back.
TEST(TrajectoryIo, MetadataThatReadsAlsoWritesAndReadsBack) {
  using F = TrajectoryFormat;
  expect_input_error([] { parse("# slamkit trajectory 1\n# meta k\ry=v\n", F::kSlamkit); }, 2, "meta", "control character");
  expect_input_error([] { parse("# slamkit trajectory 1\n# meta key=a\rb\n", F::kSlamkit); }, 2, "meta", "control character");
  expect_input_error([] { parse("# slamkit trajectory 1\n# meta key=a\tb\n", F::kSlamkit); }, 2, "meta", "control character");
  expect_input_error([] { parse("# slamkit trajectory 1\n# meta  =v\n", F::kSlamkit); }, 2, "meta");
  // A CRLF file still reads: the line's own '\r' is not part of the value.
  const Trajectory crlf = parse("# slamkit trajectory 1\r\n# meta key = some value \r\n1 0 0 0 0 0 0 1\r\n", F::kSlamkit);
  EXPECT_EQ(crlf.metadata.at("key"), "some value");
  const Trajectory again = parse(render(crlf, F::kSlamkit), F::kSlamkit);
  EXPECT_EQ(again.metadata, crlf.metadata);
  // The writer refuses exactly what the reader would not give back.
  for (const auto& [key, value] : std::vector<std::pair<std::string, std::string>>{
           {"a=b", "v"}, {"", "v"}, {" k", "v"}, {"k", "v "}, {"k", "a\rb"}, {"k\x7f", "v"}}) {
    Trajectory m = crlf;
    m.metadata = {{key, value}};
    EXPECT_THROW(render(m, F::kSlamkit), InputError) << "key '" << key << "' value '" << value << "'";
  }
}

// Fuzz findings of the round-trip property (read → write → read gives the same values).
TEST(TrajectoryIo, RoundTripFuzzFindings) {
  using F = TrajectoryFormat;
  // Rows must share one column layout: a velocity on some rows only could not be written back.
  expect_input_error([] { parse("# slamkit trajectory 1\n0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1 0.1 0 0\n", F::kSlamkit); },
                     3, "", "first row had 8");
  expect_input_error([] { parse("1,0,0,0,1,0,0,0,0,0,0\n2,0,0,0,1,0,0,0\n", F::kEuroc); }, 2, "", "first row had 11");
  // EuRoC rows with velocity but no biases keep their velocity.
  const Trajectory v = parse("1,0,0,0,1,0,0,0,0.5,0.25,0\n", F::kEuroc);
  ASSERT_TRUE(v[0].v_world.has_value());
  const Trajectory back = parse(render(v, F::kEuroc), F::kEuroc);
  ASSERT_TRUE(back[0].v_world.has_value());
  EXPECT_EQ(*back[0].v_world, *v[0].v_world);
  // A stamp of −0 reads as 0 (its exact-ns text has no sign), so it writes and reads back as 0.
  const Trajectory z = parse("-0 0 0 0 0 0 0 1\n", F::kTum);
  EXPECT_FALSE(std::signbit(z[0].stamp));
  EXPECT_FALSE(std::signbit(parse(render(z, F::kTum), F::kTum)[0].stamp));
}

TEST(TrajectoryIo, StampsWithoutNanosecondsAreRoundedForEuroc) {
  Trajectory t;
  t.push_back(1.5, SE3());
  t.push_back(2.0000000016, SE3());
  const Trajectory back = parse(render(t, TrajectoryFormat::kEuroc), TrajectoryFormat::kEuroc);
  EXPECT_EQ(*back[0].stamp_ns, 1500000000);
  EXPECT_EQ(*back[1].stamp_ns, 2000000002);
}

TEST(TrajectoryIo, MutatedInputGivesInputErrorsNeverAnythingElse) {
  // A small fuzzer: random byte edits of valid files either parse or throw InputError.
  std::mt19937 rng(11);
  const std::pair<TrajectoryFormat, std::string> seeds[] = {
      {TrajectoryFormat::kTum, "# c\n1.0 1 2 3 0 0 0 1\n1.5 1 2 3 0 0 0.6 0.8\n"},
      {TrajectoryFormat::kEuroc, "#h\n10,1,2,3,1,0,0,0,0.1,0.2,0.3,0,0,0,0,0,0\n20,1,2,3,0.8,0.6,0,0,0,0,0,0,0,0,0,0,0\n"},
      {TrajectoryFormat::kKitti, "1 0 0 1 0 1 0 2 0 0 1 3\n0 -1 0 4 1 0 0 5 0 0 1 6\n"},
      {TrajectoryFormat::kSlamkit, "# slamkit trajectory 1\n# meta a=b\n1 1 2 3 0 0 0 1 0 0 0\n2 1 2 3 0 0 0 1 0 0 0\n"}};
  const std::string alphabet = "0123456789.-+eE,# \t\nnaix";
  std::uniform_int_distribution<int> pick(0, static_cast<int>(alphabet.size()) - 1);
  int parsed = 0, rejected = 0;
  for (const auto& [format, seed] : seeds) {
    for (int trial = 0; trial < 3000; ++trial) {
      std::string text = seed;
      const int edits = 1 + trial % 4;
      for (int e = 0; e < edits; ++e) {
        std::uniform_int_distribution<std::size_t> pos(0, text.size() - 1);
        const std::size_t p = pos(rng);
        switch (rng() % 3) {
          case 0: text[p] = alphabet[static_cast<std::size_t>(pick(rng))]; break;
          case 1: text.insert(p, 1, alphabet[static_cast<std::size_t>(pick(rng))]); break;
          default: text.erase(p, 1);
        }
      }
      try {
        parse(text, format);
        ++parsed;
      } catch (const InputError&) {
        ++rejected;
      } catch (const std::exception& e) {
        ADD_FAILURE() << to_string(format) << ": unexpected " << typeid(e).name() << ": " << e.what() << "\n" << text;
      }
    }
  }
  EXPECT_GT(parsed, 100);
  EXPECT_GT(rejected, 1000);
}

TEST(TrajectoryIo, ReadsTheDatasetFiles) {
  SCOPED_TRACE("vio/README.md row counts");
  SLAMKIT_REQUIRE_DATA(v102, "vio/euroc/gt/V1_02_medium_gt.csv");
  SLAMKIT_REQUIRE_DATA(room1, "vio/tumvi/gt/dataset-room1_512_16.csv");
  SLAMKIT_REQUIRE_DATA(fr2, "vio/eval_reference/fr2_desk_groundtruth.txt");
  SLAMKIT_REQUIRE_DATA(kitti, "vio/eval_reference/KITTI_00_gt.txt");
  SLAMKIT_REQUIRE_DATA(est, "vio/eval_reference/V102.txt");
  const Trajectory gt = read_trajectory(v102.string());
  EXPECT_EQ(gt.size(), 16702u);
  EXPECT_TRUE(gt.has_velocities() && gt.has_biases() && gt.has_stamps_ns());
  EXPECT_NEAR(gt.duration(), 83.5, 0.05);
  EXPECT_NEAR(gt.path_length(), 75.9, 0.1);
  const Trajectory r1 = read_trajectory(room1.string());
  EXPECT_EQ(r1.size(), 16541u);
  EXPECT_FALSE(r1.has_velocities());
  EXPECT_NEAR(r1.path_length(), 146.8, 0.1);
  EXPECT_EQ(read_trajectory(fr2.string()).size(), 20957u);  // has one duplicated stamp: accepted
  EXPECT_EQ(read_trajectory(kitti.string()).size(), 4541u);
  EXPECT_EQ(read_trajectory(est.string()).size(), 807u);
}

}  // namespace
}  // namespace slamkit
