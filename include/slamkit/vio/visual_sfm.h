// Visual structure from motion over a short window of frames (the start-up of the VIO, as in
// VINS-Mono T-RO 2018 §V-A): camera poses T_c0_ck in the frame c0 of the first camera, up to
// one global scale, and the tracked points in c0.
//   1. Reference pair (0, j): the latest frame j sharing ≥ min_common_tracks with frame 0 at a
//      mean raw bearing parallax ≥ min_pair_parallax_deg; essential matrix by the 5-point
//      algorithm with RANSAC on normalized coordinates (OpenCV findEssentialMat), relative pose
//      by recoverPose; the baseline |c_j − c_0| = 1 fixes the scale.
//   2. Points seen in two posed frames: linear triangulation from bearings,
//      min_k Σ ‖[b_k]× (R_ck_c0 P + t_ck_c0)‖², kept if in front of every camera with a
//      parallax ≥ min_point_parallax_deg.
//   3. Every other frame: PnP + RANSAC on the triangulated points (OpenCV solvePnPRansac,
//      from the previous frame's pose), then new points are triangulated with it.
//   4. Visual-only bundle adjustment with slamkit's Optimizer (LM, points eliminated by the
//      Schur complement, Cauchy loss, σ = σ_px / (f cos²θ) for a bearing θ off the axis, as
//      1 px moves the normalized point that much at most) of the NormalizedReprojectionFactor below; frame 0 is
//      held fixed and a BaselineFactor keeps |c_j| = 1 (the gauge: origin, orientation, scale;
//      OpenCV's essential matrix comes from a minimal sample, so frame j must move too).
// Only bearings with z ≥ min_bearing_z (in front, ≲ 75° off the axis) are used, since the
// normalized image plane x/z, y/z is the measurement. Failure is a message, never NaN.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "slamkit/core/factor.h"
#include "slamkit/geometry/se3.h"

namespace slamkit {

/// A feature as a unit bearing in its camera frame, with its track id.
struct SfmObservation {
  std::uint64_t track_id = 0;
  Eigen::Vector3d bearing = Eigen::Vector3d::UnitZ();
};

struct VisualSfmOptions {
  double focal_px = 300.0;               ///< to express pixel thresholds on the normalized plane
  double pixel_sigma = 1.0;              ///< [px] for the BA noise
  double ransac_threshold_px = 1.5;      ///< essential-matrix inlier threshold
  double pnp_threshold_px = 3.0;         ///< PnP inlier threshold
  int min_common_tracks = 30;
  int min_inliers = 25;
  double min_pair_parallax_deg = 3.0;    ///< mean raw bearing angle of the reference pair
  double min_point_parallax_deg = 1.0;
  double min_bearing_z = 0.25;
  int ba_iterations = 20;
  double cauchy_delta = 2.0;             ///< on the whitened residual
};

struct VisualSfmResult {
  bool success = false;
  std::string message;
  int reference_frame = -1;                 ///< j of the pair (0, j)
  std::vector<SE3> T_c0_cam;                ///< camera k in c0 (k = 0 is the identity)
  std::unordered_map<std::uint64_t, Eigen::Vector3d> points;  ///< by track id, in c0
  double reprojection_rmse_px = 0.0;        ///< after BA, over inlier observations (σ-scaled, ≈ px)
};

VisualSfmResult solve_visual_sfm(const std::vector<std::vector<SfmObservation>>& frames,
                                 const VisualSfmOptions& options = {});

/// The point P (world) seen by the camera at T_world_cam on its normalized image plane:
///   q = T⁻¹ P,  r = (q_x / q_z, q_y / q_z) − z.
/// Jacobians (right perturbation T Exp(δ), δ = [ρ; φ]): ∂q/∂δ = [−I, [q]×], ∂q/∂P = Rᵀ,
/// ∂r/∂q = [[1/q_z, 0, −q_x/q_z²], [0, 1/q_z, −q_y/q_z²]]. A point with q_z ≤ 1e-6 gives the
/// constant residual (kOutOfView, kOutOfView) and zero Jacobians.
class NormalizedReprojectionFactor final : public FactorN<2, SE3, Eigen::Vector3d> {
 public:
  static constexpr double kOutOfView = 1.0;
  NormalizedReprojectionFactor(Key pose, Key point, const Eigen::Vector2d& measured,
                               std::shared_ptr<const NoiseModel> noise, std::shared_ptr<const RobustKernel> kernel = nullptr)
      : FactorN({pose, point}, std::move(noise), std::move(kernel)), measured_(measured) {}
  Residual error(const SE3& T_world_cam, const Eigen::Vector3d& P, Jacobian<SE3>* J_T,
                 Jacobian<Eigen::Vector3d>* J_P) const override;

 private:
  Eigen::Vector2d measured_;
};

/// The scale gauge of the SfM: r = ‖t‖ − 1 for the pose T = (R, t) of the reference frame.
/// Jacobian (right perturbation, t ← t + R ρ): ∂r/∂ρ = (t/‖t‖)ᵀ R, ∂r/∂φ = 0.
class BaselineFactor final : public FactorN<1, SE3> {
 public:
  BaselineFactor(Key pose, std::shared_ptr<const NoiseModel> noise) : FactorN({pose}, std::move(noise)) {}
  Residual error(const SE3& T, Jacobian<SE3>* J_T) const override;
};

}  // namespace slamkit
