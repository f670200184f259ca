#include "slamkit/linear/normal_equations.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

// dest(di × dj, leading dimension ld) += Aᵀ B, with A: rows × di and B: rows × dj column-major.
template <int R, int DI, int DJ>
void add_at_b_fixed(const double* a, const double* b, double* dest, int ld) {
  const Eigen::Map<const Eigen::Matrix<double, R, DI>> A(a);
  const Eigen::Map<const Eigen::Matrix<double, R, DJ>> B(b);
  Eigen::Map<Eigen::Matrix<double, DI, DJ>, 0, Eigen::OuterStride<>> D(dest, Eigen::OuterStride<>(ld));
  D.noalias() += A.transpose().lazyProduct(B);  // small fixed sizes: no GEMM packing (2×9×9 would use it)
}

// Two residual rows (reprojection factors): dest(r, c) += a0_r b0_c + a1_r b1_c, written out so
// that it compiles to straight-line code for the fixed sizes.
template <int DI, int DJ>
void add_at_b_rows2(const double* a, const double* b, double* dest, int ld) {
  for (int c = 0; c < DJ; ++c) {
    const double b0 = b[2 * c], b1 = b[2 * c + 1];
    double* d = dest + static_cast<std::ptrdiff_t>(c) * ld;
    for (int r = 0; r < DI; ++r) d[r] += a[2 * r] * b0 + a[2 * r + 1] * b1;
  }
}

// The 2D pose-graph shapes (3 residual rows of 3-dimensional variables, SE2): dest(i, j) +=
// Σ_r A(r, i) B(r, j), summed in r order (Eigen's order: the same bits), as plain loops that
// unroll into straight-line code, out of line so that these calls do not pay the large frame of
// add_at_b_other. (For 6×6 Eigen's vectorized product is faster: 1.3 % fewer instructions on
// parking-garage than these loops.)
template <int R, int DI, int DJ>
[[gnu::noinline]] void add_at_b_small(const double* a, const double* b, double* dest, int ld) {
  for (int j = 0; j < DJ; ++j) {
    double* d = dest + static_cast<std::ptrdiff_t>(j) * ld;
    for (int i = 0; i < DI; ++i) {
      double s = a[i * R] * b[j * R];
      for (int r = 1; r < R; ++r) s += a[i * R + r] * b[j * R + r];
      d[i] += s;
    }
  }
}

[[gnu::noinline]] void add_at_b_other(const double* a, const double* b, double* dest, int rows, int di, int dj, int ld) {
  if (rows == 6 && di == 6 && dj == 6) return add_at_b_fixed<6, 6, 6>(a, b, dest, ld);
  if (rows == 2 && di == 3 && dj == 2) return add_at_b_fixed<2, 3, 2>(a, b, dest, ld);
  if (rows == 3 && di == 6 && dj == 3) return add_at_b_fixed<3, 6, 3>(a, b, dest, ld);
  if (rows == 2 && di == 2 && dj == 2) return add_at_b_fixed<2, 2, 2>(a, b, dest, ld);
  if (rows == 6 && di == 6 && dj == 1) return add_at_b_fixed<6, 6, 1>(a, b, dest, ld);  // gradients
  if (rows == 3 && di == 3 && dj == 1) return add_at_b_fixed<3, 3, 1>(a, b, dest, ld);
  // bundle adjustment: 2D reprojection of a 9-parameter camera and a 3D point
  if (rows == 2 && di == 9 && dj == 3) return add_at_b_rows2<9, 3>(a, b, dest, ld);
  if (rows == 2 && di == 9 && dj == 9) return add_at_b_rows2<9, 9>(a, b, dest, ld);
  if (rows == 2 && di == 3 && dj == 3) return add_at_b_rows2<3, 3>(a, b, dest, ld);
  if (rows == 2 && di == 9 && dj == 1) return add_at_b_rows2<9, 1>(a, b, dest, ld);
  if (rows == 2 && di == 3 && dj == 1) return add_at_b_rows2<3, 1>(a, b, dest, ld);
  const Eigen::Map<const Eigen::MatrixXd> A(a, rows, di), B(b, rows, dj);
  Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>> D(dest, di, dj, Eigen::OuterStride<>(ld));
  D.noalias() += A.transpose() * B;
}

inline void add_at_b(const double* a, const double* b, double* dest, int rows, int di, int dj, int ld) {
  if (rows == 3 && di == 3) {
    if (dj == 3) return add_at_b_small<3, 3, 3>(a, b, dest, ld);
    if (dj == 1) return add_at_b_small<3, 3, 1>(a, b, dest, ld);
  }
  add_at_b_other(a, b, dest, rows, di, dj, ld);
}

// Parallel grains: below these sizes a phase costs less than waking the pool's worker and
// joining it (tens of µs when it polls, milliseconds when it is descheduled on a loaded VM), so
// it runs on the calling thread. In residual rows (≈ 40–150 ns each to linearize), in tangent
// dimensions of block columns (assembly), in variables (retraction, ≈ 50 ns each).
constexpr std::size_t kParallelResidualRows = 6144;
constexpr std::size_t kParallelColumnDims = 3072;
constexpr std::size_t kParallelVariables = 4096;

// The chunk size (in items) for parallel_for: at least `min_units` of work per chunk, and
// no split at all unless there are two such chunks. (A grain alone lets parallel_for split
// 1.2 grains into a full chunk and a sliver, which starts and wakes the worker thread for a
// few µs of work: INTEL's, intel's and CSAIL's assembly, intel's evaluation.)
std::size_t grain_for(std::size_t total_units, std::size_t items, std::size_t min_units) {
  const std::size_t per_item = items == 0 ? 1 : std::max<std::size_t>(1, total_units / items);
  const std::size_t grain = std::max<std::size_t>(1, min_units / per_item);
  return items < 2 * grain ? std::max<std::size_t>(1, items) : grain;
}

}  // namespace

NormalEquations::NormalEquations(const FactorGraph& graph, const Values& values, OrderingMethod ordering,
                                 const EliminationOrder* variable_order)
    : graph_(graph) {
  graph.check_against(values);
  const std::size_t nf = graph.size();
  std::vector<char> touched(values.size(), 0);
  slots_.reserve(nf);
  std::size_t residual_total = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    const Factor& factor = graph[f];
    slots_.push_back({&factor, factor.residual_dim(), residual_total, var_index_.size()});
    residual_total += factor.residual_dim();
    for (Key k : factor.keys()) {
      const std::size_t i = values.index_of(k);
      var_index_.push_back(i);
      touched[i] = 1;
    }
    max_arity_ = std::max(max_arity_, factor.keys().size());
  }
  for (const FactorSlot& s : slots_) {
    const std::size_t k = s.factor->keys().size();
    for (std::size_t a = 0; a < k; ++a)
      for (std::size_t b = a + 1; b < k; ++b)
        if (var_index_[s.first_var + a] == var_index_[s.first_var + b])
          throw InputError("", 0, "key", "a factor uses variable " +
                                             key_to_string(values.key(var_index_[s.first_var + a])) + " twice");
  }

  // Free variables (fixed ones and those no factor touches are left out), their graph.
  std::vector<int> free_index(values.size(), -1);
  std::vector<std::size_t> free_vars;
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!values.fixed(i) && touched[i]) free_index[i] = static_cast<int>(free_vars.size()), free_vars.push_back(i);
  if (free_vars.empty()) throw InputError("", 0, "", "the problem has no free variable to optimize");
  const int n = static_cast<int>(free_vars.size());
  std::vector<std::pair<int, int>> edges;
  edges.reserve(slots_.size() * (max_arity_ * (max_arity_ - (max_arity_ > 0 ? 1 : 0)) / 2));
  for (const FactorSlot& s : slots_) {
    const std::size_t k = s.factor->keys().size();
    for (std::size_t a = 0; a < k; ++a)
      for (std::size_t b = a + 1; b < k; ++b) {
        const int fa = free_index[var_index_[s.first_var + a]], fb = free_index[var_index_[s.first_var + b]];
        if (fa >= 0 && fb >= 0) edges.emplace_back(fa, fb);
      }
  }

  // Elimination order → block numbering.
  EliminationOrder order;
  if (variable_order && !variable_order->order.empty()) {
    order.method = variable_order->method;
    std::vector<char> seen(n, 0);
    for (int v : variable_order->order) {
      if (v < 0 || static_cast<std::size_t>(v) >= values.size())
        throw InputError("", 0, "variable_order", "variable order names index " + std::to_string(v));
      const int f = free_index[static_cast<std::size_t>(v)];
      if (f < 0) continue;
      if (seen[f]++) throw InputError("", 0, "variable_order", "variable order repeats index " + std::to_string(v));
      order.order.push_back(f);
    }
    if (static_cast<int>(order.order.size()) != n)
      throw InputError("", 0, "variable_order", "variable order does not cover every free variable");
    order = postordered(n, edges, std::move(order));
  } else {
    order = compute_elimination_order(n, edges, ordering);
  }
  ordering_ = order.method;
  block_of_var_.assign(values.size(), -1);
  std::vector<int> dims(n);
  free_vars_.resize(n);
  for (int b = 0; b < n; ++b) {
    const std::size_t i = free_vars[order.order[b]];
    free_vars_[b] = i;
    block_of_var_[i] = b;
    dims[b] = values.manifold(i).tangent_dim();
  }

  // Jacobian slots for free variables; the block pattern from every pair of them.
  var_jacobian_.assign(var_index_.size(), -1);
  std::size_t jac_total = 0;
  std::vector<std::pair<int, int>> pattern;
  pattern.reserve(edges.size());  // one entry per pair of free variables of a factor
  for (const FactorSlot& s : slots_) {
    const std::size_t k = s.factor->keys().size();
    for (std::size_t a = 0; a < k; ++a) {
      const int ba = block_of_var_[var_index_[s.first_var + a]];
      if (ba < 0) continue;
      var_jacobian_[s.first_var + a] = static_cast<std::ptrdiff_t>(jac_total);
      jac_total += static_cast<std::size_t>(s.residual_dim) * dims[ba];
      for (std::size_t b = 0; b < k; ++b) {
        const int bb = block_of_var_[var_index_[s.first_var + b]];
        if (bb >= 0 && ba > bb) pattern.emplace_back(ba, bb);
      }
    }
  }
  H_ = BlockSparseMatrix(dims, std::move(pattern));
  jacobians_.assign(jac_total, 0.0);
  residuals_.assign(residual_total, 0.0);
  factor_cost_.assign(nf, 0.0);
  g_ = Eigen::VectorXd::Zero(H_.rows());
  diag_ = Eigen::VectorXd::Zero(H_.rows());

  // Contributions grouped by block column (the smaller block index), in factor order: one
  // flat array, column j at [contribution_start_[j], contribution_start_[j + 1]) (counting
  // sort: a first pass counts per column, the second fills).
  contribution_start_.assign(static_cast<std::size_t>(H_.num_blocks()) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::size_t> next;
    if (pass == 1) {
      for (int j = 0; j < H_.num_blocks(); ++j) contribution_start_[j + 1] += contribution_start_[j];
      contributions_.resize(contribution_start_.back());
      next.assign(contribution_start_.begin(), contribution_start_.end() - 1);
    }
    for (const FactorSlot& s : slots_) {
      const std::size_t k = s.factor->keys().size();
      for (std::size_t a = 0; a < k; ++a) {
        const int ba = block_of_var_[var_index_[s.first_var + a]];
        if (ba < 0) continue;
        for (std::size_t b = 0; b < k; ++b) {
          const int bb = block_of_var_[var_index_[s.first_var + b]];
          if (bb < 0 || ba < bb || (ba == bb && a != b)) continue;
          if (pass == 0) {
            ++contribution_start_[bb + 1];
            continue;
          }
          Contribution& c = contributions_[next[bb]++];
          c.ja = static_cast<std::size_t>(var_jacobian_[s.first_var + a]);
          c.jb = static_cast<std::size_t>(var_jacobian_[s.first_var + b]);
          c.dest = H_.block_offset(ba, bb);
          c.rows = s.residual_dim;
          c.di = dims[ba];
          c.dj = dims[bb];
          c.ld = H_.leading_dim(bb);
          c.residual = s.residual_offset;
          c.diagonal = ba == bb;
        }
      }
    }
  }
}

void NormalEquations::linearize_factors(const Values& x, std::size_t begin, std::size_t end) {
  std::vector<const double*> params(max_arity_);
  std::vector<double*> jac(max_arity_);
  for (std::size_t f = begin; f < end; ++f) {
    const FactorSlot& s = slots_[f];
    const std::size_t k = s.factor->keys().size();
    for (std::size_t v = 0; v < k; ++v) {
      params[v] = x.params(var_index_[s.first_var + v]);
      const std::ptrdiff_t off = var_jacobian_[s.first_var + v];
      jac[v] = off >= 0 ? jacobians_.data() + off : nullptr;
    }
    factor_cost_[f] = s.factor->linearize(params.data(), residuals_.data() + s.residual_offset, jac.data());
  }
}

void NormalEquations::assemble_column(int j) {
  // Zero the block column and the gradient block, then add contributions in factor order.
  const int dj = H_.block_dim(j), ld = H_.leading_dim(j);
  double* col = H_.values().data() + H_.block_offset(j, j);  // the diagonal block starts the column
  std::fill(col, col + static_cast<std::ptrdiff_t>(ld) * dj, 0.0);
  Eigen::Map<Eigen::VectorXd> gj(g_.data() + H_.block_start(j), dj);
  gj.setZero();
  for (std::size_t q = contribution_start_[j]; q < contribution_start_[j + 1]; ++q) {
    const Contribution& c = contributions_[q];
    add_at_b(jacobians_.data() + c.ja, jacobians_.data() + c.jb, H_.values().data() + c.dest, c.rows, c.di, c.dj, c.ld);
    if (c.diagonal) add_at_b(jacobians_.data() + c.jb, residuals_.data() + c.residual, gj.data(), c.rows, c.dj, 1, dj);
  }
  for (int c = 0; c < dj; ++c) {
    const int r = H_.block_start(j) + c;
    diag_[r] = H_.values()[H_.diagonal_positions()[r]];
  }
}

double NormalEquations::evaluate(const Values& x, const ThreadPool& pool) {
  pool.parallel_for(
      slots_.size(), [&](std::size_t b, std::size_t e) { linearize_factors(x, b, e); },
      grain_for(residuals_.size(), slots_.size(), kParallelResidualRows));
  double total = 0.0;
  for (double c : factor_cost_) total += c;
  evaluated_ = std::isfinite(total);
  return total;
}

void NormalEquations::assemble(const ThreadPool& pool) {
  if (!evaluated_) throw std::logic_error("NormalEquations::assemble without a finite evaluate()");
  pool.parallel_for(
      static_cast<std::size_t>(H_.num_blocks()),
      [&](std::size_t b, std::size_t e) {
        for (std::size_t j = b; j < e; ++j) assemble_column(static_cast<int>(j));
      },
      grain_for(static_cast<std::size_t>(H_.rows()), static_cast<std::size_t>(H_.num_blocks()), kParallelColumnDims));
}

double NormalEquations::linearize(const Values& x, const ThreadPool& pool) {
  const double total = evaluate(x, pool);
  if (std::isfinite(total)) assemble(pool);
  return total;
}

std::ptrdiff_t NormalEquations::first_nonfinite_factor() const {
  for (std::size_t f = 0; f < factor_cost_.size(); ++f)
    if (!std::isfinite(factor_cost_[f])) return static_cast<std::ptrdiff_t>(f);
  return -1;
}

void NormalEquations::set_diagonal_damping(const Eigen::VectorXd& damping) {
  const auto& pos = H_.diagonal_positions();
  for (int r = 0; r < H_.rows(); ++r) H_.values()[pos[r]] = diag_[r] + damping[r];
}

void NormalEquations::clear_damping() {
  const auto& pos = H_.diagonal_positions();
  for (int r = 0; r < H_.rows(); ++r) H_.values()[pos[r]] = diag_[r];
}

void NormalEquations::retract(const Values& x, const double* delta, Values& out, const ThreadPool& pool) const {
  pool.parallel_for(
      free_vars_.size(),
      [&](std::size_t b, std::size_t e) {
        for (std::size_t k = b; k < e; ++k) {
          const std::size_t i = free_vars_[k];
          x.manifold(i).plus(x.params(i), delta + H_.block_start(static_cast<int>(k)), out.params(i));
        }
      },
      grain_for(free_vars_.size(), free_vars_.size(), kParallelVariables));
}

}  // namespace slamkit
