// Visual-inertial initialization (VINS-Mono, Qin et al. T-RO 2018, section V), from a short
// visual structure-from-motion window: body rotations R_c0_bk and up-to-scale camera centres
// p̄_c0_ck in the frame c0 of the SfM, and the IMU preintegrated between consecutive frames.
//   1. Gyroscope bias: min Σ_k ‖Log(ΔR_k(b_g)ᵀ R_bkᵀ R_bk+1)‖², linearized with
//      ΔR(b_g) ≈ ΔR Exp(J_R^g δb_g): δb_g = (Σ JᵀJ)⁻¹ Σ Jᵀ Log(ΔRᵀ R_bkᵀ R_bk+1), twice.
//   2. Velocities v_k (in c0), gravity g (in c0) and the scale s by linear least squares on
//      every consecutive pair (p_bk = s p̄_ck − R_bk p_bc; Δt, Δp, Δv at the new b_g):
//        s (p̄_k+1 − p̄_k) − v_k Δt − ½ g Δt² = R_bk Δp + (R_bk+1 − R_bk) p_bc
//        v_k+1 − v_k − g Δt                    = R_bk Δv
//   3. Gravity refinement on its sphere: g = G ĝ + B w with B a basis of
//      ĝ's tangent plane, w ∈ ℝ², the same least squares in (v, w, s), 4 times, renormalized.
// Failure (never NaN): too few frames, too little excitation (the std of the preintegrated
// accelerations Δv/Δt below min_accel_excitation), SfM rotations that disagree with the
// gyroscope (after step 1, the RMS over consecutive pairs of |Log(ΔR(b_g)ᵀ R_bkᵀ R_bk+1)| above
// max_rotation_rms_deg: the SfM reconstructed something other than the camera's motion, e.g. a
// crowd moving together), a non-positive scale, a scale the window does not determine (its
// standard deviation from the alignment's residual above max_scale_rel_sigma of it), |g| away
// from G, or a singular system;
// `message` says which.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "slamkit/factors/imu_preintegration.h"
#include "slamkit/geometry/camera_models.h"
#include "slamkit/vio/sliding_window_estimator.h"
#include "slamkit/vio/visual_sfm.h"

namespace slamkit {

struct InitializerOptions {
  double gravity_magnitude = 9.81;     ///< G [m/s²]
  double max_gravity_error = 0.1;      ///< relative | |g| − G | / G accepted from step 2
  double min_accel_excitation = 0.25;  ///< [m/s²] std of Δv/Δt over the window (VINS-Mono's check)
  /// [deg] RMS disagreement of the SfM's relative rotations with the gyroscope's, after the bias
  /// fit (rendered rooms: 0.02–0.6° for accepted windows; ≤ 0 or NaN disables the check).
  double max_rotation_rms_deg = 2.0;
  /// The scale's standard deviation (σ̂² (H⁻¹)_ss of the last alignment, σ̂² from its residual)
  /// relative to the scale; a larger one means the window does not determine the scale
  /// (≤ 0 or NaN disables the check).
  double max_scale_rel_sigma = 0.25;
  int min_frames = 4;
  int refinement_iterations = 4;
};

struct InitializerInput {
  std::vector<SO3> R_c0_body;                 ///< body (IMU) rotation of frame k in c0
  std::vector<Eigen::Vector3d> p_c0_cam;      ///< camera centre of frame k in c0, up to scale
  std::vector<ImuPreintegration> imu;         ///< frame k → k+1 (size frames − 1)
  Eigen::Vector3d p_imu_cam = Eigen::Vector3d::Zero();  ///< camera position in the IMU frame
};

struct InitializerResult {
  bool success = false;
  std::string message;
  double scale = 0.0;
  double rotation_rms_deg = 0.0;  ///< SfM against gyroscope after the bias fit (step 1)
  double scale_sigma = 0.0;       ///< the scale's standard deviation from the alignment's residual
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d gravity_c0 = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> velocities_c0;
  /// The states in a gravity-aligned world frame (z up, g = (0, 0, −G), yaw and origin of frame 0):
  /// R_world_body, p (metric), v, b_g, b_a = 0.
  std::vector<ImuState> states;
  SO3 R_world_c0;
};

InitializerResult initialize_visual_inertial(const InitializerInput& input, const InitializerOptions& options = {});

/// The whole start-up on a window of frames (pixels with track ids) and the IMU covering them:
/// bearings through the camera model, visual SfM (vio/visual_sfm.h) for R_c0_body = R_c0_ck R_cb
/// and p̄_c0_ck, the IMU preintegrated between consecutive frames (zero bias), then
/// initialize_visual_inertial. `sfm` (optional) receives the SfM result.
InitializerResult initialize_from_frames(const std::vector<CameraFrame>& frames, const std::vector<ImuMeasurement>& imu,
                                         const CameraModel& camera, const SE3& T_imu_cam, const ImuNoise& noise,
                                         const VisualSfmOptions& sfm_options = {},
                                         const InitializerOptions& options = {}, VisualSfmResult* sfm = nullptr);

}  // namespace slamkit
