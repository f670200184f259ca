// CHOLMOD backend of SparseCholesky. Matrices arrive in elimination order (see
// compute_elimination_order: fill-reducing on the block graph, postordered) and lower
// triangular, which is the form CHOLMOD's supernodal factorization consumes without copying
// or permuting it. Numeric factorizations reuse one symbolic analysis. Sparse factors of
// equal-block matrices in stored order go to the block simplicial factorization instead
// (block_cholesky.h) up to 120 flops per factor nonzero (kBlockSwitch).
#include <cholmod.h>

#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "slamkit/core/error.h"
#include "block_cholesky.h"
#include "slamkit/linear/blas_runtime.h"
#include "sparse_cholesky_backends.h"

namespace slamkit {
namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

cholmod_sparse wrap_lower(int n, const std::vector<int>& col_ptr, const std::vector<int>& rows, double* values,
                          int stype = -1) {
  cholmod_sparse A;
  std::memset(&A, 0, sizeof(A));
  A.nrow = A.ncol = static_cast<size_t>(n);
  A.nzmax = rows.size();
  A.p = const_cast<int*>(col_ptr.data());
  A.i = const_cast<int*>(rows.data());
  A.x = values;
  A.stype = stype;  // symmetric: −1 lower triangle stored, +1 upper
  A.itype = CHOLMOD_INT;
  A.xtype = values ? CHOLMOD_REAL : CHOLMOD_PATTERN;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = 1;
  A.packed = 1;
  return A;
}

cholmod_dense wrap_dense(int rows, int cols, double* x) {
  cholmod_dense D;
  std::memset(&D, 0, sizeof(D));
  D.nrow = static_cast<size_t>(rows);
  D.ncol = static_cast<size_t>(cols);
  D.nzmax = D.nrow * D.ncol;
  D.d = D.nrow;
  D.x = x;
  D.xtype = CHOLMOD_REAL;
  D.dtype = CHOLMOD_DOUBLE;
  return D;
}

// Block simplicial below this flops / nnz(L) (scalar counts of the unamalgamated factor).
// Measured (callgrind Ir of optimize_pose_graph; process CPU time, 9 interleaved runs, load 2–3):
// parking-garage (ratio 52) 385.6 → 334.6 M, 0.178 → 0.162 s; city10000 (83) 951.1 → 902.1 M,
// 0.269 → 0.236 s; sphere2500 (252) 1342 → 2763 M, 0.274 → 0.311 s: supernodal from there on.
constexpr double kBlockSwitch = 120.0;

class CholmodCholesky final : public SparseCholesky {
 public:
  CholmodCholesky(OrderingMethod ordering, int blas_threads)
      : ordering_(ordering), serial_factorization_(blas_threads == 1) {
    cholmod_start(&c_);
    // Supernodal (BLAS-3) when it pays, i.e. flops/nnz(L) ≥ 40 (CHOLMOD's switch): all 3D
    // pose graphs and large 2D ones; simplicial for sparse 2D factors, where per-supernode
    // BLAS calls cost more than they save (M3500: 3.8 ms instead of 8.2 ms). Always LLᵀ, so
    // a matrix that is not positive definite is reported either way.
    c_.supernodal = CHOLMOD_AUTO;
    c_.final_ll = 1;
    c_.print = 0;
    c_.error_handler = nullptr;
    c_.quick_return_if_not_posdef = 1;
    // Relaxed supernodal amalgamation: CHOLMOD's defaults (nrelax 4/16/48) leave most
    // supernodes one 3- or 6-column block wide on pose graphs; merging up to 8/32/96 columns
    // (with the default zrelax bounds on the explicit zeros this adds) gives BLAS larger
    // blocks: 10–25% less time per factorization on parking-garage, sphere2500, torus3D,
    // city10000 and cubicle_psd, for 15–25% more factor storage.
    c_.nrelax[0] = 8;
    c_.nrelax[1] = 32;
    c_.nrelax[2] = 96;
    set_blas_threads(blas_threads);
  }
  ~CholmodCholesky() override {
    if (L_) cholmod_free_factor(&L_, &c_);
    if (X_) cholmod_free_dense(&X_, &c_);
    if (Y_) cholmod_free_dense(&Y_, &c_);
    if (E_) cholmod_free_dense(&E_, &c_);
    cholmod_finish(&c_);
  }

  std::string name() const override {
    if (use_block_) return "slamkit block simplicial";
    return "CHOLMOD " + std::to_string(CHOLMOD_MAIN_VERSION) + "." + std::to_string(CHOLMOD_SUB_VERSION) + "." +
           std::to_string(CHOLMOD_SUBSUB_VERSION) + (L_ && !L_->is_super ? " simplicial" : " supernodal");
  }
  bool is_fallback() const override { return false; }

  void analyze(const BlockSparseMatrix& A, const EliminationOrder* block_order) override {
    analyze_with(A, block_order, nullptr);
  }
  void analyze_sharing(const BlockSparseMatrix& A, const SharedSymbolic& shared) override {
    analyze_with(A, nullptr, shared);
  }
  SharedSymbolic shared_symbolic() const override { return use_block_ ? block_.symbolic() : nullptr; }

  void analyze_with(const BlockSparseMatrix& A, const EliminationOrder* block_order, const SharedSymbolic& shared) {
    const double t0 = now_s();
    if (L_) cholmod_free_factor(&L_, &c_);
    n_ = A.rows();
    use_block_ = false;
    stats_.shared_analysis = false;
    if (!block_order && detail::BlockCholesky::supports(A)) {
      // Stored order, equal blocks: the block factorization does CHOLMOD's simplicial work
      // with D×D kernels and no scalar symbolic analysis, and up to flops / nnz(L) < 120
      // (CHOLMOD's switch to supernodal is 40, on the same scalar counts) it also beats the
      // supernodal BLAS-3 path, whose supernodes are still narrow there.
      block_.analyze(A, shared);
      if (block_.factor_flops() < kBlockSwitch * block_.factor_nnz()) {
        use_block_ = true;
        stats_.shared_analysis = block_.reused_symbolic();
        stats_.ordering = "as stored";
        stats_.factor_nnz = block_.factor_nnz();
        stats_.factor_flops = block_.factor_flops();
        stats_.analyze_time_s = now_s() - t0;
        return;
      }
      block_ = detail::BlockCholesky();
    }
    cholmod_sparse S = wrap_lower(n_, A.col_ptr(), A.row_index(), nullptr);
    c_.nmethods = 1;
    if (!block_order) {
      // A is stored in elimination order (and postordered): CHOLMOD factorizes it as is,
      // the fastest path (no transposition or permutation of A per factorization).
      c_.method[0].ordering = CHOLMOD_NATURAL;
      c_.postorder = 0;
      stats_.ordering = "as stored";
      L_ = cholmod_analyze(&S, &c_);
    } else {
      if (static_cast<int>(block_order->order.size()) != A.num_blocks())
        throw std::invalid_argument("SparseCholesky::analyze: block order has the wrong size");
      std::vector<int> perm;
      perm.reserve(n_);
      for (int b : block_order->order)
        for (int r = 0; r < A.block_dim(b); ++r) perm.push_back(A.block_start(b) + r);
      c_.method[0].ordering = CHOLMOD_GIVEN;
      c_.postorder = 1;
      stats_.ordering = block_order->method;
      L_ = cholmod_analyze_p(&S, perm.data(), nullptr, 0, &c_);
    }
    if (!L_ || c_.status < CHOLMOD_OK)
      throw NumericalError("CHOLMOD symbolic analysis failed (status " + std::to_string(c_.status) + ")");
    upper_col_ptr_.clear(), upper_rows_.clear(), upper_source_.clear(), upper_values_.clear();
    if (!block_order && !L_->is_super) build_upper(A);
    stats_.factor_nnz = c_.lnz;
    stats_.factor_flops = c_.fl;
    stats_.analyze_time_s = now_s() - t0;
  }

  bool factorize(const BlockSparseMatrix& A) override {
    if (use_block_) return block_.factorize(A);
    if (!L_ || A.rows() != n_) throw std::logic_error("SparseCholesky::factorize before analyze");
    cholmod_sparse S;
    if (!upper_source_.empty()) {
      // Simplicial, natural order: CHOLMOD's row-oriented factorization reads the upper
      // triangle by columns; given the lower one it transposes A (pattern and values) at every
      // factorization. A gather through the index built at analysis is several times cheaper.
      const double* x = A.values().data();
      for (std::size_t q = 0; q < upper_source_.size(); ++q) upper_values_[q] = x[upper_source_[q]];
      S = wrap_lower(n_, upper_col_ptr_, upper_rows_, upper_values_.data(), +1);
    } else {
      S = wrap_lower(n_, A.col_ptr(), A.row_index(), const_cast<double*>(A.values().data()));
    }
    // Debian's CHOLMOD 3 runs OpenMP regions of a fixed 4 threads (CHOLMOD_OMP_NUM_THREADS)
    // whatever OMP_NUM_THREADS says: on 2 cores that costs more than it saves (sphere2500:
    // 200 ms instead of 45 ms per factorization). A single-threaded factorization stays one.
    SerialOpenMpScope serial(serial_factorization_);
    const int ok = cholmod_factorize(&S, L_, &c_);
    return ok && c_.status == CHOLMOD_OK && L_->minor == L_->n;
  }

  void solve(const double* b, double* x) override {
    if (use_block_) {
      std::memcpy(x, b, sizeof(double) * n_);
      return block_.solve(x, 1);
    }
    cholmod_dense B = wrap_dense(n_, 1, const_cast<double*>(b));
    if (!cholmod_solve2(CHOLMOD_A, L_, &B, nullptr, &X_, nullptr, &Y_, &E_, &c_))
      throw NumericalError("CHOLMOD solve failed");
    std::memcpy(x, X_->x, sizeof(double) * n_);
  }

  Eigen::MatrixXd solve(const Eigen::MatrixXd& Bm) override {
    Eigen::MatrixXd copy = Bm;
    if (use_block_) {
      block_.solve(copy.data(), static_cast<int>(copy.cols()));
      return copy;
    }
    cholmod_dense B = wrap_dense(n_, static_cast<int>(copy.cols()), copy.data());
    if (!cholmod_solve2(CHOLMOD_A, L_, &B, nullptr, &X_, nullptr, &Y_, &E_, &c_))
      throw NumericalError("CHOLMOD solve failed");
    return Eigen::Map<Eigen::MatrixXd>(static_cast<double*>(X_->x), n_, copy.cols());
  }

  double inverse_factor_norm2(const double* v) override {
    if (use_block_) return block_.inverse_factor_norm2(v);
    cholmod_dense B = wrap_dense(n_, 1, const_cast<double*>(v));
    cholmod_dense* P = nullptr;
    if (!cholmod_solve2(CHOLMOD_P, L_, &B, nullptr, &P, nullptr, &Y_, &E_, &c_) ||
        !cholmod_solve2(CHOLMOD_L, L_, P, nullptr, &X_, nullptr, &Y_, &E_, &c_)) {
      if (P) cholmod_free_dense(&P, &c_);
      throw NumericalError("CHOLMOD triangular solve failed");
    }
    cholmod_free_dense(&P, &c_);
    return Eigen::Map<const Eigen::VectorXd>(static_cast<double*>(X_->x), n_).squaredNorm();
  }

  const CholeskyStats& stats() const override { return stats_; }

 private:
  // The upper triangle of A by columns (= its lower triangle by rows): column r lists the rows
  // c ≤ r of the lower entries (r, c), ascending; upper_source_ gives each one's index in A's values.
  void build_upper(const BlockSparseMatrix& A) {
    const std::vector<int>& cp = A.col_ptr();
    const std::vector<int>& ri = A.row_index();
    upper_col_ptr_.assign(static_cast<std::size_t>(n_) + 1, 0);
    for (int r : ri) ++upper_col_ptr_[r + 1];
    for (int r = 0; r < n_; ++r) upper_col_ptr_[r + 1] += upper_col_ptr_[r];
    std::vector<int> next(upper_col_ptr_.begin(), upper_col_ptr_.end() - 1);
    upper_rows_.resize(ri.size());
    upper_source_.resize(ri.size());
    upper_values_.resize(ri.size());
    for (int c = 0; c < n_; ++c)
      for (int k = cp[c]; k < cp[c + 1]; ++k) {
        const int q = next[ri[k]]++;
        upper_rows_[q] = c;
        upper_source_[q] = k;
      }
  }

  OrderingMethod ordering_;
  bool serial_factorization_;  // blas_threads == 1: no OpenMP threads inside CHOLMOD either
  cholmod_common c_;
  cholmod_factor* L_ = nullptr;
  cholmod_dense *X_ = nullptr, *Y_ = nullptr, *E_ = nullptr;
  int n_ = 0;
  CholeskyStats stats_;
  bool use_block_ = false;  // the block simplicial factorization replaces CHOLMOD's for this pattern
  detail::BlockCholesky block_;
  std::vector<int> upper_col_ptr_, upper_rows_, upper_source_;  // simplicial natural-order path only
  std::vector<double> upper_values_;
};

}  // namespace

std::unique_ptr<SparseCholesky> make_cholmod_cholesky(OrderingMethod ordering, int blas_threads) {
  return std::make_unique<CholmodCholesky>(ordering, blas_threads);
}

}  // namespace slamkit
