#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <type_traits>

#include "slamkit/factors/bal_normal_equations.h"

// The AVX-512 clones below have FMA: keep a·b + c as two roundings there too (every clone and
// the scalar kernel give the same bits).
#pragma GCC optimize("fp-contract=off")

namespace slamkit {
namespace {

constexpr int kChunk = 256;  // points per cost chunk (fixed: the summation order)
constexpr int kSub = 64;     // points per back-substitution step in retract_and_linearize (~45 KB of W: L2)

using Mat29 = Eigen::Matrix<double, 2, 9>;
using Mat23 = Eigen::Matrix<double, 2, 3>;
template <int R, int C>
using CMapS = Eigen::Map<const Eigen::Matrix<double, R, C>, 0, Eigen::OuterStride<>>;

// The robust kernel's correction of one residual (as Factor::linearize): returns ρ(s) and
// rescales r, F, E so that ½‖Ĵδ + r̂‖² is the kernel's second-order model.
double robust_correct(const RobustKernel& k, Eigen::Vector2d& r, Mat29* F, Mat23* E) {
  const double s = r.squaredNorm();
  double rho[3];
  k.evaluate(s, rho);
  if (!F) return rho[0];
  if (!(rho[1] > 0.0) || s == 0.0) {
    const double scale = rho[1] > 0.0 ? std::sqrt(rho[1]) : 0.0;
    r *= scale, *F *= scale, *E *= scale;
    return rho[0];
  }
  const double sqrt_rho1 = std::sqrt(rho[1]);
  double alpha = 0.0;
  if (rho[2] > 0.0) alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
  if (alpha != 0.0) {
    const double a = alpha / s;
    *F -= a * r * (r.transpose() * *F);
    *E -= a * r * (r.transpose() * *E);
  }
  *F *= sqrt_rho1, *E *= sqrt_rho1;
  r *= sqrt_rho1 / (1.0 - alpha);
  return rho[0];
}

// Four observations, one per lane (GCC vector: AVX2 in the avx2 clones, two SSE2 halves in the
// default ones; elementwise IEEE either way, so both clones give the same bits).
constexpr int kLanes = 8;
typedef double Lanes __attribute__((vector_size(8 * kLanes)));

// robust_correct on lanes [0, n) of r, E, F (each lane as the scalar code does it); cost ← ρ.
template <class V>
inline void robust_correct_lanes(const RobustKernel& kernel, int n, V* r, V* E, V* F, V* cost) {
  for (int k = 0; k < n; ++k) {
    Eigen::Vector2d rv(r[0][k], r[1][k]);
    Mat29 Fl;
    Mat23 El;
    for (int a = 0; a < 9; ++a) Fl(0, a) = F[a][k], Fl(1, a) = F[9 + a][k];
    for (int a = 0; a < 3; ++a) El(0, a) = E[a][k], El(1, a) = E[3 + a][k];
    (*cost)[k] = robust_correct(kernel, rv, &Fl, &El);
    for (int a = 0; a < 9; ++a) F[a][k] = Fl(0, a), F[9 + a][k] = Fl(1, a);
    for (int a = 0; a < 3; ++a) E[a][k] = El(0, a), E[3 + a][k] = El(1, a);
    r[0][k] = rv[0], r[1][k] = rv[1];
  }
}

// What the point and camera passes read and write.
struct PassData {
  const Eigen::Vector3d* points;
  const BalCameraFrame* frames;
  const BalPointObservation* pt_obs;  // point order (the point pass)
  const int* pt_ptr;
  const std::ptrdiff_t* c_off;  // offset of C_j in H's values
  const BalCameraObservation* cam_obs;  // camera order (the camera pass)
  const int* cam_ptr;
  double* H;
  double* g;
  double* diag;
  const BlockSparseMatrix* hessian;
  const RobustKernel* kernel;
  int np;
  // Optional: H's columns of the next sub-chunk [pf_begin, pf_end), prefetched into L2 while
  // these points are linearized (the next back-substitution reads them).
  const char* pf_begin = nullptr;
  const char* pf_end = nullptr;
};

// Prefetch the share [g, g+1) of G equal shares of d's prefetch range, one 64-byte line at a time.
inline void prefetch_share(const PassData& d, long g, long G) {
  if (!d.pf_begin || G <= 0) return;
  const long bytes = d.pf_end - d.pf_begin;
  for (long o = (bytes * g / G) & ~63L, e = bytes * (g + 1) / G; o < e; o += 64) __builtin_prefetch(d.pf_begin + o, 1, 2);
}

// Point j's blocks from its sums: C_j (symmetric, from the upper triangle c00 c01 c02 c11 c12
// c22), g_j and the diagonal D_j = diag(C_j).
inline void store_point_blocks(const PassData& d, int j, double c00, double c01, double c02, double c11, double c12,
                               double c22, double g0, double g1, double g2) {
  const int ld = d.hessian->leading_dim(j);
  double* Cj = d.H + d.c_off[j];
  Cj[0] = c00, Cj[1] = c01, Cj[2] = c02;
  Cj[ld] = c01, Cj[ld + 1] = c11, Cj[ld + 2] = c12;
  Cj[2 * ld] = c02, Cj[2 * ld + 1] = c12, Cj[2 * ld + 2] = c22;
  d.g[3 * j] = g0, d.g[3 * j + 1] = g1, d.g[3 * j + 2] = g2;
  d.diag[3 * j] = c00, d.diag[3 * j + 1] = c11, d.diag[3 * j + 2] = c22;
}

// Four lanes (the point pass without AVX-512, the camera pass's sums).
typedef double L4 __attribute__((vector_size(32)));
typedef double L4u __attribute__((vector_size(32), aligned(8), may_alias));
typedef long long I4 __attribute__((vector_size(32)));
inline void store4(double* p, const L4& v) { *reinterpret_cast<L4u*>(p) = v; }
// out[a][k] = in[k][a] for 4×4 (rows a, b, c, d in, columns out): shuffles only, bits unchanged.
inline void transpose4(const L4& a, const L4& b, const L4& c, const L4& d, L4* out) {
  const L4 t0 = __builtin_shuffle(a, b, I4{0, 4, 2, 6}), t1 = __builtin_shuffle(a, b, I4{1, 5, 3, 7});
  const L4 t2 = __builtin_shuffle(c, d, I4{0, 4, 2, 6}), t3 = __builtin_shuffle(c, d, I4{1, 5, 3, 7});
  out[0] = __builtin_shuffle(t0, t2, I4{0, 1, 4, 5}), out[1] = __builtin_shuffle(t1, t3, I4{0, 1, 4, 5});
  out[2] = __builtin_shuffle(t0, t2, I4{2, 3, 6, 7}), out[3] = __builtin_shuffle(t1, t3, I4{2, 3, 6, 7});
}
static_assert(sizeof(BalCameraFrame) == 16 * sizeof(double) && std::is_standard_layout<BalCameraFrame>::value,
              "the point pass reads a frame as 16 doubles");
struct LaneFrame4 {
  L4 R[9], t[3], f, k1, k2;
};

// Points [j_begin, j_end): their observations in point order, then camera order, four at a
// time in lanes (whatever points they belong to): the fused kernel's r, E, F (F stays local: the
// camera pass recomputes it), the robust correction per lane, W_ij = F_ijᵀE_ij and the terms of
// C_j, g_j in lanes; then per observation in order: W_ij into the point's column of H,
// C_j += E_ijᵀE_ij, g_j += E_ijᵀr_ij, the cost. The lanes are moved in and out by 4×4 transposes
// (the cameras' frames in, W and the C_j terms out), which move bits and round nothing; every
// sum runs in the scalar code's order: the same bits as one observation at a time.
// Returns sum + Σ ρ(‖r‖²) in point order.
#pragma GCC diagnostic push  // GCC 12 warns of X, z "maybe uninitialized" in the avx2 clone: a false alarm
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
__attribute__((target_clones("avx2", "default"))) double linearize_points4(const PassData& d, int j_begin, int j_end,
                                                                            double sum) {
  // C_j (upper triangle c00 c01 c02 c11 c12 c22) and g_j of point j: (c00 c01 c02 c11), (c12 c22 g0 g1), g2.
  L4 acc0, acc1;
  double g2;
  int j = j_begin;
  auto reset = [&] { acc0 = L4{}, acc1 = L4{}, g2 = 0.0; };
  auto flush = [&] {
    store_point_blocks(d, j, acc0[0], acc0[1], acc0[2], acc0[3], acc1[0], acc1[1], acc1[2], acc1[3], g2);
    ++j;
    reset();
  };
  reset();
  const int q_end = d.pt_ptr[j_end], q_begin = d.pt_ptr[j_begin];
  const long groups = (q_end - q_begin + 3) / 4;
  for (int q = q_begin; q < q_end; q += 4) {
    prefetch_share(d, (q - q_begin) / 4, groups);
    const int n = std::min(4, q_end - q);
    const BalPointObservation* o[4];
    for (int k = 0; k < 4; ++k) o[k] = d.pt_obs + q + std::min(k, n - 1);
    // The four cameras' frames (16 doubles each: R, t, f, k1, k2, padding), transposed into lanes.
    L4 fr[16];
    for (int b = 0; b < 16; b += 4) {
      const double* f0 = reinterpret_cast<const double*>(d.frames + o[0]->camera);
      const double* f1 = reinterpret_cast<const double*>(d.frames + o[1]->camera);
      const double* f2 = reinterpret_cast<const double*>(d.frames + o[2]->camera);
      const double* f3 = reinterpret_cast<const double*>(d.frames + o[3]->camera);
      const L4 r0 = *reinterpret_cast<const L4u*>(f0 + b), r1 = *reinterpret_cast<const L4u*>(f1 + b);
      const L4 r2 = *reinterpret_cast<const L4u*>(f2 + b), r3 = *reinterpret_cast<const L4u*>(f3 + b);
      transpose4(r0, r1, r2, r3, fr + b);
    }
    LaneFrame4 c;
    for (int a = 0; a < 9; ++a) c.R[a] = fr[a];
    for (int a = 0; a < 3; ++a) c.t[a] = fr[9 + a];
    c.f = fr[12], c.k1 = fr[13], c.k2 = fr[14];
    const double *P0 = d.points[o[0]->point].data(), *P1 = d.points[o[1]->point].data();
    const double *P2 = d.points[o[2]->point].data(), *P3 = d.points[o[3]->point].data();
    const L4 X[3] = {{P0[0], P1[0], P2[0], P3[0]}, {P0[1], P1[1], P2[1], P3[1]}, {P0[2], P1[2], P2[2], P3[2]}};
    const L4 z[2] = {{o[0]->z[0], o[1]->z[0], o[2]->z[0], o[3]->z[0]}, {o[0]->z[1], o[1]->z[1], o[2]->z[1], o[3]->z[1]}};
    L4 r[2], E[6], F[18];
    bal_linearize(c, X, z, r, E, F);
    L4 cost = r[0] * r[0] + r[1] * r[1];
    if (d.kernel) robust_correct_lanes(*d.kernel, n, r, E, F, &cost);
    // W_ij = F_ijᵀE_ij (9×3) column by column, the scalar expression per lane; rows 0..7 of each
    // column transposed: WT[col][h][k] = rows 4h..4h+3 of column col for lane k.
    L4 W[27], WT[3][2][4];
    for (int col = 0; col < 3; ++col)
      for (int a = 0; a < 9; ++a) W[9 * col + a] = F[a] * E[col] + F[9 + a] * E[3 + col];
    for (int col = 0; col < 3; ++col)
      for (int h = 0; h < 2; ++h) {
        const L4* w = W + 9 * col + 4 * h;
        transpose4(w[0], w[1], w[2], w[3], WT[col][h]);
      }
    // The terms of C_j and g_j (E_ijᵀE_ij, E_ijᵀr_ij), in the accumulators' layout per lane.
    L4 T0[4], T1[4];
    transpose4(E[0] * E[0] + E[3] * E[3], E[0] * E[1] + E[3] * E[4], E[0] * E[2] + E[3] * E[5],
               E[1] * E[1] + E[4] * E[4], T0);
    transpose4(E[1] * E[2] + E[4] * E[5], E[2] * E[2] + E[5] * E[5], E[0] * r[0] + E[3] * r[1],
               E[1] * r[0] + E[4] * r[1], T1);
    const L4 t_g2 = E[2] * r[0] + E[5] * r[1];
    for (int k = 0; k < n; ++k) {
      while (q + k >= d.pt_ptr[j + 1]) flush();
      sum += cost[k];
      acc0 += T0[k], acc1 += T1[k], g2 += t_g2[k];
      // A repeated (camera, point) pair is adjacent in camera order and shares its W block.
      const bool accumulate = q + k > 0 && d.pt_obs[q + k - 1].w_off == o[k]->w_off;
      const int ld = d.hessian->leading_dim(j);
      double* __restrict w = d.H + o[k]->w_off;
      if (!accumulate) {
        for (int col = 0; col < 3; ++col, w += ld)
          store4(w, WT[col][0][k]), store4(w + 4, WT[col][1][k]), w[8] = W[9 * col + 8][k];
      } else {
        for (int col = 0; col < 3; ++col, w += ld)
          store4(w, L4(*reinterpret_cast<const L4u*>(w)) + WT[col][0][k]),
              store4(w + 4, L4(*reinterpret_cast<const L4u*>(w + 4)) + WT[col][1][k]), w[8] += W[9 * col + 8][k];
      }
    }
  }
  while (j < j_end) flush();  // the last point (and any without observations)
  return sum;
}
#pragma GCC diagnostic pop

// The same with eight observations at a time (AVX-512: L8 in zmm registers) and 8×8 transposes:
// the same per-observation expressions and sums in the same order, so the same bits as the
// four-lane pass (and the scalar code).
typedef double L8 __attribute__((vector_size(64)));
typedef double L8u __attribute__((vector_size(64), aligned(8), may_alias));
typedef long long I8 __attribute__((vector_size(64)));
struct LaneFrame8 {
  L8 R[9], t[3], f, k1, k2;
};
// out[a][k] = in[k][a] for 8×8 (in: 8 rows).
__attribute__((target("avx512f"), always_inline)) inline void transpose8(const L8* r, L8* out) {
  L8 t[8], u[8];
  for (int p = 0; p < 4; ++p) {
    t[2 * p] = __builtin_shuffle(r[2 * p], r[2 * p + 1], I8{0, 8, 2, 10, 4, 12, 6, 14});
    t[2 * p + 1] = __builtin_shuffle(r[2 * p], r[2 * p + 1], I8{1, 9, 3, 11, 5, 13, 7, 15});
  }
  for (int h = 0; h < 2; ++h) {  // rows 4h..4h+3: u[4h + c] holds columns c and c + 4 of them
    const L8 *a = t + 4 * h, *b = t + 4 * h + 2;
    u[4 * h] = __builtin_shuffle(a[0], b[0], I8{0, 1, 8, 9, 4, 5, 12, 13});
    u[4 * h + 1] = __builtin_shuffle(a[1], b[1], I8{0, 1, 8, 9, 4, 5, 12, 13});
    u[4 * h + 2] = __builtin_shuffle(a[0], b[0], I8{2, 3, 10, 11, 6, 7, 14, 15});
    u[4 * h + 3] = __builtin_shuffle(a[1], b[1], I8{2, 3, 10, 11, 6, 7, 14, 15});
  }
  for (int c = 0; c < 4; ++c) {
    out[c] = __builtin_shuffle(u[c], u[4 + c], I8{0, 1, 2, 3, 8, 9, 10, 11});
    out[c + 4] = __builtin_shuffle(u[c], u[4 + c], I8{4, 5, 6, 7, 12, 13, 14, 15});
  }
}

__attribute__((target("avx512f"))) double linearize_points8(const PassData& d, int j_begin, int j_end, double sum) {
  // (c00 c01 c02 c11 c12 c22 g0 g1) and g2 of point j.
  L8 acc;
  double g2;
  int j = j_begin;
  auto reset = [&] { acc = L8{}, g2 = 0.0; };
  auto flush = [&] {
    store_point_blocks(d, j, acc[0], acc[1], acc[2], acc[3], acc[4], acc[5], acc[6], acc[7], g2);
    ++j;
    reset();
  };
  reset();
  const int q_end = d.pt_ptr[j_end], q_begin = d.pt_ptr[j_begin];
  const long groups = (q_end - q_begin + 7) / 8;
  for (int q = q_begin; q < q_end; q += 8) {
    prefetch_share(d, (q - q_begin) / 8, groups);
    const int n = std::min(8, q_end - q);
    const BalPointObservation* o[8];
    for (int k = 0; k < 8; ++k) o[k] = d.pt_obs + q + std::min(k, n - 1);
    L8 fr[16], in[8];
    for (int b = 0; b < 16; b += 8) {
      for (int k = 0; k < 8; ++k) in[k] = *reinterpret_cast<const L8u*>(reinterpret_cast<const double*>(d.frames + o[k]->camera) + b);
      transpose8(in, fr + b);
    }
    LaneFrame8 c;
    for (int a = 0; a < 9; ++a) c.R[a] = fr[a];
    for (int a = 0; a < 3; ++a) c.t[a] = fr[9 + a];
    c.f = fr[12], c.k1 = fr[13], c.k2 = fr[14];
    L8 X[3], z[2];
    for (int k = 0; k < 8; ++k) {
      const double* P = d.points[o[k]->point].data();
      in[k] = L8{P[0], P[1], P[2], o[k]->z[0], o[k]->z[1], 0.0, 0.0, 0.0};
    }
    {
      L8 xz[8];
      transpose8(in, xz);
      X[0] = xz[0], X[1] = xz[1], X[2] = xz[2], z[0] = xz[3], z[1] = xz[4];
    }
    L8 r[2], E[6], F[18];
    bal_linearize(c, X, z, r, E, F);
    L8 cost = r[0] * r[0] + r[1] * r[1];
    if (d.kernel) robust_correct_lanes(*d.kernel, n, r, E, F, &cost);
    L8 W[27], WT[3][8];
    for (int col = 0; col < 3; ++col) {
      for (int a = 0; a < 9; ++a) W[9 * col + a] = F[a] * E[col] + F[9 + a] * E[3 + col];
      transpose8(W + 9 * col, WT[col]);
    }
    L8 T[8];
    {
      const L8 terms[8] = {E[0] * E[0] + E[3] * E[3], E[0] * E[1] + E[3] * E[4], E[0] * E[2] + E[3] * E[5],
                           E[1] * E[1] + E[4] * E[4], E[1] * E[2] + E[4] * E[5], E[2] * E[2] + E[5] * E[5],
                           E[0] * r[0] + E[3] * r[1],  E[1] * r[0] + E[4] * r[1]};
      transpose8(terms, T);
    }
    const L8 t_g2 = E[2] * r[0] + E[5] * r[1];
    for (int k = 0; k < n; ++k) {
      while (q + k >= d.pt_ptr[j + 1]) flush();
      sum += cost[k];
      acc += T[k], g2 += t_g2[k];
      // A repeated (camera, point) pair is adjacent in camera order and shares its W block.
      const bool accumulate = q + k > 0 && d.pt_obs[q + k - 1].w_off == o[k]->w_off;
      const int ld = d.hessian->leading_dim(j);
      double* __restrict w = d.H + o[k]->w_off;
      for (int col = 0; col < 3; ++col, w += ld) {
        L8u* w8 = reinterpret_cast<L8u*>(w);
        if (!accumulate) {
          *w8 = WT[col][k], w[8] = W[9 * col + 8][k];
        } else {
          *w8 = L8(*w8) + WT[col][k], w[8] += W[9 * col + 8][k];
        }
      }
    }
  }
  while (j < j_end) flush();
  return sum;
}

const bool kHaveAvx512 = [] {
  __builtin_cpu_init();  // a static initializer may run before the CPU model is known
  return __builtin_cpu_supports("avx512f") != 0;
}();
std::atomic<bool> allow_eight_lanes{true};  // bal_point_pass_allow_eight_lanes (tests)

// The point pass, eight lanes where the CPU has AVX-512, else four (the same bits either way).
double linearize_points(const PassData& d, int j_begin, int j_end, double sum) {
  return kHaveAvx512 && allow_eight_lanes.load(std::memory_order_relaxed) ? linearize_points8(d, j_begin, j_end, sum)
                                                                          : linearize_points4(d, j_begin, j_end, sum);
}

// Cameras [i_begin, i_end): B_i = Σ_j F_ijᵀF_ij and g_i = Σ_j F_ijᵀr_ij. F_ij, r_ij are recomputed
// here by the fused kernel (after the robust correction: the point pass's bits), eight
// observations at a time in lanes; nothing is stored per observation. The sums run on four
// lanes over the camera's groups of four (each group of eight adds its lanes 0..3, then 4..7),
// then over the lanes 0..3: the order depends only on the camera's observation count and is the
// one of a four-lane pass. Padded lanes (the last group) repeat its last observation and
// contribute zeros (a last half of only padding is not added).
__attribute__((target_clones("avx512f", "avx2", "default"))) void linearize_cameras(const PassData& d, int i_begin,
                                                                         int i_end) {
  for (int i = i_begin; i < i_end; ++i) {
    const BalCameraFrame& c = d.frames[i];
    L4 B[45], gi[9];  // B's lower triangle row by row: (a, b) at a(a+1)/2 + b; four lanes
    for (L4& v : B) v = L4{};
    for (L4& v : gi) v = L4{};
    const int q_end = d.cam_ptr[i + 1];
    for (int q = d.cam_ptr[i]; q < q_end; q += kLanes) {
      const int n = std::min(kLanes, q_end - q);
      Lanes X[3], z[2], r[2], E[6], F[18];
      for (int k = 0; k < kLanes; ++k) {
        const BalCameraObservation& o = d.cam_obs[q + std::min(k, n - 1)];
        const double* P = d.points[o.point].data();
        X[0][k] = P[0], X[1][k] = P[1], X[2][k] = P[2];
        z[0][k] = o.z[0], z[1][k] = o.z[1];
      }
      bal_linearize(c, X, z, r, E, F);
      if (d.kernel) {
        Lanes cost;
        robust_correct_lanes(*d.kernel, n, r, E, F, &cost);
      }
      for (int k = n; k < kLanes; ++k) {
        r[0][k] = r[1][k] = 0.0;
        for (Lanes& v : F) v[k] = 0.0;
      }
      // Products on eight lanes; summed as two groups of four (lanes 0..3, then 4..7 if any).
      const bool second = n > 4;
      for (int a = 0, t = 0; a < 9; ++a) {
        for (int b = 0; b <= a; ++b, ++t) {
          const Lanes v = F[a] * F[b] + F[9 + a] * F[9 + b];
          B[t] += __builtin_shufflevector(v, v, 0, 1, 2, 3);
          if (second) B[t] += __builtin_shufflevector(v, v, 4, 5, 6, 7);
        }
        const Lanes v = F[a] * r[0] + F[9 + a] * r[1];
        gi[a] += __builtin_shufflevector(v, v, 0, 1, 2, 3);
        if (second) gi[a] += __builtin_shufflevector(v, v, 4, 5, 6, 7);
      }
    }
    const int bi = d.np + i, ld = d.hessian->leading_dim(bi), s = d.hessian->block_start(bi);
    double* Bi = d.H + d.hessian->block_offset(bi, bi);
    for (int a = 0, t = 0; a < 9; ++a) {
      for (int b = 0; b <= a; ++b, ++t) {
        const double v = ((B[t][0] + B[t][1]) + B[t][2]) + B[t][3];
        Bi[static_cast<std::ptrdiff_t>(b) * ld + a] = v, Bi[static_cast<std::ptrdiff_t>(a) * ld + b] = v;
      }
      d.g[s + a] = ((gi[a][0] + gi[a][1]) + gi[a][2]) + gi[a][3];
      d.diag[s + a] = Bi[static_cast<std::ptrdiff_t>(a) * ld + a];
    }
  }
}

}  // namespace

BalState make_bal_state(const BalProblem& p) {
  BalState x;
  x.cameras.reserve(p.cameras.size());
  for (const auto& c : p.cameras) x.cameras.push_back(BalCamera::from_bal(c));
  x.points = p.points;
  return x;
}

void copy_bal_state(const BalState& x, BalProblem& p) {
  for (std::size_t i = 0; i < x.cameras.size(); ++i) p.cameras[i] = x.cameras[i].to_bal();
  p.points = x.points;
}

BalNormalEquations::BalNormalEquations(const BalProblem& p, std::shared_ptr<const RobustKernel> kernel,
                                       const ThreadPool& pool)
    : p_(p), kernel_(std::move(kernel)), pool_(pool), np_(p.num_points()), nc_(p.num_cameras()) {
  const int no = p.num_observations();
  if (np_ == 0 || nc_ == 0) throw std::invalid_argument("BalNormalEquations: no points or no cameras");
  // Observations grouped by point (camera order) and by camera (point order); stable sorts.
  pt_ptr_.assign(np_ + 1, 0), cam_ptr_.assign(nc_ + 1, 0);
  for (const BalObservation& o : p.observations) {
    if (o.camera < 0 || o.camera >= nc_ || o.point < 0 || o.point >= np_)
      throw std::invalid_argument("BalNormalEquations: observation of a missing camera or point");
    ++pt_ptr_[o.point + 1], ++cam_ptr_[o.camera + 1];
  }
  std::partial_sum(pt_ptr_.begin(), pt_ptr_.end(), pt_ptr_.begin());
  std::partial_sum(cam_ptr_.begin(), cam_ptr_.end(), cam_ptr_.begin());
  std::vector<int> cam_obs(no);
  {
    std::vector<int> fill(cam_ptr_.begin(), cam_ptr_.end() - 1);
    std::vector<int> by_point(no);
    std::iota(by_point.begin(), by_point.end(), 0);
    std::stable_sort(by_point.begin(), by_point.end(),
                     [&](int a, int b) { return p.observations[a].point < p.observations[b].point; });
    for (int k : by_point) cam_obs[fill[p.observations[k].camera]++] = k;  // camera, then point order
  }
  // H's pattern: point j is block j, camera i block np + i; one block per observed pair.
  std::vector<int> dims(static_cast<std::size_t>(np_) + nc_, 9);
  std::fill(dims.begin(), dims.begin() + np_, 3);
  std::vector<std::pair<int, int>> pattern;
  pattern.reserve(no);
  for (const BalObservation& o : p.observations) pattern.emplace_back(np_ + o.camera, o.point);
  hessian_ = BlockSparseMatrix(std::move(dims), std::move(pattern));
  // Observations in point order, then camera order (a repeated pair is adjacent).
  pt_obs_.resize(no);
  {
    std::vector<int> pfill(pt_ptr_.begin(), pt_ptr_.end() - 1);
    for (int k : cam_obs) {
      const BalObservation& o = p.observations[k];
      PointObs& po = pt_obs_[pfill[o.point]++];
      po.w_off = hessian_.block_offset(np_ + o.camera, o.point);
      po.camera = o.camera, po.point = o.point;
      po.z[0] = o.pixel.x(), po.z[1] = o.pixel.y();
    }
  }
  g_.setZero(hessian_.rows());
  diag_.setZero(hessian_.rows());
  cam_obs_.resize(no);
  for (int q = 0; q < no; ++q) {
    const BalObservation& o = p.observations[cam_obs[q]];
    cam_obs_[q].point = o.point, cam_obs_[q].z[0] = o.pixel.x(), cam_obs_[q].z[1] = o.pixel.y();
  }
  c_off_.resize(np_);
  for (int j = 0; j < np_; ++j) c_off_[j] = hessian_.block_offset(j, j);
  frames_.resize(nc_);
  chunk_cost_.assign((np_ + kChunk - 1) / kChunk, 0.0);
}

std::vector<char> BalNormalEquations::eliminate_flags() const {
  std::vector<char> e(static_cast<std::size_t>(np_) + nc_, 0);
  std::fill(e.begin(), e.begin() + np_, 1);
  return e;
}

void BalNormalEquations::camera_frames(const BalState& x) const {
  pool_.parallel_for(
      nc_, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) frames_[i] = BalCameraFrame::from(x.cameras[i]);
      },
      64);
}

// Per point j (chunks of kChunk points), its observations in camera order: their residuals and
// ρ; with Jacobians also C_j, g_j and W_ij (linearize_points). The frames must be formed.
template <bool kJacobians>
double BalNormalEquations::point_pass(const BalState& x, std::vector<double>* chunk_cost,
                                      const std::function<void(int, int)>* before_chunk) {
  const int nchunks = static_cast<int>(chunk_cost->size());
  double* H = hessian_.values().data();
  const RobustKernel* kernel = kernel_.get();
  pool_.parallel_for(
      nchunks,
      [&](std::size_t cb, std::size_t ce) {
        for (std::size_t c = cb; c < ce; ++c) {
          double sum = 0.0;
          const int j_begin = static_cast<int>(c) * kChunk;
          const int j_end = std::min<int>(np_, j_begin + kChunk);
          if (before_chunk && !kJacobians) (*before_chunk)(j_begin, j_end);
          if (kJacobians) {
            PassData d{x.points.data(), frames_.data(), pt_obs_.data(), pt_ptr_.data(), c_off_.data(), cam_obs_.data(),
                       cam_ptr_.data(), H, g_.data(), diag_.data(), &hessian_, kernel, np_};
            // With before_chunk, sub-chunks of kSub points: its reads of their H columns are
            // still in L2 when they are overwritten (the cost is summed in the same order). 64
            // rather than 16: fewer part-filled lane groups at sub-chunk ends (s27: fused pass
            // − plain linearization 0.8–1.1 → 0.6–0.8 ms on problem-49/21).
            const int sub = before_chunk ? kSub : kChunk;
            for (int jb = j_begin; jb < j_end; jb += sub) {
              const int je = std::min(j_end, jb + sub);
              if (before_chunk) (*before_chunk)(jb, je);
              // The next sub-chunk (maybe of the next chunk): its columns of H into L2 for its back-substitution.
              const int jn = std::min(np_, je + sub);
              if (before_chunk && je < jn) {
                d.pf_begin = reinterpret_cast<const char*>(H + c_off_[je]);
                d.pf_end = reinterpret_cast<const char*>(H + c_off_[jn - 1] + 3 * hessian_.leading_dim(jn - 1));
              } else {
                d.pf_begin = d.pf_end = nullptr;
              }
              sum = linearize_points(d, jb, je, sum);
            }
          } else {
            for (int j = j_begin; j < j_end; ++j) {
              const double* X = x.points[j].data();
              for (const PointObs* ob = pt_obs_.data() + pt_ptr_[j]; ob != pt_obs_.data() + pt_ptr_[j + 1]; ++ob) {
                double r[2];
                bal_residual(frames_[ob->camera], X, ob->z, r);
                const double s2 = r[0] * r[0] + r[1] * r[1];
                if (kernel) {
                  double rho[3];
                  kernel->evaluate(s2, rho);
                  sum += rho[0];
                } else {
                  sum += s2;
                }
              }
            }
          }
          (*chunk_cost)[c] = sum;
        }
      },
      1);
  double total = 0.0;
  for (double s : *chunk_cost) total += s;
  return total;
}

double BalNormalEquations::cost(const BalState& x) const {
  // point_pass<false> writes nothing but frames_ and the chunk sums (both mutable scratch).
  camera_frames(x);
  return const_cast<BalNormalEquations*>(this)->point_pass<false>(x, &chunk_cost_);
}

double BalNormalEquations::linearize(const BalState& x) {
  damped_ = false;
  camera_frames(x);
  // Points: C_j, g_j, W_ij and the cost; then cameras: B_i, g_i (F_ij recomputed in lanes).
  const double total = point_pass<true>(x, &chunk_cost_);
  linearize_camera_blocks(x);
  return total;
}

double BalNormalEquations::retract_and_linearize(const BalState& x, double* step, BalState& out,
                                                 const std::function<void(int, int, double*)>& back_substitute) {
  damped_ = false;
  out.cameras.resize(nc_), out.points.resize(np_);
  retract_cameras(x, step, out);
  camera_frames(out);
  // Per chunk: δ_j by back-substitution (reads W_·j, C_j⁻¹), X_j ⊞ δ_j, then W_·j, C_j, g_j at out.
  const std::function<void(int, int)> before = [&](int j_begin, int j_end) {
    back_substitute(j_begin, j_end, step);
    for (int j = j_begin; j < j_end; ++j) out.points[j] = x.points[j] + Eigen::Map<const Eigen::Vector3d>(step + 3 * j);
  };
  const double total = point_pass<true>(out, &chunk_cost_, &before);
  linearize_camera_blocks(out);
  return total;
}

void BalNormalEquations::linearize_camera_blocks(const BalState& x) {
  const PassData d{x.points.data(), frames_.data(), pt_obs_.data(), pt_ptr_.data(), c_off_.data(), cam_obs_.data(), cam_ptr_.data(),
                   hessian_.values().data(), g_.data(), diag_.data(), &hessian_, kernel_.get(), np_};
  pool_.parallel_for(
      nc_, [&](std::size_t b, std::size_t e) { linearize_cameras(d, static_cast<int>(b), static_cast<int>(e)); }, 1);
}

int BalNormalEquations::first_nonfinite_observation(const BalState& x) const {
  for (int k = 0; k < p_.num_observations(); ++k) {
    const BalObservation& o = p_.observations[k];
    const BalCamera& c = x.cameras[o.camera];
    if (!bal_reprojection(c.rotation.matrix(), c, x.points[o.point], o.pixel, nullptr, nullptr).allFinite()) return k;
  }
  return -1;
}

void BalNormalEquations::set_diagonal_damping(const Eigen::VectorXd& damping) {
  const auto& pos = hessian_.diagonal_positions();
  auto& v = hessian_.values();
  for (int a = 0; a < dim(); ++a) v[pos[a]] = diag_[a] + damping[a];
  damping_ = damping;
  damped_ = true, damped_from_ = 0;
}

void BalNormalEquations::set_diagonal_damping(double lambda, const Eigen::VectorXd& D, bool points_in_h) {
  const auto& pos = hessian_.diagonal_positions();
  auto& v = hessian_.values();
  damping_.resize(dim());
  damped_from_ = points_in_h ? 0 : 3 * np_;
  for (int a = 0; a < damped_from_; ++a) damping_[a] = lambda * D[a];
  for (int a = damped_from_; a < dim(); ++a) {
    damping_[a] = lambda * D[a];
    v[pos[a]] = diag_[a] + damping_[a];
  }
  damped_ = true;
}

void BalNormalEquations::clear_damping() {
  if (!damped_) return;
  const auto& pos = hessian_.diagonal_positions();
  auto& v = hessian_.values();
  for (int a = damped_from_; a < dim(); ++a) v[pos[a]] = diag_[a];
  damped_ = false;
}

double BalNormalEquations::quadratic(const Eigen::VectorXd& d) const {
  // δᵀHδ = Σ_j (δ_jᵀ C_j δ_j + 2 Σ_i δ_iᵀ W_ij δ_j) + Σ_i δ_iᵀ B_i δ_i, from the stored blocks
  // (their diagonals may carry damping: subtracted at the end).
  const double* H = hessian_.values().data();
  const int nchunks = static_cast<int>(chunk_cost_.size());
  std::vector<double> part(nchunks, 0.0);
  pool_.parallel_for(
      nchunks,
      [&](std::size_t cb, std::size_t ce) {
        for (std::size_t c = cb; c < ce; ++c) {
          double sum = 0.0;
          const int j_end = std::min<int>(np_, static_cast<int>(c + 1) * kChunk);
          for (int j = static_cast<int>(c) * kChunk; j < j_end; ++j) {
            const int ld = hessian_.leading_dim(j);
            const Eigen::Vector3d dj = d.segment<3>(3 * j);
            sum += dj.dot(CMapS<3, 3>(H + hessian_.block_offset(j, j), 3, 3, Eigen::OuterStride<>(ld)) * dj);
            int previous_camera = -1;
            for (int q = pt_ptr_[j]; q < pt_ptr_[j + 1]; ++q) {
              const PointObs& o = pt_obs_[q];
              if (o.camera == previous_camera) continue;  // a repeated pair shares its W block
              previous_camera = o.camera;
              const int s = hessian_.block_start(np_ + o.camera);
              sum += 2.0 * d.segment<9>(s).dot(CMapS<9, 3>(H + o.w_off, 9, 3, Eigen::OuterStride<>(ld)) * dj);
            }
          }
          part[c] = sum;
        }
      },
      1);
  double q = 0.0;
  for (double s : part) q += s;
  for (int i = 0; i < nc_; ++i) {
    const int bi = np_ + i, s = hessian_.block_start(bi);
    const Eigen::Matrix<double, 9, 1> di = d.segment<9>(s);
    q += di.dot(CMapS<9, 9>(H + hessian_.block_offset(bi, bi), 9, 9, Eigen::OuterStride<>(hessian_.leading_dim(bi))) * di);
  }
  if (damped_ && damped_from_ == 0) q -= (damping_.array() * d.array().square()).sum();
  if (damped_ && damped_from_ > 0) {
    const int n = dim() - damped_from_;
    q -= (damping_.tail(n).array() * d.tail(n).array().square()).sum();
  }
  return q;
}

void BalNormalEquations::retract(const BalState& x, const double* step, BalState& out) const {
  out.cameras.resize(nc_), out.points.resize(np_);
  pool_.parallel_for(np_, [&](std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) out.points[j] = x.points[j] + Eigen::Map<const Eigen::Vector3d>(step + 3 * j);
  });
  retract_cameras(x, step, out);
}

void BalNormalEquations::retract_cameras(const BalState& x, const double* step, BalState& out) const {
  const double* sc = step + 3 * static_cast<std::ptrdiff_t>(np_);
  pool_.parallel_for(
      nc_, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i)
          out.cameras[i] = x.cameras[i].plus(Eigen::Map<const BalCamera::Tangent>(sc + 9 * i));
      },
      16);
}

double BalNormalEquations::parameter_norm(const BalState& x) {
  double s = 0.0;
  for (const BalCamera& c : x.cameras)
    s += c.rotation.quaternion().coeffs().squaredNorm() + c.translation.squaredNorm() + c.f * c.f + c.k1 * c.k1 +
         c.k2 * c.k2;
  for (const auto& X : x.points) s += X.squaredNorm();
  return std::sqrt(s);
}

void bal_point_pass_allow_eight_lanes(bool allow) { allow_eight_lanes.store(allow); }

}  // namespace slamkit
