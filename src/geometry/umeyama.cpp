#include "slamkit/geometry/umeyama.h"

#include <Eigen/SVD>
#include <cmath>
#include <stdexcept>
#include <string>

namespace slamkit {

namespace {

void check_inputs(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, const char* who) {
  if (src.cols() != dst.cols())
    throw std::invalid_argument(std::string(who) + ": point sets differ in size (" +
                                std::to_string(src.cols()) + " vs " + std::to_string(dst.cols()) + ")");
  if (src.cols() < 3)
    throw std::invalid_argument(std::string(who) + ": needs at least 3 point pairs, got " +
                                std::to_string(src.cols()));
  if (!src.allFinite() || !dst.allFinite()) throw std::invalid_argument(std::string(who) + ": points are not finite");
}

}  // namespace

Similarity3 umeyama(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst, bool with_scale) {
  check_inputs(src, dst, "umeyama");
  const double n = static_cast<double>(src.cols());
  const Eigen::Vector3d mean_x = src.rowwise().mean();
  const Eigen::Vector3d mean_y = dst.rowwise().mean();
  const Eigen::Matrix3Xd xc = src.colwise() - mean_x;
  const Eigen::Matrix3Xd yc = dst.colwise() - mean_y;
  const double sigma_x2 = xc.squaredNorm() / n;             // eq. 36
  const Eigen::Matrix3d cov = (yc * xc.transpose()) / n;    // eq. 38

  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d d = svd.singularValues();  // descending
  // Rank ≥ 2 is needed for a unique rotation (eq. 39 ff.); relative threshold, scale-free.
  if (!(d(0) > 0.0) || d(1) <= 1e-12 * d(0))
    throw std::invalid_argument("umeyama: degenerate point configuration (collinear or coincident points)");

  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();  // eq. 43
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) S(2, 2) = -1.0;

  Similarity3 out;
  out.R = svd.matrixU() * S * svd.matrixV().transpose();                      // eq. 40
  out.scale = with_scale ? (d.asDiagonal() * S).trace() / sigma_x2 : 1.0;     // eq. 42
  out.t = mean_y - out.scale * (out.R * mean_x);                              // eq. 41
  return out;
}

Similarity3 umeyama_yaw(const Eigen::Matrix3Xd& src, const Eigen::Matrix3Xd& dst) {
  check_inputs(src, dst, "umeyama_yaw");
  const Eigen::Vector3d mean_x = src.rowwise().mean();
  const Eigen::Vector3d mean_y = dst.rowwise().mean();
  const Eigen::Matrix3Xd xc = src.colwise() - mean_x;
  const Eigen::Matrix3Xd yc = dst.colwise() - mean_y;
  // Σ yᵀ Rz(θ) x = cos θ · a + sin θ · b + const, maximized at θ = atan2(b, a).
  const double a = (yc.row(0).cwiseProduct(xc.row(0)) + yc.row(1).cwiseProduct(xc.row(1))).sum();
  const double b = (yc.row(1).cwiseProduct(xc.row(0)) - yc.row(0).cwiseProduct(xc.row(1))).sum();
  const double spread = std::sqrt(xc.topRows<2>().squaredNorm() * yc.topRows<2>().squaredNorm());
  if (!(spread > 0.0) || std::hypot(a, b) <= 1e-12 * spread)
    throw std::invalid_argument("umeyama_yaw: degenerate point configuration (no horizontal spread)");
  const double theta = std::atan2(b, a);
  Similarity3 out;
  out.R = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  out.t = mean_y - out.R * mean_x;
  return out;
}

}  // namespace slamkit
