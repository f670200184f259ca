// PNG input/output through OpenCV and the EuRoC/ASL image-sequence layout (image_io.h).
#include "slamkit/vio/image_io.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/core/path_query.h"
#include "slamkit/io/imu_io.h"
#include "slamkit/io/text_reader.h"
#include "slamkit/io/trajectory_io.h"

namespace slamkit {
namespace {

namespace fs = std::filesystem;

std::ofstream open_out(const fs::path& path) {
  std::ofstream out(path);
  if (!out) throw InputError(path.string(), 0, "images", "cannot open for writing");
  out << std::setprecision(17);
  return out;
}

void close_out(std::ofstream& out, const fs::path& path) {
  out.close();
  if (!out) throw InputError(path.string(), 0, "images", "write failed");
}

// One line of a "#timestamp [ns],filename" list.
struct StampedFile {
  std::int64_t t_ns;
  std::string name;
  int line;  ///< 1-based line of the csv, for errors found later
};

// The list of a data.csv, stamps strictly increasing.
std::vector<StampedFile> read_stamp_list(const fs::path& csv) {
  TextReader::Options opt;
  opt.delimiter = ',';
  auto reader = TextReader::open(csv.string(), opt);
  std::vector<StampedFile> out;
  while (reader->next_line()) {
    reader->expect_fields(2, "frame");
    const std::int64_t t = reader->integer(0, "timestamp");
    std::string name(reader->field(1));
    while (!name.empty() && (name.back() == ' ' || name.back() == '\r')) name.pop_back();
    while (!name.empty() && name.front() == ' ') name.erase(name.begin());
    if (name.empty()) reader->fail("filename", "empty");
    if (!out.empty() && t <= out.back().t_ns) reader->fail("timestamp", "does not increase");
    out.push_back({t, name, reader->line_number()});
  }
  if (out.empty()) throw InputError(csv.string(), 0, "frame", "no frames");
  return out;
}

}  // namespace

std::int64_t stamp_ns(double t) { return std::llround(t * 1e9); }

void write_png(const std::string& path, const GrayImage& image) {
  if (image.empty()) throw InputError(path, 0, "image", "empty image");
  const cv::Mat mat(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.pixels.data()));
  bool ok = false;
  try {
    ok = cv::imwrite(path, mat, {cv::IMWRITE_PNG_COMPRESSION, 1});
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "image", std::string("cannot write PNG: ") + e.what());
  }
  if (!ok) throw InputError(path, 0, "image", "cannot write PNG");
}

GrayImage read_png(const std::string& path) {
  if (!is_file_path(path)) throw InputError(path, 0, "image", "no such file");
  cv::Mat mat;
  try {
    mat = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "image", std::string("cannot read image: ") + e.what());
  }
  if (mat.empty()) throw InputError(path, 0, "image", "not an image OpenCV can read");
  if (mat.channels() == 3) cv::cvtColor(mat, mat, cv::COLOR_BGR2GRAY);
  else if (mat.channels() == 4) cv::cvtColor(mat, mat, cv::COLOR_BGRA2GRAY);
  if (mat.depth() == CV_16U) mat.convertTo(mat, CV_8U, 1.0 / 257.0);
  if (mat.type() != CV_8UC1) throw InputError(path, 0, "image", "unsupported pixel type");
  GrayImage image(mat.cols, mat.rows);
  for (int y = 0; y < mat.rows; ++y) std::copy(mat.ptr<std::uint8_t>(y), mat.ptr<std::uint8_t>(y) + mat.cols, image.row(y));
  return image;
}

ImageSequence read_image_sequence(const std::string& dir) {
  const fs::path root(dir);
  const fs::path cam = root / "mav0/cam0";
  if (!is_directory_path(cam)) throw InputError(dir, 0, "images", "no mav0/cam0 folder (EuRoC/ASL layout expected)");
  ImageSequence seq;
  seq.root = dir;
  const auto frames = read_stamp_list(cam / "data.csv");
  for (const StampedFile& e : frames) {
    ImageSequenceFrame f;
    f.t_ns = e.t_ns;
    f.t = static_cast<double>(e.t_ns) * 1e-9;
    f.image_path = (cam / "data" / e.name).string();
    if (!is_file_path(f.image_path))
      throw InputError((cam / "data.csv").string(), e.line, "filename", "missing image " + f.image_path);
    seq.frames.push_back(f);
  }
  const fs::path labels = root / "mav0/labels0/data.csv";
  if (path_exists(labels)) {
    const auto list = read_stamp_list(labels);
    if (list.size() != frames.size())
      throw InputError(labels.string(), 0, "timestamp", "has " + std::to_string(list.size()) + " frames, cam0 has " +
                                                            std::to_string(frames.size()));
    for (std::size_t k = 0; k < list.size(); ++k) {
      if (list[k].t_ns != frames[k].t_ns) throw InputError(labels.string(), list[k].line, "timestamp", "differs from cam0's");
      seq.frames[k].label_path = (root / "mav0/labels0/data" / list[k].name).string();
      if (!is_file_path(seq.frames[k].label_path))
        throw InputError(labels.string(), list[k].line, "filename", "missing label image " + seq.frames[k].label_path);
    }
  }
  const fs::path imu = root / "mav0/imu0/data.csv";
  if (path_exists(imu)) seq.imu = read_imu_csv(imu.string());
  const fs::path gt = root / "mav0/state_groundtruth_estimate0/data.csv";
  if (path_exists(gt)) seq.groundtruth = read_trajectory(gt.string(), TrajectoryFormat::kEuroc);
  return seq;
}

ImageSequenceWriter::ImageSequenceWriter(std::string dir) : root_(std::move(dir)) {
  const fs::path root(root_);
  std::error_code ec;
  for (const char* sub : {"mav0/cam0/data", "mav0/labels0/data", "mav0/imu0", "mav0/state_groundtruth_estimate0"}) {
    fs::create_directories(root / sub, ec);
    if (ec || !fs::is_directory(root / sub))
      throw InputError(root_, 0, "images", "cannot create folder " + (root / sub).string() + (ec ? ": " + ec.message() : ""));
  }
  const fs::path probe = root / "mav0/cam0/data/.slamkit_probe";
  {
    std::ofstream out(probe);
    if (!(out << "probe")) throw InputError(root_, 0, "images", "cannot write into " + (root / "mav0/cam0/data").string());
  }
  fs::remove(probe, ec);
}

void ImageSequenceWriter::add_frame(double t, const GrayImage& image, const GrayImage* labels) {
  const std::int64_t ns = stamp_ns(t);
  if (!stamps_.empty() && ns <= stamps_.back())
    throw std::invalid_argument("ImageSequenceWriter: frame stamps must increase");
  const std::string name = std::to_string(ns) + ".png";
  write_png((fs::path(root_) / "mav0/cam0/data" / name).string(), image);
  if (labels) write_png((fs::path(root_) / "mav0/labels0/data" / name).string(), *labels);
  labels_ = labels_ || labels;
  stamps_.push_back(ns);
}

void ImageSequenceWriter::write_imu(const std::vector<SimImuSample>& imu) const {
  const fs::path path = fs::path(root_) / "mav0/imu0/data.csv";
  std::ofstream out = open_out(path);
  out << "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],"
         "a_RS_S_z [m s^-2]\n";
  for (const SimImuSample& m : imu)
    out << stamp_ns(m.t) << ',' << m.gyro.x() << ',' << m.gyro.y() << ',' << m.gyro.z() << ',' << m.accel.x() << ','
        << m.accel.y() << ',' << m.accel.z() << '\n';
  close_out(out, path);
}

void ImageSequenceWriter::write_groundtruth(const std::vector<SimState>& states) const {
  const fs::path path = fs::path(root_) / "mav0/state_groundtruth_estimate0/data.csv";
  std::ofstream out = open_out(path);
  out << "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
         "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], "
         "b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n";
  for (const SimState& s : states) {
    const Eigen::Quaterniond& q = s.q_world_imu;
    out << stamp_ns(s.t) << ',' << s.p_world.x() << ',' << s.p_world.y() << ',' << s.p_world.z() << ',' << q.w() << ','
        << q.x() << ',' << q.y() << ',' << q.z() << ',' << s.v_world.x() << ',' << s.v_world.y() << ',' << s.v_world.z()
        << ',' << s.b_g.x() << ',' << s.b_g.y() << ',' << s.b_g.z() << ',' << s.b_a.x() << ',' << s.b_a.y() << ','
        << s.b_a.z() << '\n';
  }
  close_out(out, path);
}

void ImageSequenceWriter::write_objects(const RenderedScene& scene) const {
  const fs::path path = fs::path(root_) / "objects.csv";
  std::ofstream out = open_out(path);
  out << "#id,group,t_on [ns],t_off [ns],speed [m s^-1],start_x [m],start_y [m],start_z [m],v_x [m s^-1],v_y [m s^-1],"
         "v_z [m s^-1],yaw [rad],half_x [m],half_y [m],half_z [m]\n";
  for (const SceneWalker& w : scene.walkers)
    out << static_cast<int>(w.id) << ',' << w.path.id << ',' << stamp_ns(w.path.t_on) << ',' << stamp_ns(w.path.t_off)
        << ',' << w.speed << ',' << w.path.start.x() << ',' << w.path.start.y() << ',' << w.path.start.z() << ','
        << w.path.velocity.x() << ',' << w.path.velocity.y() << ',' << w.path.velocity.z() << ',' << w.path.yaw << ','
        << scene.person_half.x() << ',' << scene.person_half.y() << ',' << scene.person_half.z() << '\n';
  close_out(out, path);
}

void ImageSequenceWriter::finish() const {
  const fs::path root(root_);
  for (const bool labels : {false, true}) {
    if (labels && !labels_) continue;
    const fs::path path = root / (labels ? "mav0/labels0/data.csv" : "mav0/cam0/data.csv");
    std::ofstream out = open_out(path);
    out << "#timestamp [ns],filename\n";
    for (const std::int64_t t : stamps_) out << t << ',' << t << ".png\n";
    close_out(out, path);
  }
  const fs::path path = root / "times.txt";
  std::ofstream out = open_out(path);
  for (const std::int64_t t : stamps_) out << t << '\n';
  close_out(out, path);
}

}  // namespace slamkit
