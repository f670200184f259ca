// VIO on rendered images (issue 13, `slamkit vio --sim NAME --images`): the frames of a simulated
// run are rendered (in memory, or read from a folder written by `slamkit simulate --images`),
// the DVI front end (vio/image_frontend.h) tracks and classifies their pixels, and its tracks
// replace the simulator's ideal features: the returned run has, per frame, one observation per
// tracked feature (track id = feature id, uv = the raw fisheye pixel, which the estimator
// undistorts to a bearing with the camera model; dynamic = flagged dynamic by the epipolar test,
// unknown counted as static). The IMU, the truth and the camera are the simulator's.
// Every classified feature is scored against the label image (vio/frontend_scoring.h, objects
// slower than min_speed_mps excluded) by the patch rule (the labels under its KLT window; mixed
// patches counted apart) and by the centre-pixel rule. With the objects' distances (walker_distances),
// the patch-rule score counts only objects within [score_min_distance_m, score_max_distance_m] of
// the camera in the scored frame (issue 13: "at 2–6 m"; the others are neither hits, misses nor false
// alarms, like the slow ones); score_all_distances keeps every distance. Image time (rendering or PNG reading) is timed
// apart from tracking and classification.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "slamkit/core/parallel.h"
#include "slamkit/sim/image_renderer.h"
#include "slamkit/sim/rendered_scene.h"
#include "slamkit/sim/visual_inertial_sim.h"
#include "slamkit/vio/frontend_scoring.h"
#include "slamkit/vio/image_frontend.h"

namespace slamkit {

struct ImageVioOptions {
  /// With frontend.filter.known_rotation the front end is given each frame's rotation from the
  /// gyroscope (gyro_camera_rotations, bias zero: the front end runs before the window, whose bias
  /// estimate is not known yet; the simulator's gyro bias, σ 0.002 rad/s, turns a 4-frame test by ≤ 0.1 px).
  ImageFrontendOptions frontend;
  /// σ of the front end's pixels in the estimator [px] (KLT tracks; replaces the simulator's).
  double pixel_sigma = 1.0;
  double mask_margin_px = 8.0;  ///< corners are detected this far inside the fisheye mask circle
  double min_speed_mps = 0.3;   ///< slower objects are not scored (issue 13)
  /// Patch rule of the scoring (vio/frontend_scoring.h): half side of the label patch; −1: the KLT
  /// window's (klt_window / 2), 0: centre pixel only. The centre rule is always reported too.
  int score_patch_half_size_px = -1;
  /// Distance range of the scored objects (with object distances; see above) [m].
  double score_min_distance_m = 2.0, score_max_distance_m = 6.0;
  /// Called for every scored feature of frame k (analysis, `slamkit vio --feature-log`): its
  /// patch-rule truth (frontend_scoring.h: 0 static, > 0 object, kMixedTruth, kOutsideTruth) and
  /// the distance of that object (NaN if none or unknown). May be empty.
  std::function<void(std::size_t k, const FrontendFeature& f, int truth, double object_distance_m)> on_scored;
};

struct ImageVioReport {
  DetectionScore score;                 ///< over all frames, patch rule, objects in the distance range
  DetectionScore score_all_distances;   ///< the same at any distance (= score without object distances)
  bool distance_range_applied = false;  ///< object distances were given
  DetectionScore score_centre;          ///< over all frames, centre-pixel rule
  int score_patch_half_size_px = 0;     ///< the patch rule's h
  double static_ratio_mean = 1.0, static_ratio_min = 1.0;
  std::size_t frames = 0;
  std::size_t realigned_affine = 0, unflagged_affine = 0, refits_affine = 0;  ///< ImageFrontendOptions::affine_realign's counts
  std::size_t contests_lost = 0;   ///< tests whose trusted model gave way (ImageFrontendOptions::trust_contest_ratio)
  std::size_t isolated_flags = 0;  ///< isolated dynamic flags (ImageFrontendOptions::groups): left out, scored as not dynamic
  std::size_t graced_flags = 0;  ///< flags kept through a test under the threshold (ImageFrontendOptions::mover_grace_claims)
  std::size_t trust_undecided_frames = 0;  ///< frames whose flags were all isolated (ImageFrontendOptions::young_trust_majority)
  std::size_t frames_too_few_matches = 0, frames_no_fundamental = 0, frames_static_camera = 0;
  /// Frames by the motion model of their longest test (DynamicFeatureFilter's MotionModel, status kEpipolar).
  std::size_t frames_known_rotation = 0, frames_pure_rotation = 0, frames_rotation_rejected = 0;
  std::size_t frames_gyro_seeded = 0;  ///< frames whose KLT was seeded by the gyroscope (tracker.gyro_klt)
  /// Tracker counts per frame (means over the frames): tracks carried over, lost by KLT (status,
  /// ambiguity) and by the forward-backward check.
  double tracked_per_frame = 0.0, lost_klt_per_frame = 0.0, lost_forward_backward_per_frame = 0.0;
  double features_per_frame = 0.0;
  double image_ms_per_frame = 0.0;      ///< rendering (or reading the PNGs), wall clock
  double tracking_ms_per_frame = 0.0, classification_ms_per_frame = 0.0;
  double image_s = 0.0, frontend_s = 0.0;  ///< totals (wall clock)
  double frontend_cpu_s = 0.0;          ///< tracking + classification, process CPU time (all threads)
  std::string image_source;             ///< "rendered in memory" or the folder
};

/// Per frame k of the run: object id (label) -> distance of the object from the camera [m].
using ObjectDistances = std::function<std::map<int, double>(std::size_t k)>;

/// image (and labels) of frame k of the run; labels may be left empty (then nothing is scored).
using FrameImageSource = std::function<void(std::size_t k, GrayImage* image, GrayImage* labels)>;

/// Runs the front end on every frame and returns the run with its tracks (see above).
/// progress(k, n) after every frame (may be empty). Throws InputError for a run without frames
/// or camera; the front end's std::invalid_argument (frame size) becomes InputError naming frame k.
VisualInertialSim track_images(const VisualInertialSim& sim, const FrameImageSource& source,
                               const std::map<int, double>& label_speed_mps, const ImageVioOptions& options,
                               ImageVioReport* report, const std::function<void(std::size_t, std::size_t)>& progress = {});
/// The same with the objects' distances (may be empty: no distance range).
VisualInertialSim track_images(const VisualInertialSim& sim, const FrameImageSource& source,
                               const std::map<int, double>& label_speed_mps, const ObjectDistances& object_distance_m,
                               const ImageVioOptions& options, ImageVioReport* report,
                               const std::function<void(std::size_t, std::size_t)>& progress = {});

/// Per frame k ≥ 1 of the run: the camera's rotation from frame k − 1 to frame k, R_{c_k c_{k−1}}
/// (x_{c_k} = R x_{c_{k−1}} + t), from the gyroscope: ΔR = R_{i_{k−1}}ᵀ R_{i_k} by the midpoint
/// preintegration (factors/imu_preintegration.h) at gyro_bias, then R = R_ci ΔRᵀ R_ic with R_ci
/// the rotation of T_cam_imu. Entry 0, and frames whose interval the IMU does not cover: empty.
std::vector<std::optional<Eigen::Matrix3d>> gyro_camera_rotations(const VisualInertialSim& sim,
                                                                  const Eigen::Vector3d& gyro_bias = Eigen::Vector3d::Zero());

/// Object id -> speed of the scene's walkers (the scoring's speed map).
std::map<int, double> walker_speeds(const RenderedScene& scene);
/// Object id -> distance from the camera centre (true pose of frame k) to the centre of the
/// walker's box, for the walkers active at the frame's time; a label shared by several active
/// walkers (ids repeat mod 255) takes the nearest. Copies what it needs (scene and sim may go).
ObjectDistances walker_distances(const RenderedScene& scene, const VisualInertialSim& sim);

/// Frames rendered in memory by `renderer` (the scene it draws must outlive the source).
FrameImageSource rendered_frames(const VisualInertialSim& sim, const ImageRenderer& renderer, const ThreadPool* pool);

/// Frames read from a folder written by `slamkit simulate --images DIR` for the same run: its
/// cam0 stamps must be the run's frame stamps (InputError naming DIR/mav0/cam0/data.csv if not).
FrameImageSource folder_frames(const VisualInertialSim& sim, const std::string& dir);

}  // namespace slamkit
