#include "slamkit/factors/bundle_adjustment.h"

#include <chrono>

#include "slamkit/factors/bal_normal_equations.h"
#include "slamkit/factors/bal_reprojection_factor.h"

namespace slamkit {

BundleAdjustmentProblem build_bundle_adjustment_problem(const BalProblem& p, std::shared_ptr<const RobustKernel> kernel) {
  BundleAdjustmentProblem ba;
  // Points first: the Optimizer eliminates them first anyway; keeps Values in that order.
  for (int j = 0; j < p.num_points(); ++j) ba.values.insert(bal_point_key(j), p.points[j]);
  for (int i = 0; i < p.num_cameras(); ++i) ba.values.insert(bal_camera_key(i), BalCamera::from_bal(p.cameras[i]));
  const auto noise = NoiseModel::unit(2);
  for (const BalObservation& o : p.observations)
    ba.graph.emplace<BalReprojectionFactor>(bal_camera_key(o.camera), bal_point_key(o.point), o.pixel, noise, kernel);
  return ba;
}

void copy_bundle_adjustment_estimates(const Values& values, BalProblem& p) {
  for (int j = 0; j < p.num_points(); ++j) p.points[j] = values.at<Eigen::Vector3d>(bal_point_key(j));
  for (int i = 0; i < p.num_cameras(); ++i) p.cameras[i] = values.at<BalCamera>(bal_camera_key(i)).to_bal();
}

OptimizerOptions BundleAdjustmentOptions::default_optimizer() {
  OptimizerOptions o;
  o.algorithm = Algorithm::kLevenbergMarquardt;
  o.lm_initial_lambda = 1e-4;
  o.function_tolerance = 1e-6;
  o.max_iterations = 100;
  o.schur_eliminate = is_bal_point_key;
  return o;
}

BundleAdjustmentResult optimize_bundle_adjustment(BalProblem& p, const BundleAdjustmentOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!options.use_factor_graph && options.optimizer.algorithm == Algorithm::kLevenbergMarquardt) {
    BalState x = make_bal_state(p);
    BundleAdjustmentResult r;
    r.time_build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    r.summary = optimize_bal_levenberg_marquardt(p, x, options.optimizer, options.kernel);
    r.initial_cost = 0.5 * r.summary.initial_cost;
    r.final_cost = 0.5 * r.summary.final_cost;
    copy_bal_state(x, p);
    return r;
  }
  BundleAdjustmentProblem ba = build_bundle_adjustment_problem(p, options.kernel);
  BundleAdjustmentResult r;
  r.time_build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  OptimizerOptions o = options.optimizer;
  if (!o.schur_eliminate) o.schur_eliminate = is_bal_point_key;
  r.summary = Optimizer(o).optimize(ba.graph, ba.values);
  r.initial_cost = 0.5 * r.summary.initial_cost;
  r.final_cost = 0.5 * r.summary.final_cost;
  copy_bundle_adjustment_estimates(ba.values, p);
  return r;
}

}  // namespace slamkit
