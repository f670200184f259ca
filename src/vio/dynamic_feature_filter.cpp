// Epipolar classification of matched features (see the header for the algorithm).
#include "slamkit/vio/dynamic_feature_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <Eigen/LU>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

namespace slamkit {

const char* to_string(FeatureMotion m) {
  switch (m) {
    case FeatureMotion::kStatic: return "static";
    case FeatureMotion::kDynamic: return "dynamic";
    default: return "unknown";
  }
}

const char* to_string(ClassificationStatus s) {
  switch (s) {
    case ClassificationStatus::kEpipolar: return "epipolar";
    case ClassificationStatus::kStaticCamera: return "static_camera";
    case ClassificationStatus::kTooFewMatches: return "too_few_matches";
    default: return "no_fundamental_matrix";
  }
}

DynamicFeatureFilter::DynamicFeatureFilter(DynamicFilterOptions o, std::shared_ptr<const CameraModel> camera)
    : options_(o), camera_(std::move(camera)) {
  if (!(o.threshold_px > 0.0) || !(o.ransac_threshold_px > 0.0))
    throw std::invalid_argument("dynamic feature filter: threshold_px and ransac_threshold_px must be > 0");
  if (!(o.ransac_confidence > 0.0 && o.ransac_confidence < 1.0) || o.ransac_max_iterations < 1)
    throw std::invalid_argument("dynamic feature filter: ransac_confidence in (0, 1), ransac_max_iterations >= 1");
  if (o.min_matches < 8) throw std::invalid_argument("dynamic feature filter: min_matches must be >= 8 (8-point algorithm)");
  if (camera_) {
    const Eigen::VectorXd k = camera_->intrinsics();
    fx_ = k[0], fy_ = k[1], cx_ = k[2], cy_ = k[3];
  }
}

bool DynamicFeatureFilter::undistort(const Eigen::Vector2d& uv, Eigen::Vector2d* out) const {
  if (!uv.allFinite()) return false;
  if (!camera_ || camera_->model_name() == "pinhole") {
    *out = uv;
    return true;
  }
  Eigen::Vector3d b;
  if (!camera_->unproject(uv, &b) || !(b.z() > options_.min_bearing_z * b.norm())) return false;
  *out = Eigen::Vector2d(fx_ * b.x() / b.z() + cx_, fy_ * b.y() / b.z() + cy_);
  return true;
}

bool DynamicFeatureFilter::undistort_jacobian(const Eigen::Vector2d& uv, Eigen::Matrix2d* J) const {
  if (!camera_ || camera_->model_name() == "pinhole") return false;
  const double h = 0.5;  // px, central differences
  for (int axis = 0; axis < 2; ++axis) {
    Eigen::Vector2d plus, minus;
    if (!undistort(uv + h * Eigen::Vector2d::Unit(axis), &plus) || !undistort(uv - h * Eigen::Vector2d::Unit(axis), &minus))
      return false;
    J->col(axis) = (plus - minus) / (2.0 * h);
  }
  return J->allFinite() && std::abs(J->determinant()) > 1e-9;
}

Classification DynamicFeatureFilter::classify(const std::vector<Eigen::Vector2d>& prev,
                                              const std::vector<Eigen::Vector2d>& cur) const {
  if (prev.size() != cur.size())
    throw std::invalid_argument("dynamic feature filter: " + std::to_string(prev.size()) + " previous and " +
                                std::to_string(cur.size()) + " current pixels");
  const std::size_t n = prev.size();
  Classification c;
  c.flags.assign(n, FeatureMotion::kUnknown);
  c.distance_px.assign(n, std::numeric_limits<double>::quiet_NaN());

  // 1. Undistort into the virtual pinhole.
  std::vector<std::size_t> index;  // usable match -> input index
  std::vector<cv::Point2d> p1, p2;
  std::vector<double> flow;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector2d a, b;
    if (!undistort(prev[i], &a) || !undistort(cur[i], &b)) continue;
    index.push_back(i);
    p1.emplace_back(a.x(), a.y()), p2.emplace_back(b.x(), b.y());
    flow.push_back((b - a).norm());
  }
  const std::size_t m = index.size();
  auto finish = [&]() {
    for (FeatureMotion f : c.flags) (f == FeatureMotion::kStatic ? c.n_static : f == FeatureMotion::kDynamic ? c.n_dynamic : c.n_unknown)++;
    const int classified = c.n_static + c.n_dynamic;
    c.static_ratio = classified > 0 ? double(c.n_static) / classified : 1.0;
    return c;
  };
  if (int(m) < options_.min_matches) {
    c.status = ClassificationStatus::kTooFewMatches;
    return finish();
  }
  auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  c.median_flow_px = median(flow);

  // 2. A camera that does not move: the dominant motion is the median flow (about zero).
  if (c.median_flow_px < options_.static_camera_flow_px) {
    std::vector<double> fx(m), fy(m);
    for (std::size_t k = 0; k < m; ++k) fx[k] = p2[k].x - p1[k].x, fy[k] = p2[k].y - p1[k].y;
    const double mx = median(fx), my = median(fy);
    for (std::size_t k = 0; k < m; ++k) {
      const double d = std::hypot(fx[k] - mx, fy[k] - my);
      c.distance_px[index[k]] = d;
      c.flags[index[k]] = d > options_.threshold_px ? FeatureMotion::kDynamic : FeatureMotion::kStatic;
    }
    c.status = ClassificationStatus::kStaticCamera;
    return finish();
  }

  // 3. F by normalized 8-point + RANSAC, epipolar distance of every match.
  cv::Mat inliers;
  const cv::Mat F = cv::findFundamentalMat(p1, p2, cv::FM_RANSAC, options_.ransac_threshold_px,
                                           options_.ransac_confidence, options_.ransac_max_iterations, inliers);
  if (F.rows != 3 || F.cols != 3) {
    c.status = ClassificationStatus::kNoFundamental;
    return finish();
  }
  cv::Mat F_refined = F;
  if (options_.refit_on_inliers) {  // the normalized 8-point least squares on every RANSAC inlier
    std::vector<cv::Point2d> q1, q2;
    for (std::size_t k = 0; k < m; ++k)
      if (inliers.at<uchar>(int(k))) q1.push_back(p1[k]), q2.push_back(p2[k]);
    if (q1.size() >= 8) {
      const cv::Mat G = cv::findFundamentalMat(q1, q2, cv::FM_8POINT);
      if (G.rows == 3 && G.cols == 3) F_refined = G;
    }
  }
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) c.F(r, k) = F_refined.at<double>(r, k);
  for (std::size_t k = 0; k < m; ++k) {
    const Eigen::Vector3d a(p1[k].x, p1[k].y, 1.0), b(p2[k].x, p2[k].y, 1.0);
    const Eigen::Vector3d l = c.F * a;  // (X, Y, Z)
    const double norm = std::hypot(l.x(), l.y());
    double d = norm > 0.0 ? std::abs(b.dot(l)) / norm : std::numeric_limits<double>::infinity();
    // Back to image pixels: a raw displacement δ moves the virtual pixel by J δ, so the raw
    // distance to the line is d / |Jᵀ n| with n the line's unit normal (J = I for a pinhole).
    Eigen::Matrix2d J;
    if (std::isfinite(d) && undistort_jacobian(cur[index[k]], &J)) d /= (J.transpose() * (l.head<2>() / norm)).norm();
    c.distance_px[index[k]] = d;
    c.flags[index[k]] = d > options_.threshold_px ? FeatureMotion::kDynamic : FeatureMotion::kStatic;
  }
  c.status = ClassificationStatus::kEpipolar;
  return finish();
}

}  // namespace slamkit
