#include "slamkit/vio/imu_consistency.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "slamkit/geometry/lie_math.h"

namespace slamkit {
namespace {

// Local quadratic fit y(τ) = c0 + c1 τ + c2 τ² over samples [lo, hi] around k (τ = t − t_k).
struct LocalFit {
  Eigen::Matrix3d XtX_inv;
  double ssr = 0.0;  // summed squared residual of all 3 axes
  int n = 0;
  Eigen::Vector3d slope;
};

template <class Value>
LocalFit fit_quadratic(const Trajectory& gt, std::size_t k, std::size_t lo, std::size_t hi, Value value) {
  const int n = static_cast<int>(hi - lo + 1);
  Eigen::MatrixXd X(n, 3), Y(n, 3);
  for (int r = 0; r < n; ++r) {
    const double tau = gt[lo + r].stamp - gt[k].stamp;
    X.row(r) << 1.0, tau, tau * tau;
    Y.row(r) = value(lo + r).transpose();
  }
  LocalFit f;
  f.XtX_inv = (X.transpose() * X).inverse();
  const Eigen::MatrixXd C = f.XtX_inv * X.transpose() * Y;
  f.ssr = (Y - X * C).squaredNorm();
  f.n = n;
  f.slope = C.row(1).transpose();
  return f;
}

}  // namespace

GroundTruthDifferentiation differentiate_ground_truth(Trajectory& gt, double half_width) {
  GroundTruthDifferentiation out;
  out.velocity_sigma.assign(gt.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<double> var_factor(gt.size(), 0.0), local_var(gt.size(), 0.0);
  double ssr_p = 0.0, ssr_r = 0.0;
  long dof = 0;
  std::size_t lo = 0, hi = 0;
  for (std::size_t k = 0; k < gt.size(); ++k) {
    gt[k].v_world.reset();
    const double t = gt[k].stamp;
    while (gt[lo].stamp < t - half_width) ++lo;
    if (hi < k) hi = k;
    while (hi + 1 < gt.size() && gt[hi + 1].stamp <= t + half_width) ++hi;
    if (k < lo + 2 || hi < k + 2) continue;
    if (t - gt[lo].stamp < 0.6 * half_width || gt[hi].stamp - t < 0.6 * half_width) continue;
    const LocalFit fp = fit_quadratic(gt, k, lo, hi, [&](std::size_t m) { return gt[m].T_world_body.translation(); });
    const SO3 Rk = gt[k].T_world_body.rotation();
    const LocalFit fr = fit_quadratic(gt, k, lo, hi, [&](std::size_t m) { return gt[m].T_world_body.rotation().minus(Rk); });
    gt[k].v_world = fp.slope;
    var_factor[k] = fp.XtX_inv(1, 1);
    local_var[k] = fp.ssr / (3.0 * (fp.n - 3));
    ssr_p += fp.ssr, ssr_r += fr.ssr;
    dof += 3 * (fp.n - 3);
  }
  if (dof > 0) {
    out.position_sigma = std::sqrt(ssr_p / dof);
    out.rotation_sigma = std::sqrt(ssr_r / dof);
  }
  for (std::size_t k = 0; k < gt.size(); ++k)
    if (gt[k].v_world)
      out.velocity_sigma[k] = std::sqrt(std::max(out.position_sigma * out.position_sigma, local_var[k]) * var_factor[k]);
  return out;
}

std::vector<ImuWindow> select_imu_windows(const Trajectory& gt, const std::vector<ImuMeasurement>& imu, double length,
                                          double max_gap) {
  std::vector<ImuWindow> out;
  if (gt.size() < 2 || imu.size() < 2) return out;
  std::size_t i = 0;
  while (i < gt.size()) {
    if (!gt[i].v_world || gt[i].stamp < imu.front().stamp) { ++i; continue; }
    std::size_t j = i;
    bool gap = false;
    while (j + 1 < gt.size() && gt[j].stamp < gt[i].stamp + length) {
      if (gt[j + 1].stamp - gt[j].stamp > max_gap) gap = true;
      ++j;
    }
    const double len = gt[j].stamp - gt[i].stamp;
    if (gap || !gt[j].v_world || std::abs(len - length) > 0.1 * length || gt[j].stamp > imu.back().stamp) {
      i = std::max(i + 1, j);
      continue;
    }
    out.push_back({i, j, gt[i].stamp, gt[j].stamp});
    i = j;
  }
  return out;
}

double ImuWindowError::nees_imu_only() const { return residual.dot(P_imu.ldlt().solve(residual)); }
double ImuWindowError::nees() const { return residual.dot((P_imu + P_gt).ldlt().solve(residual)); }

ImuWindowError imu_window_error(const std::vector<ImuMeasurement>& imu, const TrajectorySample& a,
                                const TrajectorySample& b, const ImuBias& bias, const ImuNoise& noise,
                                const Eigen::Vector3d& g_world, const Eigen::Vector3d& gt_sigma_i,
                                const Eigen::Vector3d& gt_sigma_j) {
  ImuPreintegration pim(bias, noise);
  pim.integrate_between(imu, a.stamp, b.stamp);
  ImuState xi, xj;
  xi.R = a.T_world_body.rotation(), xi.p = a.T_world_body.translation(), xi.v = a.v_world.value();
  xj.R = b.T_world_body.rotation(), xj.p = b.T_world_body.translation(), xj.v = b.v_world.value();
  xi.bg = xj.bg = bias.gyro, xi.ba = xj.ba = bias.accel;
  const ImuFactor f(0, 1, pim, g_world);
  Eigen::Matrix<double, 15, 15> Ji, Jj;
  const Eigen::Matrix<double, 15, 1> r = f.error(xi, xj, &Ji, &Jj);
  ImuWindowError e;
  e.residual = r.head<9>();
  e.P_imu = pim.covariance().topLeftCorner<9, 9>();
  const auto sigma2 = [](const Eigen::Vector3d& s) {
    Eigen::Matrix<double, 9, 1> d;
    d << Eigen::Vector3d::Constant(s(0) * s(0)), Eigen::Vector3d::Constant(s(1) * s(1)),
        Eigen::Vector3d::Constant(s(2) * s(2));
    return d;
  };
  const Eigen::Matrix<double, 9, 9> Ai = Ji.topLeftCorner<9, 9>(), Aj = Jj.topLeftCorner<9, 9>();
  e.P_gt = Ai * sigma2(gt_sigma_i).asDiagonal() * Ai.transpose() + Aj * sigma2(gt_sigma_j).asDiagonal() * Aj.transpose();
  e.J_bias = Ji.block<9, 6>(0, 9);
  return e;
}

ImuBias fit_constant_bias(const std::vector<ImuMeasurement>& imu, const Trajectory& gt,
                          const std::vector<ImuWindow>& windows, const ImuNoise& noise, const Eigen::Vector3d& g_world,
                          const std::vector<Eigen::Vector3d>& gt_sigma, int iterations, Eigen::Vector3d* g_tilted) {
  ImuBias b;
  Eigen::Vector3d g = g_world;
  const int n = g_tilted ? 8 : 6;
  for (int it = 0; it < iterations; ++it) {
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd grad = Eigen::VectorXd::Zero(n);
    for (const ImuWindow& w : windows) {
      const ImuWindowError e = imu_window_error(imu, gt[w.i], gt[w.j], b, noise, g, gt_sigma[w.i], gt_sigma[w.j]);
      const Eigen::Matrix<double, 9, 9> W = (e.P_imu + e.P_gt).inverse();
      Eigen::MatrixXd J(9, n);
      J.leftCols<6>() = e.J_bias;
      if (g_tilted) {
        // ∂r/∂g: r_v = R_iᵀ(… − g T), r_p = R_iᵀ(… − ½ g T²); g ← g − [g]× θ.
        const double T = w.t1 - w.t0;
        const Eigen::Matrix3d RiT = gt[w.i].T_world_body.rotation().matrix().transpose();
        Eigen::Matrix<double, 9, 3> J_g = Eigen::Matrix<double, 9, 3>::Zero();
        J_g.middleRows<3>(3) = -RiT * T;
        J_g.middleRows<3>(6) = -0.5 * RiT * T * T;
        J.rightCols<2>() = (J_g * (-skew(g))).leftCols<2>();
      }
      H += J.transpose() * W * J;
      grad += J.transpose() * W * e.residual;
    }
    const Eigen::VectorXd d = -H.ldlt().solve(grad);
    if (!d.allFinite()) break;
    b.gyro += d.head<3>(), b.accel += d.segment<3>(3);
    if (g_tilted) g = SO3::exp(Eigen::Vector3d(d(6), d(7), 0.0)).act(g);
  }
  if (g_tilted) *g_tilted = g;
  return b;
}

}  // namespace slamkit
