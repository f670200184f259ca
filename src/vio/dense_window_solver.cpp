#include "slamkit/vio/dense_window_solver.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/factors/marginalization_prior.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {
namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix26 = Eigen::Matrix<double, 2, 6>;
constexpr int kS = 15;  // state block size
// Internal column c of a state block holds tangent component kToTangent[c]: [δφ, δp, δv, δb_g, δb_a].
constexpr std::array<int, kS> kToTangent = {0, 1, 2, 6, 7, 8, 3, 4, 5, 9, 10, 11, 12, 13, 14};
constexpr double kOutOfView = 1e3;  // residual of a point the camera cannot project (InverseDepthFactor's)

double clamp_diag(double d) { return std::min(std::max(d, 1e-6), 1e32); }

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Internal-order step of one state → tangent order.
ImuState::Tangent to_tangent(const Eigen::VectorXd& d, int state) {
  ImuState::Tangent t;
  for (int c = 0; c < kS; ++c) t(kToTangent[c]) = d(kS * state + c);
  return t;
}

// Per-state quantities the reprojections reuse.
struct StateFrame {
  Eigen::Matrix3d R, RT;
  Eigen::Vector3d p;
};

}  // namespace

struct DenseWindowSolver::Linearization {
  Eigen::MatrixXd H;  // internal order, upper blocks valid (diagonal blocks full)
  Eigen::VectorXd g;
  std::vector<double> hff, gf;  // per feature
  // Feature f's states are frames[offset[f] .. offset[f] + count[f]) (slots for 1 + its
  // observations are reserved, so each feature writes its own range in any block order).
  std::vector<int> offset, count;
  std::vector<int> frames;
  std::vector<Vector6d> w;      // w_i = Σ J_iᵀ J_ρ per (feature, state)
  std::vector<char> touched;    // per state: some factor of the system acts on it
  std::vector<int> block_begin; // feature blocks [block_begin[b], block_begin[b + 1])
};

namespace {

// Fixed partition of the features into kBlocks blocks of about equal observation count. Each
// block accumulates into its own buffers, summed in block order afterwards, so the result is
// the same for any number of threads (the partition never depends on it).
constexpr int kBlocks = 4;

std::vector<int> feature_blocks(const std::vector<WindowFeature>& features) {
  std::size_t total = 0;
  for (const WindowFeature& f : features) total += 1 + f.obs.size();
  std::vector<int> begin(kBlocks + 1, static_cast<int>(features.size()));
  begin[0] = 0;
  std::size_t acc = 0;
  int b = 1;
  for (std::size_t f = 0; f < features.size() && b < kBlocks; ++f) {
    acc += 1 + features[f].obs.size();
    while (b < kBlocks && acc * kBlocks >= total * b) begin[b++] = static_cast<int>(f + 1);
  }
  return begin;
}

// Runs fn(b) for every block b on the pool (or serially without one).
void for_blocks(const ThreadPool* pool, const std::function<void(int)>& fn) {
  if (!pool || pool->threads() <= 1) {
    for (int b = 0; b < kBlocks; ++b) fn(b);
    return;
  }
  pool->parallel_for(kBlocks, [&](std::size_t b0, std::size_t b1) {
    for (std::size_t b = b0; b < b1; ++b) fn(static_cast<int>(b));
  }, 1);
}

}  // namespace

DenseWindowSolver::DenseWindowSolver(std::shared_ptr<const CameraModel> camera, const SE3& T_imu_cam, double pixel_sigma,
                                     std::shared_ptr<const RobustKernel> kernel, const ThreadPool* pool)
    : camera_(std::move(camera)),
      T_imu_cam_(T_imu_cam),
      inv_sigma_(1.0 / pixel_sigma),
      kernel_(std::move(kernel)),
      pool_(pool) {
  if (!camera_) throw std::invalid_argument("DenseWindowSolver: no camera model");
  if (!(pixel_sigma > 0.0)) throw std::invalid_argument("DenseWindowSolver: pixel_sigma must be positive");
}

namespace {

void check_indices(int n, const std::vector<WindowFeature>& features, const std::vector<WindowStateFactor>& factors) {
  for (const WindowStateFactor& f : factors) {
    if (!f.factor || f.states.size() != f.factor->keys().size())
      throw std::invalid_argument("DenseWindowSolver: a state factor without its window indices");
    for (int s : f.states)
      if (s < 0 || s >= n) throw std::invalid_argument("DenseWindowSolver: state index out of range");
  }
  for (const WindowFeature& f : features) {
    if (f.anchor < 0 || f.anchor >= n) throw std::invalid_argument("DenseWindowSolver: anchor index out of range");
    for (const WindowObservation& o : f.obs)
      if (o.state < 0 || o.state >= n || o.state == f.anchor)
        throw std::invalid_argument("DenseWindowSolver: observation state out of range or equal to the anchor");
  }
}

std::vector<StateFrame> state_frames(const std::vector<ImuState>& states) {
  std::vector<StateFrame> out(states.size());
  for (std::size_t i = 0; i < states.size(); ++i) {
    out[i].R = states[i].R.matrix();
    out[i].RT = out[i].R.transpose();
    out[i].p = states[i].p;
  }
  return out;
}

// Robust weighting of a whitened 2-residual (Triggs' correction as Factor::linearize): returns
// ρ(s) and sets the 2×2 map M with r̂ = M_r r̃ (scalar) and Ĵ = M J̃.
double robust_2d(const RobustKernel* kernel, const Eigen::Vector2d& r, double* r_scale, Eigen::Matrix2d* M) {
  const double s = r.squaredNorm();
  if (!kernel) {
    *r_scale = 1.0, M->setIdentity();
    return s;
  }
  double rho[3];
  kernel->evaluate(s, rho);
  if (!(rho[1] > 0.0) || s == 0.0) {
    const double scale = rho[1] > 0.0 ? std::sqrt(rho[1]) : 0.0;
    *r_scale = scale, *M = scale * Eigen::Matrix2d::Identity();
    return rho[0];
  }
  const double sq = std::sqrt(rho[1]);
  const double alpha = rho[2] > 0.0 ? 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]) : 0.0;
  *M = sq * (Eigen::Matrix2d::Identity() - (alpha / s) * r * r.transpose());
  *r_scale = sq / (1.0 - alpha);
  return rho[0];
}

}  // namespace

double DenseWindowSolver::feature_cost(const std::vector<ImuState>& states, const WindowFeature& f,
                                       double inv_depth) const {
  const ImuState& a = states[f.anchor];
  const Eigen::Vector3d P_w = a.R.act(T_imu_cam_.act(f.bearing / inv_depth)) + a.p;
  const SE3 T_cam_imu = T_imu_cam_.inverse();
  double c = 0.0;
  for (const WindowObservation& o : f.obs) {
    if (!(o.weight > 0.0)) continue;
    const ImuState& k = states[o.state];
    const Eigen::Vector3d P_k = T_cam_imu.act(k.R.inverse().act(P_w - k.p));
    Eigen::Vector2d uv;
    Eigen::Vector2d r = camera_->project(P_k, &uv) ? Eigen::Vector2d((uv - o.pixel) * inv_sigma_)
                                                   : Eigen::Vector2d(kOutOfView * inv_sigma_, kOutOfView * inv_sigma_);
    const double s = r.squaredNorm();
    double rho[3] = {s, 1.0, 0.0};
    if (kernel_) kernel_->evaluate(s, rho);
    c += o.weight * rho[0];
  }
  return c;
}

double DenseWindowSolver::cost(const std::vector<ImuState>& states, const std::vector<WindowFeature>& features,
                               const std::vector<WindowStateFactor>& factors) const {
  check_indices(static_cast<int>(states.size()), features, factors);
  std::vector<std::array<double, 16>> params(states.size());
  for (std::size_t i = 0; i < states.size(); ++i) ManifoldTraits<ImuState>::to_params(states[i], params[i].data());
  double c = 0.0;
  std::vector<double> work;
  std::vector<const double*> ptrs;
  for (const WindowStateFactor& sf : factors) {
    work.resize(sf.factor->residual_dim());
    ptrs.clear();
    for (int s : sf.states) ptrs.push_back(params[s].data());
    c += sf.factor->cost(ptrs.data(), work.data());
  }
  for (const WindowFeature& f : features) c += feature_cost(states, f, f.inv_depth);
  return c;
}

double DenseWindowSolver::linearize(const std::vector<ImuState>& states, const std::vector<WindowFeature>& features,
                                    const std::vector<WindowStateFactor>& factors, bool only_first,
                                    Linearization& lin) const {
  const int n = static_cast<int>(states.size());
  lin.H.setZero(kS * n, kS * n);
  lin.g.setZero(kS * n);
  lin.touched.assign(n, 0);
  lin.hff.assign(features.size(), 0.0);
  lin.gf.assign(features.size(), 0.0);
  double cost = 0.0;

  // State factors (prior, IMU) through the generic Factor::linearize, columns permuted.
  std::vector<std::array<double, 16>> params(n);
  for (int i = 0; i < n; ++i) ManifoldTraits<ImuState>::to_params(states[i], params[i].data());
  std::vector<const double*> ptrs;
  std::vector<Eigen::MatrixXd> J, Jint;
  std::vector<double*> jptrs;
  Eigen::VectorXd r;
  for (const WindowStateFactor& sf : factors) {
    if (only_first && std::find(sf.states.begin(), sf.states.end(), 0) == sf.states.end()) continue;
    const int m = sf.factor->residual_dim();
    const std::size_t k = sf.states.size();
    r.resize(m);
    ptrs.clear();
    for (std::size_t v = 0; v < k; ++v) ptrs.push_back(params[sf.states[v]].data());
    if (dynamic_cast<const MarginalizationPrior<ImuState>*>(sf.factor.get())) {
      // Constant Jacobian: JᵀJ from the cache, only the residual is evaluated.
      if (prior_cache_.factor != sf.factor) {
        J.assign(k, Eigen::MatrixXd(m, kS));
        jptrs.clear();
        for (std::size_t v = 0; v < k; ++v) jptrs.push_back(J[v].data());
        if (!std::isfinite(sf.factor->linearize(ptrs.data(), r.data(), jptrs.data())))
          throw NumericalError("dense window: the prior does not evaluate to a finite number");
        prior_cache_.J.resize(m, kS * k);
        for (std::size_t v = 0; v < k; ++v)
          for (int col = 0; col < kS; ++col) prior_cache_.J.col(kS * v + col) = J[v].col(kToTangent[col]);
        prior_cache_.H.noalias() = prior_cache_.J.transpose() * prior_cache_.J;
        prior_cache_.factor = sf.factor;
      }
      const double c = sf.factor->linearize(ptrs.data(), r.data(), nullptr);
      if (!std::isfinite(c)) throw NumericalError("dense window: the prior does not evaluate to a finite number");
      cost += c;
      const Eigen::VectorXd gp = prior_cache_.J.transpose() * r;
      for (std::size_t a = 0; a < k; ++a) {
        const int sa = sf.states[a];
        lin.touched[sa] = 1;
        lin.g.segment<kS>(kS * sa) += gp.segment<kS>(kS * a);
        for (std::size_t b = 0; b < k; ++b) {
          const int sb = sf.states[b];
          if (sa <= sb) lin.H.block<kS, kS>(kS * sa, kS * sb) += prior_cache_.H.block<kS, kS>(kS * a, kS * b);
        }
      }
      continue;
    }
    J.assign(k, Eigen::MatrixXd(m, kS));
    Jint.assign(k, Eigen::MatrixXd(m, kS));
    jptrs.clear();
    for (std::size_t v = 0; v < k; ++v) jptrs.push_back(J[v].data());
    const double c = sf.factor->linearize(ptrs.data(), r.data(), jptrs.data());
    if (!std::isfinite(c)) throw NumericalError("dense window: a prior or IMU factor does not evaluate to a finite number");
    cost += c;
    for (std::size_t v = 0; v < k; ++v)
      for (int col = 0; col < kS; ++col) Jint[v].col(col) = J[v].col(kToTangent[col]);
    for (std::size_t a = 0; a < k; ++a) {
      const int sa = sf.states[a];
      lin.touched[sa] = 1;
      lin.g.segment<kS>(kS * sa).noalias() += Jint[a].transpose() * r;
      for (std::size_t b = 0; b < k; ++b) {
        const int sb = sf.states[b];
        if (sa <= sb) lin.H.block<kS, kS>(kS * sa, kS * sb).noalias() += Jint[a].transpose() * Jint[b];
      }
    }
  }

  // Reprojections: fixed-size 2×6 pose blocks and the 2×1 inverse-depth column, per feature
  // block into that block's pose-only buffers (6n × 6n, upper blocks), then summed in order.
  const std::vector<StateFrame> sfr = state_frames(states);
  const Eigen::Matrix3d R_bc = T_imu_cam_.rotation().matrix(), R_cb = R_bc.transpose();
  const Eigen::Vector3d t_bc = T_imu_cam_.translation();
  lin.offset.assign(features.size() + 1, 0);
  lin.count.assign(features.size(), 0);
  for (std::size_t fi = 0; fi < features.size(); ++fi)
    lin.offset[fi + 1] = lin.offset[fi] + (only_first && features[fi].anchor != 0 ? 0 : 1 + static_cast<int>(features[fi].obs.size()));
  lin.frames.assign(lin.offset.back(), 0);
  lin.w.resize(lin.offset.back());
  lin.block_begin = feature_blocks(features);
  std::array<Eigen::MatrixXd, kBlocks> Hp;
  std::array<Eigen::VectorXd, kBlocks> gp;
  std::array<double, kBlocks> cost_p{};
  std::vector<std::vector<char>> touched_p(kBlocks, std::vector<char>(n, 0));
  for_blocks(pool_, [&](int blk) {
    Eigen::MatrixXd& Hb = Hp[blk];
    Eigen::VectorXd& gb = gp[blk];
    Hb.setZero(6 * n, 6 * n);
    gb.setZero(6 * n);
    std::vector<char>& touched = touched_p[blk];
    double cost_b = 0.0;
    for (int fi = lin.block_begin[blk]; fi < lin.block_begin[blk + 1]; ++fi) {
      const WindowFeature& f = features[fi];
      if (only_first && f.anchor != 0) continue;
      const StateFrame& A = sfr[f.anchor];
      const double rho = f.inv_depth;
      const Eigen::Vector3d P_ba = R_bc * (f.bearing / rho) + t_bc;
      const Eigen::Vector3d P_w = A.R * P_ba + A.p;
      const Eigen::Matrix3d Ra_skew = A.R * skew(P_ba);
      const Eigen::Vector3d dPw_drho = A.R * (R_bc * (-f.bearing / (rho * rho)));
      int* local = &lin.frames[lin.offset[fi]];
      Vector6d* wl = &lin.w[lin.offset[fi]];
      int nl = 1;
      local[0] = f.anchor, wl[0].setZero();
      double hff = 0.0, gf = 0.0;
      for (const WindowObservation& o : f.obs) {
        if (!(o.weight > 0.0)) continue;
        const StateFrame& K = sfr[o.state];
        const Eigen::Vector3d P_bk = K.RT * (P_w - K.p);
        const Eigen::Vector3d P_k = R_cb * (P_bk - t_bc);
        Eigen::Vector2d uv;
        Eigen::Matrix<double, 2, 3> J_pi;
        const double sw = std::sqrt(o.weight);
        double rs;
        Eigen::Matrix2d M;
        if (!camera_->project(P_k, &uv, &J_pi)) {
          // Out of view: constant residual, no force (its cost is capped by the kernel).
          const Eigen::Vector2d rr(kOutOfView * inv_sigma_, kOutOfView * inv_sigma_);
          cost_b += o.weight * robust_2d(kernel_.get(), rr, &rs, &M);
          continue;
        }
        const Eigen::Vector2d rt = (uv - o.pixel) * inv_sigma_;
        cost_b += o.weight * robust_2d(kernel_.get(), rt, &rs, &M);
        const Eigen::Matrix2d Mw = (sw * inv_sigma_) * M;  // whitening, kernel, weight on the raw Jacobians
        const Eigen::Vector2d rh = (sw * rs) * rt;
        const Eigen::Matrix<double, 2, 3> J_Pbk = Mw * J_pi * R_cb;
        const Eigen::Matrix<double, 2, 3> J_Pw = J_Pbk * K.RT;
        Matrix26 Ja, Jk;
        Ja.leftCols<3>() = -J_Pw * Ra_skew;
        Ja.rightCols<3>() = J_Pw;
        Jk.leftCols<3>() = J_Pbk * skew(P_bk);
        Jk.rightCols<3>() = -J_Pbk * K.RT;
        const Eigen::Vector2d Jr = J_Pw * dPw_drho;
        const int a = f.anchor, k = o.state;
        Hb.block<6, 6>(6 * a, 6 * a).noalias() += Ja.transpose() * Ja;
        Hb.block<6, 6>(6 * k, 6 * k).noalias() += Jk.transpose() * Jk;
        if (a < k) Hb.block<6, 6>(6 * a, 6 * k).noalias() += Ja.transpose() * Jk;
        else Hb.block<6, 6>(6 * k, 6 * a).noalias() += Jk.transpose() * Ja;
        gb.segment<6>(6 * a).noalias() += Ja.transpose() * rh;
        gb.segment<6>(6 * k).noalias() += Jk.transpose() * rh;
        int ik = 1;
        while (ik < nl && local[ik] != k) ++ik;
        if (ik == nl) local[nl] = k, wl[nl].setZero(), ++nl;
        wl[0].noalias() += Ja.transpose() * Jr;
        wl[ik].noalias() += Jk.transpose() * Jr;
        hff += Jr.squaredNorm();
        gf += Jr.dot(rh);
        touched[a] = touched[k] = 1;
      }
      if (!std::isfinite(cost_b)) throw NumericalError("dense window: a reprojection does not evaluate to a finite number");
      lin.hff[fi] = hff, lin.gf[fi] = gf;
      lin.count[fi] = hff > 0.0 ? nl : 0;
    }
    cost_p[blk] = cost_b;
  });
  for (int blk = 0; blk < kBlocks; ++blk) {
    cost += cost_p[blk];
    for (int i = 0; i < n; ++i) {
      lin.touched[i] |= touched_p[blk][i];
      lin.g.segment<6>(kS * i) += gp[blk].segment<6>(6 * i);
      for (int j = i; j < n; ++j) lin.H.block<6, 6>(kS * i, kS * j) += Hp[blk].block<6, 6>(6 * i, 6 * j);
    }
  }
  return cost;
}

void DenseWindowSolver::reduce(const Linearization& lin, double lambda, Eigen::MatrixXd& S, Eigen::VectorXd& s) const {
  const int n = static_cast<int>(lin.touched.size());
  S = lin.H;
  s = lin.g;
  if (lambda > 0.0)
    for (Eigen::Index i = 0; i < S.rows(); ++i) S(i, i) += lambda * clamp_diag(lin.H(i, i));
  // Σ_f w wᵀ / h_f and Σ_f w g_f / h_f per feature block (pose-only buffers), subtracted in block order.
  std::array<Eigen::MatrixXd, kBlocks> Pp;
  std::array<Eigen::VectorXd, kBlocks> pp;
  for_blocks(pool_, [&](int blk) {
    Eigen::MatrixXd& P = Pp[blk];
    Eigen::VectorXd& q = pp[blk];
    P.setZero(6 * n, 6 * n);
    q.setZero(6 * n);
    for (int f = lin.block_begin[blk]; f < lin.block_begin[blk + 1]; ++f) {
      const int b0 = lin.offset[f], b1 = b0 + lin.count[f];
      if (b0 == b1) continue;
      const double h = lin.hff[f] + (lambda > 0.0 ? lambda * clamp_diag(lin.hff[f]) : 0.0);
      const double inv = 1.0 / h;
      for (int a = b0; a < b1; ++a) {
        const int fa = lin.frames[a];
        const Vector6d wa = inv * lin.w[a];
        q.segment<6>(6 * fa).noalias() += wa * lin.gf[f];
        for (int b = b0; b < b1; ++b) {
          const int fb = lin.frames[b];
          if (fa <= fb) P.block<6, 6>(6 * fa, 6 * fb).noalias() += wa * lin.w[b].transpose();
        }
      }
    }
  });
  for (int blk = 0; blk < kBlocks; ++blk)
    for (int i = 0; i < n; ++i) {
      s.segment<6>(kS * i) -= pp[blk].segment<6>(6 * i);
      for (int j = i; j < n; ++j) S.block<6, 6>(kS * i, kS * j) -= Pp[blk].block<6, 6>(6 * i, 6 * j);
    }
  // Blocks were accumulated in the upper triangle (block row ≤ block column): mirror them.
  for (Eigen::Index j = 0; j < S.cols(); ++j)
    for (Eigen::Index i = j + 1; i < S.rows(); ++i) S(i, j) = S(j, i);
}

DenseWindowSummary DenseWindowSolver::optimize(std::vector<ImuState>& states, std::vector<WindowFeature>& features,
                                               const std::vector<WindowStateFactor>& factors,
                                               const DenseWindowOptions& options) const {
  const int n = static_cast<int>(states.size());
  check_indices(n, features, factors);
  DenseWindowSummary sum;
  Linearization lin;
  auto t0 = std::chrono::steady_clock::now();
  double cost = linearize(states, features, factors, false, lin);
  sum.linearize_ms += ms_since(t0);
  sum.initial_cost = sum.final_cost = cost;
  double lambda = options.initial_lambda, nu = 2.0;
  Eigen::MatrixXd S;
  Eigen::VectorXd s, dx;
  std::vector<double> drho(features.size());
  std::vector<ImuState> cand_states(states.size());
  std::vector<WindowFeature> cand;  // inverse depths of the candidate (observations shared by copy)
  for (int iter = 0; iter < options.max_iterations; ++iter) {
    ++sum.iterations;
    t0 = std::chrono::steady_clock::now();
    reduce(lin, lambda, S, s);
    const Eigen::LLT<Eigen::MatrixXd> llt(S);
    if (llt.info() != Eigen::Success) {
      sum.solve_ms += ms_since(t0);
      lambda *= nu, nu *= 2.0;  // not positive definite: damp more
      if (lambda > options.max_lambda) break;
      continue;
    }
    dx = llt.solve(-s);
    sum.solve_ms += ms_since(t0);
    // Back-substitution and the model's predicted decrease −gᵀδ + λ δᵀDδ (δ solves the damped system).
    double predicted = -lin.g.dot(dx);
    for (Eigen::Index i = 0; i < dx.size(); ++i) predicted += lambda * clamp_diag(lin.H(i, i)) * dx(i) * dx(i);
    // Per feature block: δρ_f, its share of the predicted decrease and the candidate's cost.
    for (int i = 0; i < n; ++i) cand_states[i] = states[i].plus(to_tangent(dx, i));
    std::array<double, kBlocks> predicted_p{}, cost_p{};
    for_blocks(pool_, [&](int blk) {
      double pr = 0.0, c = 0.0;
      for (int f = lin.block_begin[blk]; f < lin.block_begin[blk + 1]; ++f) {
        drho[f] = 0.0;
        const int b0 = lin.offset[f], b1 = b0 + lin.count[f];
        if (b0 != b1) {
          const double d = lambda * clamp_diag(lin.hff[f]);
          double rhs = lin.gf[f];
          for (int b = b0; b < b1; ++b) rhs += lin.w[b].dot(dx.segment<6>(kS * lin.frames[b]));
          drho[f] = -rhs / (lin.hff[f] + d);
          pr += -lin.gf[f] * drho[f] + d * drho[f] * drho[f];
        }
        c += feature_cost(cand_states, features[f], features[f].inv_depth + drho[f]);
      }
      predicted_p[blk] = pr, cost_p[blk] = c;
    });
    double new_cost = 0.0;
    {
      std::vector<std::array<double, 16>> params(n);
      for (int i = 0; i < n; ++i) ManifoldTraits<ImuState>::to_params(cand_states[i], params[i].data());
      std::vector<double> work;
      std::vector<const double*> ptrs;
      for (const WindowStateFactor& sf : factors) {
        work.resize(sf.factor->residual_dim());
        ptrs.clear();
        for (int st : sf.states) ptrs.push_back(params[st].data());
        new_cost += sf.factor->cost(ptrs.data(), work.data());
      }
    }
    for (int blk = 0; blk < kBlocks; ++blk) predicted += predicted_p[blk], new_cost += cost_p[blk];
    const double actual = cost - new_cost;
    double rho = predicted > 0.0 ? actual / predicted : (actual > 0.0 ? 1.0 : -1.0);
    if (!std::isfinite(new_cost)) rho = -std::numeric_limits<double>::infinity();
    if (rho > 0.0) {
      const double t = 2.0 * rho - 1.0;
      lambda *= std::max(1.0 / 3.0, 1.0 - t * t * t);
      nu = 2.0;
      states.swap(cand_states);
      for (std::size_t f = 0; f < features.size(); ++f) features[f].inv_depth += drho[f];
      const double previous = cost;
      cost = new_cost;
      if (std::abs(actual) <= options.function_tolerance * previous || iter + 1 == options.max_iterations) break;
      t0 = std::chrono::steady_clock::now();
      cost = linearize(states, features, factors, false, lin);
      sum.linearize_ms += ms_since(t0);
    } else {
      lambda *= nu, nu *= 2.0;
      if (lambda > options.max_lambda) break;
    }
  }
  sum.final_cost = cost;
  return sum;
}

DenseMarginal DenseWindowSolver::marginalize_first(const std::vector<ImuState>& states,
                                                   const std::vector<WindowFeature>& features,
                                                   const std::vector<WindowStateFactor>& factors) const {
  const int n = static_cast<int>(states.size());
  check_indices(n, features, factors);
  if (n < 2) throw std::invalid_argument("DenseWindowSolver::marginalize_first: no state would be left");
  Linearization lin;
  linearize(states, features, factors, true, lin);
  Eigen::MatrixXd S;
  Eigen::VectorXd s;
  reduce(lin, 0.0, S, s);
  DenseMarginal out;
  for (int i = 1; i < n; ++i)
    if (lin.touched[i]) out.kept.push_back(i);
  const int m = static_cast<int>(out.kept.size());
  // Row of (state, tangent component) in S.
  std::array<int, kS> internal_of{};
  for (int c = 0; c < kS; ++c) internal_of[kToTangent[c]] = c;
  auto row = [&](int state, int t) { return kS * state + internal_of[t]; };
  Eigen::Matrix<double, kS, kS> A;
  Eigen::Matrix<double, kS, 1> g0;
  Eigen::MatrixXd B(kS, kS * m), C(kS * m, kS * m);
  Eigen::VectorXd gk(kS * m);
  for (int t = 0; t < kS; ++t) {
    g0(t) = s(row(0, t));
    for (int u = 0; u < kS; ++u) A(t, u) = S(row(0, t), row(0, u));
    for (int b = 0; b < m; ++b)
      for (int u = 0; u < kS; ++u) B(t, kS * b + u) = S(row(0, t), row(out.kept[b], u));
  }
  for (int a = 0; a < m; ++a)
    for (int t = 0; t < kS; ++t) {
      gk(kS * a + t) = s(row(out.kept[a], t));
      for (int b = 0; b < m; ++b)
        for (int u = 0; u < kS; ++u) C(kS * a + t, kS * b + u) = S(row(out.kept[a], t), row(out.kept[b], u));
    }
  const Eigen::LLT<Eigen::Matrix<double, kS, kS>> llt(A);
  if (llt.info() != Eigen::Success)
    throw NumericalError("marginalize: the leaving keyframe has no positive-definite information");
  const Eigen::MatrixXd AinvB = llt.solve(B);
  out.H = C - B.transpose() * AinvB;
  out.g = gk - AinvB.transpose() * g0;
  if (!out.H.allFinite() || !out.g.allFinite()) throw NumericalError("marginalize: the marginal system is not finite");
  return out;
}

}  // namespace slamkit
