// Numeric Jacobians in the tangent space, shared by every Jacobian test.
//
// For f : In → Out between manifolds, the analytic J_out_in is checked against central
// differences J(:, k) ≈ (g(h e_k) − g(−h e_k)) / 2h with g(δ) = f(x ⊞ δ) ⊟ f(x).
// The check FAILS on mismatch and names the worst entry.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <functional>
#include <sstream>
#include <string>

namespace slamkit::testing {

using TangentMap = std::function<Eigen::VectorXd(const Eigen::VectorXd&)>;

inline Eigen::MatrixXd numeric_jacobian(const TangentMap& g, int in_dim, double h = 1e-6) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(in_dim);
  Eigen::MatrixXd J;
  for (int k = 0; k < in_dim; ++k) {
    d(k) = h;
    const Eigen::VectorXd plus = g(d);
    d(k) = -h;
    const Eigen::VectorXd minus = g(d);
    d(k) = 0.0;
    if (k == 0) J.resize(plus.size(), in_dim);
    J.col(k) = (plus - minus) / (2.0 * h);
  }
  return J;
}

/// Entry-wise relative error |a − n| / max(1, |n|); fails above tol and reports the worst entry.
inline ::testing::AssertionResult jacobians_match(const Eigen::MatrixXd& analytic,
                                                  const Eigen::MatrixXd& numeric, double tol,
                                                  const std::string& what = "J") {
  if (analytic.rows() != numeric.rows() || analytic.cols() != numeric.cols()) {
    return ::testing::AssertionFailure() << what << ": analytic is " << analytic.rows() << "x"
                                         << analytic.cols() << ", numeric is " << numeric.rows()
                                         << "x" << numeric.cols();
  }
  double worst = -1.0;
  Eigen::Index wr = 0, wc = 0;
  for (Eigen::Index r = 0; r < analytic.rows(); ++r) {
    for (Eigen::Index c = 0; c < analytic.cols(); ++c) {
      const double a = analytic(r, c), n = numeric(r, c);
      double err = std::abs(a - n) / std::max(1.0, std::abs(n));
      if (!std::isfinite(a) || !std::isfinite(n)) err = std::numeric_limits<double>::infinity();
      if (err > worst) worst = err, wr = r, wc = c;
    }
  }
  if (worst <= tol) return ::testing::AssertionSuccess();
  std::ostringstream os;
  os << what << ": worst entry (" << wr << "," << wc << ") analytic " << analytic(wr, wc)
     << " numeric " << numeric(wr, wc) << " relative error " << worst << " > " << tol
     << "\nanalytic:\n" << analytic << "\nnumeric:\n" << numeric;
  return ::testing::AssertionFailure() << os.str();
}

/// Checks J_out_in of y = f(x) for Lie-group (or vector) types with plus()/minus().
template <class Out, class In, class F>
::testing::AssertionResult check_jacobian(F f, const In& x, const Eigen::MatrixXd& J_analytic,
                                          double tol = 1e-6, const std::string& what = "J",
                                          double h = 1e-6) {
  const Out y0 = f(x);
  const TangentMap g = [&](const Eigen::VectorXd& d) -> Eigen::VectorXd {
    const Out y = f(x.plus(typename In::Tangent(d)));
    return y.minus(y0);
  };
  return jacobians_match(J_analytic, numeric_jacobian(g, In::kDim, h), tol, what);
}

}  // namespace slamkit::testing
