// RenderedScene (rendered_scene.h): the room of the feature simulator, furniture and walkers.
#include "slamkit/sim/rendered_scene.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace slamkit {
namespace {

std::mt19937_64 scene_rng(std::uint64_t seed) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + 5 * 0xBF58476D1CE4E5B9ULL + 0x94D049BB133111EBULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return std::mt19937_64(z ^ (z >> 31));
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
  std::mt19937_64 rng = scene_rng(sim_options.seed);
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
  return scene;
}

}  // namespace slamkit
