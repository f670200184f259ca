// PNG and EuRoC/ASL sequence input/output of rendered images (vio/image_io.h): round trip of
// images, labels, IMU and ground truth; unwritable folders fail at once; malformed layouts
// give InputError naming the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "slamkit/core/error.h"
#include "slamkit/vio/image_io.h"

namespace slamkit {
namespace {

namespace fs = std::filesystem;

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("slamkit_render_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                        "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
  }
  ~TempDir() { fs::remove_all(path); }
};

GrayImage pattern(int w, int h, int salt) {
  GrayImage g(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) g.at(x, y) = static_cast<std::uint8_t>((x * 7 + y * 13 + salt) % 256);
  return g;
}

TEST(RenderImageIo, PngRoundTrip) {
  TempDir dir;
  fs::create_directories(dir.path);
  const GrayImage g = pattern(37, 21, 5);
  write_png((dir.path / "a.png").string(), g);
  EXPECT_EQ(read_png((dir.path / "a.png").string()), g);
  EXPECT_THROW(read_png((dir.path / "missing.png").string()), InputError);
  std::ofstream((dir.path / "junk.png").string()) << "not a png";
  EXPECT_THROW(read_png((dir.path / "junk.png").string()), InputError);
  EXPECT_THROW(write_png((dir.path / "no/such/dir/b.png").string(), g), InputError);
  EXPECT_THROW(write_png((dir.path / "c.png").string(), GrayImage()), InputError);
}

TEST(RenderImageIo, SequenceRoundTrip) {
  TempDir dir;
  ImageSequenceWriter writer(dir.path.string());
  std::vector<SimImuSample> imu;
  std::vector<SimState> truth;
  for (int k = 0; k < 30; ++k) {
    SimImuSample m;
    m.t = 1520530308.25 + 0.005 * k;
    m.gyro = Eigen::Vector3d(0.1 * k, -0.2, 0.3);
    m.accel = Eigen::Vector3d(0.0, 0.1, 9.81);
    imu.push_back(m);
    SimState s;
    s.t = m.t;
    s.p_world = Eigen::Vector3d(k, 2.0, 3.0);
    truth.push_back(s);
  }
  for (int k = 0; k < 3; ++k) {
    const GrayImage img = pattern(64, 48, k), lab = pattern(64, 48, 100 + k);
    writer.add_frame(imu[static_cast<std::size_t>(10 * k)].t, img, &lab);
  }
  EXPECT_THROW(writer.add_frame(imu[0].t, pattern(64, 48, 0), nullptr), std::invalid_argument);  // stamps increase
  writer.write_imu(imu);
  writer.write_groundtruth(truth);
  writer.finish();
  const ImageSequence seq = read_image_sequence(dir.path.string());
  ASSERT_EQ(seq.frames.size(), 3u);
  ASSERT_TRUE(seq.has_labels());
  for (int k = 0; k < 3; ++k) {
    const ImageSequenceFrame& f = seq.frames[static_cast<std::size_t>(k)];
    EXPECT_EQ(f.t_ns, stamp_ns(imu[static_cast<std::size_t>(10 * k)].t));
    EXPECT_NEAR(f.t, imu[static_cast<std::size_t>(10 * k)].t, 1e-6);
    EXPECT_EQ(read_png(f.image_path), pattern(64, 48, k));
    EXPECT_EQ(read_png(f.label_path), pattern(64, 48, 100 + k));
  }
  ASSERT_EQ(seq.imu.size(), 30u);
  EXPECT_NEAR(seq.imu[7].gyro.x(), 0.7, 1e-12);
  EXPECT_EQ(seq.imu[7].stamp_ns.value(), stamp_ns(imu[7].t));
  ASSERT_EQ(seq.groundtruth.size(), 30u);
  // times.txt has one stamp per frame.
  std::ifstream times((dir.path / "times.txt").string());
  std::int64_t t = 0;
  int lines = 0;
  while (times >> t) ++lines;
  EXPECT_EQ(lines, 3);

  // Labels whose stamps differ from cam0's, a missing image: InputError naming the file.
  std::ofstream((dir.path / "mav0/labels0/data.csv").string()) << "#timestamp [ns],filename\n1,1.png\n2,2.png\n3,3.png\n";
  try {
    read_image_sequence(dir.path.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("labels0/data.csv"), std::string::npos) << e.what();
  }
  // A label image that is not there: the line and field of labels0/data.csv (before any work).
  fs::remove(dir.path / "mav0/labels0/data.csv");
  writer.finish();
  fs::remove(seq.frames[2].label_path);
  try {
    read_image_sequence(dir.path.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find("labels0/data.csv"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), 4);
    EXPECT_EQ(e.field(), "filename");
  }
  fs::remove(dir.path / "mav0/labels0/data.csv");
  fs::remove(seq.frames[1].image_path);
  try {
    read_image_sequence(dir.path.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "filename");
  }
  // A file name the OS refuses (longer than NAME_MAX): an InputError, not a filesystem_error
  // (found by fuzz_image_sequence).
  std::ofstream((dir.path / "mav0/cam0/data.csv").string()) << "#timestamp [ns],filename\n1," << std::string(300, 'x')
                                                             << ".png\n";
  EXPECT_THROW(read_image_sequence(dir.path.string()), InputError);
  std::ofstream((dir.path / "mav0/cam0/data.csv").string()) << "#timestamp [ns],filename\n5,a.png\n4,b.png\n";
  try {
    read_image_sequence(dir.path.string());
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "timestamp");
  }
  EXPECT_THROW(read_image_sequence((dir.path / "nothing").string()), InputError);
}

TEST(RenderImageIo, UnwritableFolderFailsAtOnce) {
  TempDir dir;
  fs::create_directories(dir.path);
  std::ofstream((dir.path / "file").string()) << "x";
  EXPECT_THROW(ImageSequenceWriter((dir.path / "file").string()), InputError);          // a file, not a folder
  EXPECT_THROW(ImageSequenceWriter((dir.path / "file/below").string()), InputError);    // below a file
  EXPECT_THROW(ImageSequenceWriter("/proc/slamkit_cannot_write_here"), InputError);
}

}  // namespace
}  // namespace slamkit
