// Epipolar classification of matched features (see the header for the algorithm).
#include "slamkit/vio/dynamic_feature_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <random>
#include <opencv2/calib3d.hpp>
#include <stdexcept>

#include "slamkit/vio/known_rotation_epipolar.h"

namespace slamkit {

const char* to_string(FeatureMotion m) {
  switch (m) {
    case FeatureMotion::kStatic: return "static";
    case FeatureMotion::kDynamic: return "dynamic";
    default: return "unknown";
  }
}

const char* to_string(MotionModel m) {
  switch (m) {
    case MotionModel::kEstimated: return "estimated";
    case MotionModel::kKnownRotation: return "known_rotation";
    case MotionModel::kPureRotation: return "pure_rotation";
    default: return "rotation_rejected";
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
  if (!(o.rotation_prior_sigma_rad >= 0.0) || !(o.pure_rotation_share > 0.0 && o.pure_rotation_share <= 1.0))
    throw std::invalid_argument("dynamic feature filter: rotation_prior_sigma_rad >= 0 and pure_rotation_share in (0, 1]");
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

bool DynamicFeatureFilter::spherical() const {
  return options_.spherical && camera_ && camera_->model_name() != "pinhole";
}

bool DynamicFeatureFilter::distort(const Eigen::Vector2d& virtual_uv, Eigen::Vector2d* out) const {
  if (!virtual_uv.allFinite()) return false;
  if (!camera_ || camera_->model_name() == "pinhole") {
    *out = virtual_uv;
    return true;
  }
  const Eigen::Vector3d b((virtual_uv.x() - cx_) / fx_, (virtual_uv.y() - cy_) / fy_, 1.0);
  return camera_->project(b, out) && out->allFinite();
}

double DynamicFeatureFilter::pinhole_distance(const Eigen::Matrix3d& F, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                              const Eigen::Vector2d& raw2) const {
  const Eigen::Vector3d l = F * a.homogeneous();  // (X, Y, Z)
  const double norm = std::hypot(l.x(), l.y());
  double d = norm > 0.0 ? std::abs(b.homogeneous().dot(l)) / norm : std::numeric_limits<double>::infinity();
  // Back to image pixels: a raw displacement δ moves the virtual pixel by J δ, so the raw
  // distance to the line is d / |Jᵀ n| with n the line's unit normal (J = I for a pinhole).
  Eigen::Matrix2d J;
  if (std::isfinite(d) && undistort_jacobian(raw2, &J)) d /= (J.transpose() * (l.head<2>() / norm)).norm();
  return d;
}

Classification DynamicFeatureFilter::classify(const std::vector<Eigen::Vector2d>& prev,
                                              const std::vector<Eigen::Vector2d>& cur,
                                              const std::vector<char>* trusted, const Eigen::Matrix3d* R_c2_c1) const {
  if (prev.size() != cur.size())
    throw std::invalid_argument("dynamic feature filter: " + std::to_string(prev.size()) + " previous and " +
                                std::to_string(cur.size()) + " current pixels");
  if (trusted && trusted->size() != prev.size())
    throw std::invalid_argument("dynamic feature filter: " + std::to_string(trusted->size()) + " trust flags for " +
                                std::to_string(prev.size()) + " matches");
  const std::size_t n = prev.size();
  Classification c;
  c.flags.assign(n, FeatureMotion::kUnknown);
  c.distance_px.assign(n, std::numeric_limits<double>::quiet_NaN());

  // 1. Undistort into the virtual pinhole.
  std::vector<std::size_t> index;  // usable match -> input index
  std::vector<cv::Point2d> p1, p2;
  std::vector<double> flow;
  std::vector<Eigen::Vector3d> b1, b2;  // unit bearings (spherical mode)
  const bool spherical = this->spherical();
  const bool known_rotation = options_.known_rotation && R_c2_c1 && camera_;
  for (std::size_t i = 0; i < n; ++i) {
    Eigen::Vector2d a, b;
    if (!undistort(prev[i], &a) || !undistort(cur[i], &b)) continue;
    if (spherical || known_rotation) {
      Eigen::Vector3d u, v;
      camera_->unproject(prev[i], &u), camera_->unproject(cur[i], &v);
      b1.push_back(u.normalized()), b2.push_back(v.normalized());
    }
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

  // 3. F by normalized 8-point + RANSAC, epipolar distance of every match. The model is fitted on
  // the trusted matches when there are enough of them, else on all.
  std::vector<char> fit(m, 1);
  if (trusted) {
    int n_trusted = 0;
    for (std::size_t k = 0; k < m; ++k) n_trusted += (*trusted)[index[k]] != 0;
    if (n_trusted >= options_.min_subset_fit())
      for (std::size_t k = 0; k < m; ++k) fit[k] = (*trusted)[index[k]] != 0;
  }
  if (options_.known_rotation && R_c2_c1) {  // IMU-aided: the translation direction alone (session 28)
    if (known_rotation) {
      std::vector<Eigen::Vector2d> v1(m), v2(m), raw2(m);
      for (std::size_t k = 0; k < m; ++k) v1[k] = {p1[k].x, p1[k].y}, v2[k] = {p2[k].x, p2[k].y}, raw2[k] = cur[index[k]];
      if (classify_known_rotation(b1, b2, v1, v2, raw2, index, fit, *R_c2_c1, &c)) {
        c.status = ClassificationStatus::kEpipolar;
        return finish();
      }
    }
    c.motion_model = MotionModel::kRotationRejected;  // no camera model, or R unusable: estimated below
  }
  if (spherical) {
    c.status = classify_spherical(b1, b2, index, fit, &c) ? ClassificationStatus::kEpipolar : ClassificationStatus::kNoFundamental;
    return finish();
  }
  std::vector<cv::Point2d> f1, f2;
  for (std::size_t k = 0; k < m; ++k)
    if (fit[k]) f1.push_back(p1[k]), f2.push_back(p2[k]);
  cv::Mat inliers;
  const cv::Mat F = cv::findFundamentalMat(f1, f2, cv::FM_RANSAC, options_.ransac_threshold_px,
                                           options_.ransac_confidence, options_.ransac_max_iterations, inliers);
  if (F.rows != 3 || F.cols != 3) {
    c.status = ClassificationStatus::kNoFundamental;
    return finish();
  }
  cv::Mat F_refined = F;
  if (options_.refit_on_inliers) {  // the normalized 8-point least squares on every RANSAC inlier
    std::vector<cv::Point2d> q1, q2;
    for (std::size_t k = 0; k < f1.size(); ++k)
      if (inliers.at<uchar>(int(k))) q1.push_back(f1[k]), q2.push_back(f2[k]);
    if (q1.size() >= 8) {
      const cv::Mat G = cv::findFundamentalMat(q1, q2, cv::FM_8POINT);
      if (G.rows == 3 && G.cols == 3) F_refined = G;
    }
  }
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k) c.F(r, k) = F_refined.at<double>(r, k);
  for (std::size_t k = 0; k < m; ++k) {
    const double d = pinhole_distance(c.F, Eigen::Vector2d(p1[k].x, p1[k].y), Eigen::Vector2d(p2[k].x, p2[k].y), cur[index[k]]);
    c.distance_px[index[k]] = d;
    c.flags[index[k]] = d > options_.threshold_px ? FeatureMotion::kDynamic : FeatureMotion::kStatic;
  }
  c.status = ClassificationStatus::kEpipolar;
  return finish();
}

bool DynamicFeatureFilter::contest(const std::vector<Eigen::Vector2d>& prev, const std::vector<Eigen::Vector2d>& cur,
                                   const Eigen::Matrix3d* R_c2_c1, double ratio, Classification* c) const {
  if (c->status != ClassificationStatus::kEpipolar || c->flags.size() != prev.size() ||
      c->n_dynamic < options_.min_subset_fit())
    return false;
  std::vector<char> flagged(c->flags.size());
  for (std::size_t m = 0; m < flagged.size(); ++m) flagged[m] = c->flags[m] == FeatureMotion::kDynamic;
  Classification alt = classify(prev, cur, &flagged, R_c2_c1);
  if (alt.status != ClassificationStatus::kEpipolar || !(alt.n_static > ratio * c->n_static)) return false;
  *c = std::move(alt);
  return true;
}

namespace {

// Essential matrix from ≥ 8 bearing pairs by linear least squares (b2ᵀ E b1 = 0, one row
// kron(b2, b1) per pair), projected onto the essential manifold (singular values (1, 1, 0)).
bool essential_8point(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                      const std::vector<int>& use, Eigen::Matrix3d* E) {
  Eigen::MatrixXd A(use.size(), 9);
  for (std::size_t r = 0; r < use.size(); ++r) {
    const Eigen::Vector3d& a = b1[use[r]];
    const Eigen::Vector3d& b = b2[use[r]];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) A(r, 3 * i + j) = b(i) * a(j);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd e = svd.matrixV().col(8);
  Eigen::Matrix3d M;
  M << e(0), e(1), e(2), e(3), e(4), e(5), e(6), e(7), e(8);
  Eigen::JacobiSVD<Eigen::Matrix3d> s(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  *E = s.matrixU() * Eigen::Vector3d(1, 1, 0).asDiagonal() * s.matrixV().transpose();
  return E->allFinite();
}

// Angle between b2 and the epipolar plane of b1 (normal E b1): asin(|b2·n| / |n|), b2 unit.
double epipolar_angle(const Eigen::Matrix3d& E, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2) {
  const Eigen::Vector3d n = E * b1;
  const double norm = n.norm();
  return norm > 0.0 ? std::asin(std::min(1.0, std::abs(b2.dot(n)) / norm)) : std::numeric_limits<double>::infinity();
}

// Rotation R with b2 ≈ R b1 by least squares (Kabsch: SVD of Σ b2 b1ᵀ, det R = +1).
Eigen::Matrix3d kabsch(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                       const std::vector<int>& use) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (int i : use) H += b2[i] * b1[i].transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> s(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d d(1, 1, (s.matrixU() * s.matrixV().transpose()).determinant() < 0 ? -1 : 1);
  return s.matrixU() * d.asDiagonal() * s.matrixV().transpose();
}

// The rotation that explains the most bearings within max_angle (RANSAC on pairs, then a refit on
// the inliers): under a (nearly) pure rotation E is ill-posed, but every static point, at any depth,
// moves as R says.
Eigen::Matrix3d ransac_rotation(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                                double max_angle, int iterations, std::mt19937* rng) {
  const int m = static_cast<int>(b1.size());
  const double cos_max = std::cos(max_angle);
  Eigen::Matrix3d best = Eigen::Matrix3d::Identity();
  int best_count = -1;
  std::uniform_int_distribution<int> pick(0, m - 1);
  for (int it = 0; it < iterations; ++it) {
    const int a = pick(*rng), b = pick(*rng);
    if (a == b || b1[a].cross(b1[b]).norm() < 1e-3) continue;
    const Eigen::Matrix3d R = kabsch(b1, b2, {a, b});
    int count = 0;
    for (int i = 0; i < m; ++i) count += b2[i].dot(R * b1[i]) >= cos_max;
    if (count > best_count) best_count = count, best = R;
  }
  std::vector<int> inliers;
  for (int i = 0; i < m; ++i)
    if (b2[i].dot(best * b1[i]) >= cos_max) inliers.push_back(i);
  return inliers.size() >= 2 ? kabsch(b1, b2, inliers) : best;
}

// Signed sine of the angle between b2 and the epipolar plane of b1 under (R, t): b2·n / |n|, n = t × R b1.
double epipolar_sine(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2) {
  const Eigen::Vector3d n = t.cross(R * b1);
  const double norm = n.norm();
  return norm > 0.0 ? b2.dot(n) / norm : 0.0;
}

// (R, t) moved by the 5-vector x: R ← exp(x₀..₂) R, t ← normalize(t + x₃ e₁ + x₄ e₂) (e₁, e₂ ⊥ t).
void perturb(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
             const Eigen::Matrix<double, 5, 1>& x, Eigen::Matrix3d* R2, Eigen::Vector3d* t2) {
  const Eigen::Vector3d w = x.head<3>();
  const double angle = w.norm();
  *R2 = (angle > 0.0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity()) * R;
  *t2 = (t + x(3) * e1 + x(4) * e2).normalized();
}

// Levenberg–Marquardt on the Cauchy-weighted sines (DynamicFilterOptions::refine_essential); the
// Jacobian by central differences. Returns E = [t]× R (the input's constraint up to sign at start).
Eigen::Matrix3d refine_essential_lm(const Eigen::Matrix3d& E0, const std::vector<Eigen::Vector3d>& b1,
                                    const std::vector<Eigen::Vector3d>& b2, double scale, int iterations) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(E0, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  if (U.determinant() < 0) U.col(2) *= -1;
  if (V.determinant() < 0) V.col(2) *= -1;
  Eigen::Matrix3d W;
  W << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  Eigen::Matrix3d R = U * W * V.transpose();  // [u₃]× U W Vᵀ = −E0: the same constraint
  Eigen::Vector3d t = U.col(2);
  const int m = static_cast<int>(b1.size());
  const double c2 = scale * scale;
  auto cost = [&](const Eigen::Matrix3d& Rr, const Eigen::Vector3d& tt) {
    double sum = 0.0;
    for (int i = 0; i < m; ++i) {
      const double s = epipolar_sine(Rr, tt, b1[i], b2[i]);
      sum += std::log1p(s * s / c2);
    }
    return sum;
  };
  double current = cost(R, t), lambda = 1e-3;
  for (int it = 0; it < iterations; ++it) {
    Eigen::Vector3d e1 = t.unitOrthogonal(), e2 = t.cross(e1);
    Eigen::Matrix<double, 5, 5> H = Eigen::Matrix<double, 5, 5>::Zero();
    Eigen::Matrix<double, 5, 1> g = Eigen::Matrix<double, 5, 1>::Zero();
    // The ±h moves of the five coordinates do not depend on the match: built once per iteration.
    const double h = 1e-6;
    Eigen::Matrix3d Rp[5], Rm[5];
    Eigen::Vector3d tp[5], tm[5];
    for (int k = 0; k < 5; ++k) {
      Eigen::Matrix<double, 5, 1> x = Eigen::Matrix<double, 5, 1>::Zero();
      x(k) = h, perturb(R, t, e1, e2, x, &Rp[k], &tp[k]);
      x(k) = -h, perturb(R, t, e1, e2, x, &Rm[k], &tm[k]);
    }
    for (int i = 0; i < m; ++i) {
      const double s = epipolar_sine(R, t, b1[i], b2[i]);
      Eigen::Matrix<double, 1, 5> J;
      for (int k = 0; k < 5; ++k)
        J(k) = (epipolar_sine(Rp[k], tp[k], b1[i], b2[i]) - epipolar_sine(Rm[k], tm[k], b1[i], b2[i])) / (2 * h);
      const double w = 1.0 / (1.0 + s * s / c2);  // IRLS weight of the Cauchy loss
      H += w * J.transpose() * J, g += w * J.transpose() * s;
    }
    bool improved = false;
    for (int tries = 0; tries < 6 && !improved; ++tries) {
      Eigen::Matrix<double, 5, 5> A = H;
      A.diagonal() *= 1.0 + lambda;
      const Eigen::Matrix<double, 5, 1> dx = A.ldlt().solve(-g);
      if (!dx.allFinite()) break;
      Eigen::Matrix3d R2;
      Eigen::Vector3d t2;
      perturb(R, t, e1, e2, dx, &R2, &t2);
      const double next = cost(R2, t2);
      if (next < current) R = R2, t = t2, current = next, lambda *= 0.3, improved = true;
      else lambda *= 10.0;
    }
    if (!improved) break;
  }
  Eigen::Matrix3d tx;
  tx << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  return tx * R;
}

}  // namespace

bool DynamicFeatureFilter::classify_spherical(const std::vector<Eigen::Vector3d>& all_b1,
                                              const std::vector<Eigen::Vector3d>& all_b2,
                                              const std::vector<std::size_t>& index, const std::vector<char>& fit,
                                              Classification* c) const {
  std::vector<Eigen::Vector3d> b1, b2;  // the matches the models are fitted on
  for (std::size_t k = 0; k < all_b1.size(); ++k)
    if (fit[k]) b1.push_back(all_b1[k]), b2.push_back(all_b2[k]);
  const int m = static_cast<int>(b1.size());
  const double f = fx_;  // pixels per radian at the centre (and radially everywhere, equidistant)
  const double inlier_angle = options_.ransac_threshold_px / f;
  std::mt19937 rng(0x5eed);  // fixed seed: the same matches give the same flags
  std::vector<int> all(m), sample(8);
  for (int i = 0; i < m; ++i) all[i] = i;
  Eigen::Matrix3d best = Eigen::Matrix3d::Zero();
  int best_count = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  long iterations = options_.ransac_max_iterations;
  for (long it = 0; it < iterations; ++it) {
    for (int j = 0; j < 8; ++j) {  // partial Fisher-Yates: 8 distinct indices
      std::uniform_int_distribution<int> pick(j, m - 1);
      std::swap(all[j], all[pick(rng)]);
      sample[j] = all[j];
    }
    Eigen::Matrix3d E;
    if (!essential_8point(b1, b2, sample, &E)) continue;
    int count = 0;
    double cost = 0.0;  // MSAC: inliers cost their error, outliers the threshold
    for (int i = 0; i < m; ++i) {
      const double a = epipolar_angle(E, b1[i], b2[i]);
      if (a <= inlier_angle) ++count, cost += a; else cost += inlier_angle;
    }
    if (cost < best_cost) {
      best_cost = cost, best_count = count, best = E;
      const double w = double(count) / m;  // adaptive number of iterations for the confidence
      const double miss = 1.0 - std::pow(w, 8);
      if (miss <= 0.0) break;
      const double need = std::log(1.0 - options_.ransac_confidence) / std::log(miss);
      iterations = std::min<long>(iterations, std::max<long>(100, static_cast<long>(std::ceil(3 * need))));
    }
  }
  if (best_count < 8) return false;
  std::vector<int> inliers;
  for (int i = 0; i < m; ++i)
    if (epipolar_angle(best, b1[i], b2[i]) <= inlier_angle) inliers.push_back(i);
  if (options_.refit_on_inliers && inliers.size() >= 8) {
    Eigen::Matrix3d E;
    if (essential_8point(b1, b2, inliers, &E)) best = E;
  }
  if (options_.refine_essential) {  // on the matches the linear model keeps under the classification threshold
    std::vector<Eigen::Vector3d> q1, q2;
    for (int i = 0; i < m; ++i)
      if (epipolar_angle(best, b1[i], b2[i]) <= options_.threshold_px / f) q1.push_back(b1[i]), q2.push_back(b2[i]);
    if (q1.size() >= 8) {
      const Eigen::Matrix3d E = refine_essential_lm(best, q1, q2, options_.ransac_threshold_px / f, 10);
      if (E.allFinite()) best = E;
    }
  }
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = fx_, K(1, 1) = fy_, K(0, 2) = cx_, K(1, 2) = cy_;
  const Eigen::Matrix3d Kinv = K.inverse();
  c->F = Kinv.transpose() * best * Kinv;  // the same constraint on the virtual pinhole
  // A point that moves as the pure rotation says is static whatever E says (E is ill-posed when the
  // translation is small); one that breaks both models is dynamic. d = min(epipolar, rotation) · f.
  const Eigen::Matrix3d R = ransac_rotation(b1, b2, options_.threshold_px / f, 200, &rng);
  for (std::size_t i = 0; i < all_b1.size(); ++i) {
    const double rot = std::acos(std::clamp(all_b2[i].dot(R * all_b1[i]), -1.0, 1.0));
    const double d = f * std::min(epipolar_angle(best, all_b1[i], all_b2[i]), rot);
    c->distance_px[index[i]] = d;
    c->flags[index[i]] = d > options_.threshold_px ? FeatureMotion::kDynamic : FeatureMotion::kStatic;
  }
  return true;
}

double DynamicFeatureFilter::rotation_distance(const Eigen::Matrix3d& R, const Eigen::Vector3d& b1, const Eigen::Vector2d& b,
                                               const Eigen::Vector2d& raw2) const {
  const Eigen::Vector3d a = R * b1;
  if (!(a.z() > 0.0)) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d q(fx_ * a.x() / a.z() + cx_, fy_ * a.y() / a.z() + cy_);  // R b1 on the virtual pinhole
  Eigen::Matrix2d J;
  if (undistort_jacobian(raw2, &J)) return (J.inverse() * (b - q)).norm();  // virtual → raw pixels
  return (b - q).norm();
}

bool DynamicFeatureFilter::classify_known_rotation(const std::vector<Eigen::Vector3d>& all_b1,
                                                   const std::vector<Eigen::Vector3d>& all_b2,
                                                   const std::vector<Eigen::Vector2d>& v1, const std::vector<Eigen::Vector2d>& v2,
                                                   const std::vector<Eigen::Vector2d>& raw2, const std::vector<std::size_t>& index,
                                                   const std::vector<char>& fit, const Eigen::Matrix3d& R,
                                                   Classification* c) const {
  std::vector<Eigen::Vector3d> b1, b2;
  for (std::size_t k = 0; k < all_b1.size(); ++k)
    if (fit[k]) b1.push_back(all_b1[k]), b2.push_back(all_b2[k]);
  const double f = fx_;  // pixels per radian (see classify_spherical)
  KnownRotationOptions ko;
  ko.inlier_angle_rad = options_.ransac_threshold_px / f;
  ko.confidence = options_.ransac_confidence;
  ko.max_iterations = options_.ransac_max_iterations;
  ko.min_inliers = options_.min_matches;
  ko.pure_rotation_share = options_.pure_rotation_share;
  ko.refit = options_.refit_on_inliers;
  ko.refine = options_.refine_essential;
  ko.refine_angle_rad = options_.threshold_px / f;
  ko.cauchy_scale_rad = options_.ransac_threshold_px / f;
  ko.rotation_prior_sigma_rad = options_.rotation_prior_sigma_rad;
  const KnownRotationModel model = fit_known_rotation(b1, b2, R, ko);
  if (model.status != KnownRotationStatus::kTranslation && model.status != KnownRotationStatus::kPureRotation) return false;
  const bool pure = model.status == KnownRotationStatus::kPureRotation;
  c->motion_model = pure ? MotionModel::kPureRotation : MotionModel::kKnownRotation;
  c->R = model.R, c->t = model.t;
  Eigen::Matrix3d tx;
  tx << 0, -model.t.z(), model.t.y(), model.t.z(), 0, -model.t.x(), -model.t.y(), model.t.x(), 0;
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = fx_, K(1, 1) = fy_, K(0, 2) = cx_, K(1, 2) = cy_;
  const Eigen::Matrix3d Kinv = K.inverse();
  c->F = Kinv.transpose() * tx * model.R * Kinv;  // zero under pure rotation (no epipolar line)
  const bool sph = spherical();
  // Cheirality (model.t is oriented by the fit): a match behind R b1, a negative depth for a static
  // point, by more than the threshold is as far from the static model as the distance says.
  const bool cheirality = options_.cheirality && !pure;
  for (std::size_t k = 0; k < all_b1.size(); ++k) {
    // Spherical: f · the angle to the epipolar plane (pure rotation: to R b1); pinhole: the
    // virtual-pinhole distance mapped to raw pixels, as for an estimated F.
    double d = sph    ? f * known_rotation_angle(model.R, model.t, all_b1[k], all_b2[k])
               : pure ? rotation_distance(model.R, all_b1[k], v2[k], raw2[k])
                      : pinhole_distance(c->F, v1[k], v2[k], raw2[k]);
    if (cheirality) {
      const double behind = -f * known_rotation_parallax(model.R, model.t, all_b1[k], all_b2[k]);
      if (behind > d) d = behind;  // NaN parallax: d unchanged
    }
    c->distance_px[index[k]] = d;
    c->flags[index[k]] = d > options_.threshold_px ? FeatureMotion::kDynamic : FeatureMotion::kStatic;
  }
  return true;
}

double DynamicFeatureFilter::epipolar_distance(const Classification& c, const Eigen::Vector2d& raw1,
                                               const Eigen::Vector2d& raw2) const {
  Eigen::Vector2d a, b;
  if (c.status != ClassificationStatus::kEpipolar || !undistort(raw1, &a) || !undistort(raw2, &b))
    return std::numeric_limits<double>::quiet_NaN();
  if (c.motion_model == MotionModel::kKnownRotation || c.motion_model == MotionModel::kPureRotation) {
    Eigen::Vector3d u, v;
    if (!camera_->unproject(raw1, &u) || !camera_->unproject(raw2, &v)) return std::numeric_limits<double>::quiet_NaN();
    if (c.motion_model == MotionModel::kPureRotation && !spherical()) return rotation_distance(c.R, u.normalized(), b, raw2);
    if (!spherical()) return pinhole_distance(c.F, a, b, raw2);
    return fx_ * known_rotation_angle(c.R, c.t, u, v);
  }
  if (!spherical()) return pinhole_distance(c.F, a, b, raw2);
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();  // c.F = K⁻ᵀ E K⁻¹, so E = Kᵀ F K (up to scale)
  K(0, 0) = fx_, K(1, 1) = fy_, K(0, 2) = cx_, K(1, 2) = cy_;
  Eigen::Vector3d u, v;
  if (!camera_->unproject(raw1, &u) || !camera_->unproject(raw2, &v)) return std::numeric_limits<double>::quiet_NaN();
  return fx_ * epipolar_angle(K.transpose() * c.F * K, u.normalized(), v.normalized());
}

bool DynamicFeatureFilter::epipolar_point(const Classification& c, const Eigen::Vector2d& raw1, const Eigen::Vector2d& raw2,
                                          double offset_px, Eigen::Vector2d* raw_on_line) const {
  Eigen::Vector2d a, b;
  if (c.status != ClassificationStatus::kEpipolar || !undistort(raw1, &a) || !undistort(raw2, &b)) return false;
  const Eigen::Vector3d l = c.F * a.homogeneous();
  const double norm = std::hypot(l.x(), l.y());
  if (!(norm > 0.0) || !l.allFinite()) return false;
  const Eigen::Vector2d n = l.head<2>() / norm;              // unit normal of the line
  const Eigen::Vector2d foot = b - (b.dot(n) + l.z() / norm) * n;  // n·q + l_z/|l_xy| = 0 on the line
  return distort(foot + offset_px * Eigen::Vector2d(-n.y(), n.x()), raw_on_line);
}

}  // namespace slamkit
