// Eigen SimplicialLDLT backend: the fallback when CHOLMOD is not available. Correct but
// several times slower on large problems; name() and is_fallback() say so.
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <chrono>
#include <stdexcept>

#include "slamkit/core/error.h"
#include "sparse_cholesky_backends.h"

namespace slamkit {
namespace {

class EigenCholesky final : public SparseCholesky {
 public:
  explicit EigenCholesky(OrderingMethod ordering) : natural_requested_(ordering == OrderingMethod::kNatural) {}
  std::string name() const override { return "Eigen SimplicialLDLT (FALLBACK: slow, CHOLMOD not used)"; }
  bool is_fallback() const override { return true; }

  // Without a block order A is already in elimination order (natural); with one, Eigen
  // computes its own AMD ordering instead of the given one.
  void analyze(const BlockSparseMatrix& A, const EliminationOrder* block_order) override {
    const auto t0 = std::chrono::steady_clock::now();
    natural_ = natural_requested_ || block_order == nullptr;
    const auto M = map(A);
    if (natural_) {
      natural_ldlt_.analyzePattern(M);
    } else {
      ldlt_.analyzePattern(M);
    }
    stats_.ordering = natural_ ? "as stored" : "AMD (Eigen)";
    stats_.analyze_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    n_ = A.rows();
  }

  bool factorize(const BlockSparseMatrix& A) override {
    const auto M = map(A);
    if (natural_) {
      natural_ldlt_.factorize(M);
      return natural_ldlt_.info() == Eigen::Success && (natural_ldlt_.vectorD().array() > 0.0).all();
    }
    ldlt_.factorize(M);
    return ldlt_.info() == Eigen::Success && (ldlt_.vectorD().array() > 0.0).all();
  }

  void solve(const double* b, double* x) override {
    const Eigen::Map<const Eigen::VectorXd> bv(b, n_);
    const Eigen::VectorXd sol = natural_ ? Eigen::VectorXd(natural_ldlt_.solve(bv)) : Eigen::VectorXd(ldlt_.solve(bv));
    Eigen::Map<Eigen::VectorXd>(x, n_) = sol;
  }

  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) override {
    return natural_ ? Eigen::MatrixXd(natural_ldlt_.solve(B)) : Eigen::MatrixXd(ldlt_.solve(B));
  }

  double inverse_factor_norm2(const double* v) override {
    // A = Pᵀ L D Lᵀ P ⇒ the LLᵀ factor is L D^½: ‖(L D^½)⁻¹ P v‖² = Σ y_i² / d_i, L y = P v.
    const Eigen::Map<const Eigen::VectorXd> vv(v, n_);
    auto norm2 = [&](const auto& ldlt) {
      // Eigen leaves P empty for the natural ordering.
      Eigen::VectorXd y = ldlt.permutationP().size() ? Eigen::VectorXd(ldlt.permutationP() * vv) : Eigen::VectorXd(vv);
      ldlt.matrixL().solveInPlace(y);
      return (y.array().square() / ldlt.vectorD().array()).sum();
    };
    return natural_ ? norm2(natural_ldlt_) : norm2(ldlt_);
  }

  const CholeskyStats& stats() const override { return stats_; }

 private:
  using Sparse = Eigen::Map<const Eigen::SparseMatrix<double, Eigen::ColMajor, int>>;
  static Sparse map(const BlockSparseMatrix& A) {
    return Sparse(A.rows(), A.rows(), static_cast<int>(A.nnz()), A.col_ptr().data(), A.row_index().data(),
                  A.values().data());
  }
  bool natural_requested_;
  bool natural_ = true;
  int n_ = 0;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> natural_ldlt_;
  CholeskyStats stats_;
};

}  // namespace

std::unique_ptr<SparseCholesky> make_eigen_cholesky(OrderingMethod ordering) {
  return std::make_unique<EigenCholesky>(ordering);
}

}  // namespace slamkit
