#include "slamkit/sim/visual_inertial_sim.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

// Independent random streams derived from the seed (splitmix64 of seed and stream number).
std::mt19937_64 stream(std::uint64_t seed, std::uint64_t which) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + which * 0xBF58476D1CE4E5B9ULL + 0x94D049BB133111EBULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return std::mt19937_64(z ^ (z >> 31));
}

Eigen::Vector3d gaussian3(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> n(0.0, sigma);
  return Eigen::Vector3d(n(rng), n(rng), n(rng));
}

struct Box {
  Eigen::Vector3d lo, hi;
};

// Points uniformly on the 6 faces of the box, `density` per m².
void add_room_landmarks(const Box& box, double density, std::mt19937_64& rng, std::vector<SimLandmark>* out) {
  const Eigen::Vector3d size = box.hi - box.lo;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    const double area = size(a) * size(b);
    const int count = static_cast<int>(std::round(density * area));
    for (int side = 0; side < 2; ++side) {
      for (int k = 0; k < count; ++k) {
        SimLandmark l;
        l.id = static_cast<std::int64_t>(out->size());
        l.position(axis) = side == 0 ? box.lo(axis) : box.hi(axis);
        l.position(a) = box.lo(a) + unit(rng) * size(a);
        l.position(b) = box.lo(b) + unit(rng) * size(b);
        out->push_back(l);
      }
    }
  }
}

// The person-sized box of a moving group, in the group frame (origin at the feet, x forward).
const Eigen::Vector3d kPersonHalf(0.25, 0.15, 0.875);
const Eigen::Vector3d kPersonLo(-0.25, -0.15, 0.0), kPersonHi(0.25, 0.15, 1.75);

// True if the segment a → b (group frame) passes through the person box before reaching b
// (slab test on a + s (b − a), s ∈ [0, 1]). A camera inside the box does not occlude.
bool box_occludes(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d d = b - a;
  double s_in = -1e300, s_out = 1e300;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(d(i)) < 1e-15) {
      if (a(i) < kPersonLo(i) || a(i) > kPersonHi(i)) return false;
      continue;
    }
    double s0 = (kPersonLo(i) - a(i)) / d(i), s1 = (kPersonHi(i) - a(i)) / d(i);
    if (s0 > s1) std::swap(s0, s1);
    s_in = std::max(s_in, s0), s_out = std::min(s_out, s1);
  }
  return s_in <= s_out && s_in > 0.0 && s_in < 1.0 - 1e-7;
}

// Points on the surface of a person-sized box, in the group frame (origin at the feet).
void add_group_landmarks(int group, std::mt19937_64& rng, std::vector<SimLandmark>* out) {
  const Eigen::Vector3d& half = kPersonHalf;
  std::uniform_int_distribution<int> count(20, 50);
  std::uniform_real_distribution<double> sym(-1.0, 1.0);
  std::uniform_int_distribution<int> face(0, 5);
  const int n = count(rng);
  for (int k = 0; k < n; ++k) {
    Eigen::Vector3d q(sym(rng), sym(rng), sym(rng));
    const int f = face(rng);
    q(f / 2) = f % 2 ? 1.0 : -1.0;
    SimLandmark l;
    l.id = static_cast<std::int64_t>(out->size());
    l.group = group;
    l.position = q.cwiseProduct(half) + Eigen::Vector3d(0.0, 0.0, half.z());
    out->push_back(l);
  }
}

// Grid of kept feature pixels for the minimum-distance test.
class PixelGrid {
 public:
  PixelGrid(int width, int height, double cell) : cell_(cell), cols_(static_cast<int>(width / cell) + 1),
                                                  rows_(static_cast<int>(height / cell) + 1), cells_(cols_ * rows_) {}
  bool free(const Eigen::Vector2d& uv) const {
    const int cx = col(uv.x()), cy = row(uv.y());
    for (int y = std::max(0, cy - 1); y <= std::min(rows_ - 1, cy + 1); ++y)
      for (int x = std::max(0, cx - 1); x <= std::min(cols_ - 1, cx + 1); ++x)
        for (const Eigen::Vector2d& p : cells_[y * cols_ + x])
          if ((p - uv).squaredNorm() < cell_ * cell_) return false;
    return true;
  }
  void add(const Eigen::Vector2d& uv) { cells_[row(uv.y()) * cols_ + col(uv.x())].push_back(uv); }

 private:
  int col(double u) const { return std::clamp(static_cast<int>(u / cell_), 0, cols_ - 1); }
  int row(double v) const { return std::clamp(static_cast<int>(v / cell_), 0, rows_ - 1); }
  double cell_;
  int cols_, rows_;
  std::vector<std::vector<Eigen::Vector2d>> cells_;
};

SimState true_state(const BSplineState& s, double t, const Eigen::Vector3d& b_a, const Eigen::Vector3d& b_g) {
  SimState x;
  x.t = t;
  x.p_world = s.T_world_body.translation();
  x.v_world = s.v_world;
  x.q_world_imu = s.T_world_body.rotation().quaternion();
  x.b_a = b_a, x.b_g = b_g;
  return x;
}

}  // namespace

const char* to_string(DynamicLevel level) {
  switch (level) {
    case DynamicLevel::kNone: return "none";
    case DynamicLevel::kLow: return "low";
    case DynamicLevel::kHigh: return "high";
  }
  return "none";
}

DynamicLevel parse_dynamic_level(const std::string& text) {
  if (text == "none") return DynamicLevel::kNone;
  if (text == "low") return DynamicLevel::kLow;
  if (text == "high") return DynamicLevel::kHigh;
  throw InputError("", 0, "dynamic", "expected none, low or high, got '" + text.substr(0, 40) + "'");
}

SE3 SimMovingGroup::pose(double t) const {
  return SE3(SO3::exp(Eigen::Vector3d(0.0, 0.0, yaw)), start + velocity * (t - t_on));
}

Eigen::Vector3d VisualInertialSim::landmark_world(const SimLandmark& l, double t) const {
  if (l.group < 0) return l.position;
  return groups.at(static_cast<std::size_t>(l.group)).pose(t).act(l.position);
}

VisualInertialSim simulate_visual_inertial(const BSplineTrajectory& trajectory, std::shared_ptr<CameraModel> camera,
                                           const SE3& T_cam_imu, const VisualInertialSimOptions& o) {
  if (!camera) throw std::invalid_argument("simulate_visual_inertial: no camera");
  if (!(o.imu_rate > 0.0) || o.imu_per_frame < 1 || o.features_per_frame < 1 || !(o.pixel_noise_sigma >= 0.0) ||
      !(o.landmark_density > 0.0) || !(o.min_feature_distance_px > 0.0) || !(o.duration >= 0.0))
    throw std::invalid_argument("simulate_visual_inertial: invalid options");
  VisualInertialSim sim;
  sim.seed = o.seed;
  sim.dynamic = o.dynamic;
  sim.camera = camera;
  sim.T_cam_imu = T_cam_imu;
  sim.mask_radius_px = o.mask_radius_px;
  sim.imu_noise = o.imu_noise;
  sim.imu_rate = o.imu_rate;
  sim.gravity_world = Eigen::Vector3d(0.0, 0.0, -o.gravity);
  sim.pixel_noise_sigma = o.pixel_noise_sigma;

  const double t_start = trajectory.start_time();
  const double t_end = o.duration > 0.0 ? std::min(trajectory.end_time(), t_start + o.duration) : trajectory.end_time();
  const double dt = 1.0 / o.imu_rate;
  const std::size_t n_imu = static_cast<std::size_t>(std::floor((t_end - t_start) * o.imu_rate + 1e-9)) + 1;

  // ---- the room: a box around the path ----
  std::mt19937_64 world_rng = stream(o.seed, 1);
  Box box{Eigen::Vector3d::Constant(1e300), Eigen::Vector3d::Constant(-1e300)};
  for (double t = t_start; t <= t_end; t += 0.1) {
    const Eigen::Vector3d p = trajectory.pose(t).translation();
    box.lo = box.lo.cwiseMin(p), box.hi = box.hi.cwiseMax(p);
  }
  box.lo -= Eigen::Vector3d(o.wall_margin, o.wall_margin, o.floor_below);
  box.hi += Eigen::Vector3d(o.wall_margin, o.wall_margin, o.ceiling_above);
  add_room_landmarks(box, o.landmark_density, world_rng, &sim.landmarks);

  // ---- moving groups (own stream: the static world does not depend on the level) ----
  std::mt19937_64 group_rng = stream(o.seed, 2);
  if (o.dynamic != DynamicLevel::kNone) {
    const bool high = o.dynamic == DynamicLevel::kHigh;
    std::uniform_real_distribution<double> window(5.0, 10.0), speed(0.5, 1.5);
    std::uniform_real_distribution<double> passing(high ? 0.6 : 2.0, high ? 1.5 : 5.0), unit(0.0, 1.0);
    const double span = t_end - t_start;
    const int count = std::max(1, static_cast<int>(std::ceil(span * (high ? 0.8 * 10.0 : 0.3) / 7.5)));
    for (int g = 0; g < count; ++g) {
      SimMovingGroup grp;
      grp.id = g;
      const double len = std::min(window(group_rng), span);
      grp.t_on = t_start + unit(group_rng) * (span - len);
      grp.t_off = grp.t_on + len;
      // Crosses the camera's (horizontal) viewing direction at the window's middle, at a
      // passing distance in front of it, walking at ±30° from perpendicular to the view.
      const SE3 T_mid = trajectory.pose(0.5 * (grp.t_on + grp.t_off));
      Eigen::Vector3d view = T_mid.rotation().act(T_cam_imu.rotation().inverse().act(Eigen::Vector3d::UnitZ()));
      view.z() = 0.0;
      if (view.norm() < 1e-6) view = Eigen::Vector3d::UnitX();
      view.normalize();
      const double sign = unit(group_rng) < 0.5 ? -1.0 : 1.0;
      const double heading = std::atan2(view.y(), view.x()) + sign * M_PI / 2 + (unit(group_rng) - 0.5) * M_PI / 3;
      const Eigen::Vector3d dir(std::cos(heading), std::sin(heading), 0.0);
      const double v = speed(group_rng);
      Eigen::Vector3d mid = T_mid.translation() + passing(group_rng) * view;
      mid.z() = box.lo.z();  // feet on the floor
      grp.velocity = v * dir;
      grp.start = mid - grp.velocity * (0.5 * len);
      grp.yaw = heading;
      sim.groups.push_back(grp);
      add_group_landmarks(g, group_rng, &sim.landmarks);
    }
  }

  // ---- IMU: measurements and true states at every IMU time ----
  std::mt19937_64 imu_rng = stream(o.seed, 3);
  const double sg = o.imu_noise.gyro_noise_density * std::sqrt(o.imu_rate);
  const double sa = o.imu_noise.accel_noise_density * std::sqrt(o.imu_rate);
  const double wg = o.imu_noise.gyro_random_walk * std::sqrt(dt);
  const double wa = o.imu_noise.accel_random_walk * std::sqrt(dt);
  Eigen::Vector3d b_g = gaussian3(imu_rng, o.initial_gyro_bias_sigma);
  Eigen::Vector3d b_a = gaussian3(imu_rng, o.initial_accel_bias_sigma);
  sim.imu.reserve(n_imu);
  sim.imu_truth.reserve(n_imu);
  for (std::size_t k = 0; k < n_imu; ++k) {
    const double t = std::min(t_start + static_cast<double>(k) * dt, trajectory.end_time());
    const BSplineState s = trajectory.evaluate(t);
    SimImuSample m;
    m.t = t;
    m.gyro = s.omega_body + b_g + gaussian3(imu_rng, sg);
    m.accel = s.T_world_body.rotation().inverse().act(s.a_world - sim.gravity_world) + b_a + gaussian3(imu_rng, sa);
    sim.imu.push_back(m);
    sim.imu_truth.push_back(true_state(s, t, b_a, b_g));
    b_g += gaussian3(imu_rng, wg);
    b_a += gaussian3(imu_rng, wa);
  }

  // ---- camera frames and feature tracks ----
  std::mt19937_64 track_rng = stream(o.seed, 4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> pixel_noise(0.0, 1.0);
  const Eigen::VectorXd K = camera->intrinsics();
  const Eigen::Vector2d principal(K(2), K(3));
  const SE3 T_imu_cam = T_cam_imu.inverse();
  std::unordered_map<std::int64_t, std::int64_t> tracked;  // landmark id → track id
  std::int64_t next_track = 0;
  struct Candidate {
    std::int64_t landmark;
    Eigen::Vector2d uv;
  };
  std::vector<Candidate> visible;
  for (std::size_t k = 0; k < n_imu; k += static_cast<std::size_t>(o.imu_per_frame)) {
    SimFrame frame;
    frame.t = sim.imu[k].t;
    frame.imu_index = k;
    frame.truth = sim.imu_truth[k];
    const SE3 T_world_imu(SO3(frame.truth.q_world_imu), frame.truth.p_world);
    const SE3 T_cam_world = (T_world_imu * T_imu_cam).inverse();
    visible.clear();
    // Active groups and the camera centre in each group's frame (for occlusion).
    std::vector<std::pair<SE3, Eigen::Vector3d>> active;  // T_group_world, camera centre
    const Eigen::Vector3d centre = T_cam_world.inverse().translation();
    for (const SimMovingGroup& g : sim.groups)
      if (g.active(frame.t)) {
        const SE3 T_group_world = g.pose(frame.t).inverse();
        active.emplace_back(T_group_world, T_group_world.act(centre));
      }
    for (const SimLandmark& l : sim.landmarks) {
      if (l.group >= 0 && !sim.groups[static_cast<std::size_t>(l.group)].active(frame.t)) continue;
      const Eigen::Vector3d pw = sim.landmark_world(l, frame.t);
      const Eigen::Vector3d pc = T_cam_world.act(pw);
      if (pc.z() <= 0.0) continue;
      bool hidden = false;
      for (const auto& [T_group_world, c] : active)
        if ((hidden = box_occludes(c, T_group_world.act(pw)))) break;
      if (hidden) continue;
      const double range = pc.norm();
      if (pc.z() <= 0.0 || range < 0.1 || range > o.max_depth) continue;
      Eigen::Vector2d uv;
      if (!camera->project(pc, &uv) || !camera->in_image(uv, o.border_px)) continue;
      if (o.mask_radius_px > 0.0 && (uv - principal).norm() > o.mask_radius_px) continue;
      visible.push_back({l.id, uv});
    }
    // Keep the tracks whose landmark is still visible, then fill up with new tracks (in random
    // order; with dynamic_detection_priority the points of moving groups first).
    std::shuffle(visible.begin(), visible.end(), track_rng);
    if (o.dynamic_detection_priority)
      std::stable_partition(visible.begin(), visible.end(), [&](const Candidate& c) {
        return sim.landmarks[static_cast<std::size_t>(c.landmark)].group >= 0;
      });
    PixelGrid grid(camera->width(), camera->height(), o.min_feature_distance_px);
    std::unordered_map<std::int64_t, std::int64_t> next_tracked;
    std::vector<std::pair<std::int64_t, const Candidate*>> chosen;  // track id, candidate
    for (const Candidate& c : visible) {
      const auto it = tracked.find(c.landmark);
      if (it == tracked.end() || unit(track_rng) < o.track_loss_probability) continue;
      if (static_cast<int>(chosen.size()) >= o.features_per_frame) break;
      chosen.emplace_back(it->second, &c);
      next_tracked[c.landmark] = it->second;
      grid.add(c.uv);
    }
    for (const Candidate& c : visible) {
      if (static_cast<int>(chosen.size()) >= o.features_per_frame) break;
      if (next_tracked.count(c.landmark) || !grid.free(c.uv)) continue;
      chosen.emplace_back(next_track, &c);
      next_tracked[c.landmark] = next_track++;
      grid.add(c.uv);
    }
    tracked.swap(next_tracked);
    std::sort(chosen.begin(), chosen.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [track, c] : chosen) {
      SimObservation obs;
      obs.track_id = track;
      obs.landmark_id = c->landmark;
      obs.uv = c->uv + o.pixel_noise_sigma * Eigen::Vector2d(pixel_noise(track_rng), pixel_noise(track_rng));
      obs.dynamic = sim.landmarks[static_cast<std::size_t>(c->landmark)].group >= 0;
      frame.observations.push_back(obs);
    }
    sim.frames.push_back(std::move(frame));
  }
  return sim;
}

SimSummary summarize(const VisualInertialSim& sim) {
  SimSummary s;
  s.frames = sim.frames.size();
  s.imu_samples = sim.imu.size();
  s.groups = sim.groups.size();
  for (const auto& l : sim.landmarks) (l.group < 0 ? s.static_landmarks : s.dynamic_landmarks)++;
  if (sim.imu.size() >= 2) s.duration = sim.imu.back().t - sim.imu.front().t;
  std::size_t all = 0, dynamic = 0;
  double ratio_sum = 0.0;
  std::unordered_map<std::int64_t, std::size_t> track_lengths;
  s.features_per_frame_min = sim.frames.empty() ? 0 : static_cast<std::size_t>(-1);
  for (const auto& f : sim.frames) {
    std::size_t d = 0;
    for (const auto& o : f.observations) {
      d += o.dynamic;
      ++track_lengths[o.track_id];
    }
    all += f.observations.size();
    dynamic += d;
    s.features_per_frame_min = std::min(s.features_per_frame_min, f.observations.size());
    if (d > 0) ++s.frames_with_dynamic;
    const double M = f.observations.empty() ? 1.0 : 1.0 - static_cast<double>(d) / f.observations.size();
    s.static_ratio_min = std::min(s.static_ratio_min, M);
    ratio_sum += M;
    if (M < 0.5) ++s.frames_static_below_half;
  }
  if (!sim.frames.empty()) {
    s.features_per_frame_mean = static_cast<double>(all) / sim.frames.size();
    s.static_ratio_mean = ratio_sum / sim.frames.size();
  }
  if (all > 0) s.dynamic_share = static_cast<double>(dynamic) / all;
  s.tracks = track_lengths.size();
  if (!track_lengths.empty()) s.mean_track_length = static_cast<double>(all) / track_lengths.size();
  return s;
}

}  // namespace slamkit
