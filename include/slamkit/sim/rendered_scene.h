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
//   value) and speed |velocity|;
// * crowd bursts (high dynamic level only, `burst_interval_s` > 0): platoons the feature
//   simulator does not have, added so that the front end's static ratio M falls below θ for
//   stretches (issue 13). A burst centred at t_c is `burst_rows` queues of
//   `burst_people_per_row` person boxes `burst_spacing` apart along their walk, row j passing
//   d_j = d_0 + j · burst_row_gap in front of the camera's horizontal view direction at t_c
//   (d_0 ∈ [burst_first_row_min, burst_first_row_max]), and `burst_rows_behind` more queues
//   mirrored behind the camera (at −d_j, their own d_0), so that the stream passes on both sides
//   and stays in view while the handheld camera turns; all walking one heading (perpendicular to
//   the view ± 15°) at a per-row speed in [burst_speed_min, burst_speed_max]; the queue's middle
//   crosses the view axis at t_c (rows staggered by a random phase). A burst walker is present
//   within burst_half_window_s of t_c while 0.3 m inside the walls, and is left out if the camera
//   comes within burst_camera_clearance of it (horizontally) in that time. Burst centres: the
//   first at burst_first_s + U(0, 1) · interval after the start, then gaps of U(0.5, 1.5) · interval.
//   Group ids continue after the simulator's (label 1 + id mod 255).
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
  double burst_interval_s = 12.0;  ///< mean time between crowd bursts (high level); 0: none
  double burst_first_s = 5.0;      ///< no burst centre before start + this (start-up)
  int burst_rows = 4, burst_people_per_row = 10;
  /// Queues behind the camera; 0 (default): none. Measured in session 25 with 2 + 2 queues of 12
  /// at 1.0–1.6 m + j · 0.8 m: no longer stretches of M < θ and a smaller DVI gain (docs/vio.md).
  int burst_rows_behind = 0;
  double burst_spacing = 0.55;     ///< m between walkers of a queue
  double burst_first_row_min = 0.8, burst_first_row_max = 1.4, burst_row_gap = 0.6;  ///< m
  double burst_speed_min = 0.6, burst_speed_max = 1.2;  ///< m/s
  double burst_half_window_s = 3.0;
  double burst_camera_clearance = 0.6;  ///< m
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
  std::vector<SceneWalker> walkers;   ///< the simulator's groups first, then the burst walkers
  std::vector<double> burst_centres;  ///< t_c of each crowd burst
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
