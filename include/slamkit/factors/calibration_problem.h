// Calibration variables and factors of a pose-graph problem (core/calibration.h), their
// marginal uncertainty and an observability check.
//
// Variables: calibration vertex id → key vertex_key(id) (SE2 offset, Vector3 (k_l, k_r, b),
// Vector9 K); g2o offset parameter id → key symbol('o', id) (SE2 or SE3), created for the
// parameters the offset edges use. Which are free follows CalibrationOptions; the others are
// held fixed (fixed variables of Values). Priors become PriorFactor<SE2 | Vector>.
//
// Observability of each free parameter (after the Schur complement S of the Hessian onto the
// calibration block, solvers/marginal_information.h):
//   * rank: an eigenvector of the correlation-scaled S = D⁻¹ S D⁻¹ (D² = diag H_cc) with
//     eigenvalue < 1e-9 names the parameters with weight > 0.3 in it; a parameter no factor
//     sees (diag H_cc · scale² / n < 1e-12, scale and n as below) is unobservable too;
//   * excitation: q = (scale/σ)² / n, σ the marginal sigma, n the factors that see the variable,
//     scale = 1 m (offset translation), 1 rad (offset rotation), 1 (wheel scales, K), |b|
//     (baseline): the information per measurement about a change of one "scale". A parameter
//     the data excites only at the noise level (a straight path for the baseline or the offset
//     translation: q ≲ 1 from fitting noise) has q < min_excitation (default 1.5).
// Unobservable parameters (checked at the optimum) get a warning naming them; optimize_pose_graph
// then holds the least excited one at its initial value with a tight prior (σ = 1e-6 scale),
// optimizes again from the initial values and checks again, until the rest is observable (one
// unobservable parameter, e.g. a baseline drifting to infinity, can make others look so).
// The result is not a drift in the null space; held parameters report a null sigma.
#pragma once

#include <string>
#include <vector>

#include "slamkit/core/factor_graph.h"
#include "slamkit/core/pose_graph.h"

namespace slamkit {

struct CalibrationOptions {
  bool offsets = true;             ///< estimate sensor-offset vertices (VERTEX_SE2 of EDGE_SE2_CALIB)
  bool odometry = true;            ///< estimate odometry vertices
  bool offset_parameters = false;  ///< also estimate the PARAMS_* the offset edges use (--calibrate offset)
  double min_excitation = 1.5;     ///< see above (fitting noise alone gives q ≈ 1)
};

/// One free or fixed calibration variable of a problem.
/// The --calibrate option (and Python's calibrate=): "auto" (the file's calibration vertices;
/// PARAMS_* constants as in g2o, estimated for sim:calib*), "none", or a comma list of "offset"
/// (vertices and PARAMS_* offsets) and "odometry". Throws InputError for another word.
CalibrationOptions parse_calibrate_option(const std::string& value);

struct CalibrationVariable {
  Key key = 0;
  std::string name;  ///< "offset[1000]", "odometry[1001]", "params_se3offset[0]"
  enum class Type { kOffset2, kOffset3, kOdomDifferential, kOdomLinear } type = Type::kOffset2;
  std::int64_t id = 0;
  bool parameter = false;  ///< a g2o PARAMS_* (else a vertex)
  bool estimated = false;
  int dim = 3;  ///< tangent dimension
};

/// Names of the tangent coordinates of a variable: x y theta | x y z rx ry rz | k_left k_right
/// baseline | K11..K33.
std::vector<std::string> coordinate_names(const CalibrationVariable& v);

struct CalibrationParameterEstimate {
  std::string name;   ///< "odometry[1001].baseline"
  double value = 0.0;  ///< offsets: x, y, θ (SE3: translation and rotation vector Log(R))
  double sigma = 0.0;  ///< marginal standard deviation (NaN when unobservable)
  bool observable = true;
  double excitation = 0.0;  ///< q above (0: no information)
  std::string reason;       ///< why it is unobservable
};

struct CalibrationReport {
  std::vector<CalibrationParameterEstimate> parameters;  ///< estimated parameters, in variable order
  std::vector<std::string> warnings;                      ///< one per unobservable parameter
  std::vector<std::string> held;  ///< parameters held at their initial value (unobservable)
  Eigen::MatrixXd covariance;     ///< joint marginal covariance of `parameters` (pseudo-inverse)
};

/// Adds the calibration variables (after all vertices), the calibrated-edge factors and the
/// priors on calibration vertices (the factors of the calibrated edges are make_calibrated_factor's).
/// Appends the variables to `out`.
void add_calibration_to_problem(const PoseGraph& g, const CalibrationOptions& options, Values& values,
                                FactorGraph& graph, std::vector<CalibrationVariable>& out);

/// Factor of one calibrated edge (pose keys vertex_key(from/to)).
std::shared_ptr<Factor> make_calibrated_factor(const GraphEdge& e, std::shared_ptr<const NoiseModel> noise,
                                               std::shared_ptr<const RobustKernel> kernel);

/// Estimates, marginal sigmas and the observability check at `values` (see above).
CalibrationReport analyze_calibration(const FactorGraph& graph, const Values& values,
                                      const std::vector<CalibrationVariable>& variables,
                                      const CalibrationOptions& options);

/// Adds a tight prior (σ = 1e-6 scale) holding parameter `name` (as the report names it) at its
/// value in `initial`: tangent coordinate k of x ⊟ x₀. False if no free variable has it.
bool hold_calibration_parameter(const std::string& name, const std::vector<CalibrationVariable>& variables,
                                const Values& initial, FactorGraph& graph);

/// Copies the calibration variables' values back into the graph and refreshes the effective
/// measurements of its calibrated edges.
void copy_calibration_estimates(const Values& values, PoseGraph& g);

}  // namespace slamkit
