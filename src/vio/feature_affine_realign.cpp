// Affine re-alignment of the dynamic-flagged features (see the header). OpenCV's ECC does the
// alignment; this file cuts the patches and judges the result.
#include "slamkit/vio/feature_affine_realign.h"
#include "opencv_gray.h"

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>

namespace slamkit {

namespace {

bool inside(const Eigen::Vector2d& p, int half, const GrayImage& g) {
  return p.allFinite() && p.x() >= half && p.y() >= half && p.x() <= g.width - 1 - half && p.y() <= g.height - 1 - half;
}

// The aligned position of the patch about p1 (in `before`) near p2 (in `after`), or false.
bool align(const cv::Mat& before, const cv::Mat& after, const Eigen::Vector2d& p1, const Eigen::Vector2d& p2,
           const AffineRealignOptions& o, Eigen::Vector2d* q) {
  const int h = o.patch_half_px, r = o.patch_half_px + o.search_margin_px;
  cv::Mat templ, search;
  cv::getRectSubPix(before, cv::Size(2 * h + 1, 2 * h + 1), cv::Point2f(float(p1.x()), float(p1.y())), templ, CV_32F);
  cv::getRectSubPix(after, cv::Size(2 * r + 1, 2 * r + 1), cv::Point2f(float(p2.x()), float(p2.y())), search, CV_32F);
  // Warp W maps template pixels into the search patch: x' = A x + b; the identity at p2 is b = (m, m).
  cv::Mat W = (cv::Mat_<float>(2, 3) << 1, 0, float(o.search_margin_px), 0, 1, float(o.search_margin_px));
  double correlation = 0.0;
  try {
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, o.max_iterations, o.epsilon);
    correlation = cv::findTransformECC(templ, search, W, cv::MOTION_AFFINE, term, cv::noArray(), 1);
  } catch (const cv::Exception&) {
    return false;  // ECC did not converge (or the patch has no texture)
  }
  if (!(correlation >= o.min_correlation)) return false;
  const double a = W.at<float>(0, 0), b = W.at<float>(0, 1), c = W.at<float>(1, 0), d = W.at<float>(1, 1);
  const double area = a * d - b * c;
  if (!(area >= 0.5 && area <= 2.0)) return false;
  const Eigen::Vector2d centre(a * h + b * h + W.at<float>(0, 2), c * h + d * h + W.at<float>(1, 2));
  *q = p2 + centre - Eigen::Vector2d(r, r);
  return q->allFinite() && (*q - p2).norm() <= o.max_shift_px;
}

}  // namespace

void check_affine_realign_options(const AffineRealignOptions& o) {
  if (o.patch_half_px < 2 || o.patch_half_px > 64)
    throw std::invalid_argument("affine realign: patch_half_px must be in 2..64");
  if (!(o.max_shift_px > 0.0) || !(o.search_margin_px > o.max_shift_px) || o.search_margin_px > 64)
    throw std::invalid_argument("affine realign: need 0 < max_shift_px < search_margin_px <= 64");
  if (!(o.min_correlation >= -1.0 && o.min_correlation <= 1.0))
    throw std::invalid_argument("affine realign: min_correlation must be in [-1, 1]");
  if (!(o.static_distance_ratio > 0.0 && o.static_distance_ratio <= 1.0))
    throw std::invalid_argument("affine realign: static_distance_ratio must be in (0, 1]");
  if (o.max_iterations < 1 || !(o.epsilon > 0.0))
    throw std::invalid_argument("affine realign: max_iterations >= 1 and epsilon > 0");
}

AffineRealignResult realign_affine(const GrayImage& before, const GrayImage& after,
                                   const std::vector<Eigen::Vector2d>& prev, std::vector<Eigen::Vector2d>* cur,
                                   const DynamicFeatureFilter& filter, Classification* c,
                                   const AffineRealignOptions& o, const std::vector<char>* consider) {
  check_affine_realign_options(o);
  const std::size_t n = prev.size();
  if (cur->size() != n || c->flags.size() != n || c->distance_px.size() != n || (consider && consider->size() != n))
    throw std::invalid_argument("affine realign: the matches, flags and mask differ in size");
  if (!valid(before) || !valid(after) || before.width != after.width || before.height != after.height)
    throw std::invalid_argument("affine realign: the images are empty or differ in size");
  AffineRealignResult r;
  r.realigned.assign(n, 0), r.unflagged.assign(n, 0);
  if (c->status != ClassificationStatus::kEpipolar) return r;
  const cv::Mat img1 = wrap(before), img2 = wrap(after);
  const double threshold = filter.options().threshold_px;
  const int reach = o.patch_half_px + o.search_margin_px;
  for (std::size_t i = 0; i < n; ++i) {
    if (c->flags[i] != FeatureMotion::kDynamic || (consider && !(*consider)[i])) continue;
    if (!inside(prev[i], o.patch_half_px + 1, before) || !inside((*cur)[i], reach + 1, after)) continue;
    ++r.tried;
    Eigen::Vector2d q;
    if (!align(img1, img2, prev[i], (*cur)[i], o, &q)) continue;
    const double d = filter.epipolar_distance(*c, prev[i], q);
    if (std::isnan(d)) continue;
    (*cur)[i] = q;
    c->distance_px[i] = d;
    r.realigned[i] = 1, ++r.realigned_count;
    if (d <= o.static_distance_ratio * threshold) c->flags[i] = FeatureMotion::kStatic, r.unflagged[i] = 1, ++r.unflagged_count;
  }
  c->n_static += r.unflagged_count, c->n_dynamic -= r.unflagged_count;
  const int classified = c->n_static + c->n_dynamic;
  c->static_ratio = classified > 0 ? double(c->n_static) / classified : 1.0;
  return r;
}

}  // namespace slamkit
