// Robust kernels ρ(s) of the squared whitened residual s = ‖R r‖².
//
// A factor contributes ρ(s) to the cost (ρ(s) = s without a kernel). δ is the residual
// magnitude where the kernel departs from least squares (the "inlier scale"); every kernel
// satisfies ρ(s) ≈ s for s ≪ δ². evaluate() returns ρ, ρ' = dρ/ds, ρ'' = d²ρ/ds².
//   Huber      s ≤ δ²: s                       else 2δ√s − δ²
//   Cauchy     δ² ln(1 + s/δ²)
//   Tukey      s ≤ δ²: δ²/3 (1 − (1 − s/δ²)³)   else δ²/3
//   GemanMcClure  δ² s / (δ² + s)
//   DCS (dynamic covariance scaling, Agarwal et al. 2013), Φ = δ²:
//              s ≤ Φ: s                        else Φ (3s − Φ) / (Φ + s)
// Immutable; thread-safe.
#pragma once

#include <memory>
#include <string>

namespace slamkit {

class RobustKernel {
 public:
  explicit RobustKernel(double delta);
  virtual ~RobustKernel() = default;
  virtual std::string name() const = 0;
  /// rho[0] = ρ(s), rho[1] = ρ'(s), rho[2] = ρ''(s).
  virtual void evaluate(double s, double rho[3]) const = 0;
  double delta() const { return delta_; }

 protected:
  double delta_;
  double delta2_;
};

class HuberKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  std::string name() const override { return "huber"; }
  void evaluate(double s, double rho[3]) const override;
};

class CauchyKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  std::string name() const override { return "cauchy"; }
  void evaluate(double s, double rho[3]) const override;
};

class TukeyKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  std::string name() const override { return "tukey"; }
  void evaluate(double s, double rho[3]) const override;
};

class GemanMcClureKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  std::string name() const override { return "geman-mcclure"; }
  void evaluate(double s, double rho[3]) const override;
};

class DcsKernel final : public RobustKernel {
 public:
  using RobustKernel::RobustKernel;
  std::string name() const override { return "dcs"; }
  void evaluate(double s, double rho[3]) const override;
};

/// "huber", "cauchy", "tukey", "geman-mcclure" (or "gm"), "dcs"; throws InputError otherwise.
std::shared_ptr<const RobustKernel> make_robust_kernel(const std::string& name, double delta);
/// Parses "KERNEL:δ" (e.g. "huber:1.5"); throws InputError naming the bad part.
std::shared_ptr<const RobustKernel> parse_robust_kernel(const std::string& spec);

}  // namespace slamkit
