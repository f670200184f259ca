// Epipolar re-search of the dynamic-flagged features (see the header). OpenCV's KLT does the
// search; this file only places the seeds on the line and judges the candidates.
#include "slamkit/vio/feature_epipolar_search.h"
#include "opencv_gray.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>
#include <string>

#include "slamkit/vio/feature_tracker.h"

namespace slamkit {

namespace {

// The best offset along the line of raw1's patch in `after` (1-D scan, see the header): the patch
// about raw1 and a strip about the foot, both in the line's frame (u along it, n across), correlated
// by matchTemplate; false if the line cannot be mapped.
bool scan_line(const cv::Mat& before, const cv::Mat& after, const DynamicFeatureFilter& filter, const Classification& c,
               const Eigen::Vector2d& raw1, const Eigen::Vector2d& raw2, int half, int reach, Eigen::Vector2d* best) {
  Eigen::Vector2d foot, ahead;
  if (!filter.epipolar_point(c, raw1, raw2, 0.0, &foot) || !filter.epipolar_point(c, raw1, raw2, 1.0, &ahead)) return false;
  const Eigen::Vector2d u = (ahead - foot).normalized(), n(-u.y(), u.x());  // the line's local frame in raw pixels
  if (!u.allFinite()) return false;
  // warpAffine with WARP_INVERSE_MAP: dst(x, y) = src(A (x, y, 1)), A = [u n origin].
  auto sample = [&](const cv::Mat& src, const Eigen::Vector2d& centre, int half_x, cv::Mat* dst) {
    const Eigen::Vector2d origin = centre - half_x * u - half * n;
    const cv::Mat A = (cv::Mat_<double>(2, 3) << u.x(), n.x(), origin.x(), u.y(), n.y(), origin.y());
    cv::warpAffine(src, *dst, A, cv::Size(2 * half_x + 1, 2 * half + 1), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                   cv::BORDER_REPLICATE);
    dst->convertTo(*dst, CV_32F);
  };
  cv::Mat patch, strip, score;
  sample(before, raw1, half, &patch);
  sample(after, foot, half + reach, &strip);
  cv::matchTemplate(strip, patch, score, cv::TM_CCOEFF_NORMED);
  cv::Point at;
  cv::minMaxLoc(score, nullptr, nullptr, nullptr, &at);
  double x = at.x;  // sub-pixel: the parabola through the peak and its neighbours
  if (at.x > 0 && at.x + 1 < score.cols) {
    const double l = score.at<float>(0, at.x - 1), m = score.at<float>(0, at.x), r = score.at<float>(0, at.x + 1);
    const double den = l - 2 * m + r;
    if (den < 0) x += std::clamp(0.5 * (l - r) / den, -0.5, 0.5);
  }
  *best = foot + (x - reach) * u;
  return best->allFinite();
}

double median_of(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

void check_epipolar_search_options(const EpipolarSearchOptions& o) {
  if (!(o.line_scan_half_px >= 0.0 && o.line_scan_half_px <= 256.0))
    throw std::invalid_argument("epipolar search: line_scan_half_px must be in [0, 256]");
  if (!(o.search_half_px >= 0.0) || !(o.seed_step_px > 0.0))
    throw std::invalid_argument("epipolar search: search_half_px must be >= 0 and seed_step_px > 0");
  if (o.klt_window < 3 || o.klt_pyramid_levels < 0 || o.klt_max_iterations < 1 || !(o.klt_epsilon > 0.0))
    throw std::invalid_argument("epipolar search: klt_window >= 3, klt_pyramid_levels >= 0, klt_max_iterations >= 1, klt_epsilon > 0");
  if (!(o.forward_backward_px > 0.0) || !(o.max_ncc_drop >= 0.0) || !(o.min_ncc >= -1.0 && o.min_ncc <= 1.0) ||
      o.patch_half_px < 1)
    throw std::invalid_argument(
        "epipolar search: forward_backward_px > 0, max_ncc_drop >= 0, min_ncc in [-1, 1], patch_half_px >= 1");
  if (o.search_half_px / o.seed_step_px > 64) throw std::invalid_argument("epipolar search: more than 129 seeds per feature");
}

EpipolarSearchResult search_along_epipolar(const GrayImage& before, const GrayImage& after,
                                           const std::vector<Eigen::Vector2d>& prev, std::vector<Eigen::Vector2d>* cur,
                                           const DynamicFeatureFilter& filter, Classification* c,
                                           const EpipolarSearchOptions& o, const std::vector<char>* consider) {
  check_epipolar_search_options(o);
  const std::size_t n = prev.size();
  if (cur->size() != n || c->flags.size() != n || (consider && consider->size() != n))
    throw std::invalid_argument("epipolar search: the matches, flags and mask differ in size");
  if (!valid(before) || !valid(after) || before.width != after.width || before.height != after.height)
    throw std::invalid_argument("epipolar search: the images are empty or differ in size");
  EpipolarSearchResult r;
  r.refound.assign(n, 0);
  if (c->status != ClassificationStatus::kEpipolar) return r;
  std::vector<std::size_t> tried;
  for (std::size_t i = 0; i < n; ++i)
    if (c->flags[i] == FeatureMotion::kDynamic && (!consider || (*consider)[i])) tried.push_back(i);
  if (tried.empty()) return r;

  // 1. Seeds on each line: the foot of cur, the 1-D offsets, the median static flow's prediction.
  Eigen::Vector2d median_flow(0, 0);
  bool have_median = false;
  if (o.seed_median_flow) {
    std::vector<double> fx, fy;
    for (std::size_t i = 0; i < n; ++i)
      if (c->flags[i] == FeatureMotion::kStatic) fx.push_back((*cur)[i].x() - prev[i].x()), fy.push_back((*cur)[i].y() - prev[i].y());
    if (!fx.empty()) median_flow = Eigen::Vector2d(median_of(fx), median_of(fy)), have_median = true;
  }
  const int steps = static_cast<int>(std::floor(o.search_half_px / o.seed_step_px));
  std::vector<cv::Point2f> from, seeds;
  std::vector<std::size_t> owner;  // match of each seed
  for (std::size_t i : tried) {
    auto add = [&](const Eigen::Vector2d& q) {
      if (q.x() < 0 || q.y() < 0 || q.x() > after.width - 1 || q.y() > after.height - 1) return;
      from.emplace_back(float(prev[i].x()), float(prev[i].y()));
      seeds.emplace_back(float(q.x()), float(q.y()));
      owner.push_back(i);
    };
    Eigen::Vector2d q;
    for (int k = -steps; k <= steps; ++k)
      if (filter.epipolar_point(*c, prev[i], (*cur)[i], k * o.seed_step_px, &q)) add(q);
    if (have_median && filter.epipolar_point(*c, prev[i], prev[i] + median_flow, 0.0, &q)) add(q);
  }
  r.tried = static_cast<int>(tried.size());
  if (seeds.empty()) return r;

  // 2. KLT from every seed, then back to the first image.
  const cv::Size window(o.klt_window, o.klt_window);
  std::vector<cv::Mat> pyr1, pyr2;
  cv::buildOpticalFlowPyramid(wrap(before), pyr1, window, o.klt_pyramid_levels);
  cv::buildOpticalFlowPyramid(wrap(after), pyr2, window, o.klt_pyramid_levels);
  const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, o.klt_max_iterations, o.klt_epsilon);
  std::vector<cv::Point2f> found = seeds, back = from;
  std::vector<uchar> status, status_back;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(pyr1, pyr2, from, found, status, err, window, o.klt_pyramid_levels, term,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  cv::calcOpticalFlowPyrLK(pyr2, pyr1, found, back, status_back, err, window, o.klt_pyramid_levels, term,
                           cv::OPTFLOW_USE_INITIAL_FLOW);

  // 3. The best candidate per match (highest NCC among those on the line), judged against the track.
  const double threshold = filter.options().threshold_px;
  std::vector<double> best_ncc(n, -2.0), best_d(n, 0.0);
  std::vector<Eigen::Vector2d> best_q(n);
  auto consider_candidate = [&](std::size_t i, const Eigen::Vector2d& q) {
    const double d = filter.epipolar_distance(*c, prev[i], q);
    if (!(d <= threshold)) return;
    const double ncc = patch_ncc(before, prev[i], after, q, o.patch_half_px);
    if (ncc > best_ncc[i]) best_ncc[i] = ncc, best_d[i] = d, best_q[i] = q;  // NaN never wins
  };
  for (std::size_t s = 0; s < seeds.size(); ++s)
    if (status[s] && status_back[s] && cv::norm(back[s] - from[s]) <= o.forward_backward_px)
      consider_candidate(owner[s], Eigen::Vector2d(found[s].x, found[s].y));
  const int reach = static_cast<int>(std::ceil(o.line_scan_half_px));
  if (reach > 0)
    for (std::size_t i : tried) {
      Eigen::Vector2d q;
      if (scan_line(wrap(before), wrap(after), filter, *c, prev[i], (*cur)[i], o.patch_half_px, reach, &q))
        consider_candidate(i, q);
    }
  for (std::size_t i : tried) {
    if (best_ncc[i] < -1.0) continue;
    const double own = patch_ncc(before, prev[i], after, (*cur)[i], o.patch_half_px);
    if (!(best_ncc[i] >= o.min_ncc) || !(best_ncc[i] >= own - o.max_ncc_drop)) continue;  // NaN own: no verdict
    (*cur)[i] = best_q[i];
    c->flags[i] = FeatureMotion::kStatic;
    c->distance_px[i] = best_d[i];
    r.refound[i] = 1, ++r.refound_count;
  }
  c->n_static += r.refound_count, c->n_dynamic -= r.refound_count;
  const int classified = c->n_static + c->n_dynamic;
  c->static_ratio = classified > 0 ? double(c->n_static) / classified : 1.0;
  return r;
}

}  // namespace slamkit
