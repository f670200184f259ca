// SparseCholesky: factorization A = L Lᵀ (or L D Lᵀ) of a symmetric positive definite
// BlockSparseMatrix, with a fill-reducing ordering computed ONCE on the block graph
// (analyze) and reused by every numeric factorization (factorize) with the same pattern.
//
// Backends: CHOLMOD supernodal (the main one) and Eigen's SimplicialLDLT (a fallback that
// is reported loudly: it is several times slower). Orderings: AMD, METIS (nested
// dissection), CHOLMOD's NESDIS, or auto (the one with the fewest factorization flops).
// One object per problem; not thread-safe.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "slamkit/linear/block_sparse_matrix.h"

namespace slamkit {

enum class SparseBackend { kAuto, kCholmod, kEigen };
enum class OrderingMethod { kAuto, kAmd, kMetis, kNesdis, kNatural };

const char* to_string(SparseBackend b);
const char* to_string(OrderingMethod m);
/// "auto", "cholmod", "eigen"; throws InputError otherwise.
SparseBackend parse_sparse_backend(const std::string& s);
/// "auto", "amd", "metis", "nesdis", "natural"; throws InputError otherwise.
OrderingMethod parse_ordering(const std::string& s);

/// A fill-reducing elimination order of a graph (nodes 0..n−1, undirected edges).
struct EliminationOrder {
  std::vector<int> order;  ///< order[k] = node eliminated k-th
  std::string method;      ///< "AMD", "METIS", "NESDIS", "natural"
  double flops = 0.0;      ///< Cholesky flops of the unit-block pattern under this order
};

namespace detail {
struct BlockSymbolic;
}
/// A symbolic analysis that systems over the same block pattern (of any uniform block size)
/// can share; opaque outside the linear module.
using SharedSymbolic = std::shared_ptr<const detail::BlockSymbolic>;

struct CholeskyStats {
  std::string ordering;     ///< the ordering actually used
  bool shared_analysis = false;  ///< the last analyze adopted a shared pattern analysis
  double analyze_time_s = 0.0;
  double factor_nnz = 0.0;  ///< nonzeros in L
  double factor_flops = 0.0;
};

class SparseCholesky {
 public:
  virtual ~SparseCholesky() = default;
  /// e.g. "CHOLMOD 3.0.14 supernodal" or "Eigen SimplicialLDLT (fallback)".
  virtual std::string name() const = 0;
  /// True for the slow fallback backend (callers must say so in their report).
  virtual bool is_fallback() const = 0;
  /// Symbolic analysis of A's pattern; must be called before factorize() and again only if
  /// the pattern changes. Without block_order, A's blocks are taken to be in elimination
  /// order already (built with compute_elimination_order): the fastest path, A is factorized
  /// as stored. With block_order (first eliminated first), A is permuted at every
  /// factorization.
  virtual void analyze(const BlockSparseMatrix& A, const EliminationOrder* block_order = nullptr) = 0;
  /// analyze(A) in stored order, adopting `shared` when it was made for A's block pattern (the
  /// pattern is compared; otherwise it is analyzed). Backends that cannot share analyze.
  virtual void analyze_sharing(const BlockSparseMatrix& A, const SharedSymbolic& /*shared*/) { analyze(A); }
  /// The pattern analysis of the last analyze, for another system over the same block pattern;
  /// null when it is not shareable (supernodal, permuted, the Eigen fallback).
  virtual SharedSymbolic shared_symbolic() const { return nullptr; }
  /// Numeric factorization of A's values. False if A is not (numerically) positive definite.
  virtual bool factorize(const BlockSparseMatrix& A) = 0;
  /// x = A⁻¹ b (b and x of length A.rows(); they may alias).
  virtual void solve(const double* b, double* x) = 0;
  /// X = A⁻¹ B for several right-hand sides.
  virtual Eigen::MatrixXd solve(const Eigen::MatrixXd& B) = 0;
  /// ‖L⁻¹ P v‖², with P Aᵀ Pᵀ = L Lᵀ (used by trust-region step control).
  virtual double inverse_factor_norm2(const double* v) = 0;
  virtual const CholeskyStats& stats() const = 0;
};

/// kAuto: AMD, and for large factorizations (≥ 1e8 unit-block flops, i.e. ≈ 2e10 for 6×6
/// blocks) also METIS and NESDIS, keeping the one with the fewest flops. The result is
/// postordered along its elimination tree (same fill; subtrees contiguous), so a matrix
/// stored in this order is factorized as is.
EliminationOrder compute_elimination_order(int n, const std::vector<std::pair<int, int>>& edges,
                                           OrderingMethod method = OrderingMethod::kAuto);
/// An order (e.g. a restriction of a larger problem's order) postordered for this graph.
EliminationOrder postordered(int n, const std::vector<std::pair<int, int>>& edges, EliminationOrder order);

/// kAuto picks CHOLMOD when slamkit was built with it. blas_threads ≤ 0 leaves BLAS alone.
std::unique_ptr<SparseCholesky> make_sparse_cholesky(SparseBackend backend = SparseBackend::kAuto,
                                                     OrderingMethod ordering = OrderingMethod::kAuto,
                                                     int blas_threads = 0);
/// Whether this build has CHOLMOD.
bool cholmod_available();

}  // namespace slamkit
