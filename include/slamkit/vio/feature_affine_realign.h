// Affine re-alignment of the features flagged dynamic over a test's baseline (DVI front end,
// issue 13; docs/frontend.md "Session 35").
//
// Why: most static false alarms left on the rendered rooms are track errors, not motion-model
// errors: a KLT track chained frame to frame over b frames, translation-only, ends 1.5–4 px off
// where the patch it started on went (the fisheye and the viewpoint change the patch's shape;
// corners drift along edges). Aligning the patch of frame t − b directly with frame t under an
// affine warp (six parameters) finds that place again; a mover's patch, aligned the same way,
// lands on the mover and stays off the epipolar line.
// How, per match p1 → p2 flagged dynamic under the classification's model (status kEpipolar):
//   1. template: the (2h+1)² patch about p1 in the first image (bilinear, float); search image:
//      the (2(h+m)+1)² patch about p2 in the second;
//   2. OpenCV's enhanced-correlation alignment (cv::findTransformECC, MOTION_AFFINE: it maximizes
//      the zero-mean normalized correlation, so gain and offset changes do not matter), started at
//      the identity warp at p2;
//   3. accepted if it converged, the correlation is ≥ min_correlation, the warp's linear part keeps
//      areas within [1/2, 2] and the patch centre moved ≤ max_shift_px: p2 moves to the warped
//      centre, its epipolar distance is recomputed under the same model, and it is static if that
//      is at most static_distance_ratio × the filter's threshold (on the rendered rooms the static
//      track errors land at a median 0.07–0.14 × the threshold, the movers that the plain threshold
//      unflags at 0.42–0.62 ×).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/gray_image.h"

namespace slamkit {

struct AffineRealignOptions {
  bool enabled = true;  ///< on by default since session 35 (docs/frontend.md)
  int patch_half_px = 10;         ///< h: template (2h+1)² (the KLT window's half size by default)
  int search_margin_px = 8;       ///< m: the search patch reaches m px beyond the template (> max_shift_px)
  double max_shift_px = 6.0;      ///< the aligned centre must lie this close to p2
  double min_correlation = 0.8;   ///< ECC's normalized correlation at convergence
  /// A realigned match turns static when its distance is at most this fraction of the threshold:
  /// a static track error lands on its line (d ≈ 0), a mover just over the threshold may not move far.
  double static_distance_ratio = 0.5;
  /// ImageFrontend: when the re-alignment turns features static, fit the camera's motion again on
  /// the trusted tracks plus those and re-align what the new model flags (session 35: 2–6 m false
  /// alarms −23 % on seeds 1–2 of the rendered rooms, recall +0.017).
  bool refit_model = true;
  int max_iterations = 50;
  double epsilon = 1e-4;          ///< ECC stops when the correlation gains less than this
};

struct AffineRealignResult {
  std::vector<char> realigned;  ///< one per match: moved to its aligned pixel (distance recomputed)
  std::vector<char> unflagged;  ///< one per match: realigned and now static
  int tried = 0;                ///< dynamic matches aligned
  int realigned_count = 0;
  int unflagged_count = 0;
};

/// Throws std::invalid_argument on bad options.
void check_affine_realign_options(const AffineRealignOptions& o);

/// Re-aligns the matches prev[i] (in `before`) → cur[i] (in `after`) flagged dynamic in *c, with
/// consider[i] != 0 if given (see above). A realigned match gets cur[i] = the aligned pixel and
/// distance_px = its epipolar distance; under the threshold its flag turns static and c's counts
/// and M are updated. Nothing changes unless c->status is kEpipolar. `filter` must be the one that
/// made *c. Throws std::invalid_argument if sizes differ or the images are empty or differ in size.
AffineRealignResult realign_affine(const GrayImage& before, const GrayImage& after,
                                   const std::vector<Eigen::Vector2d>& prev, std::vector<Eigen::Vector2d>* cur,
                                   const DynamicFeatureFilter& filter, Classification* c,
                                   const AffineRealignOptions& options, const std::vector<char>* consider = nullptr);

}  // namespace slamkit
