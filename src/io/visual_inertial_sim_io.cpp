#include "slamkit/io/visual_inertial_sim_io.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <ostream>
#include <set>
#include <stdexcept>
#include <vector>

#include "pose_graph_format.h"
#include "slamkit/core/error.h"
#include "slamkit/core/output_file.h"
#include "slamkit/io/text_reader.h"

namespace slamkit {
namespace {

constexpr const char* kHeader = "# slamkit visual-inertial simulation 1";
const char* const kHeaderRecords[] = {"source",  "seed",     "dynamic", "camera",  "mask_radius", "T_cam_imu",
                                      "imu_noise", "imu_rate", "gravity", "pixel_noise"};

using io_detail::append_integer;
using io_detail::append_number;
using io_detail::append_numbers;  // via add(), which rejects non-finite values

Eigen::Vector3d vec3(const TextReader& r, std::size_t i, const char* name) {
  const std::string n(name);
  return Eigen::Vector3d(r.number(i, n + "_x"), r.number(i + 1, n + "_y"), r.number(i + 2, n + "_z"));
}

// A quaternion w x y z within 1e-6 of unit norm; normalized unless already unit to 1e-12
// (so that the written values read back bit-identical).
Eigen::Quaterniond quat(const TextReader& r, std::size_t i) {
  const Eigen::Quaterniond q(r.number(i, "qw"), r.number(i + 1, "qx"), r.number(i + 2, "qy"), r.number(i + 3, "qz"));
  const double n = q.norm();
  if (std::abs(n - 1.0) > 1e-6) r.fail("qw", "quaternion is not unit (norm " + std::to_string(n) + ")");
  return std::abs(n - 1.0) < 1e-12 ? q : q.normalized();
}

double positive_or_zero(const TextReader& r, std::size_t i, const char* name) {
  const double v = r.number(i, name);
  if (v < 0.0) r.fail(name, "must be >= 0");
  return v;
}

}  // namespace

VisualInertialSim read_visual_inertial_sim(std::istream& in, const std::string& source) {
  TextReader::Options opt;
  opt.comment_prefix = "";  // '#' lines are handled here: the first one is the header
  TextReader r(in, source, opt);
  if (!r.next_line() || r.line() != kHeader) {
    if (r.line_number() == 0) throw InputError(source, 0, "header", "empty file (expected '" + std::string(kHeader) + "')");
    r.fail("header", "first line must be '" + std::string(kHeader) + "'");
  }
  VisualInertialSim sim;
  std::set<std::string> seen;
  bool body = false;
  struct PendingFrame {
    int line;
    std::size_t expected;
  };
  std::vector<PendingFrame> frame_lines;
  std::vector<int> obs_lines;  // line of each observation, for errors found at the end
  std::size_t open_obs = 0;    // observations still expected by the last frame
  bool expect_truth = false;
  std::set<std::int64_t> frame_tracks;
  const auto close_frame = [&]() {
    if (open_obs > 0)
      r.fail("obs", "frame at line " + std::to_string(frame_lines.back().line) + " expects " +
                        std::to_string(frame_lines.back().expected) + " observations, got " +
                        std::to_string(frame_lines.back().expected - open_obs));
  };
  while (r.next_line()) {
    const std::string tag(r.field(0));
    if (tag[0] == '#') continue;
    if (tag != "obs") close_frame();
    if (expect_truth && tag != "truth") r.fail("truth", "an imu line must be followed by its truth line");
    const bool header_record = std::find(std::begin(kHeaderRecords), std::end(kHeaderRecords), tag) != std::end(kHeaderRecords);
    if (header_record) {
      if (body) r.fail(tag, "header record after the first landmark/imu/frame record");
      if (!seen.insert(tag).second) r.fail(tag, "repeated header record");
    }
    if (tag == "source") {
      r.expect_fields(2, tag);
      sim.source = std::string(r.field(1));
    } else if (tag == "seed") {
      r.expect_fields(2, tag);
      const std::int64_t s = r.integer(1, "seed");
      if (s < 0) r.fail("seed", "must be >= 0");
      sim.seed = static_cast<std::uint64_t>(s);
    } else if (tag == "dynamic") {
      r.expect_fields(2, tag);
      try {
        sim.dynamic = parse_dynamic_level(std::string(r.field(1)));
      } catch (const InputError&) {
        r.fail("dynamic", "expected none, low or high");
      }
    } else if (tag == "camera") {
      r.expect_min_fields(4, tag);
      const std::string model(r.field(1));
      const std::int64_t w = r.integer(2, "width"), h = r.integer(3, "height");
      if (w < 1 || h < 1 || w > 100000 || h > 100000) r.fail("width", "resolution must be positive");
      std::vector<double> k;
      for (std::size_t i = 4; i < r.num_fields(); ++i) k.push_back(r.number(i, "intrinsics"));
      try {
        sim.camera = make_camera_model(model, k, static_cast<int>(w), static_cast<int>(h));
      } catch (const std::invalid_argument& e) {
        r.fail("camera", e.what());
      }
    } else if (tag == "mask_radius") {
      r.expect_fields(2, tag);
      sim.mask_radius_px = positive_or_zero(r, 1, "mask_radius");
    } else if (tag == "T_cam_imu") {
      r.expect_fields(8, tag);
      sim.T_cam_imu = SE3(SO3(quat(r, 4)), vec3(r, 1, "t"));
    } else if (tag == "imu_noise") {
      r.expect_fields(5, tag);
      sim.imu_noise = ImuNoiseDensities{positive_or_zero(r, 1, "gyro_noise_density"),
                                        positive_or_zero(r, 2, "gyro_random_walk"),
                                        positive_or_zero(r, 3, "accel_noise_density"),
                                        positive_or_zero(r, 4, "accel_random_walk")};
    } else if (tag == "imu_rate") {
      r.expect_fields(2, tag);
      sim.imu_rate = r.number(1, "imu_rate");
      if (!(sim.imu_rate > 0.0)) r.fail("imu_rate", "must be > 0");
    } else if (tag == "gravity") {
      r.expect_fields(4, tag);
      sim.gravity_world = vec3(r, 1, "gravity");
    } else if (tag == "pixel_noise") {
      r.expect_fields(2, tag);
      sim.pixel_noise_sigma = positive_or_zero(r, 1, "pixel_noise");
    } else if (tag == "landmark" || tag == "group" || tag == "imu" || tag == "truth" || tag == "frame" || tag == "obs") {
      if (!body) {
        for (const char* need : kHeaderRecords)
          if (!seen.count(need)) r.fail(need, "missing header record before the data");
        body = true;
      }
      if (tag == "landmark") {
        r.expect_fields(6, tag);
        SimLandmark l;
        l.id = r.integer(1, "id");
        if (l.id != static_cast<std::int64_t>(sim.landmarks.size()))
          r.fail("id", "landmark ids must be 0, 1, 2, ... in order (expected " + std::to_string(sim.landmarks.size()) + ")");
        const std::int64_t g = r.integer(2, "group");
        if (g < -1 || g > 1000000) r.fail("group", "must be -1 (static) or a group id");
        l.group = static_cast<int>(g);
        l.position = vec3(r, 3, "p");
        sim.landmarks.push_back(l);
      } else if (tag == "group") {
        r.expect_fields(11, tag);
        SimMovingGroup g;
        const std::int64_t id = r.integer(1, "id");
        if (id != static_cast<std::int64_t>(sim.groups.size()))
          r.fail("id", "group ids must be 0, 1, 2, ... in order (expected " + std::to_string(sim.groups.size()) + ")");
        g.id = static_cast<int>(id);
        g.t_on = r.number(2, "t_on");
        g.t_off = r.number(3, "t_off");
        if (g.t_off < g.t_on) r.fail("t_off", "before t_on");
        g.start = vec3(r, 4, "start");
        g.velocity = vec3(r, 7, "velocity");
        g.yaw = r.number(10, "yaw");
        sim.groups.push_back(g);
      } else if (tag == "imu") {
        r.expect_fields(8, tag);
        SimImuSample m;
        m.t = r.number(1, "t");
        if (!sim.imu.empty() && !(m.t > sim.imu.back().t)) r.fail("t", "IMU times must increase");
        m.gyro = vec3(r, 2, "gyro");
        m.accel = vec3(r, 5, "accel");
        sim.imu.push_back(m);
        expect_truth = true;
      } else if (tag == "truth") {
        r.expect_fields(18, tag);
        if (!expect_truth) r.fail("truth", "a truth line must follow an imu line");
        SimState x;
        x.t = r.number(1, "t");
        if (x.t != sim.imu.back().t) r.fail("t", "truth time differs from its imu line's");
        x.p_world = vec3(r, 2, "p");
        x.v_world = vec3(r, 5, "v");
        x.q_world_imu = quat(r, 8);
        x.b_a = vec3(r, 12, "b_a");
        x.b_g = vec3(r, 15, "b_g");
        sim.imu_truth.push_back(x);
        expect_truth = false;
      } else if (tag == "frame") {
        r.expect_fields(3, tag);
        SimFrame f;
        f.t = r.number(1, "t");
        if (!sim.frames.empty() && !(f.t > sim.frames.back().t)) r.fail("t", "frame times must increase");
        const std::int64_t n = r.integer(2, "observations");
        if (n < 0 || n > 1000000) r.fail("observations", "bad count");
        sim.frames.push_back(f);
        frame_lines.push_back({r.line_number(), static_cast<std::size_t>(n)});
        open_obs = static_cast<std::size_t>(n);
        frame_tracks.clear();
      } else {  // obs
        r.expect_fields(6, tag);
        if (sim.frames.empty() || open_obs == 0) r.fail("obs", "observation outside a frame (or more than its count)");
        SimObservation o;
        o.track_id = r.integer(1, "track");
        if (o.track_id < 0) r.fail("track", "must be >= 0");
        if (!frame_tracks.insert(o.track_id).second) r.fail("track", "repeated in the frame");
        o.landmark_id = r.integer(2, "landmark");
        o.uv = Eigen::Vector2d(r.number(3, "u"), r.number(4, "v"));
        const std::string_view label = r.field(5);
        if (label != "s" && label != "d") r.fail("label", "expected s (static) or d (dynamic)");
        o.dynamic = label == "d";
        sim.frames.back().observations.push_back(o);
        obs_lines.push_back(r.line_number());
        --open_obs;
      }
    } else {
      r.fail("record", "unknown record '" + tag.substr(0, 40) + "'");
    }
  }
  close_frame();
  if (expect_truth) r.fail("truth", "the last imu line has no truth line");
  if (!body)
    for (const char* need : kHeaderRecords)
      if (!seen.count(need)) r.fail(need, "missing header record");
  if (sim.imu.empty()) r.fail("imu", "no IMU samples");
  if (sim.frames.empty()) r.fail("frame", "no frames");
  // Cross references, checked once everything is read.
  for (const SimLandmark& l : sim.landmarks)
    if (l.group >= static_cast<int>(sim.groups.size()))
      throw InputError(source, 0, "group", "landmark " + std::to_string(l.id) + " refers to group " +
                                                std::to_string(l.group) + ", which is not defined");
  std::size_t k = 0;
  for (std::size_t f = 0; f < sim.frames.size(); ++f) {
    SimFrame& frame = sim.frames[f];
    const auto it = std::lower_bound(sim.imu.begin(), sim.imu.end(), frame.t,
                                     [](const SimImuSample& m, double t) { return m.t < t; });
    if (it == sim.imu.end() || it->t != frame.t)
      throw InputError(source, frame_lines[f].line, "t", "frame time is not the time of an IMU sample");
    frame.imu_index = static_cast<std::size_t>(it - sim.imu.begin());
    frame.truth = sim.imu_truth[frame.imu_index];
    for (const SimObservation& o : frame.observations) {
      const int line = obs_lines[k++];
      if (o.landmark_id < 0 || o.landmark_id >= static_cast<std::int64_t>(sim.landmarks.size()))
        throw InputError(source, line, "landmark", "unknown landmark " + std::to_string(o.landmark_id));
      if (o.dynamic != (sim.landmarks[static_cast<std::size_t>(o.landmark_id)].group >= 0))
        throw InputError(source, line, "label", "label disagrees with the landmark's group");
    }
  }
  return sim;
}

VisualInertialSim read_visual_inertial_sim(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, 0, "", "cannot open file");
  return read_visual_inertial_sim(f, path);
}

namespace {

// ' ' + shortest round-trip text of each value; a non-finite value cannot be written.
void add(std::string& out, std::initializer_list<double> values) {
  for (double v : values)
    if (!std::isfinite(v)) throw std::invalid_argument("write_visual_inertial_sim: a number is not finite");
  append_numbers(out, values);
}
void append_vec(std::string& out, const Eigen::Vector3d& v) { add(out, {v.x(), v.y(), v.z()}); }
void append_quat(std::string& out, const Eigen::Quaterniond& q) { add(out, {q.w(), q.x(), q.y(), q.z()}); }

std::string to_text(const VisualInertialSim& sim) {
  if (!sim.camera) throw std::invalid_argument("write_visual_inertial_sim: no camera");
  std::string out;
  out.reserve(64 * (sim.imu.size() * 3 + sim.landmarks.size()) + 48 * 160 * sim.frames.size());
  out += kHeader;
  std::string src = sim.source.empty() ? std::string("unknown") : sim.source;
  for (char& c : src)
    if (c == ' ' || c == '\t' || c == '\n' || c == '\r') c = '_';
  out += "\nsource " + src + "\nseed ";
  append_integer(out, static_cast<std::int64_t>(sim.seed));
  out += std::string("\ndynamic ") + to_string(sim.dynamic) + "\ncamera " + sim.camera->model_name() + ' ';
  append_integer(out, sim.camera->width());
  out += ' ';
  append_integer(out, sim.camera->height());
  const Eigen::VectorXd k = sim.camera->intrinsics();
  for (Eigen::Index i = 0; i < k.size(); ++i) add(out, {k(i)});
  out += "\nmask_radius";
  add(out, {sim.mask_radius_px});
  out += "\nT_cam_imu";
  append_vec(out, sim.T_cam_imu.translation());
  append_quat(out, sim.T_cam_imu.rotation().quaternion());
  out += "\nimu_noise";
  add(out, {sim.imu_noise.gyro_noise_density, sim.imu_noise.gyro_random_walk,
                       sim.imu_noise.accel_noise_density, sim.imu_noise.accel_random_walk});
  out += "\nimu_rate";
  add(out, {sim.imu_rate});
  out += "\ngravity";
  append_vec(out, sim.gravity_world);
  out += "\npixel_noise";
  add(out, {sim.pixel_noise_sigma});
  out += '\n';
  for (const SimLandmark& l : sim.landmarks) {
    out += "landmark ";
    append_integer(out, l.id);
    out += ' ';
    append_integer(out, l.group);
    append_vec(out, l.position);
    out += '\n';
  }
  for (const SimMovingGroup& g : sim.groups) {
    out += "group ";
    append_integer(out, g.id);
    add(out, {g.t_on, g.t_off});
    append_vec(out, g.start);
    append_vec(out, g.velocity);
    add(out, {g.yaw});
    out += '\n';
  }
  if (sim.imu_truth.size() != sim.imu.size())
    throw std::invalid_argument("write_visual_inertial_sim: one true state per IMU sample is needed");
  for (std::size_t i = 0; i < sim.imu.size(); ++i) {
    const SimImuSample& m = sim.imu[i];
    const SimState& x = sim.imu_truth[i];
    out += "imu";
    add(out, {m.t});
    append_vec(out, m.gyro);
    append_vec(out, m.accel);
    out += "\ntruth";
    add(out, {x.t});
    append_vec(out, x.p_world);
    append_vec(out, x.v_world);
    append_quat(out, x.q_world_imu);
    append_vec(out, x.b_a);
    append_vec(out, x.b_g);
    out += '\n';
  }
  for (const SimFrame& f : sim.frames) {
    out += "frame";
    add(out, {f.t});
    out += ' ';
    append_integer(out, static_cast<std::int64_t>(f.observations.size()));
    out += '\n';
    for (const SimObservation& o : f.observations) {
      out += "obs ";
      append_integer(out, o.track_id);
      out += ' ';
      append_integer(out, o.landmark_id);
      add(out, {o.uv.x(), o.uv.y()});
      out += o.dynamic ? " d\n" : " s\n";
    }
  }
  return out;
}

}  // namespace

void write_visual_inertial_sim(std::ostream& out, const VisualInertialSim& sim) { out << to_text(sim); }

void write_visual_inertial_sim(const std::string& path, const VisualInertialSim& sim) {
  write_file_atomically(path, to_text(sim), "output");
}

}  // namespace slamkit
