// RenderedScene (rendered_scene.h): the room of the feature simulator, furniture and walkers.
#include "slamkit/sim/rendered_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace slamkit {
namespace {

// Stream `which` of a seed (5: the scene, 6: the crowd bursts), splitmix-style.
std::mt19937_64 scene_rng(std::uint64_t seed, std::uint64_t which) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + which * 0xBF58476D1CE4E5B9ULL + 0x94D049BB133111EBULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return std::mt19937_64(z ^ (z >> 31));
}

// Crowd bursts (header): platoons of queues crossing the camera's view, appended to scene->walkers.
void add_crowd_bursts(const VisualInertialSim& sim, const BSplineTrajectory& trajectory, std::uint64_t seed,
                      const RenderedSceneOptions& o, const std::vector<int>& person_textures, RenderedScene* scene) {
  if (sim.dynamic != DynamicLevel::kHigh || !(o.burst_interval_s > 0.0) || sim.frames.empty() ||
      o.burst_rows + std::max(0, o.burst_rows_behind) < 1 || o.burst_people_per_row < 1)
    return;
  std::mt19937_64 rng = scene_rng(seed, 6);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto uni = [&](double a, double b) { return a + (b - a) * unit(rng); };
  const double t0 = sim.frames.front().t, t1 = sim.frames.back().t;
  const auto clamp_t = [&](double t) { return std::clamp(t, trajectory.start_time(), trajectory.end_time()); };
  const auto camera_at = [&](double t) { return trajectory.pose(clamp_t(t)) * sim.T_cam_imu.inverse(); };
  constexpr double kWallGap = 0.3;  // as the simulator's walkers
  const Eigen::Vector3d lo = scene->room_lo, hi = scene->room_hi;
  int next_id = static_cast<int>(sim.groups.size());
  for (double tc = t0 + o.burst_first_s + unit(rng) * o.burst_interval_s; tc < t1 - 1.0;
       tc += uni(0.5, 1.5) * o.burst_interval_s) {
    scene->burst_centres.push_back(tc);
    const SE3 T_wc = camera_at(tc);
    Eigen::Vector3d view = T_wc.rotation().act(Eigen::Vector3d::UnitZ());
    view.z() = 0.0;
    if (view.norm() < 1e-6) view = Eigen::Vector3d::UnitX();
    view.normalize();
    const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
    const double heading = std::atan2(view.y(), view.x()) + sign * M_PI / 2 + uni(-M_PI / 12, M_PI / 12);
    const Eigen::Vector3d dir(std::cos(heading), std::sin(heading), 0.0);
    const double d0 = uni(o.burst_first_row_min, o.burst_first_row_max);
    // Drawn only with queues behind, so that the default scene's stream is that of session 24.
    const double d0_behind = o.burst_rows_behind > 0 ? uni(o.burst_first_row_min, o.burst_first_row_max) : 0.0;
    for (int j = 0; j < o.burst_rows + std::max(0, o.burst_rows_behind); ++j) {
      const bool behind = j >= o.burst_rows;
      const double d = behind ? -(d0_behind + (j - o.burst_rows) * o.burst_row_gap) : d0 + j * o.burst_row_gap;
      const double v = uni(o.burst_speed_min, o.burst_speed_max), phase = uni(0.0, o.burst_spacing);
      const int texture_base = static_cast<int>(uni(0.0, static_cast<double>(person_textures.size())));
      Eigen::Vector3d mid = T_wc.translation() + d * view;
      mid.z() = lo.z();  // feet on the floor
      for (int i = 0; i < o.burst_people_per_row; ++i) {
        // Position at t: mid + (offset + v (t − t_c)) · dir, the queue's middle at mid at t_c.
        const double offset = -(i - 0.5 * (o.burst_people_per_row - 1)) * o.burst_spacing - phase;
        const Eigen::Vector3d at_tc = mid + offset * dir;
        const Eigen::Vector3d velocity = v * dir;
        double on = std::max(t0, tc - o.burst_half_window_s), off = std::min(t1, tc + o.burst_half_window_s);
        for (int a = 0; a < 2; ++a) {  // inside the walls: lo + gap ≤ x_a(t) ≤ hi − gap
          if (std::abs(velocity(a)) < 1e-9) {
            if (at_tc(a) < lo(a) + kWallGap || at_tc(a) > hi(a) - kWallGap) off = on - 1.0;
            continue;
          }
          double ta = tc + (lo(a) + kWallGap - at_tc(a)) / velocity(a), tb = tc + (hi(a) - kWallGap - at_tc(a)) / velocity(a);
          if (ta > tb) std::swap(ta, tb);
          on = std::max(on, ta), off = std::min(off, tb);
        }
        if (!(off - on > 0.5)) continue;
        bool clear = true;
        for (double t = on; t <= off && clear; t += 0.05) {
          const Eigen::Vector3d p = at_tc + velocity * (t - tc);
          clear = (camera_at(t).translation() - p).head<2>().norm() >= o.burst_camera_clearance;
        }
        if (!clear) continue;
        SceneWalker w;
        w.path.id = next_id++;
        w.path.t_on = on, w.path.t_off = off;
        w.path.start = at_tc + velocity * (on - tc);
        w.path.velocity = velocity;
        w.path.yaw = heading;
        w.id = static_cast<std::uint8_t>(1 + w.path.id % 255);
        w.speed = v;
        w.texture = person_textures[static_cast<std::size_t>(texture_base + i) % person_textures.size()];
        w.texture_offset = Eigen::Vector2d(uni(0, 8), uni(0, 8));
        scene->walkers.push_back(w);
      }
    }
  }
}

}  // namespace

void simulator_room_box(const BSplineTrajectory& trajectory, const VisualInertialSimOptions& o, Eigen::Vector3d* lo,
                        Eigen::Vector3d* hi) {
  // Same sampling as simulate_visual_inertial (visual_inertial_sim.cpp, "the room").
  const double t_start = trajectory.start_time();
  const double t_end = o.duration > 0.0 ? std::min(trajectory.end_time(), t_start + o.duration) : trajectory.end_time();
  Eigen::Vector3d a = Eigen::Vector3d::Constant(1e300), b = Eigen::Vector3d::Constant(-1e300);
  for (double t = t_start; t <= t_end; t += 0.1) {
    const Eigen::Vector3d p = trajectory.pose(t).translation();
    a = a.cwiseMin(p), b = b.cwiseMax(p);
  }
  *lo = a - Eigen::Vector3d(o.wall_margin, o.wall_margin, o.floor_below);
  *hi = b + Eigen::Vector3d(o.wall_margin, o.wall_margin, o.ceiling_above);
}

std::vector<SceneBox> RenderedScene::boxes_at(double t) const {
  std::vector<SceneBox> boxes = furniture;
  for (const SceneWalker& w : walkers) {
    if (!w.path.active(t)) continue;
    const SE3 T = w.path.pose(t);
    SceneBox b;
    b.centre = T.act(Eigen::Vector3d(0.0, 0.0, person_half.z()));
    b.half = person_half;
    b.yaw = w.path.yaw;
    b.texture = w.texture;
    b.label = w.id;
    b.texture_offset = w.texture_offset;
    boxes.push_back(b);
  }
  return boxes;
}

RenderedScene build_rendered_scene(const VisualInertialSim& sim, const BSplineTrajectory& trajectory,
                                   const VisualInertialSimOptions& sim_options, const RenderedSceneOptions& o) {
  RenderedScene scene;
  scene.texel_size = o.texel_size;
  simulator_room_box(trajectory, sim_options, &scene.room_lo, &scene.room_hi);
  std::mt19937_64 rng = scene_rng(sim_options.seed, 5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto uni = [&](double a, double b) { return a + (b - a) * unit(rng); };

  // Textures: walls posters/blobs/noise, floor tiles, ceiling value noise, then furniture and clothing.
  const auto add = [&](TextureKind kind, int size) {
    scene.textures.push_back(std::make_shared<const ProceduralTexture>(kind, rng(), size));
    return static_cast<int>(scene.textures.size() - 1);
  };
  const TextureKind wall_kinds[4] = {TextureKind::kPosters, TextureKind::kBlobs, TextureKind::kPosters,
                                     TextureKind::kValueNoise};
  for (int f = 0; f < 4; ++f) scene.room_texture[f] = add(wall_kinds[f], 2 * o.texture_size);
  scene.room_texture[4] = add(TextureKind::kTiles, 2 * o.texture_size);
  scene.room_texture[5] = add(TextureKind::kValueNoise, 2 * o.texture_size);
  std::vector<int> furniture_textures, person_textures;
  const TextureKind furniture_kinds[4] = {TextureKind::kValueNoise, TextureKind::kTiles, TextureKind::kBlobs,
                                          TextureKind::kPosters};
  for (int k = 0; k < o.furniture_textures; ++k) furniture_textures.push_back(add(furniture_kinds[k % 4], o.texture_size));
  for (int k = 0; k < std::max(1, o.person_textures); ++k) person_textures.push_back(add(TextureKind::kClothing, o.texture_size));

  // Path samples (horizontal) every 0.25 s, for the clearance test.
  std::vector<Eigen::Vector2d> path;
  for (const SimState& s : sim.imu_truth)
    if (path.empty() || static_cast<std::size_t>(&s - sim.imu_truth.data()) % 50 == 0) path.push_back(s.p_world.head<2>());
  const Eigen::Vector3d size = scene.room_hi - scene.room_lo;
  for (int attempt = 0; attempt < 400 && static_cast<int>(scene.furniture.size()) < o.furniture_count; ++attempt) {
    SceneBox b;
    b.half = 0.5 * Eigen::Vector3d(uni(0.4, 1.6), uni(0.4, 1.0), uni(0.4, 2.0));
    b.half.z() = std::min(b.half.z(), 0.45 * size.z());
    Eigen::Vector2d c;
    if (unit(rng) < 0.7) {  // against a wall, long side along it
      const int wall = static_cast<int>(uni(0, 4)) % 4, axis = wall / 2;  // axis 0: x walls, 1: y walls
      const double along = uni(0, 1);
      b.yaw = axis == 0 ? M_PI / 2 : 0.0;  // box x axis along the wall
      const double off = b.half.y() + 0.05;
      c(axis) = wall % 2 == 0 ? scene.room_lo(axis) + off : scene.room_hi(axis) - off;
      c(1 - axis) = scene.room_lo(1 - axis) + b.half.x() + along * std::max(0.0, size(1 - axis) - 2 * b.half.x());
    } else {
      b.yaw = uni(-M_PI, M_PI);
      c = Eigen::Vector2d(uni(scene.room_lo.x() + 0.8, scene.room_hi.x() - 0.8), uni(scene.room_lo.y() + 0.8, scene.room_hi.y() - 0.8));
    }
    const double radius = b.half.head<2>().norm();
    bool ok = true;
    for (const Eigen::Vector2d& p : path)
      if ((p - c).norm() < radius + o.path_clearance) { ok = false; break; }
    for (const SceneBox& other : scene.furniture)
      if (ok && (other.centre.head<2>() - c).norm() < radius + other.half.head<2>().norm() + 0.1) ok = false;
    if (!ok) continue;
    b.centre = Eigen::Vector3d(c.x(), c.y(), scene.room_lo.z() + b.half.z());
    b.texture = furniture_textures.empty() ? scene.room_texture[0]
                                           : furniture_textures[static_cast<std::size_t>(uni(0, furniture_textures.size())) %
                                                                furniture_textures.size()];
    b.texture_offset = Eigen::Vector2d(uni(0, 8), uni(0, 8));
    scene.furniture.push_back(b);
  }

  for (const SimMovingGroup& g : sim.groups) {
    SceneWalker w;
    w.path = g;
    w.id = static_cast<std::uint8_t>(1 + g.id % 255);
    w.speed = g.velocity.norm();
    w.texture = person_textures[static_cast<std::size_t>(g.id) % person_textures.size()];
    w.texture_offset = Eigen::Vector2d(uni(0, 8), uni(0, 8));
    scene.walkers.push_back(w);
  }
  add_crowd_bursts(sim, trajectory, sim_options.seed, o, person_textures, &scene);
  return scene;
}

}  // namespace slamkit
