#include "slamkit/io/bal_io.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/core/output_file.h"
#include "slamkit/io/text_reader.h"

namespace slamkit {
namespace {

// Whitespace tokens across lines, with the line each came from.
class TokenStream {
 public:
  TokenStream(std::istream& in, const std::string& source) : reader_(in, source) {}
  const std::string& source() const { return reader_.source(); }

  double number(const std::string& field) {
    advance(field);
    return reader_.number(pos_++, field);
  }
  std::int64_t integer(const std::string& field) {
    advance(field);
    return reader_.integer(pos_++, field);
  }
  int line() const { return reader_.line_number(); }
  /// Throws if anything but whitespace/comments is left.
  void expect_end() {
    if (pos_ < reader_.num_fields() || reader_.next_line())
      reader_.fail(std::string(reader_.field(pos_ < reader_.num_fields() ? pos_ : 0)),
                   "unexpected data after the last point");
  }

 private:
  void advance(const std::string& field) {
    while (pos_ >= reader_.num_fields()) {
      if (!reader_.next_line())
        throw InputError(reader_.source(), reader_.line_number(), field, "the file ends early (truncated?)");
      pos_ = 0;
    }
  }
  TextReader reader_;
  std::size_t pos_ = 0;
};

int count(TokenStream& ts, const char* name) {
  const std::int64_t n = ts.integer(name);
  if (n <= 0 || n > 2'000'000'000) throw InputError(ts.source(), ts.line(), name, "must be a positive count, is " + std::to_string(n));
  return static_cast<int>(n);
}

void append_double(std::string& s, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof(buf), v);
  s.append(buf, r.ptr);
}

}  // namespace

BalProblem read_bal(std::istream& in, const std::string& source, BalReadReport* report) {
  TokenStream ts(in, source);
  BalProblem p;
  p.source = source;
  const int nc = count(ts, "num_cameras"), np = count(ts, "num_points"), no = count(ts, "num_observations");
  // Reserve at most what a plausible file of this size could hold (counts come from the input).
  p.observations.reserve(static_cast<std::size_t>(std::min(no, 1 << 20)));
  for (int k = 0; k < no; ++k) {
    BalObservation o;
    const std::string at = "observation " + std::to_string(k);
    const std::int64_t c = ts.integer(at + " camera");
    if (c < 0 || c >= nc)
      throw InputError(source, ts.line(), at + " camera",
                       "camera index " + std::to_string(c) + " out of range (the file has " + std::to_string(nc) +
                           " cameras)");
    const std::int64_t j = ts.integer(at + " point");
    if (j < 0 || j >= np)
      throw InputError(source, ts.line(), at + " point",
                       "point index " + std::to_string(j) + " out of range (the file has " + std::to_string(np) +
                           " points)");
    o.camera = static_cast<int>(c), o.point = static_cast<int>(j);
    o.pixel.x() = ts.number(at + " x");
    o.pixel.y() = ts.number(at + " y");
    p.observations.push_back(o);
  }
  static const char* cam_fields[9] = {"rx", "ry", "rz", "tx", "ty", "tz", "f", "k1", "k2"};
  p.cameras.reserve(static_cast<std::size_t>(std::min(nc, 1 << 16)));
  for (int i = 0; i < nc; ++i) {
    BalProblem::CameraParams c;
    for (int a = 0; a < 9; ++a) c[a] = ts.number("camera " + std::to_string(i) + " " + cam_fields[a]);
    p.cameras.push_back(c);
  }
  static const char* pt_fields[3] = {"x", "y", "z"};
  p.points.reserve(static_cast<std::size_t>(std::min(np, 1 << 20)));
  for (int j = 0; j < np; ++j) {
    Eigen::Vector3d X;
    for (int a = 0; a < 3; ++a) X[a] = ts.number("point " + std::to_string(j) + " " + pt_fields[a]);
    p.points.push_back(X);
  }
  ts.expect_end();

  if (report) {
    std::vector<int> seen(np, 0);
    std::vector<char> cam_seen(nc, 0);
    for (const BalObservation& o : p.observations) ++seen[o.point], cam_seen[o.camera] = 1;
    const auto unseen = std::count(seen.begin(), seen.end(), 0);
    const auto once = std::count(seen.begin(), seen.end(), 1);
    const auto no_cam = std::count(cam_seen.begin(), cam_seen.end(), 0);
    if (unseen) report->warnings.push_back(std::to_string(unseen) + " points have no observation (left unchanged)");
    if (once) report->warnings.push_back(std::to_string(once) + " points are seen by only one camera (not constrained in depth)");
    if (no_cam) report->warnings.push_back(std::to_string(no_cam) + " cameras observe nothing (left unchanged)");
  }
  return p;
}

BalProblem read_bal(const std::string& path, BalReadReport* report) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  return read_bal(in, path, report);
}

std::string bal_to_string(const BalProblem& p) {
  std::string s;
  s.reserve(64 * (p.observations.size() + p.cameras.size() * 9 + p.points.size() * 3));
  s += std::to_string(p.cameras.size()) + " " + std::to_string(p.points.size()) + " " +
       std::to_string(p.observations.size()) + "\n";
  for (const BalObservation& o : p.observations) {
    s += std::to_string(o.camera) + " " + std::to_string(o.point) + " ";
    append_double(s, o.pixel.x());
    s += ' ';
    append_double(s, o.pixel.y());
    s += '\n';
  }
  for (const auto& c : p.cameras)
    for (int a = 0; a < 9; ++a) append_double(s, c[a]), s += '\n';
  for (const auto& X : p.points)
    for (int a = 0; a < 3; ++a) append_double(s, X[a]), s += '\n';
  return s;
}

void write_bal(std::ostream& out, const BalProblem& p) { out << bal_to_string(p); }

void write_bal(const std::string& path, const BalProblem& p) { write_file_atomically(path, bal_to_string(p)); }

bool looks_like_bal_path(const std::string& path) {
  const std::string name = path.substr(path.find_last_of('/') == std::string::npos ? 0 : path.find_last_of('/') + 1);
  auto ends_with = [&](const std::string& e) {
    return name.size() >= e.size() && name.compare(name.size() - e.size(), e.size(), e) == 0;
  };
  return ends_with(".bal") || (name.rfind("problem-", 0) == 0 && ends_with(".txt")) || ends_with("-pre.txt");
}

void validate_bal_geometry(const BalProblem& p, BalReadReport* report) {
  // Line of point j's first coordinate in the one-value-per-line layout.
  const long base = 2L + p.num_observations() + 9L * p.num_cameras();
  std::vector<char> in_front(p.points.size(), 0), seen(p.points.size(), 0);
  long behind = 0;
  for (std::size_t k = 0; k < p.observations.size(); ++k) {
    const BalObservation& o = p.observations[k];
    double pz = 0.0;
    const Eigen::Vector2d u = bal_project(p.cameras[o.camera], p.points[o.point], &pz);
    if (!u.allFinite())
      throw InputError(p.source, static_cast<int>(2 + k), "observation " + std::to_string(k),
                       "the predicted pixel is not finite (point " + std::to_string(o.point) + " on the plane of camera " +
                           std::to_string(o.camera) + ", or huge values)");
    seen[o.point] = 1;
    if (pz < 0.0) in_front[o.point] = 1; else ++behind;
  }
  long all_behind = 0, first = -1;
  for (std::size_t j = 0; j < p.points.size(); ++j)
    if (seen[j] && !in_front[j]) {
      if (all_behind++ == 0) first = static_cast<long>(j);
    }
  // Real BAL files contain such points (problem-49-7776 has some); they are optimized like the
  // others (the residual stays finite), so this is reported, not rejected.
  if (report && all_behind > 0)
    report->warnings.push_back(std::to_string(all_behind) +
                               " points are behind every camera that observes them (BAL cameras look down -z; first: "
                               "point " + std::to_string(first) + ", " + p.source + ":" +
                               std::to_string(base + 3 * first) + ")");
  if (report && behind > 0)
    report->warnings.push_back(std::to_string(behind) + " observations have their point behind the camera");
}

void write_bal_ply(const std::string& path, const BalProblem& p) {
  std::string s = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(p.points.size() + p.cameras.size()) +
                  "\nproperty float x\nproperty float y\nproperty float z\n"
                  "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  for (const auto& X : p.points) {
    for (int a = 0; a < 3; ++a) append_double(s, X[a]), s += ' ';
    s += "255 255 255\n";
  }
  for (const auto& c : p.cameras) {
    const Eigen::Vector3d C = bal_camera_center(c);
    for (int a = 0; a < 3; ++a) append_double(s, C[a]), s += ' ';
    s += "0 255 0\n";
  }
  write_file_atomically(path, s);
}

}  // namespace slamkit
