#include "block_cholesky.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace slamkit::detail {
namespace {

template <int D>
using Blk = Eigen::Matrix<double, D, D>;
template <int D>
using Vec = Eigen::Matrix<double, D, 1>;

// In-place LLᵀ of the lower triangle of a D×D block; false unless every pivot is > 0 (NaN fails).
template <int D>
bool dense_cholesky(double* a) {
  Eigen::Map<Blk<D>> L(a);
  for (int c = 0; c < D; ++c) {
    double s = L(c, c);
    for (int m = 0; m < c; ++m) s -= L(c, m) * L(c, m);
    if (!(s > 0.0)) return false;
    L(c, c) = std::sqrt(s);
    for (int r = c + 1; r < D; ++r) {
      double t = L(r, c);
      for (int m = 0; m < c; ++m) t -= L(r, m) * L(c, m);
      L(r, c) = t / L(c, c);
    }
  }
  return true;
}

// B ← B L⁻ᵀ (X Lᵀ = B) for a lower-triangular D×D L, column by column:
// X(:, c) = (B(:, c) − Σ_{m<c} X(:, m) L(c, m)) / L(c, c). (Eigen's general triangular
// solver packs and blocks even 3×3 operands.)
template <int D>
void right_solve_lower_transpose(const double* l, double* b) {
  for (int c = 0; c < D; ++c) {
    double* bc = b + c * D;
    for (int m = 0; m < c; ++m) {
      const double f = l[m * D + c];  // L(c, m)
      const double* xm = b + m * D;
      for (int r = 0; r < D; ++r) bc[r] -= xm[r] * f;
    }
    const double d = l[c * D + c];
    for (int r = 0; r < D; ++r) bc[r] /= d;
  }
}

}  // namespace

bool BlockCholesky::supports(const BlockSparseMatrix& A) {
  if (A.num_blocks() == 0) return false;
  const int d = A.block_dim(0);
  if (d != 1 && d != 2 && d != 3 && d != 6) return false;
  for (int b : A.block_dims())
    if (b != d) return false;
  return true;
}

bool BlockSymbolic::matches(const BlockSparseMatrix& A) const {
  return A.block_column_pointers() == a_col_ptr && A.block_row_indices() == a_rows;
}

void BlockCholesky::analyze(const BlockSparseMatrix& A, std::shared_ptr<const BlockSymbolic> reuse) {
  if (!supports(A)) throw std::invalid_argument("BlockCholesky: blocks must all be 1, 2, 3 or 6 wide");
  n_ = A.num_blocks();
  d_ = A.block_dim(0);
  reused_ = reuse && reuse->matches(A);
  sym_ = reused_ ? std::move(reuse) : analyze_pattern(A);
  const BlockSymbolic& sym = *sym_;
  a_base_.resize(n_);
  for (int j = 0; j < n_; ++j) a_base_[j] = A.block_offset(j, j);
  lnz_ = flops_ = 0.0;
  for (int j = 0; j < n_; ++j)
    for (int s = 0; s < d_; ++s) {
      const double cc = (d_ - s) + static_cast<double>(sym.col_start[j + 1] - sym.col_start[j]) * d_;
      lnz_ += cc;
      flops_ += cc * cc;
    }
  const std::size_t dd = static_cast<std::size_t>(d_) * d_;
  diag_.assign(dd * n_, 0.0);
  off_.assign(dd * sym.rows.size(), 0.0);
  map_.assign(n_, 0);
  head_.assign(n_, -1);
  link_.assign(n_, -1);
  next_.assign(n_, 0);
}

std::shared_ptr<const BlockSymbolic> BlockCholesky::analyze_pattern(const BlockSparseMatrix& A) {
  auto result = std::make_shared<BlockSymbolic>();
  BlockSymbolic& sym = *result;
  const int n = A.num_blocks();
  const std::vector<int>& bcp = A.block_column_pointers();
  const std::vector<int>& br = A.block_row_indices();
  sym.a_col_ptr = bcp;
  sym.a_rows = br;
  // Rows of A's strict lower triangle: row i lists the columns j < i with A(i, j) ≠ 0.
  std::vector<int> row_start(static_cast<std::size_t>(n) + 1, 0), row_cols;
  for (int j = 0; j < n; ++j)
    for (int q = bcp[j] + 1; q < bcp[j + 1]; ++q) ++row_start[br[q] + 1];  // the diagonal comes first
  for (int i = 0; i < n; ++i) row_start[i + 1] += row_start[i];
  row_cols.resize(row_start[n]);
  {
    std::vector<int> fill(row_start.begin(), row_start.end() - 1);
    for (int j = 0; j < n; ++j)
      for (int q = bcp[j] + 1; q < bcp[j + 1]; ++q) row_cols[fill[br[q]]++] = j;
  }
  // Elimination tree (Liu, with path compression).
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int k = 0; k < n; ++k)
    for (int q = row_start[k]; q < row_start[k + 1]; ++q) {
      int r = row_cols[q];
      while (ancestor[r] != -1 && ancestor[r] != k) {
        const int next = ancestor[r];
        ancestor[r] = k;
        r = next;
      }
      if (ancestor[r] == -1) ancestor[r] = k, parent[r] = k;
    }
  // Row k of L is the union of the etree paths from A's row-k columns up to k (row subtree):
  // one pass counts the blocks per column of L, a second lists them (rows ascending).
  std::vector<int> mark(n, -1);
  sym.col_start.assign(static_cast<std::size_t>(n) + 1, 0);
  sym.rows.clear();
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> fill;
    if (pass == 1) {
      for (int j = 0; j < n; ++j) sym.col_start[j + 1] += sym.col_start[j];
      sym.rows.resize(sym.col_start[n]);
      fill.assign(sym.col_start.begin(), sym.col_start.end() - 1);
      std::fill(mark.begin(), mark.end(), -1);
    }
    for (int k = 0; k < n; ++k) {
      mark[k] = k;
      for (int q = row_start[k]; q < row_start[k + 1]; ++q)
        for (int x = row_cols[q]; mark[x] != k; x = parent[x]) {
          mark[x] = k;
          if (pass == 0) ++sym.col_start[x + 1];
          else sym.rows[fill[x]++] = k;
        }
    }
  }
  // Where A's off-diagonal blocks of column j go in L's column j (A's rows ⊆ L's rows, both sorted).
  sym.a_start.assign(static_cast<std::size_t>(n) + 1, 0);
  sym.a_slot.reserve(bcp[n] - n);
  for (int j = 0; j < n; ++j) {
    int s = sym.col_start[j];
    for (int q = bcp[j] + 1; q < bcp[j + 1]; ++q) {
      while (sym.rows[s] != br[q]) ++s;
      sym.a_slot.push_back(s - sym.col_start[j]);
    }
    sym.a_start[j + 1] = static_cast<int>(sym.a_slot.size());
  }
  return result;
}

template <int D>
bool BlockCholesky::factorize_fixed(const BlockSparseMatrix& A) {
  const BlockSymbolic& sy = *sym_;
  constexpr int DD = D * D;
  using Map = Eigen::Map<Blk<D>>;
  using CMap = Eigen::Map<const Blk<D>>;
  using AMap = Eigen::Map<const Blk<D>, 0, Eigen::OuterStride<>>;
  const double* ax = A.values().data();
  std::fill(head_.begin(), head_.end(), -1);
  for (int j = 0; j < n_; ++j) {
    const int ld = A.leading_dim(j), c0 = sy.col_start[j], cnt = sy.col_start[j + 1] - c0;
    double* lj = off_.data() + static_cast<std::ptrdiff_t>(c0) * DD;
    Map Djj(diag_.data() + static_cast<std::ptrdiff_t>(j) * DD);
    // Column j of A scattered into column j of L.
    for (int q = 0; q < cnt; ++q) map_[sy.rows[c0 + q]] = q;
    std::fill(lj, lj + static_cast<std::ptrdiff_t>(cnt) * DD, 0.0);
    Djj = AMap(ax + a_base_[j], Eigen::OuterStride<>(ld));
    for (int t = sy.a_start[j]; t < sy.a_start[j + 1]; ++t)
      Map(lj + static_cast<std::ptrdiff_t>(sy.a_slot[t]) * DD) =
          AMap(ax + a_base_[j] + static_cast<std::ptrdiff_t>(t - sy.a_start[j] + 1) * D, Eigen::OuterStride<>(ld));
    // Updates from the columns k < j with L(j, k) ≠ 0: L(i, j) −= L(i, k) L(j, k)ᵀ for i ≥ j.
    for (int k = head_[j], next_k; k >= 0; k = next_k) {
      next_k = link_[k];
      const int p = next_[k], end = sy.col_start[k + 1];
      const CMap Ljk(off_.data() + static_cast<std::ptrdiff_t>(p) * DD);
      Djj.noalias() -= Ljk * Ljk.transpose();
      for (int q = p + 1; q < end; ++q)
        Map(lj + static_cast<std::ptrdiff_t>(map_[sy.rows[q]]) * DD).noalias() -=
            CMap(off_.data() + static_cast<std::ptrdiff_t>(q) * DD) * Ljk.transpose();
      if (p + 1 < end) {  // column k next updates the row of its next block
        next_[k] = p + 1;
        link_[k] = head_[sy.rows[p + 1]];
        head_[sy.rows[p + 1]] = k;
      }
    }
    if (!dense_cholesky<D>(Djj.data())) return false;
    // L(i, j) = (updated A(i, j)) L(j, j)⁻ᵀ.
    for (int q = 0; q < cnt; ++q) right_solve_lower_transpose<D>(Djj.data(), lj + static_cast<std::ptrdiff_t>(q) * DD);
    if (cnt > 0) {
      next_[j] = c0;
      link_[j] = head_[sy.rows[c0]];
      head_[sy.rows[c0]] = j;
    }
  }
  return true;
}

template <int D>
void BlockCholesky::forward_fixed(double* x) const {
  const BlockSymbolic& sy = *sym_;
  constexpr int DD = D * D;
  for (int j = 0; j < n_; ++j) {
    Eigen::Map<Vec<D>> xj(x + static_cast<std::ptrdiff_t>(j) * D);
    Eigen::Map<const Blk<D>>(diag_.data() + static_cast<std::ptrdiff_t>(j) * DD)
        .template triangularView<Eigen::Lower>()
        .solveInPlace(xj);
    for (int q = sy.col_start[j]; q < sy.col_start[j + 1]; ++q)
      Eigen::Map<Vec<D>>(x + static_cast<std::ptrdiff_t>(sy.rows[q]) * D).noalias() -=
          Eigen::Map<const Blk<D>>(off_.data() + static_cast<std::ptrdiff_t>(q) * DD) * xj;
  }
}

template <int D>
void BlockCholesky::solve_fixed(double* x, int nrhs) const {
  const BlockSymbolic& sy = *sym_;
  constexpr int DD = D * D;
  for (int c = 0; c < nrhs; ++c) {
    double* xc = x + static_cast<std::ptrdiff_t>(c) * rows();
    forward_fixed<D>(xc);
    for (int j = n_ - 1; j >= 0; --j) {  // Lᵀ x = y
      Vec<D> t = Eigen::Map<const Vec<D>>(xc + static_cast<std::ptrdiff_t>(j) * D);
      for (int q = sy.col_start[j]; q < sy.col_start[j + 1]; ++q)
        t.noalias() -= Eigen::Map<const Blk<D>>(off_.data() + static_cast<std::ptrdiff_t>(q) * DD).transpose() *
                       Eigen::Map<const Vec<D>>(xc + static_cast<std::ptrdiff_t>(sy.rows[q]) * D);
      const auto Ljj = Eigen::Map<const Blk<D>>(diag_.data() + static_cast<std::ptrdiff_t>(j) * DD)
                           .template triangularView<Eigen::Lower>();
      Ljj.transpose().solveInPlace(t);
      Eigen::Map<Vec<D>>(xc + static_cast<std::ptrdiff_t>(j) * D) = t;
    }
  }
}

bool BlockCholesky::factorize(const BlockSparseMatrix& A) {
  if (A.num_blocks() != n_ || A.rows() != rows()) throw std::logic_error("BlockCholesky::factorize: not the analyzed pattern");
  switch (d_) {
    case 1: return factorize_fixed<1>(A);
    case 2: return factorize_fixed<2>(A);
    case 3: return factorize_fixed<3>(A);
    case 6: return factorize_fixed<6>(A);
  }
  throw std::logic_error("BlockCholesky::factorize before analyze");
}

void BlockCholesky::solve(double* x, int nrhs) const {
  switch (d_) {
    case 1: return solve_fixed<1>(x, nrhs);
    case 2: return solve_fixed<2>(x, nrhs);
    case 3: return solve_fixed<3>(x, nrhs);
    case 6: return solve_fixed<6>(x, nrhs);
  }
}

double BlockCholesky::inverse_factor_norm2(const double* v) const {
  std::vector<double> y(v, v + rows());
  switch (d_) {
    case 1: forward_fixed<1>(y.data()); break;
    case 2: forward_fixed<2>(y.data()); break;
    case 3: forward_fixed<3>(y.data()); break;
    case 6: forward_fixed<6>(y.data()); break;
  }
  double s = 0.0;
  for (double t : y) s += t * t;
  return s;
}

}  // namespace slamkit::detail
