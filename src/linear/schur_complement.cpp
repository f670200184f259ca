#include "slamkit/linear/schur_complement.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <type_traits>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

constexpr int Dyn = Eigen::Dynamic;
template <int R, int C>
using CMap = Eigen::Map<const Eigen::Matrix<double, R, C>, 0, Eigen::OuterStride<>>;
template <int R, int C>
using MMap = Eigen::Map<Eigen::Matrix<double, R, C>, 0, Eigen::OuterStride<>>;
template <int R>
using CVec = Eigen::Map<const Eigen::Matrix<double, R, 1>>;
template <int R>
using MVec = Eigen::Map<Eigen::Matrix<double, R, 1>>;

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Back-substitution for 9×3 blocks (cameras 9, points 3), e in [b, end):
//   out_e = C_e⁻¹ (in_e − Σ_k W_keᵀ v_k),
// W_ke column-major 9×3 at h + e_off[q] with leading dimension e_ld[e]. Per e, three eight-lane
// sums of W's columns' rows 0..7 times v_k's (row 8 apart), reduced once per e in a fixed tree:
// the products run on eight lanes where the CPU has AVX-512. Contraction into FMA is off, so both
// clones give the same bits (and any thread count: each e is computed alone).
#pragma GCC push_options
#pragma GCC optimize("fp-contract=off")
__attribute__((target_clones("avx512f", "default"))) void back_substitute_93(
    std::size_t b, std::size_t end, const double* h, const int* e_ptr, const std::ptrdiff_t* e_off, const int* e_kept,
    const int* s_start, const int* e_ld, const double* cinv, const std::ptrdiff_t* cinv_off, const double* in_e,
    const double* v, double* out_e) {
  typedef double V8 __attribute__((vector_size(64)));
  typedef double V8u __attribute__((vector_size(64), aligned(8), may_alias));
  typedef long long I8 __attribute__((vector_size(64)));
  for (std::size_t e = b; e < end; ++e) {
    const int ld = e_ld[e];
    V8 acc[3] = {};
    double tail[3] = {0.0, 0.0, 0.0};
    for (int q = e_ptr[e]; q < e_ptr[e + 1]; ++q) {
      const double* w = h + e_off[q];
      const double* x = v + s_start[e_kept[q]];
      const V8 xv = *reinterpret_cast<const V8u*>(x);
      for (int c = 0; c < 3; ++c) {
        acc[c] += *reinterpret_cast<const V8u*>(w + c * ld) * xv;
        tail[c] += w[c * ld + 8] * x[8];
      }
    }
    // Lane sums of the three accumulators at once, in the tree ((0+1)+(2+3))+((4+5)+(6+7)) of each:
    // pairs of A, B side by side, C's pairs beside them, then the halves.
    const V8 p = __builtin_shuffle(acc[0], acc[1], I8{0, 8, 2, 10, 4, 12, 6, 14}) +
                 __builtin_shuffle(acc[0], acc[1], I8{1, 9, 3, 11, 5, 13, 7, 15});  // a01 b01 a23 b23 a45 b45 a67 b67
    const V8 pc = acc[2] + __builtin_shuffle(acc[2], I8{1, 0, 3, 2, 5, 4, 7, 6});  // c01 · c23 · c45 · c67 ·
    const V8 q = __builtin_shuffle(p, pc, I8{0, 1, 8, 8, 4, 5, 12, 12}) +
                 __builtin_shuffle(p, pc, I8{2, 3, 10, 10, 6, 7, 14, 14});  // a0-3 b0-3 c0-3 · a4-7 b4-7 c4-7 ·
    const V8 sum = q + __builtin_shuffle(q, I8{4, 5, 6, 7, 0, 1, 2, 3});    // lanes 0..2: the sums of A, B, C
    double t[3];
    for (int c = 0; c < 3; ++c) t[c] = in_e[3 * e + c] - (sum[c] + tail[c]);
    const double* ci = cinv + cinv_off[e];  // C_e⁻¹, column-major 3×3
    for (int r = 0; r < 3; ++r) out_e[3 * e + r] = ci[r] * t[0] + ci[3 + r] * t[1] + ci[6 + r] * t[2];
  }
}
// The reduced rhs of one camera column s for 9×3 blocks, t in [t_begin, t_end) (s's points in
// order): r −= E_se y_e, y_e = C_e⁻¹ b_e stored right after C_e⁻¹. Rows 0..7 on eight lanes,
// row 8 apart, in the association Eigen's product gives (rows 0..7: r − ((a + b) + c); row 8, its
// scalar redux: r − (a + (b + c))), so both clones give the bits of the Eigen expression.
__attribute__((target_clones("avx512f", "default"))) void reduced_rhs_93(
    int t_begin, int t_end, const double* h, const int* k_elim, const int* k_slot, const std::ptrdiff_t* e_off,
    const int* e_ld, const double* cinv, const std::ptrdiff_t* cinv_off, double* r) {
  typedef double V8 __attribute__((vector_size(64)));
  typedef double V8u __attribute__((vector_size(64), aligned(8), may_alias));
  V8 r8 = *reinterpret_cast<const V8u*>(r);
  double r9 = r[8];
  for (int t = t_begin; t < t_end; ++t) {
    const int e = k_elim[t], ld = e_ld[e];
    const double* w = h + e_off[k_slot[t]];
    const double* y = cinv + cinv_off[e] + 9;
    const V8 a = *reinterpret_cast<const V8u*>(w) * y[0];
    const V8 b = *reinterpret_cast<const V8u*>(w + ld) * y[1];
    const V8 c = *reinterpret_cast<const V8u*>(w + 2 * ld) * y[2];
    r8 = r8 - ((a + b) + c);
    r9 = r9 - (w[8] * y[0] + (w[ld + 8] * y[1] + w[2 * ld + 8] * y[2]));
  }
  *reinterpret_cast<V8u*>(r) = r8;
  r[8] = r9;
}
#pragma GCC pop_options

}  // namespace

const char* to_string(SchurMethod m) {
  switch (m) {
    case SchurMethod::kAuto: return "auto";
    case SchurMethod::kDense: return "schur-dense";
    case SchurMethod::kCholesky: return "schur-cholesky";
    case SchurMethod::kPcg: return "schur-pcg";
  }
  return "?";
}

SchurMethod parse_schur_method(const std::string& s) {
  for (auto m : {SchurMethod::kAuto, SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg})
    if (s == to_string(m) || "schur-" + s == to_string(m)) return m;
  throw InputError("", 0, "linear", "unknown linear solver '" + s + "' (auto, schur-dense, schur-cholesky, schur-pcg)");
}

struct SchurComplementSolver::Impl {
  // ---- structure (analyze) ----
  const BlockSparseMatrix* A = nullptr;
  int ne = 0, nk = 0, nS = 0;
  std::vector<int> ed, e_start, e_diag_ld;  // per eliminated block: dim, start in H, ld of its column
  std::vector<std::ptrdiff_t> e_diag_off;   // offset of C_e in H's values
  std::vector<int> e_ptr;                   // kept neighbours of e: [e_ptr[e], e_ptr[e+1])
  std::vector<int> e_kept;                  //   their S index
  std::vector<std::ptrdiff_t> e_off;        //   offset of H(k, e) (d_k × d_e, ld e_diag_ld[e])
  std::vector<int> kd, k_start, s_start;    // per kept block (S index): dim, start in H, start in S
  std::vector<int> k_ptr, k_elim, k_slot;   // eliminated neighbours of s and the slot of s in e's list
  struct BEntry {
    int other;  // S index of the other block
    std::ptrdiff_t off;
    int ld;
    bool transpose;  // the stored block is H(s, other)ᵀ's transpose: use its transpose
  };
  std::vector<int> bl_ptr;  // lower part of column s of B: rows other ≥ s
  std::vector<BEntry> bl;
  std::vector<int> bf_ptr;  // row s of B, both triangles (for products)
  std::vector<BEntry> bf;
  std::vector<std::ptrdiff_t> cinv_off;
  int kind = 0;  // 1: kept 9 / elim 3, 2: kept 6 / elim 3, 3: kept 6 / elim 1, 4: kept 15 / elim 1 (VIO), 0: general

  // ---- numeric ----
  std::vector<double> cinv;  // C_e⁻¹ per eliminated block
  Eigen::MatrixXd dense;
  std::optional<Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>>> llt;
  BlockSparseMatrix S;
  std::unique_ptr<SparseCholesky> chol;
  std::vector<double> precond;  // PCG: inverse diagonal blocks
  std::vector<std::ptrdiff_t> precond_off;
  Eigen::VectorXd ye, rk, xk, be, bk, work_e, pr, pz, pp, pq;
  bool rhs_formed = false;  // rk (and be, bk) hold the rhs of the b given to factorize(A, b)
  bool kept_solved = false;  // xk solves the last factorization's reduced system

  // be = b_e (packed), bk = b_k (S numbering).
  void gather_rhs(const double* b) {
    const int de = ne > 0 ? ed[0] : 0;
    for (int e = 0; e < ne; ++e)
      for (int a = 0; a < de; ++a) be[e * de + a] = b[e_start[e] + a];
    for (int s = 0; s < nk; ++s)
      for (int a = 0; a < kd[s]; ++a) bk[s_start[s] + a] = b[k_start[s] + a];
  }

  template <class F>
  void dispatch(F&& f) {
    switch (kind) {
      case 1: return f(std::integral_constant<int, 9>{}, std::integral_constant<int, 3>{});
      case 2: return f(std::integral_constant<int, 6>{}, std::integral_constant<int, 3>{});
      case 3: return f(std::integral_constant<int, 6>{}, std::integral_constant<int, 1>{});
      case 4: return f(std::integral_constant<int, 15>{}, std::integral_constant<int, 1>{});
      default: return f(std::integral_constant<int, Dyn>{}, std::integral_constant<int, Dyn>{});
    }
  }

  const double* H() const { return A->values().data(); }

  // C_e⁻¹ for e in [b, e); false if some C_e is not positive definite.
  // With shift (H's row order), C_e + diag(shift_e). With b_e (packed), also y_e = C_e⁻¹ b_e,
  // stored right after C_e⁻¹: forming the reduced rhs then reads it with C_e⁻¹, in cache,
  // instead of b_e from a vector indexed by e in each camera's order (a cache miss per pair).
  template <int ED>
  bool invert_c(std::size_t begin, std::size_t end, const double* shift, const double* be_packed) {
    using M = Eigen::Matrix<double, ED, ED>;
    if constexpr (ED == 3) return invert_c3(begin, end, shift, be_packed);
    for (std::size_t e = begin; e < end; ++e) {
      const int d = ed[e];
      M C = CMap<ED, ED>(H() + e_diag_off[e], d, d, Eigen::OuterStride<>(e_diag_ld[e]));
      if (shift)
        for (int a = 0; a < d; ++a) C(a, a) += shift[e_start[e] + a];
      Eigen::LLT<M> l(C);
      if (l.info() != Eigen::Success) return false;
      MMap<ED, ED> out(cinv.data() + cinv_off[e], d, d, Eigen::OuterStride<>(d));
      out = l.solve(M::Identity(d, d));
      if (!out.allFinite()) return false;
      if (be_packed)
        MVec<ED>(cinv.data() + cinv_off[e] + d * d, d).noalias() =
            out * CVec<ED>(be_packed + static_cast<std::ptrdiff_t>(e) * d, d);
    }
    return true;
  }

  // invert_c for 3×3 blocks in closed form (the generic LLT + triangular solve of Eigen costs
  // several times more): C = L D Lᵀ from the lower triangle (L unit lower: l10, l20, l21),
  // pivots d0, d1, d2 > 0 (else not positive definite, NaN included), then
  // C⁻¹ = L⁻ᵀ D⁻¹ L⁻¹ with L⁻¹ unit lower: m10 = −l10, m21 = −l21, m20 = l10 l21 − l20.
  bool invert_c3(std::size_t begin, std::size_t end, const double* shift, const double* be_packed) {
    for (std::size_t e = begin; e < end; ++e) {
      const double* C = H() + e_diag_off[e];
      const int ld = e_diag_ld[e];
      double c00 = C[0], c10 = C[1], c20 = C[2], c11 = C[ld + 1], c21 = C[ld + 2], c22 = C[2 * ld + 2];
      if (shift) {
        const double* sh = shift + e_start[e];
        c00 += sh[0], c11 += sh[1], c22 += sh[2];
      }
      const double d0 = c00;
      if (!(d0 > 0.0)) return false;
      const double l10 = c10 / d0, l20 = c20 / d0;
      const double d1 = c11 - l10 * c10;
      if (!(d1 > 0.0)) return false;
      const double t21 = c21 - l20 * c10, l21 = t21 / d1;
      const double d2 = c22 - l20 * c20 - l21 * t21;
      if (!(d2 > 0.0)) return false;
      const double i0 = 1.0 / d0, i1 = 1.0 / d1, i2 = 1.0 / d2;
      const double m10 = -l10, m21 = -l21, m20 = l10 * l21 - l20;
      const double a2 = m20 * i2, b2 = m21 * i2;
      const double v00 = i0 + m10 * m10 * i1 + m20 * a2, v10 = m10 * i1 + m20 * b2, v20 = a2;
      const double v11 = i1 + m21 * b2, v21 = b2, v22 = i2;
      double* out = cinv.data() + cinv_off[e];
      out[0] = v00, out[1] = v10, out[2] = v20;
      out[3] = v10, out[4] = v11, out[5] = v21;
      out[6] = v20, out[7] = v21, out[8] = v22;
      for (int a = 0; a < 9; ++a)
        if (!std::isfinite(out[a])) return false;
      if (be_packed) {
        const double* b = be_packed + static_cast<std::ptrdiff_t>(e) * 3;
        out[9] = v00 * b[0] + v10 * b[1] + v20 * b[2];
        out[10] = v10 * b[0] + v11 * b[1] + v21 * b[2];
        out[11] = v20 * b[0] + v21 * b[1] + v22 * b[2];
      }
    }
    return true;
  }

  // dest(kd_i × kd_s) -= Σ_e E_ie C_e⁻¹ E_seᵀ for the rows i ≥ s, plus B's lower blocks; with
  // rhs, also rk_s = b_s − Σ_e E_se y_e from bk and y_e = C_e⁻¹ b_e (invert_c).
  template <int KD, int ED, class Dest>
  void form_column(int s, Dest&& dest, bool rhs) {
    const int ds = kd[s];
    Eigen::Matrix<double, KD, 1> r(ds);
    if (rhs) r = bk.segment(s_start[s], ds);
    for (int b = bl_ptr[s]; b < bl_ptr[s + 1]; ++b) {
      const BEntry& x = bl[b];
      const int di = kd[x.other];
      MMap<KD, KD> D = dest(x.other);
      if (x.transpose)
        D += CMap<KD, KD>(H() + x.off, ds, di, Eigen::OuterStride<>(x.ld)).transpose();
      else
        D += CMap<KD, KD>(H() + x.off, di, ds, Eigen::OuterStride<>(x.ld));
    }
    // 9×3 blocks: the rhs on eight lanes (same bits), before S's products read the same blocks.
    constexpr bool lanes = KD == 9 && ED == 3;
    if constexpr (lanes)
      if (rhs)
        reduced_rhs_93(k_ptr[s], k_ptr[s + 1], H(), k_elim.data(), k_slot.data(), e_off.data(), e_diag_ld.data(),
                       cinv.data(), cinv_off.data(), r.data());
    for (int t = k_ptr[s]; t < k_ptr[s + 1]; ++t) {
      const int e = k_elim[t], de = ed[e], ld = e_diag_ld[e];
      const CMap<KD, ED> Ese(H() + e_off[k_slot[t]], ds, de, Eigen::OuterStride<>(ld));
      const CMap<ED, ED> Ci(cinv.data() + cinv_off[e], de, de, Eigen::OuterStride<>(de));
      const Eigen::Matrix<double, ED, KD> F = Ci.lazyProduct(Ese.transpose());
      if (!lanes && rhs) r.noalias() -= Ese * CVec<ED>(cinv.data() + cinv_off[e] + de * de, de);
      for (int q = e_ptr[e]; q < e_ptr[e + 1]; ++q) {
        const int i = e_kept[q];
        if (i < s) continue;
        MMap<KD, KD> D = dest(i);
        D.noalias() -= CMap<KD, ED>(H() + e_off[q], kd[i], de, Eigen::OuterStride<>(ld)).lazyProduct(F);
      }
    }
    if (rhs) rk.segment(s_start[s], ds) = r;
  }

  template <int KD, int ED>
  void form_dense(const ThreadPool& pool, bool rhs) {
    pool.parallel_for(
        nk,
        [&](std::size_t b, std::size_t e) {
          for (std::size_t s = b; s < e; ++s) {
            const int c0 = s_start[s], ds = kd[s];
            dense.block(c0, c0, nS - c0, ds).setZero();
            form_column<KD, ED>(static_cast<int>(s), [&](int i) {
              return MMap<KD, KD>(dense.data() + static_cast<std::ptrdiff_t>(c0) * nS + s_start[i], kd[i], ds,
                                  Eigen::OuterStride<>(nS));
            }, rhs);
          }
        },
        1);
  }

  template <int KD, int ED>
  void form_sparse(const ThreadPool& pool, bool rhs) {
    pool.parallel_for(
        nk,
        [&](std::size_t b, std::size_t e) {
          std::vector<std::ptrdiff_t> where(nk, -1);
          for (std::size_t s = b; s < e; ++s) {
            const int si = static_cast<int>(s), ds = kd[s], ld = S.leading_dim(si);
            double* col = S.values().data() + S.block_offset(si, si);
            std::fill(col, col + static_cast<std::ptrdiff_t>(ld) * ds, 0.0);
            for (const int* r = S.column_blocks_begin(si); r != S.column_blocks_end(si); ++r)
              where[*r] = S.block_offset(*r, si);
            form_column<KD, ED>(si, [&](int i) {
              return MMap<KD, KD>(S.values().data() + where[i], kd[i], ds, Eigen::OuterStride<>(ld));
            }, rhs);
          }
        },
        1);
  }

  // Inverse diagonal blocks of S (Schur-Jacobi) or of B (block-Jacobi); false if one is not PD.
  // With rhs (Schur-Jacobi only), also rk as in form_column.
  template <int KD, int ED>
  bool form_preconditioner(std::size_t begin, std::size_t end, bool schur, bool rhs) {
    using M = Eigen::Matrix<double, KD, KD>;
    for (std::size_t s = begin; s < end; ++s) {
      const int ds = kd[s];
      M D = M::Zero(ds, ds);
      Eigen::Matrix<double, KD, 1> r(ds);
      if (rhs) r = bk.segment(s_start[s], ds);
      for (int b = bl_ptr[s]; b < bl_ptr[s + 1]; ++b)
        if (bl[b].other == static_cast<int>(s))
          D += CMap<KD, KD>(H() + bl[b].off, ds, ds, Eigen::OuterStride<>(bl[b].ld));
      if (schur) {
        for (int t = k_ptr[s]; t < k_ptr[s + 1]; ++t) {
          const int e = k_elim[t], de = ed[e];
          const CMap<KD, ED> Ese(H() + e_off[k_slot[t]], ds, de, Eigen::OuterStride<>(e_diag_ld[e]));
          const CMap<ED, ED> Ci(cinv.data() + cinv_off[e], de, de, Eigen::OuterStride<>(de));
          const Eigen::Matrix<double, ED, KD> F = Ci.lazyProduct(Ese.transpose());
          D.noalias() -= Ese.lazyProduct(F);
          if (rhs) r.noalias() -= Ese * CVec<ED>(cinv.data() + cinv_off[e] + de * de, de);
        }
      }
      if (rhs) rk.segment(s_start[s], ds) = r;
      Eigen::LLT<M> l(D);
      if (l.info() != Eigen::Success) return false;
      MMap<KD, KD>(precond.data() + precond_off[s], ds, ds, Eigen::OuterStride<>(ds)) = l.solve(M::Identity(ds, ds));
    }
    return true;
  }

  // out_e = C_e⁻¹ (in_e − Σ_k E_keᵀ v_k) (v may be null: no kept part); in/out over eliminated storage.
  template <int KD, int ED>
  void eliminated_solve(const ThreadPool& pool, const double* in_e, const double* v, double* out_e) {
    pool.parallel_for(ne, [&](std::size_t b, std::size_t end) { eliminated_solve_range<KD, ED>(b, end, in_e, v, out_e); });
  }

  // eliminated_solve on e in [b, end), serially: reads only those e's blocks of H and C_e⁻¹.
  template <int KD, int ED>
  void eliminated_solve_range(std::size_t b, std::size_t end, const double* in_e, const double* v, double* out_e) {
    if constexpr (KD == 9 && ED == 3) {
      if (in_e && v)
        return back_substitute_93(b, end, H(), e_ptr.data(), e_off.data(), e_kept.data(), s_start.data(), e_diag_ld.data(),
                                  cinv.data(), cinv_off.data(), in_e, v, out_e);
    }
    {
      for (std::size_t e = b; e < end; ++e) {
        const int de = ed[e], ld = e_diag_ld[e];
        const std::ptrdiff_t o = static_cast<std::ptrdiff_t>(e) * de;  // start of e in eliminated storage
        Eigen::Matrix<double, ED, 1> t(de);
        if (in_e) t = CVec<ED>(in_e + o, de); else t.setZero();
        if (v)
          for (int q = e_ptr[e]; q < e_ptr[e + 1]; ++q) {
            const int i = e_kept[q];
            t.noalias() -= CMap<KD, ED>(H() + e_off[q], kd[i], de, Eigen::OuterStride<>(ld)).transpose() *
                           CVec<KD>(v + s_start[i], kd[i]);
          }
        MVec<ED>(out_e + o, de).noalias() = CMap<ED, ED>(cinv.data() + cinv_off[e], de, de, Eigen::OuterStride<>(de)) * t;
      }
    }
  }

  // out_s = sign_b · (B v)_s − Σ_e E_se y_e (+ base_s); y over eliminated storage.
  template <int KD, int ED>
  void kept_gather(const ThreadPool& pool, const double* base, const double* v, const double* y, double* out) {
    pool.parallel_for(nk, [&](std::size_t b, std::size_t end) {
      for (std::size_t s = b; s < end; ++s) {
        const int ds = kd[s];
        Eigen::Matrix<double, KD, 1> t(ds);
        if (base) t = CVec<KD>(base + s_start[s], ds); else t.setZero();
        if (v)
          for (int q = bf_ptr[s]; q < bf_ptr[s + 1]; ++q) {
            const BEntry& x = bf[q];
            const int dc = kd[x.other];
            if (x.transpose)
              t.noalias() += CMap<KD, KD>(H() + x.off, dc, ds, Eigen::OuterStride<>(x.ld)).transpose() *
                             CVec<KD>(v + s_start[x.other], dc);
            else
              t.noalias() += CMap<KD, KD>(H() + x.off, ds, dc, Eigen::OuterStride<>(x.ld)) * CVec<KD>(v + s_start[x.other], dc);
          }
        for (int q = k_ptr[s]; q < k_ptr[s + 1]; ++q) {
          const int e = k_elim[q], de = ed[e];
          t.noalias() -= CMap<KD, ED>(H() + e_off[k_slot[q]], ds, de, Eigen::OuterStride<>(e_diag_ld[e])) *
                         CVec<ED>(y + static_cast<std::ptrdiff_t>(e) * de, de);
        }
        MVec<KD>(out + s_start[s], ds) = t;
      }
    });
  }

  template <int KD, int ED>
  void apply_preconditioner(const ThreadPool& pool, const double* r, double* z) {
    pool.parallel_for(nk, [&](std::size_t b, std::size_t end) {
      for (std::size_t s = b; s < end; ++s) {
        const int ds = kd[s];
        MVec<KD>(z + s_start[s], ds).noalias() =
            CMap<KD, KD>(precond.data() + precond_off[s], ds, ds, Eigen::OuterStride<>(ds)) * CVec<KD>(r + s_start[s], ds);
      }
    });
  }
};

SchurComplementSolver::SchurComplementSolver(std::vector<char> eliminate, const ThreadPool& pool, SchurOptions options)
    : impl_(std::make_unique<Impl>()), eliminate_(std::move(eliminate)), pool_(pool), options_(options) {}

SchurComplementSolver::~SchurComplementSolver() = default;

int SchurComplementSolver::reduced_dim() const { return impl_->nS; }
int SchurComplementSolver::num_eliminated() const { return impl_->ne; }

std::string SchurComplementSolver::name() const {
  std::string s = "Schur complement (" + std::to_string(impl_->ne) + " blocks eliminated, reduced dim " +
                  std::to_string(impl_->nS) + ") + ";
  switch (method_) {
    case SchurMethod::kDense: return s + "dense LLT";
    case SchurMethod::kCholesky: return s + (impl_->chol ? impl_->chol->name() : std::string("sparse Cholesky"));
    case SchurMethod::kPcg:
      return s + "PCG (" + (options_.preconditioner == SchurPreconditioner::kSchurJacobi ? "Schur-Jacobi" : "block-Jacobi") + ")";
    case SchurMethod::kAuto: break;
  }
  return s + "?";
}

void SchurComplementSolver::analyze(const BlockSparseMatrix& A, const EliminationOrder* block_order) {
  if (block_order) throw std::invalid_argument("SchurComplementSolver::analyze: H must be stored with its eliminated blocks first");
  const double t0 = now_s();
  Impl& m = *impl_;
  m = Impl();
  m.A = &A;
  const int nb = A.num_blocks();
  if (static_cast<int>(eliminate_.size()) != nb)
    throw std::invalid_argument("SchurComplementSolver: eliminate flags do not match the blocks of H");
  std::vector<int> eidx(nb, -1), qidx(nb, -1);  // eliminated index, provisional kept index (H order)
  std::vector<int> kept_h;
  for (int b = 0; b < nb; ++b) {
    if (eliminate_[b]) {
      eidx[b] = m.ne++;
    } else {
      qidx[b] = static_cast<int>(kept_h.size());
      kept_h.push_back(b);
    }
  }
  m.nk = static_cast<int>(kept_h.size());
  if (m.nk == 0) throw std::invalid_argument("SchurComplementSolver: every block is eliminated");

  // Structure checks and kept-kept pairs (graph of S).
  std::vector<std::pair<int, int>> edges;
  for (int c = 0; c < nb; ++c) {
    const int* r0 = A.column_blocks_begin(c);
    const int* r1 = A.column_blocks_end(c);
    if (eliminate_[c]) {
      for (const int* r = r0 + 1; r != r1; ++r)
        if (eliminate_[*r]) throw std::invalid_argument("SchurComplementSolver: two eliminated blocks are adjacent");
      for (const int* a = r0 + 1; a != r1; ++a)
        for (const int* b = a + 1; b != r1; ++b) edges.emplace_back(qidx[*b], qidx[*a]);
    } else {
      for (const int* r = r0 + 1; r != r1; ++r) {
        if (eliminate_[*r])
          throw std::invalid_argument("SchurComplementSolver: an eliminated block comes after one of its neighbours");
        edges.emplace_back(qidx[*r], qidx[c]);
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());

  // Method and the numbering of S (elimination order for the sparse factorization).
  int dimS = 0;
  for (int b : kept_h) dimS += A.block_dim(b);
  method_ = options_.method;
  EliminationOrder order;
  const bool need_order = method_ == SchurMethod::kCholesky || (method_ == SchurMethod::kAuto && dimS > options_.auto_dense_max_dim);
  if (need_order) {
    order = compute_elimination_order(m.nk, edges, options_.ordering);
    if (method_ == SchurMethod::kAuto) {
      const double avg = static_cast<double>(dimS) / m.nk;
      method_ = order.flops * avg * avg * avg > options_.auto_pcg_min_flops ? SchurMethod::kPcg : SchurMethod::kCholesky;
    }
  } else if (method_ == SchurMethod::kAuto) {
    method_ = SchurMethod::kDense;
  }
  std::vector<int> sidx(m.nk);  // provisional → S index
  if (method_ == SchurMethod::kCholesky) {
    for (int k = 0; k < m.nk; ++k) sidx[order.order[k]] = k;
  } else {
    for (int k = 0; k < m.nk; ++k) sidx[k] = k;
  }
  m.kd.resize(m.nk), m.k_start.resize(m.nk), m.s_start.resize(m.nk + 1);
  for (int q = 0; q < m.nk; ++q) {
    const int s = sidx[q];
    m.kd[s] = A.block_dim(kept_h[q]);
    m.k_start[s] = A.block_start(kept_h[q]);
  }
  for (int s = 0; s < m.nk; ++s) m.s_start[s + 1] = m.s_start[s] + m.kd[s];
  m.nS = m.s_start[m.nk];

  // Eliminated blocks and their kept neighbours.
  m.ed.resize(m.ne), m.e_start.resize(m.ne), m.e_diag_ld.resize(m.ne), m.e_diag_off.resize(m.ne);
  m.e_ptr.assign(m.ne + 1, 0);
  m.cinv_off.resize(m.ne + 1);
  std::vector<int> k_count(m.nk + 1, 0);
  bool k93 = true, k63 = true, k61 = true, k151 = true;
  std::ptrdiff_t coff = 0;
  for (int b = 0; b < nb; ++b) {
    if (!eliminate_[b]) continue;
    const int e = eidx[b];
    m.ed[e] = A.block_dim(b);
    m.e_start[e] = A.block_start(b);
    m.e_diag_ld[e] = A.leading_dim(b);
    m.e_diag_off[e] = A.block_offset(b, b);
    m.cinv_off[e] = coff;
    coff += static_cast<std::ptrdiff_t>(m.ed[e]) * (m.ed[e] + 1);  // C_e⁻¹, then y_e = C_e⁻¹ b_e
    for (const int* r = A.column_blocks_begin(b) + 1; r != A.column_blocks_end(b); ++r) {
      const int s = sidx[qidx[*r]];
      m.e_kept.push_back(s);
      m.e_off.push_back(A.block_offset(*r, b));
      ++k_count[s + 1];
    }
    m.e_ptr[e + 1] = static_cast<int>(m.e_kept.size());
    k93 = k93 && m.ed[e] == 3, k63 = k63 && m.ed[e] == 3, k61 = k61 && m.ed[e] == 1, k151 = k151 && m.ed[e] == 1;
  }
  m.cinv_off[m.ne] = coff;
  // Eliminated storage of a vector (packed): block e at e · ed[e], all dims being equal.
  {
    bool equal = true;
    for (int e = 0; e < m.ne; ++e) equal = equal && m.ed[e] == m.ed[0];
    if (!equal) throw std::invalid_argument("SchurComplementSolver: eliminated blocks must all have the same size");
  }
  for (int s = 0; s < m.nk; ++s) {
    k93 = k93 && m.kd[s] == 9, k63 = k63 && m.kd[s] == 6, k61 = k61 && m.kd[s] == 6, k151 = k151 && m.kd[s] == 15;
  }
  m.kind = k93 ? 1 : k63 ? 2 : k61 ? 3 : k151 ? 4 : 0;
  m.k_ptr.assign(m.nk + 1, 0);
  for (int s = 0; s < m.nk; ++s) m.k_ptr[s + 1] = m.k_ptr[s] + k_count[s + 1];
  m.k_elim.resize(m.e_kept.size()), m.k_slot.resize(m.e_kept.size());
  {
    std::vector<int> fill(m.k_ptr.begin(), m.k_ptr.end() - 1);
    for (int e = 0; e < m.ne; ++e)
      for (int q = m.e_ptr[e]; q < m.e_ptr[e + 1]; ++q) {
        const int s = m.e_kept[q];
        m.k_elim[fill[s]] = e, m.k_slot[fill[s]] = q, ++fill[s];
      }
  }

  // B's blocks: lower part per S column (for forming S) and full rows (for products).
  std::vector<std::vector<Impl::BEntry>> lower(m.nk), full(m.nk);
  for (int c = 0; c < nb; ++c) {
    if (eliminate_[c]) continue;
    const int sc = sidx[qidx[c]];
    for (const int* r = A.column_blocks_begin(c); r != A.column_blocks_end(c); ++r) {
      const int sr = sidx[qidx[*r]];
      const std::ptrdiff_t off = A.block_offset(*r, c);  // H(r, c): d_r × d_c
      const int ld = A.leading_dim(c);
      // Column min(sr, sc) of S gets the block (max, min).
      if (sr >= sc) lower[sc].push_back({sr, off, ld, false});
      else lower[sr].push_back({sc, off, ld, true});
      full[sr].push_back({sc, off, ld, false});
      if (sr != sc) full[sc].push_back({sr, off, ld, true});
    }
  }
  m.bl_ptr.assign(m.nk + 1, 0), m.bf_ptr.assign(m.nk + 1, 0);
  for (int s = 0; s < m.nk; ++s) {
    m.bl.insert(m.bl.end(), lower[s].begin(), lower[s].end());
    m.bf.insert(m.bf.end(), full[s].begin(), full[s].end());
    m.bl_ptr[s + 1] = static_cast<int>(m.bl.size());
    m.bf_ptr[s + 1] = static_cast<int>(m.bf.size());
  }
  m.cinv.assign(static_cast<std::size_t>(coff), 0.0);
  const int edim = m.ne > 0 ? m.ne * m.ed[0] : 0;
  m.ye.resize(edim), m.work_e.resize(edim), m.be.resize(edim);
  m.rk.resize(m.nS), m.xk.resize(m.nS), m.bk.resize(m.nS);

  stats_ = CholeskyStats();
  if (method_ == SchurMethod::kDense) {
    m.dense.setZero(m.nS, m.nS);
    stats_.ordering = "dense";
    stats_.factor_nnz = 0.5 * m.nS * (m.nS + 1.0);
    stats_.factor_flops = static_cast<double>(m.nS) * m.nS * m.nS / 3.0;
  } else if (method_ == SchurMethod::kCholesky) {
    std::vector<std::pair<int, int>> pattern;
    pattern.reserve(edges.size());
    for (const auto& [a, b] : edges) pattern.emplace_back(sidx[a], sidx[b]);
    m.S = BlockSparseMatrix(m.kd, std::move(pattern));
    m.chol = make_sparse_cholesky(SparseBackend::kAuto, options_.ordering, options_.blas_threads);
    m.chol->analyze(m.S);
    stats_.ordering = order.method;
    stats_.factor_nnz = m.chol->stats().factor_nnz;
    stats_.factor_flops = m.chol->stats().factor_flops;
  } else {
    m.precond_off.resize(m.nk + 1, 0);
    for (int s = 0; s < m.nk; ++s) m.precond_off[s + 1] = m.precond_off[s] + static_cast<std::ptrdiff_t>(m.kd[s]) * m.kd[s];
    m.precond.assign(static_cast<std::size_t>(m.precond_off[m.nk]), 0.0);
    m.pr.resize(m.nS), m.pz.resize(m.nS), m.pp.resize(m.nS), m.pq.resize(m.nS);
    stats_.ordering = "none (iterative)";
  }
  stats_.analyze_time_s = now_s() - t0;
}

bool SchurComplementSolver::factorize(const BlockSparseMatrix& A) { return factorize(A, nullptr); }

bool SchurComplementSolver::factorize(const BlockSparseMatrix& A, const double* b, const double* eliminated_shift) {
  Impl& m = *impl_;
  if (m.A == nullptr || A.rows() != m.A->rows()) throw std::logic_error("SchurComplementSolver::factorize before analyze");
  m.A = &A;
  m.rhs_formed = m.kept_solved = false;
  const double t0 = now_s();
  std::vector<char> ok(static_cast<std::size_t>(m.ne) + 1, 1);
  bool good = true;
  const bool schur_jacobi = options_.preconditioner == SchurPreconditioner::kSchurJacobi;
  const bool rhs = b != nullptr && (method_ != SchurMethod::kPcg || schur_jacobi);
  if (b) m.gather_rhs(b);
  const double* be = rhs ? m.be.data() : nullptr;
  m.dispatch([&](auto KD, auto ED) {
    constexpr int kd = decltype(KD)::value, edim = decltype(ED)::value;
    (void)kd;
    pool_.parallel_for(m.ne, [&](std::size_t b0, std::size_t e) { ok[b0] = m.template invert_c<edim>(b0, e, eliminated_shift, be); });
  });
  for (char c : ok) good = good && c;
  if (!good) return false;
  bool result = true;
  m.dispatch([&](auto KD, auto ED) {
    constexpr int kd = decltype(KD)::value, edim = decltype(ED)::value;
    if (b && !rhs) {  // block-Jacobi: no E C⁻¹ at hand while forming it
      m.template eliminated_solve<kd, edim>(pool_, m.be.data(), nullptr, m.ye.data());
      m.template kept_gather<kd, edim>(pool_, m.bk.data(), nullptr, m.ye.data(), m.rk.data());
    }
    if (method_ == SchurMethod::kDense) {
      m.template form_dense<kd, edim>(pool_, rhs);
      last_schur_time_s_ = now_s() - t0;
      const double t1 = now_s();
      m.llt.reset();
      m.llt.emplace(m.dense);
      result = m.llt->info() == Eigen::Success;
      last_factor_time_s_ = now_s() - t1;
    } else if (method_ == SchurMethod::kCholesky) {
      m.template form_sparse<kd, edim>(pool_, rhs);
      last_schur_time_s_ = now_s() - t0;
      const double t1 = now_s();
      result = m.chol->factorize(m.S);
      last_factor_time_s_ = now_s() - t1;
    } else {
      std::vector<char> pok(static_cast<std::size_t>(m.nk) + 1, 1);
      pool_.parallel_for(m.nk, [&](std::size_t b0, std::size_t e) {
        pok[b0] = m.template form_preconditioner<kd, edim>(b0, e, schur_jacobi, rhs);
      });
      for (char c : pok) result = result && c;
      last_schur_time_s_ = now_s() - t0;
      last_factor_time_s_ = 0.0;
    }
  });
  m.rhs_formed = result && b != nullptr;
  return result;
}

void SchurComplementSolver::solve(const double* b, double* x) {
  Impl& m = *impl_;
  m.gather_rhs(b);
  m.dispatch([&](auto KD, auto ED) {
    constexpr int kd = decltype(KD)::value, edim = decltype(ED)::value;
    // rhs = b_k − E C⁻¹ b_e.
    m.template eliminated_solve<kd, edim>(pool_, m.be.data(), nullptr, m.ye.data());
    m.template kept_gather<kd, edim>(pool_, m.bk.data(), nullptr, m.ye.data(), m.rk.data());
  });
  m.rhs_formed = true;
  solve_factored_rhs(x);
}

void SchurComplementSolver::solve_factored_rhs(double* x) {
  Impl& m = *impl_;
  solve_factored_kept(x);
  m.dispatch([&](auto KD, auto ED) {
    constexpr int kd = decltype(KD)::value, edim = decltype(ED)::value;
    // Back-substitution x_e = C_e⁻¹ (b_e − Σ_k E_keᵀ x_k), one pass in the E blocks' storage order.
    m.template eliminated_solve<kd, edim>(pool_, m.be.data(), m.xk.data(), m.ye.data());
  });
  const int de = m.ne > 0 ? m.ed[0] : 0;
  for (int e = 0; e < m.ne; ++e)
    for (int a = 0; a < de; ++a) x[m.e_start[e] + a] = m.ye[e * de + a];
}

void SchurComplementSolver::back_substitute(int e_begin, int e_end, double* x) {
  Impl& m = *impl_;
  if (!m.kept_solved) throw std::logic_error("SchurComplementSolver::back_substitute without solve_factored_kept");
  m.dispatch([&](auto KD, auto ED) {
    constexpr int kd = decltype(KD)::value, edim = decltype(ED)::value;
    m.template eliminated_solve_range<kd, edim>(e_begin, e_end, m.be.data(), m.xk.data(), m.ye.data());
  });
  const int de = m.ne > 0 ? m.ed[0] : 0;
  for (int e = e_begin; e < e_end; ++e)
    for (int a = 0; a < de; ++a) x[m.e_start[e] + a] = m.ye[e * de + a];
}

void SchurComplementSolver::solve_factored_kept(double* x) {
  Impl& m = *impl_;
  if (!m.rhs_formed) throw std::logic_error("SchurComplementSolver::solve_factored_rhs without a factorize(A, b)");
  last_pcg_iterations_ = 0;
  last_residual_dot_solution_ = 0.0;
  m.dispatch([&](auto KD, auto ED) {
    constexpr int kd = decltype(KD)::value, edim = decltype(ED)::value;
    if (method_ == SchurMethod::kDense) {
      m.xk = m.llt->solve(m.rk);
    } else if (method_ == SchurMethod::kCholesky) {
      m.chol->solve(m.rk.data(), m.xk.data());
    } else {
      // Conjugate gradients on S x = rhs with S v = B v − E C⁻¹ Eᵀ v, x₀ = 0. With r = rhs − Sx
      // the model is Q(x) = ½xᵀSx − rhsᵀx = −½ xᵀ(rhs + r).
      m.xk.setZero();
      m.pr = m.rk;
      const double r0 = m.pr.norm();
      if (r0 > 0.0) {
        m.template apply_preconditioner<kd, edim>(pool_, m.pr.data(), m.pz.data());
        m.pp = m.pz;
        double rz = m.pr.dot(m.pz), q_prev = 0.0;
        for (int it = 0; it < options_.pcg_max_iterations; ++it) {
          // work_e = −C⁻¹ Eᵀ p, negated; then q = B p − E (C⁻¹ Eᵀ p).
          m.template eliminated_solve<kd, edim>(pool_, nullptr, m.pp.data(), m.work_e.data());
          m.work_e = -m.work_e;
          m.template kept_gather<kd, edim>(pool_, nullptr, m.pp.data(), m.work_e.data(), m.pq.data());
          const double pq = m.pp.dot(m.pq);
          ++last_pcg_iterations_;
          if (!(pq > 0.0)) break;
          const double alpha = rz / pq;
          m.xk += alpha * m.pp;
          m.pr -= alpha * m.pq;
          if (m.pr.norm() <= options_.pcg_tolerance * r0) break;
          const double q = -0.5 * m.xk.dot(m.rk + m.pr);
          if (options_.pcg_q_tolerance > 0.0 && q < 0.0 &&
              (it + 1) * (q - q_prev) / q < options_.pcg_q_tolerance)
            break;
          q_prev = q;
          m.template apply_preconditioner<kd, edim>(pool_, m.pr.data(), m.pz.data());
          const double rz_new = m.pr.dot(m.pz);
          m.pp = m.pz + (rz_new / rz) * m.pp;
          rz = rz_new;
        }
      }
      total_pcg_iterations_ += last_pcg_iterations_;
      last_residual_dot_solution_ = m.xk.dot(m.pr);  // pr = rhs − S x_k (CG's recurrence)
    }
  });
  m.kept_solved = true;
  for (int s = 0; s < m.nk; ++s)
    for (int a = 0; a < m.kd[s]; ++a) x[m.k_start[s] + a] = m.xk[m.s_start[s] + a];
}

bool SchurComplementSolver::reduced_system(const BlockSparseMatrix& A, const double* b, Eigen::MatrixXd* S,
                                           Eigen::VectorXd* rhs) {
  Impl& m = *impl_;
  if (m.A == nullptr || A.rows() != m.A->rows()) throw std::logic_error("SchurComplementSolver::reduced_system before analyze");
  if (method_ != SchurMethod::kDense) throw std::logic_error("SchurComplementSolver::reduced_system needs the dense method");
  m.A = &A;
  bool good = true;
  m.dispatch([&](auto KD, auto ED) {
    constexpr int kd = decltype(KD)::value, edim = decltype(ED)::value;
    m.gather_rhs(b);
    good = m.template invert_c<edim>(0, m.ne, nullptr, m.be.data());
    if (!good) return;
    m.template form_dense<kd, edim>(pool_, true);
  });
  if (!good) return false;
  *S = m.dense.selfadjointView<Eigen::Lower>();
  *rhs = m.rk;
  return true;
}

Eigen::MatrixXd SchurComplementSolver::solve(const Eigen::MatrixXd& B) {
  Eigen::MatrixXd X(B.rows(), B.cols());
  for (Eigen::Index c = 0; c < B.cols(); ++c) solve(B.col(c).data(), X.col(c).data());
  return X;
}

double SchurComplementSolver::inverse_factor_norm2(const double* v) {
  const int n = impl_->A->rows();
  Eigen::VectorXd x(n);
  solve(v, x.data());
  return Eigen::Map<const Eigen::VectorXd>(v, n).dot(x);
}

}  // namespace slamkit
