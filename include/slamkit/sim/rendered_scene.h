// RenderedScene: the geometry and textures of the world the image renderer draws, the same
// world as the feature-level simulator (visual_inertial_sim.h) for one seed:
// * the room: the simulator's box around the path (wall_margin beyond its horizontal extent,
//   floor_below / ceiling_above), recomputed from the spline exactly as the simulator does; its
//   six faces (floor, ceiling, four walls) each carry a texture;
// * furniture: static boxes standing on the floor (against a wall, yaw along the wall, or
//   free-standing at a random yaw), sizes 0.4–1.6 × 0.4–1.0 × 0.4–2.0 m, kept `path_clearance`
//   horizontally from every path sample and from each other, each with its own texture offset;
// * walkers: the simulator's moving groups (same paths and time windows, hence the same
//   `--dynamic` level) drawn as person boxes of its size (0.5 × 0.3 × 1.75 m, feet at the group
//   origin, x forward), each with a clothing texture, object id k = 1 + (group mod 255) (the label
//   value) and speed |velocity|.
// Box faces are lit by a fixed direction (shade = ambient + diffuse · max(0, n·L)), so box edges
// have contrast even between equal albedos. Random choices use their own stream (seed, 5), so
// the room, the IMU and the features of the simulator are unchanged.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "slamkit/sim/procedural_texture.h"
#include "slamkit/sim/visual_inertial_sim.h"

namespace slamkit {

struct RenderedSceneOptions {
  int furniture_count = 12;
  double path_clearance = 0.6;   ///< m, furniture footprint to any path sample (horizontal)
  double texel_size = 0.007;     ///< m per level-0 texel on every surface
  int texture_size = 512;        ///< texels (power of two); room faces get twice this
  int person_textures = 6;       ///< clothing textures shared by the walkers
  int furniture_textures = 6;
};

/// A box in the world: centre, half extents in its own frame, rotated by yaw about z.
struct SceneBox {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5);
  double yaw = 0.0;
  int texture = 0;                                    ///< index into RenderedScene::textures
  Eigen::Vector2d texture_offset = Eigen::Vector2d::Zero();  ///< m, added to face coordinates
  std::uint8_t label = 0;                             ///< 0 static, k moving object id
};

/// A moving object of the scene (one per simulator group).
struct SceneWalker {
  SimMovingGroup path;
  std::uint8_t id = 1;   ///< label value, 1 + (group mod 255)
  double speed = 0.0;    ///< m/s
  int texture = 0;
  Eigen::Vector2d texture_offset = Eigen::Vector2d::Zero();  ///< m
};

struct RenderedScene {
  Eigen::Vector3d room_lo = Eigen::Vector3d::Zero(), room_hi = Eigen::Vector3d::Ones();
  /// Texture of each room face: index 2·axis + side, side 0 the lo face (floor = 4, ceiling = 5).
  int room_texture[6] = {0, 0, 0, 0, 0, 0};
  std::vector<SceneBox> furniture;
  std::vector<SceneWalker> walkers;
  Eigen::Vector3d person_half = Eigen::Vector3d(0.25, 0.15, 0.875);
  double texel_size = 0.007;
  std::vector<std::shared_ptr<const ProceduralTexture>> textures;

  /// Furniture and the walkers active at t (their boxes at their pose at t).
  std::vector<SceneBox> boxes_at(double t) const;
};

/// The scene of a simulated run: `trajectory` and `sim_options` must be those the run was made
/// with (the room box is recomputed from them), `sim` gives the groups.
RenderedScene build_rendered_scene(const VisualInertialSim& sim, const BSplineTrajectory& trajectory,
                                   const VisualInertialSimOptions& sim_options, const RenderedSceneOptions& options = {});

/// The simulator's room box for a trajectory and options: [lo, hi].
void simulator_room_box(const BSplineTrajectory& trajectory, const VisualInertialSimOptions& sim_options,
                        Eigen::Vector3d* lo, Eigen::Vector3d* hi);

}  // namespace slamkit
