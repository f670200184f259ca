// ImageRenderer: grayscale images (uint8) and per-pixel object labels of a RenderedScene seen by
// a CameraModel (TUM-VI equidistant fisheye, 512 × 512), by ray casting.
//
// Rays: the camera-frame bearing of every pixel centre (u, v) = (x, y) is computed once with
// unproject(); pixels whose unprojection fails or that lie beyond mask_radius_px from the
// principal point are black with label 0 (the TUM-VI fisheye mask). Per frame the bearings
// are rotated to the world, r(s) = c + s·R_world_cam·b, and intersected with
//   the room (camera inside: exit distance s = min_i (bound_i − c_i)/d_i over the faces ahead),
//   every box of boxes_at(t) (slab test in the box frame: s_in = max_i min(s0_i, s1_i),
//   s_out = min_i max(s0_i, s1_i), hit iff 0 < s_in ≤ s_out; a camera inside a box sees through it),
// keeping the nearest hit. Boxes are culled per 16×16 pixel tile: a box is tested in a tile only
// if its bounding sphere meets the tile's cone of rays (angle(axis, centre) ≤ half-angle +
// asin(radius / distance)).
// Shading: I = gain(t) · vignette(θ) · shade(face) · albedo + offset(t) + n, with albedo from a
// trilinear mip lookup at λ = log2(s · ω_pixel / (|cos incidence| · texel_size)) (ω_pixel: the
// angle between neighbouring pixel rays), so far and grazing texture is blurred, not aliased.
// Exposure: gain(t) = exp(g · (0.6 sin(2πt/7.3 + φ1) + 0.4 sin(2πt/2.9 + φ2))), offset(t) =
// o · sin(2πt/11 + φ3) (phases from the seed: a smooth drift per frame); n ~ N(0, σ²) per pixel
// (inverse-CDF table of 4096 quantiles indexed by a per-row generator seeded by (seed, t in ns,
// row)); vignette 1 − v·(θ/(π/2))².
// With supersample S > 1 each pixel averages S × S sub-pixel rays (edge antialiasing; the label
// is the one most sub-rays hit, ties to the first).
// Rows are rendered in parallel on a ThreadPool; every pixel depends only on the scene, the pose,
// t and the seed, so images are identical for any thread count.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "slamkit/core/parallel.h"
#include "slamkit/geometry/camera_models.h"
#include "slamkit/geometry/se3.h"
#include "slamkit/sim/gray_image.h"
#include "slamkit/sim/rendered_scene.h"

namespace slamkit {

struct ImageRendererOptions {
  std::uint64_t seed = 1;
  double mask_radius_px = 0.0;   ///< 0: no mask (only pixels that cannot be unprojected are black)
  double noise_sigma = 2.0;      ///< gray levels, per pixel
  double gain_drift = 0.08;      ///< g: relative exposure drift amplitude (log gain)
  double offset_drift = 4.0;     ///< o: gray levels
  double vignetting = 0.3;       ///< v: brightness loss at θ = 90°
  double brightness = 235.0;     ///< gray level of albedo 1 under shade 1
  double lod_bias = 0.0;         ///< added to λ (> 0 blurs more)
  int supersample = 1;           ///< S: S × S rays per pixel
};

/// One ray's nearest hit.
struct RayHit {
  bool hit = false;
  double distance = 0.0;               ///< s along the unit ray
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< world
  int face = -1;                       ///< room face 2·axis + side, or −1 for a box
  int box = -1;                        ///< index into boxes_at(t), or −1 for the room
  std::uint8_t label = 0;
};

class ImageRenderer {
 public:
  /// Throws std::invalid_argument for a scene without textures or supersample < 1.
  ImageRenderer(const RenderedScene& scene, const CameraModel& camera, const ImageRendererOptions& options = {});

  int width() const { return width_; }
  int height() const { return height_; }
  const ImageRendererOptions& options() const { return options_; }

  /// Renders the view at time t from T_world_cam into image and labels (resized as needed;
  /// labels may be null). pool null: the calling thread only.
  void render(double t, const SE3& T_world_cam, GrayImage* image, GrayImage* labels,
              const ThreadPool* pool = nullptr) const;
  /// Nearest hit of the ray through pixel position uv (not necessarily integer) at time t.
  RayHit cast(double t, const SE3& T_world_cam, const Eigen::Vector2d& uv) const;

  /// Exposure gain and offset at time t (for tests and docs).
  double gain(double t) const;
  double offset(double t) const;

 private:
  struct FrameBox;
  struct Tile {
    Eigen::Vector3f axis = Eigen::Vector3f::UnitZ();  ///< camera frame
    float cos_half = -1.0f, half_angle = 3.2f;
    bool any = false;
  };
  RayHit trace(const std::vector<FrameBox>& boxes, const std::vector<int>* candidates, const Eigen::Vector3d& c,
               const Eigen::Vector3d& d, Eigen::Vector2d* face_uv, double* cos_incidence, int* texture,
               double* shade) const;
  std::vector<FrameBox> frame_boxes(double t) const;

  const RenderedScene& scene_;  ///< must outlive the renderer
  std::shared_ptr<const CameraModel> camera_;
  ImageRendererOptions options_;
  int width_, height_, tiles_x_, tiles_y_;
  static constexpr int kTile = 16;
  std::vector<Eigen::Vector3f> rays_;   ///< camera-frame bearings, S² per pixel (sub-pixel order)
  std::vector<float> pixel_angle_;      ///< ω_pixel [rad] per pixel
  std::vector<float> vignette_;         ///< per pixel
  std::vector<std::uint8_t> valid_;     ///< per pixel
  std::vector<Tile> tiles_;
  std::vector<float> gauss_;         ///< N(0, 1) quantiles for the pixel noise
  double phase_[3];
};

/// T_world_cam of a simulated frame: T_world_imu · T_cam_imu⁻¹.
SE3 frame_camera_pose(const VisualInertialSim& sim, const SimFrame& frame);

}  // namespace slamkit
