// Step strategies: Gauss-Newton, Levenberg-Marquardt (Nielsen), the P3 trust-region LM and
// Powell's dogleg. Each works on the current normal equations H δ = −g through LinearContext.
#include "step_strategy.h"

#include <chrono>
#include <cmath>

namespace slamkit::detail {
namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Diagonal scaling clamped like Ceres' [1e-6, 1e32] so that zero-curvature directions stay damped.
Eigen::VectorXd clamped_diagonal(const Eigen::VectorXd& d) { return d.cwiseMax(1e-6).cwiseMin(1e32); }

}  // namespace

bool LinearContext::factorize(const Eigen::VectorXd* damping) {
  const double t0 = now_s();
  if (damping) {
    ne_.set_diagonal_damping(*damping);
    damped_ = true;
  } else if (damped_) {
    ne_.clear_damping();
    damped_ = false;
  }
  const bool ok = chol_.factorize(ne_.hessian());
  ++solves;
  time_s += now_s() - t0;
  return ok;
}

void LinearContext::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  const double t0 = now_s();
  x.resize(b.size());
  chol_.solve(b.data(), x.data());
  time_s += now_s() - t0;
}

double LinearContext::inverse_factor_norm2(const Eigen::VectorXd& v) {
  const double t0 = now_s();
  const double r = chol_.inverse_factor_norm2(v.data());
  time_s += now_s() - t0;
  return r;
}

double LinearContext::quadratic(const Eigen::VectorXd& d) {
  work_.resize(d.size());
  ne_.hessian().multiply(d.data(), work_.data());
  double q = d.dot(work_);
  if (damped_) {  // remove the damping currently on the diagonal
    const auto& pos = ne_.hessian().diagonal_positions();
    const auto& vals = ne_.hessian().values();
    const Eigen::VectorXd& diag = ne_.hessian_diagonal();
    for (int i = 0; i < d.size(); ++i) q -= (vals[pos[i]] - diag[i]) * d[i] * d[i];
  }
  return q;
}

double LinearContext::model_reduction(const Eigen::VectorXd& d) {
  if (!step_solves_system_) return -2.0 * gradient().dot(d) - quadratic(d);
  double reduction = -gradient().dot(d);
  if (damped_) {  // + δᵀΛδ, Λ the damping currently on the diagonal
    const auto& pos = ne_.hessian().diagonal_positions();
    const auto& vals = ne_.hessian().values();
    const Eigen::VectorXd& diag = ne_.hessian_diagonal();
    for (int i = 0; i < d.size(); ++i) reduction += (vals[pos[i]] - diag[i]) * d[i] * d[i];
  }
  return reduction;
}

namespace {

// Factorizes H + λ D for growing λ until it works; returns the λ used, or −1.
double factorize_with_fallback(LinearContext& ctx, const Eigen::VectorXd& D, double lambda0, int max_tries) {
  double lambda = lambda0;
  for (int k = 0; k < max_tries; ++k) {
    if (lambda == 0.0) {
      if (ctx.factorize(nullptr)) return 0.0;
      lambda = 1e-12;
      continue;
    }
    const Eigen::VectorXd damping = lambda * D;
    if (ctx.factorize(&damping)) return lambda;
    lambda *= 100.0;
  }
  return -1.0;
}

// ---------------------------------------------------------------- Gauss-Newton
// Always takes the full step H δ = −g. If H cannot be factorized, or the step makes the
// cost non-finite, it falls back to a damped step (λ grows ×10 per failure).
class GaussNewton final : public StepStrategy {
 public:
  bool compute_step(LinearContext& ctx, Eigen::VectorXd& step) override {
    const Eigen::VectorXd D = clamped_diagonal(ctx.equations().hessian_diagonal());
    const double used = factorize_with_fallback(ctx, D, fallback_lambda_, 12);
    if (used < 0.0) return false;
    ctx.solve(-ctx.gradient(), step);
    ctx.mark_step_solves_system();
    return step.allFinite();
  }
  bool accept(double) const override { return true; }  // the driver rejects non-finite costs
  bool update(double, bool accepted, const Eigen::VectorXd&) override {
    if (accepted) {
      fallback_lambda_ = 0.0, failures_ = 0;
      return true;
    }
    fallback_lambda_ = fallback_lambda_ == 0.0 ? 1e-4 : 10.0 * fallback_lambda_;
    return ++failures_ < 20;
  }
  double damping() const override { return fallback_lambda_; }

 private:
  double fallback_lambda_ = 0.0;
  int failures_ = 0;
};

// ---------------------------------------------------------------- Levenberg-Marquardt
class LevenbergMarquardt final : public StepStrategy {
 public:
  explicit LevenbergMarquardt(const OptimizerOptions& o) : o_(o) {}
  bool compute_step(LinearContext& ctx, Eigen::VectorXd& step) override {
    const Eigen::VectorXd& diag = ctx.equations().hessian_diagonal();
    const Eigen::VectorXd D =
        o_.lm_diagonal_scaling ? clamped_diagonal(diag) : Eigen::VectorXd::Ones(diag.size());
    if (lambda_ < 0.0) lambda_ = o_.lm_diagonal_scaling ? o_.lm_initial_lambda : o_.lm_initial_lambda * diag.maxCoeff();
    while (true) {
      const Eigen::VectorXd damping = lambda_ * D;
      if (ctx.factorize(&damping)) break;
      lambda_ *= nu_, nu_ *= 2.0;  // not positive definite: damp more
      if (lambda_ > o_.lm_max_lambda) return false;
    }
    ctx.solve(-ctx.gradient(), step);
    ctx.mark_step_solves_system();
    return step.allFinite();
  }
  bool accept(double rho) const override { return rho > 0.0; }
  bool update(double rho, bool accepted, const Eigen::VectorXd&) override {
    if (accepted) {
      const double t = 2.0 * rho - 1.0;
      lambda_ *= std::max(1.0 / 3.0, 1.0 - t * t * t);
      nu_ = 2.0;
    } else {
      lambda_ *= nu_;
      nu_ *= 2.0;
    }
    return lambda_ <= o_.lm_max_lambda;
  }
  double damping() const override { return lambda_; }

 private:
  const OptimizerOptions& o_;
  double lambda_ = -1.0;  // set from H on the first step
  double nu_ = 2.0;
};

// ---------------------------------------------------------------- P3 trust-region LM
// Step: δ(λ) = −(H + λ D²)⁻¹ g with the smallest λ ≥ 0 such that ‖D δ‖² ≤ μ, found by
// Hebden/Moré Newton iterations on 1/‖Dδ(λ)‖ (each needs a factorization, so at most
// tr_max_inner_solves of them; λ is warm-started from the previous step).
class TrustRegionLM final : public StepStrategy {
 public:
  explicit TrustRegionLM(const OptimizerOptions& o) : o_(o), mu_(o.tr_initial_radius) {}
  bool compute_step(LinearContext& ctx, Eigen::VectorXd& step) override {
    const Eigen::VectorXd& diag = ctx.equations().hessian_diagonal();
    D2_ = D2_.size() == diag.size() ? D2_.cwiseMax(clamped_diagonal(diag)) : clamped_diagonal(diag);
    const double radius = std::sqrt(mu_);
    double lambda = lambda_;
    double p = 0.0;
    for (int k = 0; k < o_.tr_max_inner_solves; ++k) {
      const Eigen::VectorXd damping = lambda * D2_;
      bool ok = ctx.factorize(lambda > 0.0 ? &damping : nullptr);
      while (!ok) {  // not positive definite: damp until it is
        lambda = lambda > 0.0 ? 10.0 * lambda : 1e-8;
        if (lambda > 1e32) return false;
        const Eigen::VectorXd d2 = lambda * D2_;
        ok = ctx.factorize(&d2);
      }
      ctx.solve(-ctx.gradient(), step);
      if (!step.allFinite()) return false;
      p = (D2_.cwiseSqrt().cwiseProduct(step)).norm();
      if (lambda == 0.0 && p <= radius) break;          // interior Gauss-Newton step
      if (std::abs(p - radius) <= 0.1 * radius) break;  // on the boundary, close enough
      if (k + 1 == o_.tr_max_inner_solves) break;
      const Eigen::VectorXd w = D2_.cwiseProduct(step);  // D² δ
      const double q2 = ctx.inverse_factor_norm2(w);     // ‖L⁻¹ P D² δ‖²
      lambda = std::max(0.0, lambda + (p * p / q2) * (p - radius) / radius);
    }
    lambda_ = lambda;
    if (p > 1.1 * radius) step *= radius / p;  // inner iterations exhausted: pull back inside
    else ctx.mark_step_solves_system();         // the last solve's damping is still on H
    return true;
  }
  bool accept(double rho) const override { return rho > o_.tr_accept_threshold; }
  bool update(double rho, bool, const Eigen::VectorXd&) override {
    if (rho > o_.tr_increase_threshold) mu_ *= o_.tr_increase_factor;
    if (rho < o_.tr_decrease_threshold) {
      mu_ *= o_.tr_decrease_factor;
      lambda_ = std::max(lambda_, 1e-8);  // the old (smaller) λ no longer fits
    }
    return mu_ >= o_.tr_min_radius;
  }
  double damping() const override { return mu_; }

 private:
  const OptimizerOptions& o_;
  double mu_;
  double lambda_ = 0.0;
  Eigen::VectorXd D2_;
};

// ---------------------------------------------------------------- Powell's dogleg
// One factorization per linearization gives the Gauss-Newton step; the Cauchy point
// δ_sd = −(gᵀg / gᵀHg) g needs only H·g. Rejected steps shrink the radius and re-blend the
// two cached steps without another factorization.
class Dogleg final : public StepStrategy {
 public:
  explicit Dogleg(const OptimizerOptions& o) : o_(o), radius_(o.dogleg_initial_radius) {}
  bool compute_step(LinearContext& ctx, Eigen::VectorXd& step) override {
    if (!cached_) {
      const Eigen::VectorXd D = clamped_diagonal(ctx.equations().hessian_diagonal());
      if (factorize_with_fallback(ctx, D, 0.0, 12) < 0.0) return false;
      ctx.solve(-ctx.gradient(), gn_);
      if (!gn_.allFinite()) return false;
      const Eigen::VectorXd& g = ctx.gradient();
      const double gHg = ctx.quadratic(g);
      sd_ = gHg > 0.0 ? Eigen::VectorXd(-(g.squaredNorm() / gHg) * g) : Eigen::VectorXd(-g);
      cached_ = true;
    }
    const double gn_norm = gn_.norm(), sd_norm = sd_.norm();
    if (gn_norm <= radius_) {
      step = gn_;
      ctx.mark_step_solves_system();  // H (+ any fallback damping, still on H) δ = −g
    } else if (sd_norm >= radius_) {
      step = (radius_ / sd_norm) * sd_;
    } else {
      // sd + β (gn − sd) with ‖·‖ = radius: a β² + 2 b β + c = 0, β ∈ [0, 1].
      const Eigen::VectorXd d = gn_ - sd_;
      const double a = d.squaredNorm(), b = sd_.dot(d), c = sd_norm * sd_norm - radius_ * radius_;
      const double beta = (-b + std::sqrt(std::max(0.0, b * b - a * c))) / a;
      step = sd_ + beta * d;
    }
    return true;
  }
  bool accept(double rho) const override { return rho > o_.dogleg_accept_threshold; }
  bool update(double rho, bool, const Eigen::VectorXd& step) override {
    const double n = step.norm();
    if (rho < 0.25) {
      radius_ = 0.25 * std::min(radius_, n);
    } else if (rho > 0.75 && n >= 0.99 * radius_) {
      radius_ = 2.0 * radius_;
    }
    return radius_ >= o_.dogleg_min_radius;
  }
  void new_linearization() override { cached_ = false; }
  double damping() const override { return radius_; }

 private:
  const OptimizerOptions& o_;
  double radius_;
  bool cached_ = false;
  Eigen::VectorXd gn_, sd_;
};

}  // namespace

std::unique_ptr<StepStrategy> make_step_strategy(const OptimizerOptions& options) {
  switch (options.algorithm) {
    case Algorithm::kGaussNewton: return std::make_unique<GaussNewton>();
    case Algorithm::kLevenbergMarquardt: return std::make_unique<LevenbergMarquardt>(options);
    case Algorithm::kTrustRegionLM: return std::make_unique<TrustRegionLM>(options);
    case Algorithm::kDogleg: return std::make_unique<Dogleg>(options);
  }
  return nullptr;
}

}  // namespace slamkit::detail
