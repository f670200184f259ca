// NoiseModel: Gaussian measurement noise as a square-root information matrix.
//
// A residual r with covariance Σ = Ω⁻¹ is whitened to R r, where R is upper triangular
// with RᵀR = Ω (R = Lᵀ from the Cholesky factor Ω = L Lᵀ), so that ‖R r‖² = rᵀ Ω r.
// Unit and diagonal models whiten without a matrix product. Immutable; thread-safe.
// A model and its coefficients (1/σ or R) are one heap block with the shared_ptr's control
// block: building one per edge of a pose graph costs a single allocation.
#pragma once

#include <Eigen/Core>
#include <memory>

namespace slamkit {

class NoiseModel {
 public:
  enum class Kind { kUnit, kDiagonal, kDense };

  static std::shared_ptr<const NoiseModel> unit(int dim);
  static std::shared_ptr<const NoiseModel> isotropic(int dim, double sigma);
  static std::shared_ptr<const NoiseModel> diagonal(const Eigen::VectorXd& sigmas);
  /// From an information matrix Ω; throws NumericalError unless Ω is symmetric positive definite.
  static std::shared_ptr<const NoiseModel> information(const Eigen::MatrixXd& omega);
  static std::shared_ptr<const NoiseModel> covariance(const Eigen::MatrixXd& sigma);

  Kind kind() const { return kind_; }
  int dim() const { return dim_; }
  /// R with RᵀR = Ω (dense upper triangular; diagonal for kDiagonal, identity for kUnit).
  Eigen::MatrixXd sqrt_information() const;
  Eigen::MatrixXd information_matrix() const;

  /// The whitening data: 1/σ (dim values) for kDiagonal, R column-major (dim × dim) for kDense,
  /// null for kUnit. For fixed-size whitening in the factors' hot path (core/factor.h).
  const double* whitening_data() const { return coeffs_; }

  /// r ← R r (length dim).
  void whiten(double* r) const;
  /// J ← R J for a column-major dim × cols block.
  void whiten_jacobian(double* J, int cols) const;

  /// An independent model with the same coefficients (models are shared; this is for owners
  /// that need their own, e.g. a mutable handle in Python).
  std::shared_ptr<NoiseModel> clone() const;

  NoiseModel(const NoiseModel&) = delete;  // coeffs_ points into the concrete model's storage
  NoiseModel& operator=(const NoiseModel&) = delete;
  ~NoiseModel() = default;  // the concrete model is destroyed through make_shared's control block

 protected:
  NoiseModel(Kind kind, int dim) : kind_(kind), dim_(dim) {}
  /// A model whose coefficients (dim for kDiagonal, dim² for kDense, none for kUnit) live in
  /// the returned object; fill them through coeffs().
  static std::shared_ptr<NoiseModel> make(Kind kind, int dim);
  double* coeffs() { return const_cast<double*>(coeffs_); }

  Kind kind_;
  int dim_;
  const double* coeffs_ = nullptr;  // kDiagonal: 1/σ; kDense: R column-major; kUnit: null
};

}  // namespace slamkit
