#include "slamkit/core/noise_model.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include "slamkit/core/error.h"

namespace slamkit {

namespace {
// The concrete models: N coefficients inline for the common sizes, a vector otherwise.
template <int N>
struct InlineModel final : NoiseModel {
  InlineModel(Kind kind, int dim) : NoiseModel(kind, dim) { coeffs_ = N > 0 ? storage : nullptr; }
  double storage[N > 0 ? N : 1];
};
struct HeapModel final : NoiseModel {
  HeapModel(Kind kind, int dim, std::size_t n) : NoiseModel(kind, dim), storage(n) { coeffs_ = storage.data(); }
  std::vector<double> storage;
};
}  // namespace

std::shared_ptr<NoiseModel> NoiseModel::make(Kind kind, int dim) {
  const std::size_t n = kind == Kind::kUnit ? 0 : kind == Kind::kDiagonal ? dim : static_cast<std::size_t>(dim) * dim;
  if (n == 0) return std::make_shared<InlineModel<0>>(kind, dim);
  if (n <= 3) return std::make_shared<InlineModel<3>>(kind, dim);
  if (n <= 9) return std::make_shared<InlineModel<9>>(kind, dim);
  if (n <= 36) return std::make_shared<InlineModel<36>>(kind, dim);
  return std::make_shared<HeapModel>(kind, dim, n);
}

std::shared_ptr<const NoiseModel> NoiseModel::unit(int dim) { return make(Kind::kUnit, dim); }

std::shared_ptr<NoiseModel> NoiseModel::clone() const {
  auto m = make(kind_, dim_);
  const std::size_t n = kind_ == Kind::kDiagonal ? dim_ : kind_ == Kind::kDense ? static_cast<std::size_t>(dim_) * dim_ : 0;
  std::copy(coeffs_, coeffs_ + n, m->coeffs());
  return m;
}

std::shared_ptr<const NoiseModel> NoiseModel::isotropic(int dim, double sigma) {
  return diagonal(Eigen::VectorXd::Constant(dim, sigma));
}

std::shared_ptr<const NoiseModel> NoiseModel::diagonal(const Eigen::VectorXd& sigmas) {
  if (!(sigmas.array() > 0.0).all() || !sigmas.allFinite())
    throw NumericalError("NoiseModel::diagonal: sigmas must be positive and finite");
  auto m = make(Kind::kDiagonal, static_cast<int>(sigmas.size()));
  Eigen::Map<Eigen::VectorXd>(m->coeffs(), sigmas.size()) = sigmas.cwiseInverse();
  return m;
}

std::shared_ptr<const NoiseModel> NoiseModel::information(const Eigen::MatrixXd& omega) {
  // The checks and the Cholesky on an N × N view: fixed-size for the pose-graph sizes (3, 6),
  // where one model is built per edge, so no dynamic-size loops or heap temporaries there.
  const auto build = [](const auto& W, int n) -> std::shared_ptr<const NoiseModel> {
    using Mat = std::decay_t<decltype(W.eval())>;
    if (!W.allFinite()) throw NumericalError("NoiseModel::information: matrix is not square or not finite");
    const double scale = W.cwiseAbs().maxCoeff();
    double asymmetry = 0.0;
    for (int c = 0; c < n; ++c)
      for (int r = c + 1; r < n; ++r) asymmetry = std::max(asymmetry, std::abs(W(r, c) - W(c, r)));
    if (asymmetry > 1e-9 * scale) throw NumericalError("NoiseModel::information: matrix is not symmetric");
    // Diagonal information: no dense whitening needed.
    bool diagonal = true;
    for (int c = 0; c < n && diagonal; ++c)
      for (int r = 0; r < n; ++r)
        if (r != c && W(r, c) != 0.0) diagonal = false;
    if (diagonal) {
      if (!(W.diagonal().array() > 0.0).all())
        throw NumericalError("NoiseModel::information: matrix is not positive definite");
      auto m = make(Kind::kDiagonal, n);
      Eigen::Map<Eigen::VectorXd>(m->coeffs(), n) = W.diagonal().cwiseSqrt();
      return m;
    }
    // R (upper, RᵀR = Ω); LLT reads only the lower triangle.
    const Eigen::LLT<Mat> llt(W);
    if (llt.info() != Eigen::Success || !(llt.matrixLLT().diagonal().array() > 0.0).all())
      throw NumericalError("NoiseModel::information: matrix is not positive definite");
    auto m = make(Kind::kDense, n);
    Eigen::Map<Eigen::MatrixXd>(m->coeffs(), n, n) = llt.matrixU();
    return m;
  };
  const int n = static_cast<int>(omega.rows());
  if (omega.cols() != n) throw NumericalError("NoiseModel::information: matrix is not square or not finite");
  if (n == 3) return build(Eigen::Map<const Eigen::Matrix3d>(omega.data()), n);
  if (n == 6) return build(Eigen::Map<const Eigen::Matrix<double, 6, 6>>(omega.data()), n);
  return build(omega, n);
}

std::shared_ptr<const NoiseModel> NoiseModel::covariance(const Eigen::MatrixXd& sigma) {
  const Eigen::LLT<Eigen::MatrixXd> llt(sigma);
  if (llt.info() != Eigen::Success) throw NumericalError("NoiseModel::covariance: not positive definite");
  return information(llt.solve(Eigen::MatrixXd::Identity(sigma.rows(), sigma.cols())));
}

Eigen::MatrixXd NoiseModel::sqrt_information() const {
  switch (kind_) {
    case Kind::kUnit: return Eigen::MatrixXd::Identity(dim_, dim_);
    case Kind::kDiagonal: return Eigen::Map<const Eigen::VectorXd>(coeffs_, dim_).asDiagonal();
    case Kind::kDense: return Eigen::Map<const Eigen::MatrixXd>(coeffs_, dim_, dim_);
  }
  return {};
}

Eigen::MatrixXd NoiseModel::information_matrix() const {
  const Eigen::MatrixXd R = sqrt_information();
  return R.transpose() * R;
}

namespace {
// v ← R v in place for upper-triangular R: row i reads only v[k ≥ i], which later rows
// (i' > i) never overwrite before use. No temporaries, no allocation.
inline void upper_times_in_place(const double* R, int n, double* v) {
  for (int i = 0; i < n; ++i) {
    double s = 0.0;
    for (int k = i; k < n; ++k) s += R[i + k * n] * v[k];
    v[i] = s;
  }
}
// The same for the common fixed sizes, as one small dense product per column block.
template <int N>
void upper_times_columns(const double* R, double* M, int cols) {
  const Eigen::Map<const Eigen::Matrix<double, N, N>> Rm(R);
  for (int c = 0; c < cols; ++c) {
    Eigen::Map<Eigen::Matrix<double, N, 1>> v(M + static_cast<std::ptrdiff_t>(c) * N);
    // A plain fixed-size product (the zeros below the diagonal included) unrolls and
    // vectorizes; Eigen's triangular kernel is a generic runtime loop, several times slower.
    const Eigen::Matrix<double, N, 1> w = Rm.lazyProduct(v);
    v = w;
  }
}
}  // namespace

void NoiseModel::whiten(double* r) const { whiten_jacobian(r, 1); }

void NoiseModel::whiten_jacobian(double* J, int cols) const {
  switch (kind_) {
    case Kind::kUnit: return;
    case Kind::kDiagonal:
      for (int c = 0; c < cols; ++c)
        for (int i = 0; i < dim_; ++i) J[static_cast<std::ptrdiff_t>(c) * dim_ + i] *= coeffs_[i];
      return;
    case Kind::kDense:
      switch (dim_) {
        case 2: return upper_times_columns<2>(coeffs_, J, cols);
        case 3: return upper_times_columns<3>(coeffs_, J, cols);
        case 6: return upper_times_columns<6>(coeffs_, J, cols);
        default:
          for (int c = 0; c < cols; ++c) upper_times_in_place(coeffs_, dim_, J + static_cast<std::ptrdiff_t>(c) * dim_);
      }
      return;
  }
}

}  // namespace slamkit
