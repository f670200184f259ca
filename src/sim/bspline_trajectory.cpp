#include "slamkit/sim/bspline_trajectory.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

// Cumulative basis B̃_j(u), j = 1..3, and its first and second derivatives in u (B̃_0 = 1).
struct Basis {
  std::array<double, 4> b, db, ddb;
};

Basis cumulative_basis(double u) {
  const double u2 = u * u, u3 = u2 * u;
  Basis B;
  B.b = {1.0, (5.0 + 3.0 * u - 3.0 * u2 + u3) / 6.0, (1.0 + 3.0 * u + 3.0 * u2 - 2.0 * u3) / 6.0, u3 / 6.0};
  B.db = {0.0, (3.0 - 6.0 * u + 3.0 * u2) / 6.0, (3.0 + 6.0 * u - 6.0 * u2) / 6.0, 0.5 * u2};
  B.ddb = {0.0, u - 1.0, 1.0 - 2.0 * u, u};
  return B;
}

// R(u) on one segment from its four control rotations.
SO3 segment_rotation(const std::array<SO3, 4>& R, const Basis& B) {
  SO3 out = R[0];
  for (int j = 1; j < 4; ++j) out = out * SO3::exp(B.b[j] * R[j - 1].between(R[j]).log());
  return out;
}

// Pose of a sampled path at time t: linear / slerp interpolation, clamped at the ends.
SE3 interpolate(const Trajectory& path, double t) {
  const auto& s = path.samples();
  if (t <= s.front().stamp) return s.front().T_world_body;
  if (t >= s.back().stamp) return s.back().T_world_body;
  const auto it = std::upper_bound(s.begin(), s.end(), t, [](double v, const TrajectorySample& x) { return v < x.stamp; });
  const TrajectorySample& b = *it;
  const TrajectorySample& a = *(it - 1);
  const double span = b.stamp - a.stamp;
  const double w = span > 0.0 ? (t - a.stamp) / span : 0.0;
  const SO3 R = a.T_world_body.rotation() * SO3::exp(w * a.T_world_body.rotation().between(b.T_world_body.rotation()).log());
  return SE3(R, (1.0 - w) * a.T_world_body.translation() + w * b.T_world_body.translation());
}

}  // namespace

BSplineTrajectory::BSplineTrajectory(double t0, double dt, std::vector<SO3> rotations,
                                     std::vector<Eigen::Vector3d> positions)
    : t0_(t0), dt_(dt), rotations_(std::move(rotations)), positions_(std::move(positions)) {
  if (!std::isfinite(t0) || !std::isfinite(dt) || dt <= 0.0) throw std::invalid_argument("BSplineTrajectory: bad t0 or dt");
  if (rotations_.size() < 4 || rotations_.size() != positions_.size())
    throw std::invalid_argument("BSplineTrajectory: need >= 4 control rotations and as many positions");
  for (const auto& p : positions_)
    if (!p.allFinite()) throw std::invalid_argument("BSplineTrajectory: control position not finite");
}

BSplineState BSplineTrajectory::evaluate(double t) const {
  if (!(t >= start_time() - 1e-9 && t <= end_time() + 1e-9))
    throw std::out_of_range("BSplineTrajectory: t = " + std::to_string(t) + " outside [" + std::to_string(start_time()) +
                            ", " + std::to_string(end_time()) + "]");
  const double s = (t - t0_) / dt_;
  const int last = static_cast<int>(rotations_.size()) - 4;
  const int i = std::clamp(static_cast<int>(std::floor(s)), 0, last);
  const double u = s - i;
  const Basis B = cumulative_basis(u);
  BSplineState out;
  // Rotation and body angular velocity (recursion in the header).
  SO3 R = rotations_[i];
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  for (int j = 1; j < 4; ++j) {
    const Eigen::Vector3d d = rotations_[i + j - 1].between(rotations_[i + j]).log();
    const SO3 A = SO3::exp(B.b[j] * d);
    R = R * A;
    omega = A.inverse().act(omega) + (B.db[j] / dt_) * d;
  }
  Eigen::Vector3d p = positions_[i];
  for (int j = 1; j < 4; ++j) {
    const Eigen::Vector3d dp = positions_[i + j] - positions_[i + j - 1];
    p += B.b[j] * dp;
    out.v_world += (B.db[j] / dt_) * dp;
    out.a_world += (B.ddb[j] / (dt_ * dt_)) * dp;
  }
  out.T_world_body = SE3(R, p);
  out.omega_body = omega;
  return out;
}

SE3 BSplineTrajectory::pose(double t) const { return evaluate(t).T_world_body; }

BSplineFitReport BSplineTrajectory::residuals(const Trajectory& path) const {
  BSplineFitReport r;
  r.control_points = rotations_.size();
  double sp = 0.0, sr = 0.0;
  for (const auto& s : path) {
    if (s.stamp < start_time() || s.stamp > end_time()) continue;
    const SE3 T = pose(s.stamp);
    const double ep = (T.translation() - s.T_world_body.translation()).norm();
    const double er = s.T_world_body.rotation().between(T.rotation()).log().norm();
    sp += ep * ep, sr += er * er;
    r.position_max = std::max(r.position_max, ep);
    r.rotation_max = std::max(r.rotation_max, er);
    ++r.samples;
  }
  if (r.samples > 0) {
    r.position_rmse = std::sqrt(sp / r.samples);
    r.rotation_rmse = std::sqrt(sr / r.samples);
  }
  return r;
}

BSplineTrajectory BSplineTrajectory::fit(const Trajectory& path, const BSplineFitOptions& options,
                                         BSplineFitReport* report) {
  const std::string source = path.metadata.count("source") ? path.metadata.at("source") : std::string("trajectory");
  if (path.size() < 2 || !(path.duration() > 0.0)) throw InputError(source, 0, "path", "needs at least 2 samples spanning > 0 s");
  if (!(options.knot_spacing > 0.0) || !std::isfinite(options.knot_spacing))
    throw InputError(source, 0, "knot_spacing", "must be > 0");
  const double dt = options.knot_spacing, t0 = path.samples().front().stamp;
  const int segments = std::max(1, static_cast<int>(std::ceil(path.duration() / dt - 1e-9)));
  const int n = segments + 3;
  // Start from the path interpolated at the control points' nominal times t0 + (k − 1) dt.
  std::vector<SO3> R(n);
  std::vector<Eigen::Vector3d> P(n);
  for (int k = 0; k < n; ++k) {
    const SE3 T = interpolate(path, t0 + (k - 1) * dt);
    R[k] = T.rotation(), P[k] = T.translation();
  }
  const auto locate = [&](double t, int* i, double* u) {
    const double s = (t - t0) / dt;
    *i = std::clamp(static_cast<int>(std::floor(s)), 0, n - 4);
    *u = s - *i;
  };
  using Triplet = Eigen::Triplet<double>;
  const double w_smooth = options.smoothness_weight;

  // ---- positions: linear least squares Σ ‖Σ_j B_j p_{i+j} − p_path‖² + w Σ ‖Δ² p‖² ----
  {
    std::vector<Triplet> trip;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 3);
    for (const auto& s : path) {
      int i;
      double u;
      locate(s.stamp, &i, &u);
      const Basis B = cumulative_basis(u);
      // Uniform (non-cumulative) weights: B_j = B̃_j − B̃_{j+1}.
      const std::array<double, 4> w = {1.0 - B.b[1], B.b[1] - B.b[2], B.b[2] - B.b[3], B.b[3]};
      for (int a = 0; a < 4; ++a) {
        rhs.row(i + a) += w[a] * s.T_world_body.translation().transpose();
        for (int b = 0; b < 4; ++b) trip.emplace_back(i + a, i + b, w[a] * w[b]);
      }
    }
    for (int k = 1; k + 1 < n; ++k) {
      const std::array<double, 3> c = {1.0, -2.0, 1.0};
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) trip.emplace_back(k - 1 + a, k - 1 + b, w_smooth * c[a] * c[b]);
    }
    for (int k = 0; k < n; ++k) trip.emplace_back(k, k, 1e-12);
    Eigen::SparseMatrix<double> H(n, n);
    H.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(H);
    if (ldlt.info() != Eigen::Success) throw InputError(source, 0, "path", "position fit is singular");
    const Eigen::MatrixXd X = ldlt.solve(rhs);
    for (int k = 0; k < n; ++k) P[k] = X.row(k).transpose();
  }

  // ---- rotations: Gauss-Newton on Σ ‖Log(R_path⁻¹ R(t))‖² + w Σ ‖d_{k+1} − d_k‖² ----
  // Jacobians of the data term by central differences wrt right perturbations of the 4 controls
  // of each sample's segment; the smoothness term uses ∂d_k/∂δ ≈ ±I (it only needs to be weak).
  int iterations = 0;
  for (int it = 0; it < options.max_iterations; ++it) {
    std::vector<Triplet> trip;
    std::array<std::vector<Eigen::Matrix3d>, 4> band;
    for (auto& b : band) b.assign(n, Eigen::Matrix3d::Zero());
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * n);
    for (const auto& s : path) {
      int i;
      double u;
      locate(s.stamp, &i, &u);
      const Basis B = cumulative_basis(u);
      std::array<SO3, 4> ctrl = {R[i], R[i + 1], R[i + 2], R[i + 3]};
      const SO3 Rinv_path = s.T_world_body.rotation().inverse();
      const Eigen::Vector3d r = (Rinv_path * segment_rotation(ctrl, B)).log();
      Eigen::Matrix<double, 3, 12> J;
      constexpr double h = 1e-6;
      for (int c = 0; c < 12; ++c) {
        const SO3 keep = ctrl[c / 3];
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d(c % 3) = h;
        ctrl[c / 3] = keep.plus(d);
        const Eigen::Vector3d rp = (Rinv_path * segment_rotation(ctrl, B)).log();
        ctrl[c / 3] = keep.plus(-d);
        const Eigen::Vector3d rm = (Rinv_path * segment_rotation(ctrl, B)).log();
        ctrl[c / 3] = keep;
        J.col(c) = (rp - rm) / (2.0 * h);
      }
      const Eigen::Matrix<double, 12, 12> JtJ = J.transpose() * J;
      g.segment<12>(3 * i) += J.transpose() * r;
      for (int a = 0; a < 4; ++a)
        for (int b = a; b < 4; ++b) band[b - a][i + a] += JtJ.block<3, 3>(3 * a, 3 * b);
    }
    // Block band (row k, column k + d) → triplets of the symmetric matrix.
    for (int d = 0; d < 4; ++d)
      for (int k = 0; k + d < n; ++k)
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            const double v = band[d][k](a, b);
            if (v == 0.0) continue;
            trip.emplace_back(3 * k + a, 3 * (k + d) + b, v);
            if (d > 0) trip.emplace_back(3 * (k + d) + b, 3 * k + a, v);
          }
    for (int k = 1; k + 1 < n; ++k) {
      const Eigen::Vector3d r = R[k].between(R[k + 1]).log() - R[k - 1].between(R[k]).log();
      const std::array<double, 3> c = {1.0, -2.0, 1.0};
      for (int a = 0; a < 3; ++a) {
        g.segment<3>(3 * (k - 1 + a)) += w_smooth * c[a] * r;
        for (int b = 0; b < 3; ++b)
          for (int e = 0; e < 3; ++e) trip.emplace_back(3 * (k - 1 + a) + e, 3 * (k - 1 + b) + e, w_smooth * c[a] * c[b]);
      }
    }
    for (int k = 0; k < 3 * n; ++k) trip.emplace_back(k, k, 1e-9);
    Eigen::SparseMatrix<double> H(3 * n, 3 * n);
    H.setFromTriplets(trip.begin(), trip.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(H);
    if (ldlt.info() != Eigen::Success) throw InputError(source, 0, "path", "rotation fit is singular");
    const Eigen::VectorXd delta = -ldlt.solve(g);
    if (!delta.allFinite()) throw InputError(source, 0, "path", "rotation fit diverged");
    for (int k = 0; k < n; ++k) R[k] = R[k].plus(delta.segment<3>(3 * k));
    ++iterations;
    if (std::getenv("SLAMKIT_SPLINE_DEBUG")) std::fprintf(stderr, "iter %d max delta %g\n", it, delta.lpNorm<Eigen::Infinity>());
    if (delta.lpNorm<Eigen::Infinity>() < 1e-6) break;  // rad
  }
  BSplineTrajectory spline(t0, dt, std::move(R), std::move(P));
  if (report) {
    *report = spline.residuals(path);
    report->iterations = iterations;
  }
  return spline;
}

}  // namespace slamkit
