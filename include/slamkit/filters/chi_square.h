// χ² distribution: the CDF (regularized lower incomplete gamma P(k/2, x/2)) and its inverse,
// for association gates (2 dof per observation, 2k for a joint hypothesis) and the NEES/ANEES
// consistency bounds (N·n dof). Accurate to ~1e-12 relative; no external dependency.
#pragma once

namespace slamkit {

/// P(X ≤ x) for X ~ χ²(dof), dof > 0.
double chi2_cdf(double x, double dof);
/// The x with chi2_cdf(x, dof) = p, 0 < p < 1 (bisection on the CDF, then exact to ~1e-12).
double chi2_quantile(double p, double dof);

}  // namespace slamkit
