#include "slamkit/io/trajectory_io.h"

#include <Eigen/Geometry>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <ostream>
#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/core/output_file.h"
#include "pose_graph_format.h"  // io_detail::exact_unit_quaternion
#include "slamkit/io/text_reader.h"

namespace slamkit {

namespace {

constexpr const char* kSlamkitHeader = "# slamkit trajectory 1";
constexpr const char* kMetaPrefix = "# meta ";
constexpr double kUnitTolerance = 1e-2;  // |‖q‖ − 1| and |RᵀR − I| accepted before normalizing

// ---- numbers ---------------------------------------------------------------------------

/// Shortest decimal text that parses back to exactly v.
std::string fmt(double v) {
  std::array<char, 32> buf{};
  const auto res = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return std::string(buf.data(), res.ptr);
}

/// Exact "s.nnnnnnnnn" for an integer ns stamp.
std::string fmt_ns_as_seconds(std::int64_t ns) {
  const bool neg = ns < 0;
  const std::uint64_t a = neg ? 0ull - static_cast<std::uint64_t>(ns) : static_cast<std::uint64_t>(ns);
  std::string frac = std::to_string(a % 1000000000ull);
  frac.insert(0, 9 - frac.size(), '0');
  return (neg ? "-" : "") + std::to_string(a / 1000000000ull) + "." + frac;
}

std::string stamp_text(const TrajectorySample& s) { return s.stamp_ns ? fmt_ns_as_seconds(*s.stamp_ns) : fmt(s.stamp); }

/// ns value of a plain decimal "[-]D+[.D{0,9}]" (no exponent), if it fits in int64.
std::optional<std::int64_t> exact_ns(std::string_view tok) {
  bool neg = false;
  if (!tok.empty() && (tok.front() == '-' || tok.front() == '+')) {
    neg = tok.front() == '-';
    tok.remove_prefix(1);
  }
  const std::size_t dot = tok.find('.');
  const std::string_view ip = tok.substr(0, dot);
  const std::string_view fp = dot == std::string_view::npos ? std::string_view() : tok.substr(dot + 1);
  if (ip.empty() || fp.size() > 9 || ip.size() > 10) return std::nullopt;
  std::int64_t v = 0;
  for (char c : ip) {
    if (c < '0' || c > '9') return std::nullopt;
    v = v * 10 + (c - '0');
  }
  std::int64_t f = 0;
  for (std::size_t k = 0; k < 9; ++k) {
    if (k < fp.size() && (fp[k] < '0' || fp[k] > '9')) return std::nullopt;
    f = f * 10 + (k < fp.size() ? fp[k] - '0' : 0);
  }
  if (v > (std::numeric_limits<std::int64_t>::max() - f) / 1000000000) return std::nullopt;
  const std::int64_t ns = v * 1000000000 + f;
  return neg ? -ns : ns;
}

// ---- shared parsing --------------------------------------------------------------------

/// Reads fields [first, first+3) as a vector.
Eigen::Vector3d vec3(const TextReader& r, std::size_t first, const char* n0, const char* n1, const char* n2) {
  return Eigen::Vector3d(r.number(first, n0), r.number(first + 1, n1), r.number(first + 2, n2));
}

SO3 checked_quaternion(const TextReader& r, double w, double x, double y, double z) {
  const Eigen::Quaterniond q(w, x, y, z);
  const double n = q.norm();
  if (std::abs(n - 1.0) > kUnitTolerance)
    r.fail("quaternion", "norm " + fmt(n) + " is not 1 (tolerance " + fmt(kUnitTolerance) + ")");
  // An exact-unit quaternion is a fixed point of normalization: written and read back, it
  // gives the same bits (the round trip the fuzzer checks).
  return SO3(io_detail::exact_unit_quaternion(q));
}

void append(Trajectory& traj, const TextReader& r, TrajectorySample s) {
  if (!traj.empty() && s.stamp < traj.samples().back().stamp)
    r.fail("timestamp", "goes back in time: " + std::string(r.field(0)) + " after " +
                            fmt(traj.samples().back().stamp));
  traj.push_back(std::move(s));
}

/// Stamp of a TUM-like line: seconds, with the exact ns when the text is a plain decimal.
void read_seconds_stamp(const TextReader& r, TrajectorySample& s) {
  s.stamp = r.number(0, "timestamp") + 0.0;  // + 0.0 turns −0 into 0: the ns text has no signed zero
  s.stamp_ns = exact_ns(r.field(0));
}

/// Parses a TUM line body (fields 1..7) and optional state columns starting at 8.
void read_tum_pose(const TextReader& r, TrajectorySample& s) {
  const Eigen::Vector3d t = vec3(r, 1, "tx", "ty", "tz");
  const SO3 R = checked_quaternion(r, r.number(7, "qw"), r.number(4, "qx"), r.number(5, "qy"), r.number(6, "qz"));
  s.T_world_body = SE3(R, t);
}

void read_state_columns(const TextReader& r, std::size_t first, TrajectorySample& s) {
  const std::size_t n = r.num_fields() - first;
  if (n >= 3) s.v_world = vec3(r, first, "vx", "vy", "vz");
  if (n >= 9) {
    ImuBias b;
    b.gyro = vec3(r, first + 3, "bgx", "bgy", "bgz");
    b.accel = vec3(r, first + 6, "bax", "bay", "baz");
    s.bias = b;
  }
}

void expect_one_of(const TextReader& r, std::initializer_list<std::size_t> counts, const char* what) {
  for (std::size_t c : counts)
    if (r.num_fields() == c) return;
  std::string allowed;
  for (std::size_t c : counts) allowed += (allowed.empty() ? "" : " or ") + std::to_string(c);
  r.fail("", std::string(what) + " needs " + allowed + " fields, line has " + std::to_string(r.num_fields()));
}

/// Rows with optional state columns must all have the layout of the first one: a trajectory
/// either has velocities (biases) for every sample or for none, as the writers write it.
void expect_same_layout(const TextReader& r, std::size_t* columns) {
  if (*columns == 0) *columns = r.num_fields();
  if (r.num_fields() != *columns)
    r.fail("", "row has " + std::to_string(r.num_fields()) + " fields but the first row had " +
                   std::to_string(*columns) + ": every row needs the same columns");
}

bool starts_with(std::string_view s, std::string_view p) { return s.substr(0, p.size()) == p; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

/// Why a metadata key or value cannot be stored in a "# meta KEY=VALUE" line, or nullptr.
/// Reader and writer share this rule, so whatever reads also writes and reads back the same:
/// no control characters (the line would break or change), no leading or trailing blanks (the
/// reader trims them), and a key is non-empty without '='.
const char* metadata_problem(std::string_view text, bool is_key) {
  for (const char c : text)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return "contains a control character";
  if (is_key && text.empty()) return "empty key";
  if (is_key && text.find('=') != std::string_view::npos) return "'=' in the key";
  if (!text.empty() && (text.front() == ' ' || text.back() == ' ')) return "leading or trailing blanks";
  return nullptr;
}

void write_quaternion_xyzw(std::ostream& out, const Eigen::Quaterniond& q) {
  out << fmt(q.x()) << ' ' << fmt(q.y()) << ' ' << fmt(q.z()) << ' ' << fmt(q.w());
}

}  // namespace

// ---- format names ----------------------------------------------------------------------

const char* to_string(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kTum: return "tum";
    case TrajectoryFormat::kEuroc: return "euroc";
    case TrajectoryFormat::kKitti: return "kitti";
    case TrajectoryFormat::kSlamkit: return "slamkit";
  }
  return "?";
}

TrajectoryFormat parse_trajectory_format(std::string_view name) {
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "euroc" || name == "asl") return TrajectoryFormat::kEuroc;
  if (name == "kitti") return TrajectoryFormat::kKitti;
  if (name == "slamkit") return TrajectoryFormat::kSlamkit;
  throw InputError("", 0, "format", "unknown trajectory format '" + std::string(name) +
                                        "' (expected tum, euroc, kitti or slamkit)");
}

TrajectoryFormat detect_trajectory_format(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  std::string line;
  while (std::getline(in, line)) {
    const std::string_view t = trim(line);
    if (t.empty()) continue;
    if (t == kSlamkitHeader) return TrajectoryFormat::kSlamkit;
    if (t.front() == '#') continue;
    break;
  }
  if (path.size() >= 4 && path.compare(path.size() - 4, 4, ".csv") == 0) return TrajectoryFormat::kEuroc;
  std::istringstream fields(line);
  std::size_t n = 0;
  for (std::string tok; fields >> tok;) ++n;
  return n == 12 ? TrajectoryFormat::kKitti : TrajectoryFormat::kTum;
}

// ---- readers ---------------------------------------------------------------------------

Trajectory read_tum(std::istream& in, const std::string& source) {
  TextReader r(in, source);
  Trajectory traj;
  while (r.next_line()) {
    r.expect_fields(8, "TUM pose (t x y z qx qy qz qw)");
    TrajectorySample s;
    read_seconds_stamp(r, s);
    read_tum_pose(r, s);
    append(traj, r, std::move(s));
  }
  return traj;
}

Trajectory read_euroc(std::istream& in, const std::string& source) {
  TextReader::Options opt;
  opt.delimiter = ',';
  TextReader r(in, source, opt);
  Trajectory traj;
  bool first = true;
  std::size_t columns = 0;
  while (r.next_line()) {
    // A header without '#' ("timestamp,p_RS_R_x,...") is accepted on the first line only.
    const bool header = first && !r.field(0).empty() && std::isalpha(static_cast<unsigned char>(r.field(0)[0]));
    first = false;
    if (header) continue;
    expect_one_of(r, {8, 11, 17}, "EuRoC/ASL row (t_ns, p, q_wxyz[, v[, b_w, b_a]])");
    expect_same_layout(r, &columns);
    TrajectorySample s;
    const std::int64_t ns = r.integer(0, "timestamp");
    s.stamp_ns = ns;
    s.stamp = static_cast<double>(ns) / 1e9;  // as evo: float(ns) / 1e9
    const Eigen::Vector3d t = vec3(r, 1, "p_x", "p_y", "p_z");
    const SO3 R = checked_quaternion(r, r.number(4, "q_w"), r.number(5, "q_x"), r.number(6, "q_y"), r.number(7, "q_z"));
    s.T_world_body = SE3(R, t);
    read_state_columns(r, 8, s);
    append(traj, r, std::move(s));
  }
  return traj;
}

Trajectory read_kitti(std::istream& in, const std::string& source) {
  static const char* kNames[12] = {"r11", "r12", "r13", "tx", "r21", "r22", "r23", "ty", "r31", "r32", "r33", "tz"};
  TextReader r(in, source);
  Trajectory traj;
  traj.set_has_timestamps(false);
  while (r.next_line()) {
    r.expect_fields(12, "KITTI pose (3x4 row-major)");
    Eigen::Matrix<double, 3, 4> T;
    for (int k = 0; k < 12; ++k) T(k / 4, k % 4) = r.number(static_cast<std::size_t>(k), kNames[k]);
    const Eigen::Matrix3d R = T.leftCols<3>();
    const double ortho = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    if (ortho > kUnitTolerance || R.determinant() <= 0.0)
      r.fail("rotation", "not a rotation matrix (max |RᵀR − I| = " + fmt(ortho) + ", det " + fmt(R.determinant()) + ")");
    TrajectorySample s;
    s.stamp = static_cast<double>(traj.size());
    s.T_world_body = SE3::from_matrix(T);
    s.source_rotation = R;
    traj.push_back(std::move(s));
  }
  return traj;
}

Trajectory read_slamkit_trajectory(std::istream& in, const std::string& source) {
  TextReader::Options opt;
  opt.comment_prefix.clear();  // '#' lines carry the header and metadata: handled here
  TextReader r(in, source, opt);
  Trajectory traj;
  bool seen_header = false;
  std::size_t columns = 0;
  while (r.next_line()) {
    const std::string_view line = trim(r.line());
    if (!seen_header) {
      if (line != kSlamkitHeader) r.fail("header", "expected '" + std::string(kSlamkitHeader) + "' as the first line");
      seen_header = true;
      continue;
    }
    if (starts_with(line, kMetaPrefix)) {
      const std::string_view kv = trim(line.substr(std::string_view(kMetaPrefix).size()));
      const std::size_t eq = kv.find('=');
      if (eq == std::string_view::npos || eq == 0) r.fail("meta", "expected '# meta KEY=VALUE'");
      const std::string_view key = trim(kv.substr(0, eq)), value = trim(kv.substr(eq + 1));
      if (const char* problem = metadata_problem(key, true)) r.fail("meta", std::string("key: ") + problem);
      if (const char* problem = metadata_problem(value, false)) r.fail("meta", std::string("value: ") + problem);
      traj.metadata[std::string(key)] = std::string(value);
      continue;
    }
    if (line.front() == '#') continue;
    expect_one_of(r, {8, 11, 17}, "slamkit pose (t x y z qx qy qz qw[ vx vy vz[ bg ba]])");
    expect_same_layout(r, &columns);
    TrajectorySample s;
    read_seconds_stamp(r, s);
    read_tum_pose(r, s);
    read_state_columns(r, 8, s);
    append(traj, r, std::move(s));
  }
  if (!seen_header) throw InputError(source, 0, "header", "empty file (no '" + std::string(kSlamkitHeader) + "' line)");
  return traj;
}

Trajectory read_trajectory(std::istream& in, const std::string& source, TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kTum: return read_tum(in, source);
    case TrajectoryFormat::kEuroc: return read_euroc(in, source);
    case TrajectoryFormat::kKitti: return read_kitti(in, source);
    case TrajectoryFormat::kSlamkit: return read_slamkit_trajectory(in, source);
  }
  throw InputError(source, 0, "format", "unknown trajectory format");
}

Trajectory read_trajectory(const std::string& path, TrajectoryFormat format) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open file");
  Trajectory traj = read_trajectory(in, path, format);
  if (traj.empty()) throw InputError(path, 0, "", std::string("no poses found (read as ") + to_string(format) + ")");
  return traj;
}

Trajectory read_trajectory(const std::string& path) { return read_trajectory(path, detect_trajectory_format(path)); }

// ---- writers ---------------------------------------------------------------------------

void write_tum(std::ostream& out, const Trajectory& traj) {
  out << "# timestamp tx ty tz qx qy qz qw\n";
  for (const auto& s : traj) {
    const Eigen::Vector3d& t = s.T_world_body.translation();
    out << stamp_text(s) << ' ' << fmt(t.x()) << ' ' << fmt(t.y()) << ' ' << fmt(t.z()) << ' ';
    write_quaternion_xyzw(out, s.T_world_body.rotation().quaternion());
    out << '\n';
  }
}

void write_euroc(std::ostream& out, const Trajectory& traj) {
  const bool vel = traj.has_velocities();
  const bool bias = vel && traj.has_biases();
  out << "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],q_RS_z []";
  if (vel) out << ",v_RS_R_x [m s^-1],v_RS_R_y [m s^-1],v_RS_R_z [m s^-1]";
  if (bias)
    out << ",b_w_RS_S_x [rad s^-1],b_w_RS_S_y [rad s^-1],"
           "b_w_RS_S_z [rad s^-1],b_a_RS_S_x [m s^-2],b_a_RS_S_y [m s^-2],b_a_RS_S_z [m s^-2]";
  out << '\n';
  for (const auto& s : traj) {
    const std::int64_t ns = s.stamp_ns ? *s.stamp_ns : std::llround(s.stamp * 1e9);
    const Eigen::Vector3d& t = s.T_world_body.translation();
    const Eigen::Quaterniond& q = s.T_world_body.rotation().quaternion();
    out << ns << ',' << fmt(t.x()) << ',' << fmt(t.y()) << ',' << fmt(t.z()) << ',' << fmt(q.w()) << ','
        << fmt(q.x()) << ',' << fmt(q.y()) << ',' << fmt(q.z());
    if (vel) out << ',' << fmt(s.v_world->x()) << ',' << fmt(s.v_world->y()) << ',' << fmt(s.v_world->z());
    if (bias)
      for (const Eigen::Vector3d* v : {&s.bias->gyro, &s.bias->accel})
        out << ',' << fmt(v->x()) << ',' << fmt(v->y()) << ',' << fmt(v->z());
    out << '\n';
  }
}

void write_kitti(std::ostream& out, const Trajectory& traj) {
  for (const auto& s : traj) {
    Eigen::Matrix<double, 3, 4> T;
    T << s.rotation_matrix(), s.T_world_body.translation();
    for (int k = 0; k < 12; ++k) out << (k ? " " : "") << fmt(T(k / 4, k % 4));
    out << '\n';
  }
}

void write_slamkit_trajectory(std::ostream& out, const Trajectory& traj) {
  const bool vel = traj.has_velocities();
  const bool bias = vel && traj.has_biases();
  out << kSlamkitHeader << '\n';
  for (const auto& [key, value] : traj.metadata) {
    const char* problem = metadata_problem(key, true);
    if (!problem) problem = metadata_problem(value, false);
    if (problem) throw InputError("", 0, "meta", "metadata '" + key + "' not writable: " + problem);
    out << kMetaPrefix << key << '=' << value << '\n';
  }
  out << "# t x y z qx qy qz qw" << (vel ? " vx vy vz" : "") << (bias ? " bgx bgy bgz bax bay baz" : "") << '\n';
  for (const auto& s : traj) {
    const Eigen::Vector3d& t = s.T_world_body.translation();
    out << stamp_text(s) << ' ' << fmt(t.x()) << ' ' << fmt(t.y()) << ' ' << fmt(t.z()) << ' ';
    write_quaternion_xyzw(out, s.T_world_body.rotation().quaternion());
    if (vel) out << ' ' << fmt(s.v_world->x()) << ' ' << fmt(s.v_world->y()) << ' ' << fmt(s.v_world->z());
    if (bias)
      for (const Eigen::Vector3d* v : {&s.bias->gyro, &s.bias->accel})
        out << ' ' << fmt(v->x()) << ' ' << fmt(v->y()) << ' ' << fmt(v->z());
    out << '\n';
  }
}

void write_trajectory(std::ostream& out, const Trajectory& traj, TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kTum: return write_tum(out, traj);
    case TrajectoryFormat::kEuroc: return write_euroc(out, traj);
    case TrajectoryFormat::kKitti: return write_kitti(out, traj);
    case TrajectoryFormat::kSlamkit: return write_slamkit_trajectory(out, traj);
  }
}

void write_trajectory(const std::string& path, const Trajectory& traj, TrajectoryFormat format) {
  std::ostringstream out;
  write_trajectory(out, traj, format);  // formats everything first: a failure leaves no file
  write_file_atomically(path, out.str());
}

}  // namespace slamkit
