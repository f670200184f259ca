// Epipolar re-search of the features flagged dynamic (DVI front end, issue 13; docs/frontend.md).
//
// Why: a static feature is flagged dynamic when KLT converged to a wrong location that still
// passes the forward-backward check (a neighbouring motif of a repeated texture, an occlusion
// edge). Its correct match lies on its epipolar line; a moving feature's does not.
// How, per match p1 → p2 flagged dynamic under the classification's model (status kEpipolar):
//   1. seeds on the epipolar line l = F p1: the point of l nearest p2 (virtual pinhole, mapped
//      back to raw pixels), that point moved by ±k·seed_step_px along l up to search_half_px
//      (a 1-D search), and, with seed_median_flow, the point of l nearest p1 + the median flow of
//      the static matches (where the dominant motion puts it);
//   2. from every seed, pyramidal KLT (calcOpticalFlowPyrLK, few levels so it stays near the
//      seed) into the second image, then back: a candidate q must converge, come back within
//      forward_backward_px of p1 and pass the epipolar test (distance ≤ the filter's threshold);
//   2b. with line_scan_half_px > 0, a 1-D scan along the line: the patch about p1 and a strip
//      along the line about the foot of p2, both sampled in the line's frame (cv::warpAffine),
//      are correlated by cv::matchTemplate (TM_CCOEFF_NORMED); its best offset is a candidate
//      (KLT's 2-D optimum may sit off the line, e.g. at an occlusion edge);
//   3. the candidate with the highest patch NCC with p1 (zero-mean, patch_ncc) is taken if its
//      NCC ≥ NCC(p1, p2) − max_ncc_drop and ≥ min_ncc: the feature is re-found static at q.
// A mover's KLT from a seed on the line converges back to its true (off-line) match or to a patch
// that looks less like it than its own track does; it stays dynamic.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "slamkit/vio/dynamic_feature_filter.h"
#include "slamkit/vio/gray_image.h"

namespace slamkit {

struct EpipolarSearchOptions {
  bool enabled = false;
  double search_half_px = 0.0;  ///< 1-D search: seeds up to this far along the line from the foot (0: foot only)
  double seed_step_px = 4.0;    ///< spacing of the 1-D seeds (virtual-pinhole px)
  bool seed_median_flow = true; ///< also seed where the median static flow puts p1, projected onto the line
  double line_scan_half_px = 0.0;  ///< 1-D NCC scan along the line up to this far from the foot (0: off)
  int klt_window = 21;
  int klt_pyramid_levels = 1;   ///< levels above the full image (few: the search stays near its seed)
  int klt_max_iterations = 30;
  double klt_epsilon = 0.01;
  double forward_backward_px = 1.0;  ///< the candidate's KLT back to the first image must land this close to p1
  double max_ncc_drop = 0.05;   ///< re-found iff NCC(candidate) ≥ NCC(track) − this
  double min_ncc = 0.5;         ///< and NCC(candidate) ≥ this
  int patch_half_px = 7;        ///< NCC patch (2h+1)²
};

struct EpipolarSearchResult {
  std::vector<char> refound;  ///< one per match: re-found static (its position and flag changed)
  int tried = 0;              ///< dynamic matches searched
  int refound_count = 0;
};

/// Throws std::invalid_argument on bad options.
void check_epipolar_search_options(const EpipolarSearchOptions& o);

/// Re-searches the matches prev[i] (in `before`) → cur[i] (in `after`) flagged dynamic in *c, with
/// consider[i] != 0 if given, along their epipolar line (see above). A re-found match gets
/// cur[i] = the candidate, flag static, distance_px = its epipolar distance; c's counts and M are
/// updated. Nothing changes unless c->status is kEpipolar. `filter` must be the one that made *c.
/// Throws std::invalid_argument if sizes differ or the images are empty or differ in size.
EpipolarSearchResult search_along_epipolar(const GrayImage& before, const GrayImage& after,
                                           const std::vector<Eigen::Vector2d>& prev, std::vector<Eigen::Vector2d>* cur,
                                           const DynamicFeatureFilter& filter, Classification* c,
                                           const EpipolarSearchOptions& options,
                                           const std::vector<char>* consider = nullptr);

}  // namespace slamkit
