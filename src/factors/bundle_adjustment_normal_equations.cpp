#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "slamkit/factors/bal_normal_equations.h"

namespace slamkit {
namespace {

constexpr int kChunk = 256;  // points per cost chunk (fixed: the summation order)
constexpr int kFt = 18;      // doubles per observation in ft_: F_ijᵀ (9×2, col-major)

using Mat29 = Eigen::Matrix<double, 2, 9>;
using Mat23 = Eigen::Matrix<double, 2, 3>;
using Mat93 = Eigen::Matrix<double, 9, 3>;
using Mat99 = Eigen::Matrix<double, 9, 9>;
template <int R, int C>
using MapS = Eigen::Map<Eigen::Matrix<double, R, C>, 0, Eigen::OuterStride<>>;
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
  cam_obs_.resize(no), pt_obs_.resize(no);
  {
    std::vector<int> fill(cam_ptr_.begin(), cam_ptr_.end() - 1);
    std::vector<int> by_point(no);
    std::iota(by_point.begin(), by_point.end(), 0);
    std::stable_sort(by_point.begin(), by_point.end(),
                     [&](int a, int b) { return p.observations[a].point < p.observations[b].point; });
    for (int k : by_point) cam_obs_[fill[p.observations[k].camera]++] = k;  // camera, then point order
    std::vector<int> pfill(pt_ptr_.begin(), pt_ptr_.end() - 1);
    for (int k : cam_obs_) pt_obs_[pfill[p.observations[k].point]++] = k;  // point, then camera order
  }
  // H's pattern: point j is block j, camera i block np + i; one block per observed pair.
  std::vector<int> dims(static_cast<std::size_t>(np_) + nc_, 9);
  std::fill(dims.begin(), dims.begin() + np_, 3);
  std::vector<std::pair<int, int>> pattern;
  pattern.reserve(no);
  for (const BalObservation& o : p.observations) pattern.emplace_back(np_ + o.camera, o.point);
  hessian_ = BlockSparseMatrix(std::move(dims), std::move(pattern));
  w_off_.resize(no), w_first_.assign(no, 1);
  for (int k = 0; k < no; ++k) w_off_[k] = hessian_.block_offset(np_ + p.observations[k].camera, p.observations[k].point);
  for (int i = 0; i < nc_; ++i)
    for (int q = cam_ptr_[i] + 1; q < cam_ptr_[i + 1]; ++q)
      if (p.observations[cam_obs_[q]].point == p.observations[cam_obs_[q - 1]].point) w_first_[cam_obs_[q]] = 0;
  g_.setZero(hessian_.rows());
  diag_.setZero(hessian_.rows());
  ft_.assign(static_cast<std::size_t>(no) * kFt, 0.0);
  r_cam_.assign(2 * static_cast<std::size_t>(no), 0.0);
  cam_slot_.resize(no);
  for (int q = 0; q < no; ++q) cam_slot_[cam_obs_[q]] = q;
  rot_.resize(nc_);
  chunk_cost_.assign((np_ + kChunk - 1) / kChunk, 0.0);
}

std::vector<char> BalNormalEquations::eliminate_flags() const {
  std::vector<char> e(static_cast<std::size_t>(np_) + nc_, 0);
  std::fill(e.begin(), e.begin() + np_, 1);
  return e;
}

void BalNormalEquations::rotations(const BalState& x) const {
  pool_.parallel_for(
      nc_, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) rot_[i] = x.cameras[i].rotation.matrix();
      },
      64);
}

// Per point j (chunks of kChunk points): residuals of its observations; with Jacobians also
// C_j, g_j, W_ij (into H, the point's own column) and F_ijᵀ, r_ij (into ft_, r_cam_).
template <bool kJacobians>
double BalNormalEquations::point_pass(const BalState& x, std::vector<double>* chunk_cost) {
  rotations(x);
  const int nchunks = static_cast<int>(chunk_cost->size());
  double* H = hessian_.values().data();
  pool_.parallel_for(
      nchunks,
      [&](std::size_t cb, std::size_t ce) {
        Mat29 F;
        Mat23 E;
        for (std::size_t c = cb; c < ce; ++c) {
          double sum = 0.0;
          const int j_end = std::min<int>(np_, static_cast<int>(c + 1) * kChunk);
          for (int j = static_cast<int>(c) * kChunk; j < j_end; ++j) {
            const Eigen::Vector3d& X = x.points[j];
            Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
            Eigen::Vector3d gj = Eigen::Vector3d::Zero();
            const int ld = kJacobians ? hessian_.leading_dim(j) : 0;
            for (int q = pt_ptr_[j]; q < pt_ptr_[j + 1]; ++q) {
              const int k = pt_obs_[q];
              const BalObservation& o = p_.observations[k];
              const BalCamera& cam = x.cameras[o.camera];
              if (!kJacobians) {
                Eigen::Vector2d r = bal_reprojection(rot_[o.camera], cam, X, o.pixel, nullptr, nullptr);
                sum += kernel_ ? robust_correct(*kernel_, r, nullptr, nullptr) : r.squaredNorm();
                continue;
              }
              Eigen::Vector2d r = bal_reprojection(rot_[o.camera], cam, X, o.pixel, &F, &E);
              sum += kernel_ ? robust_correct(*kernel_, r, &F, &E) : r.squaredNorm();
              C.noalias() += E.transpose().lazyProduct(E);
              gj.noalias() += E.transpose() * r;
              MapS<9, 3> W(H + w_off_[k], 9, 3, Eigen::OuterStride<>(ld));
              if (w_first_[k]) W.noalias() = F.transpose().lazyProduct(E);
              else W.noalias() += F.transpose().lazyProduct(E);
              // At the observation's slot in camera order: camera i's F_ijᵀ form one 9 × 2m matrix.
              const std::size_t slot = static_cast<std::size_t>(cam_slot_[k]);
              Eigen::Map<Eigen::Matrix<double, 9, 2>> Ft(ft_.data() + slot * kFt);
              Ft = F.transpose();
              r_cam_[2 * slot] = r[0], r_cam_[2 * slot + 1] = r[1];
            }
            if (kJacobians) {
              MapS<3, 3>(H + hessian_.block_offset(j, j), 3, 3, Eigen::OuterStride<>(ld)) = C;
              g_.segment<3>(3 * j) = gj;
              diag_.segment<3>(3 * j) = C.diagonal();
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
  // point_pass<false> writes nothing but rot_ and the chunk sums (both mutable scratch).
  return const_cast<BalNormalEquations*>(this)->point_pass<false>(x, &chunk_cost_);
}

double BalNormalEquations::linearize(const BalState& x) {
  damped_ = false;
  const double total = point_pass<true>(x, &chunk_cost_);
  // Cameras: B_i = Σ_j F_ijᵀF_ij and g_i = Σ_j F_ijᵀr_ij over the camera's observations in point order.
  double* H = hessian_.values().data();
  pool_.parallel_for(
      nc_,
      [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          // B_i = M Mᵀ, g_i = M r with M = [F_ij₁ᵀ … F_ijₘᵀ] (9 × 2m, contiguous): one blocked product
          // per camera instead of m tiny ones; its summation order depends only on m.
          const int m2 = 2 * (cam_ptr_[i + 1] - cam_ptr_[i]);
          const Eigen::Map<const Eigen::Matrix<double, 9, Eigen::Dynamic>> M(
              ft_.data() + static_cast<std::size_t>(cam_ptr_[i]) * kFt, 9, m2);
          Mat99 B = Mat99::Zero();
          B.selfadjointView<Eigen::Lower>().rankUpdate(M);
          B.triangularView<Eigen::StrictlyUpper>() = B.transpose();
          const Eigen::Matrix<double, 9, 1> gi = M * Eigen::Map<const Eigen::VectorXd>(r_cam_.data() + 2 * cam_ptr_[i], m2);
          const int bi = np_ + static_cast<int>(i);
          MapS<9, 9>(H + hessian_.block_offset(bi, bi), 9, 9, Eigen::OuterStride<>(hessian_.leading_dim(bi))) = B;
          const int s = hessian_.block_start(bi);
          g_.segment<9>(s) = gi;
          diag_.segment<9>(s) = B.diagonal();
        }
      },
      1);
  return total;
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
  damped_ = true;
}

void BalNormalEquations::clear_damping() {
  if (!damped_) return;
  const auto& pos = hessian_.diagonal_positions();
  auto& v = hessian_.values();
  for (int a = 0; a < dim(); ++a) v[pos[a]] = diag_[a];
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
            for (int q = pt_ptr_[j]; q < pt_ptr_[j + 1]; ++q) {
              const int k = pt_obs_[q];
              if (!w_first_[k]) continue;
              const int s = hessian_.block_start(np_ + p_.observations[k].camera);
              sum += 2.0 * d.segment<9>(s).dot(CMapS<9, 3>(H + w_off_[k], 9, 3, Eigen::OuterStride<>(ld)) * dj);
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
  if (damped_) q -= (damping_.array() * d.array().square()).sum();
  return q;
}

void BalNormalEquations::retract(const BalState& x, const double* step, BalState& out) const {
  out.cameras.resize(nc_), out.points.resize(np_);
  pool_.parallel_for(np_, [&](std::size_t b, std::size_t e) {
    for (std::size_t j = b; j < e; ++j) out.points[j] = x.points[j] + Eigen::Map<const Eigen::Vector3d>(step + 3 * j);
  });
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

}  // namespace slamkit
