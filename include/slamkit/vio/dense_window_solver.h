// DenseWindowSolver: the sliding window's nonlinear least squares, linearized straight into one
// dense system and solved with fixed-size kernels (no factor graph, no sparse machinery: the
// window has ≈ 10 × 15 state unknowns and a few hundred 1-dof inverse depths).
//
// Unknowns: N window states x_0..x_{N−1} (ImuState, tangent [δφ, δv, δp, δb_g, δb_a]) and one
// inverse depth ρ_f per feature (anchored in state a_f, bearing b_f). Cost (the engine's, no ½):
//   Σ_state factors ρ(‖r‖²)  (prior, IMU: any Factor on states)
//   + Σ_f Σ_obs w_obs · ρ_Cauchy(‖(π(P_k(x_a, x_k, ρ_f)) − z) / σ‖²)
// with P_k the InverseDepthFactor's point (factors/inverse_depth_factor.h, same formulas) and
// w_obs the observation's weight (DVI's α of its frame). Robust kernels use Triggs' correction
// as Factor::linearize does.
//
// Linear system, per LM iteration: internally each state's 15 columns are ordered [δφ, δp, δv,
// δb_g, δb_a] so the 6 pose columns a reprojection touches are one contiguous block. Every
// observation adds 2×6 Jacobian blocks (fixed size) into H_xx (6×6 blocks), its 2×1 ρ column
// into the feature's h_ff, g_f and w_i = Σ J_iᵀ J_ρ (6×1 per state it touches). The features are
// eliminated on the fly (each touches only its anchor and observers):
//   S = H_xx + λD_x − Σ_f w wᵀ / (h_ff + λ d_f),   s = g_x − Σ_f w g_f / (h_ff + λ d_f)
// S δx = −s by dense LLT; back-substitution δρ_f = −(g_f + wᵀ δx) / (h_ff + λ d_f).
// LM as the engine's (Nielsen's λ update, D = diag(H) clamped to [1e-6, 1e32], λ₀ = 1e-5, a step
// is accepted when the cost falls, stop when the relative cost change ≤ function_tolerance).
//
// Marginalization of state 0 (VINS-Mono's "marginalize the oldest"): the factors touching it
// (state factors with 0 among their states, the features anchored in it with all their
// observations) are linearized the same way; the features are eliminated (dense Schur as above,
// λ = 0), then state 0 (LLT of its 15×15 block); H*, g* on the other touched states (tangent
// order) are what MarginalizationPrior::from_hessian takes.
//
// A MarginalizationPrior<ImuState> has first-estimate (constant) Jacobians: its JᵀJ is formed
// once per prior object and cached; each linearization only evaluates its residual.
// Threads (optional ThreadPool): the features are split into a fixed number of blocks (4, of
// about equal observation count; the split depends on the features only). Linearization, the
// Schur elimination of the inverse depths, the back-substitution and the candidate's cost run
// per block into the block's own buffers, which are summed in block order afterwards. The
// reduction order is the same for any thread count, so results are bit-identical to one
// thread (tested). The state factors, the dense LLT and the marginal's 15×15 solve are serial.
// A solver object is not thread-safe (the prior cache).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "slamkit/core/factor.h"
#include "slamkit/core/parallel.h"
#include "slamkit/core/robust_kernel.h"
#include "slamkit/factors/imu_state.h"
#include "slamkit/geometry/camera_models.h"

namespace slamkit {

struct WindowObservation {
  int state = 0;  ///< window index of the observing state (≠ the anchor)
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  double weight = 1.0;  ///< multiplies the observation's cost (≥ 0)
};

struct WindowFeature {
  int anchor = 0;  ///< window index of the anchor state
  Eigen::Vector3d bearing = Eigen::Vector3d::UnitZ();  ///< unit, anchor camera frame
  double inv_depth = 1.0;
  std::vector<WindowObservation> obs;
};

/// A factor whose variables are all window states (the prior, an IMU factor).
struct WindowStateFactor {
  std::shared_ptr<const Factor> factor;
  std::vector<int> states;  ///< window index of each of the factor's variables
};

struct DenseWindowOptions {
  int max_iterations = 8;  ///< LM iterations (accepted or not) per call
  double function_tolerance = 1e-6;
  double initial_lambda = 1e-5;
  double max_lambda = 1e32;
};

struct DenseWindowSummary {
  int iterations = 0;
  double initial_cost = 0.0, final_cost = 0.0;
  double linearize_ms = 0.0, solve_ms = 0.0;  ///< time building the systems, in the reduced solves
};

struct DenseMarginal {
  std::vector<int> kept;  ///< window indices of the states of H, g (increasing)
  Eigen::MatrixXd H;      ///< 15·kept × 15·kept, tangent order per state
  Eigen::VectorXd g;
};

class DenseWindowSolver {
 public:
  /// Throws std::invalid_argument without a camera or with pixel_sigma ≤ 0. `pool` (may be
  /// null: serial) runs the feature blocks; it must outlive the solver.
  DenseWindowSolver(std::shared_ptr<const CameraModel> camera, const SE3& T_imu_cam, double pixel_sigma,
                    std::shared_ptr<const RobustKernel> kernel, const ThreadPool* pool = nullptr);

  /// LM over the states and the inverse depths (updated in place). Throws std::invalid_argument
  /// if an index is out of range.
  DenseWindowSummary optimize(std::vector<ImuState>& states, std::vector<WindowFeature>& features,
                              const std::vector<WindowStateFactor>& factors, const DenseWindowOptions& options) const;

  /// The total cost at the given values (what optimize() minimizes).
  double cost(const std::vector<ImuState>& states, const std::vector<WindowFeature>& features,
              const std::vector<WindowStateFactor>& factors) const;

  /// Marginalizes state 0 and the features anchored in it (see above). Throws NumericalError if
  /// a factor is not finite or state 0 has no positive-definite information left.
  DenseMarginal marginalize_first(const std::vector<ImuState>& states, const std::vector<WindowFeature>& features,
                                  const std::vector<WindowStateFactor>& factors) const;

 private:
  struct Linearization;
  /// H (upper blocks filled), g and the feature blocks; `only_first`: only what touches state 0.
  double linearize(const std::vector<ImuState>& states, const std::vector<WindowFeature>& features,
                   const std::vector<WindowStateFactor>& factors, bool only_first, Linearization& lin) const;
  /// Reduced system for damping λ (λ = 0: none), into S (full, symmetric) and s.
  void reduce(const Linearization& lin, double lambda, Eigen::MatrixXd& S, Eigen::VectorXd& s) const;
  double feature_cost(const std::vector<ImuState>& states, const WindowFeature& f, double inv_depth) const;

  std::shared_ptr<const CameraModel> camera_;
  SE3 T_imu_cam_;
  double inv_sigma_;
  std::shared_ptr<const RobustKernel> kernel_;
  const ThreadPool* pool_;
  struct PriorCache {
    std::shared_ptr<const Factor> factor;
    Eigen::MatrixXd J, H;  // whitened Jacobian and JᵀJ, columns in internal order per variable
  };
  mutable PriorCache prior_cache_;
};

}  // namespace slamkit
