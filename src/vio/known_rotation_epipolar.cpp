// The epipolar model with a known rotation: 2-point RANSAC on the translation direction (see the header).
#include "slamkit/vio/known_rotation_epipolar.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace slamkit {

const char* to_string(KnownRotationStatus s) {
  switch (s) {
    case KnownRotationStatus::kTranslation: return "translation";
    case KnownRotationStatus::kPureRotation: return "pure_rotation";
    case KnownRotationStatus::kTooFewMatches: return "too_few_matches";
    case KnownRotationStatus::kInvalidRotation: return "invalid_rotation";
    default: return "no_consensus";
  }
}

bool translation_from_two_matches(const Eigen::Matrix3d& R, const Eigen::Vector3d& a1, const Eigen::Vector3d& b1,
                                  const Eigen::Vector3d& a2, const Eigen::Vector3d& b2, Eigen::Vector3d* t) {
  // t · (R a × b) = 0 for both matches: t is normal to both plane normals.
  const Eigen::Vector3d n1 = (R * a1.normalized()).cross(b1.normalized());
  const Eigen::Vector3d n2 = (R * a2.normalized()).cross(b2.normalized());
  const Eigen::Vector3d v = n1.cross(n2);
  const double norm = v.norm();
  // sin of the angle between the normals, relative to their lengths: under 1e-9 they are parallel.
  if (!(norm > 1e-9 * n1.norm() * n2.norm()) || !(norm > 1e-15) || !v.allFinite()) return false;
  *t = v / norm;
  return true;
}

namespace {

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {  // robust for small angles
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Signed sine of the angle between unit b2 and the plane of t and a = R b1 (0 when undefined).
double signed_sine(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector3d& b1, const Eigen::Vector3d& b2) {
  const Eigen::Vector3d n = t.cross(R * b1);
  const double norm = n.norm();
  return norm > 1e-12 ? b2.dot(n) / norm : 0.0;
}

bool is_rotation(const Eigen::Matrix3d& R) {
  return R.allFinite() && (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-6 && R.determinant() > 0.0;
}

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& w) {
  const double angle = w.norm();
  return angle > 0.0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

Eigen::Vector3d log_so3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

// Weighted least squares t on the rows nᵢ = R b1ᵢ × b2ᵢ (weights 1 / |t × R b1ᵢ|, t the current guess):
// the smallest right singular vector; false if not defined.
bool refit_translation(const Eigen::Matrix3d& R, const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2,
                       const std::vector<int>& use, Eigen::Vector3d* t) {
  if (use.size() < 2) return false;
  Eigen::MatrixXd A(use.size(), 3);
  for (std::size_t r = 0; r < use.size(); ++r) {
    const Eigen::Vector3d a = R * b1[use[r]];
    const double w = t->cross(a).norm();
    A.row(r) = a.cross(b2[use[r]]).transpose() / std::max(w, 1e-6);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::Vector3d v = svd.matrixV().col(2);
  if (!v.allFinite() || !(svd.singularValues()(1) > 0.0)) return false;
  *t = v.dot(*t) < 0 ? Eigen::Vector3d(-v) : v;  // keep the guess's sign (cosmetic)
  return true;
}

// Levenberg–Marquardt on Σ ½ log(1 + sᵢ²/c²) [+ ½ |Log(R R₀ᵀ)|² / σ²] over t (2 tangent
// coordinates) and, with σ > 0, R (3, left increment); numeric Jacobian of the sines.
void refine(const std::vector<Eigen::Vector3d>& b1, const std::vector<Eigen::Vector3d>& b2, const std::vector<int>& use,
            const Eigen::Matrix3d& R0, double c, double sigma, Eigen::Matrix3d* R, Eigen::Vector3d* t) {
  const int np = sigma > 0.0 ? 5 : 2;
  const double c2 = c * c;
  using Vec = Eigen::Matrix<double, 5, 1>;
  auto moved = [&](const Eigen::Matrix3d& Rr, const Eigen::Vector3d& tt, const Eigen::Vector3d& e1, const Eigen::Vector3d& e2,
                   const Vec& x, Eigen::Matrix3d* R2, Eigen::Vector3d* t2) {
    *t2 = (tt + x(0) * e1 + x(1) * e2).normalized();
    *R2 = np == 5 ? exp_so3(x.tail<3>()) * Rr : Rr;
  };
  auto cost = [&](const Eigen::Matrix3d& Rr, const Eigen::Vector3d& tt) {
    double sum = 0.0;
    for (int i : use) {
      const double s = signed_sine(Rr, tt, b1[i], b2[i]);
      sum += 0.5 * std::log1p(s * s / c2);  // the sine whitened by c: the data and the prior in one unit
    }
    if (np == 5) sum += 0.5 * log_so3(Rr * R0.transpose()).squaredNorm() / (sigma * sigma);
    return sum;
  };
  double current = cost(*R, *t), lambda = 1e-3;
  for (int it = 0; it < 10; ++it) {
    const Eigen::Vector3d e1 = t->unitOrthogonal(), e2 = t->cross(e1);
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(np, np);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(np);
    const double h = 1e-6;
    std::vector<Eigen::Matrix3d> Rp(np), Rm(np);
    std::vector<Eigen::Vector3d> tp(np), tm(np);
    for (int k = 0; k < np; ++k) {
      Vec x = Vec::Zero();
      x(k) = h, moved(*R, *t, e1, e2, x, &Rp[k], &tp[k]);
      x(k) = -h, moved(*R, *t, e1, e2, x, &Rm[k], &tm[k]);
    }
    Eigen::RowVectorXd J(np);
    for (int i : use) {
      const double s = signed_sine(*R, *t, b1[i], b2[i]);
      for (int k = 0; k < np; ++k)
        J(k) = (signed_sine(Rp[k], tp[k], b1[i], b2[i]) - signed_sine(Rm[k], tm[k], b1[i], b2[i])) / (2 * h);
      const double w = 1.0 / (1.0 + s * s / c2) / c2;  // IRLS weight of the Cauchy loss on s / c
      H += w * J.transpose() * J, g += w * J.transpose() * s;
    }
    if (np == 5) {  // prior: residual Log(R R₀ᵀ) / σ, Jacobian ≈ I / σ for the left increment
      const Eigen::Vector3d r = log_so3(*R * R0.transpose()) / sigma;
      H.bottomRightCorner<3, 3>() += Eigen::Matrix3d::Identity() / (sigma * sigma);
      g.tail<3>() += r / sigma;
    }
    bool improved = false;
    for (int tries = 0; tries < 6 && !improved; ++tries) {
      Eigen::MatrixXd A = H;
      A.diagonal() *= 1.0 + lambda;
      A.diagonal().array() += 1e-12;
      const Eigen::VectorXd dx = A.ldlt().solve(-g);
      if (!dx.allFinite()) break;
      Vec x = Vec::Zero();
      x.head(np) = dx;
      Eigen::Matrix3d R2;
      Eigen::Vector3d t2;
      moved(*R, *t, e1, e2, x, &R2, &t2);
      const double next = cost(R2, t2);
      if (next < current) *R = R2, *t = t2, current = next, lambda *= 0.3, improved = true;
      else lambda *= 10.0;
    }
    if (!improved) break;
  }
}

}  // namespace

double known_rotation_angle(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector3d& b1,
                            const Eigen::Vector3d& b2) {
  const double n1 = b1.norm(), n2 = b2.norm();
  if (!(n1 > 0.0) || !(n2 > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d a = R * (b1 / n1), b = b2 / n2;
  const Eigen::Vector3d n = t.cross(a);
  const double norm = n.norm();
  if (!(norm > 1e-12)) return angle_between(a, b);  // t = 0, or the point at the epipole
  return std::asin(std::min(1.0, std::abs(b.dot(n)) / norm));
}

double known_rotation_parallax(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector3d& b1,
                               const Eigen::Vector3d& b2) {
  const double n1 = b1.norm(), n2 = b2.norm();
  if (!(n1 > 0.0) || !(n2 > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d a = R * (b1 / n1), b = b2 / n2;
  const Eigen::Vector3d u = t - t.dot(a) * a;  // the tangent at a toward t, in the epipolar plane
  const double nu = u.norm();
  if (!(nu > 1e-6)) return 0.0;  // t = 0, or a at the epipole: no direction
  return std::atan2(b.dot(u) / nu, b.dot(a));
}

Eigen::Vector3d orient_translation(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const std::vector<Eigen::Vector3d>& b1,
                                   const std::vector<Eigen::Vector3d>& b2, double inlier_angle_rad, double min_parallax_rad) {
  if (b1.size() != b2.size())
    throw std::invalid_argument("orient_translation: " + std::to_string(b1.size()) + " and " + std::to_string(b2.size()) +
                                " bearings");
  int ahead = 0, behind = 0;
  for (std::size_t k = 0; k < b1.size(); ++k) {
    if (!(known_rotation_angle(R, t, b1[k], b2[k]) <= inlier_angle_rad)) continue;  // NaN: skipped
    const double p = known_rotation_parallax(R, t, b1[k], b2[k]);
    if (p > min_parallax_rad) ++ahead;
    else if (p < -min_parallax_rad) ++behind;
  }
  return behind > ahead ? Eigen::Vector3d(-t) : t;
}

KnownRotationModel fit_known_rotation(const std::vector<Eigen::Vector3d>& in1, const std::vector<Eigen::Vector3d>& in2,
                                      const Eigen::Matrix3d& R_given, const KnownRotationOptions& o) {
  if (in1.size() != in2.size())
    throw std::invalid_argument("fit_known_rotation: " + std::to_string(in1.size()) + " and " + std::to_string(in2.size()) +
                                " bearings");
  if (!(o.inlier_angle_rad > 0.0) || !(o.confidence > 0.0 && o.confidence < 1.0) || o.max_iterations < 1 ||
      !(o.pure_rotation_share > 0.0 && o.pure_rotation_share <= 1.0) || !(o.rotation_prior_sigma_rad >= 0.0) ||
      !(o.cauchy_scale_rad > 0.0) || !(o.refine_angle_rad > 0.0) || o.min_inliers < 2)
    throw std::invalid_argument("fit_known_rotation: an option is out of range");
  KnownRotationModel m;
  m.R = R_given;
  if (!is_rotation(R_given)) {
    m.status = KnownRotationStatus::kInvalidRotation;
    return m;
  }
  std::vector<Eigen::Vector3d> b1, b2;  // usable, unit
  for (std::size_t i = 0; i < in1.size(); ++i) {
    const double n1 = in1[i].norm(), n2 = in2[i].norm();
    if (!std::isfinite(n1) || !std::isfinite(n2) || !(n1 > 0.0) || !(n2 > 0.0)) continue;
    b1.push_back(in1[i] / n1), b2.push_back(in2[i] / n2);
  }
  const int n = static_cast<int>(b1.size());
  m.usable = n;
  if (n < 2) return m;  // kTooFewMatches
  std::vector<int> informative;
  for (int i = 0; i < n; ++i)
    if (angle_between(R_given * b1[i], b2[i]) > o.inlier_angle_rad) informative.push_back(i);
  m.informative = static_cast<int>(informative.size());
  const auto count_inliers = [&](const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
    int c = 0;
    for (int i = 0; i < n; ++i) c += known_rotation_angle(R, t, b1[i], b2[i]) <= o.inlier_angle_rad;
    return c;
  };
  // Pure rotation: the rotation alone explains the share of matches; t is left undefined (0).
  if (m.informative < 2 || n - m.informative >= o.pure_rotation_share * n) {
    m.status = KnownRotationStatus::kPureRotation;
    m.inliers = count_inliers(m.R, m.t);
    return m;
  }
  // 2-point RANSAC over the informative matches, MSAC cost over all.
  std::mt19937 rng(0x2b0b);
  std::uniform_int_distribution<int> pick(0, m.informative - 1);
  double best_cost = std::numeric_limits<double>::infinity();
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  long iterations = o.max_iterations;
  for (long it = 0; it < iterations; ++it) {
    ++m.iterations;
    const int i = informative[pick(rng)], j = informative[pick(rng)];
    Eigen::Vector3d t;
    if (i == j || !translation_from_two_matches(R_given, b1[i], b2[i], b1[j], b2[j], &t)) continue;
    double cost = 0.0;
    int inl = 0;  // informative inliers: the share that sets the number of iterations
    for (int k = 0; k < n; ++k) {
      const double a = known_rotation_angle(R_given, t, b1[k], b2[k]);
      cost += std::min(a, o.inlier_angle_rad);
    }
    if (cost >= best_cost) continue;
    best_cost = cost, best = t;
    for (int k : informative) inl += known_rotation_angle(R_given, t, b1[k], b2[k]) <= o.inlier_angle_rad;
    const double w = double(inl) / m.informative;
    const double miss = 1.0 - w * w;
    if (miss <= 0.0) break;
    const double need = std::log(1.0 - o.confidence) / std::log(miss);
    iterations = std::min<long>(iterations, std::max<long>(50, static_cast<long>(std::ceil(3 * need))));
  }
  if (!(best.norm() > 0.0)) {  // every sample degenerate: no translation is defined by the matches
    m.status = KnownRotationStatus::kNoConsensus;
    return m;
  }
  m.t = best;
  if (o.refit) {
    for (int pass = 0; pass < 3; ++pass) {  // unweighted guess, then re-weighted with the new t
      std::vector<int> use;
      for (int k : informative)
        if (known_rotation_angle(m.R, m.t, b1[k], b2[k]) <= o.inlier_angle_rad) use.push_back(k);
      Eigen::Vector3d t = m.t;
      if (!refit_translation(m.R, b1, b2, use, &t)) break;
      if (count_inliers(m.R, t) < count_inliers(m.R, m.t)) break;  // the least squares must not lose the consensus
      m.t = t;
    }
  }
  if (o.refine) {
    std::vector<int> use;
    for (int k = 0; k < n; ++k)
      if (known_rotation_angle(m.R, m.t, b1[k], b2[k]) <= o.refine_angle_rad) use.push_back(k);
    if (static_cast<int>(use.size()) >= o.min_inliers) refine(b1, b2, use, R_given, o.cauchy_scale_rad, o.rotation_prior_sigma_rad, &m.R, &m.t);
  }
  m.t = orient_translation(m.R, m.t, b1, b2, o.refine_angle_rad, o.inlier_angle_rad);  // the solver's sign is arbitrary
  m.inliers = count_inliers(m.R, m.t);
  m.status = m.inliers >= o.min_inliers ? KnownRotationStatus::kTranslation : KnownRotationStatus::kNoConsensus;
  return m;
}

}  // namespace slamkit
