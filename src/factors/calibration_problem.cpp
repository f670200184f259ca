#include "slamkit/factors/calibration_problem.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <limits>
#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/core/information.h"
#include "slamkit/core/pose_graph_calibration.h"
#include "slamkit/factors/calibration_factors.h"
#include "slamkit/factors/pose_graph_problem.h"
#include "slamkit/factors/prior_factor.h"
#include "slamkit/solvers/marginal_information.h"

namespace slamkit {
namespace {

using Type = CalibrationVariable::Type;

Key offset_parameter_key(std::int64_t id) { return symbol('o', static_cast<std::uint64_t>(id)); }

// One tangent coordinate k of a prior x ⊟ x0: e = (x ⊟ x0)_k, J = row k of the prior's Jacobian.
template <class T>
class ComponentPriorFactor final : public FactorN<1, T> {
  using Base = FactorN<1, T>;

 public:
  ComponentPriorFactor(Key key, const T& mean, int k, double sigma)
      : Base({key}, NoiseModel::isotropic(1, sigma)), prior_(key, mean, NoiseModel::unit(ManifoldTraits<T>::kTangent)), k_(k) {}
  typename Base::Residual error(const T& x, typename Base::template Jacobian<T>* J) const override {
    typename PriorFactor<T>::template Jacobian<T> Jfull;
    const auto e = prior_.error(x, J ? &Jfull : nullptr);
    if (J) *J = Jfull.row(k_);
    return typename Base::Residual(e[k_]);
  }

 private:
  PriorFactor<T> prior_;
  int k_;
};

double coordinate_scale(const CalibrationVariable& v, const Values& values, int k) {
  if (v.type == Type::kOdomDifferential && k == 2) return std::abs(values.at<Eigen::Vector3d>(v.key)[2]);
  return 1.0;  // metres, radians, or a unitless factor
}

Eigen::VectorXd coordinate_values(const CalibrationVariable& v, const Values& values) {
  switch (v.type) {
    case Type::kOffset2: {
      const SE2 s = values.at<SE2>(v.key);
      return Eigen::Vector3d(s.x(), s.y(), s.theta());
    }
    case Type::kOffset3: {
      const SE3 s = values.at<SE3>(v.key);
      Eigen::VectorXd out(6);
      out << s.translation(), s.rotation().log();
      return out;
    }
    case Type::kOdomDifferential: return values.at<Eigen::Vector3d>(v.key);
    case Type::kOdomLinear: return values.at<Vector9d>(v.key);
  }
  return {};
}

}  // namespace

std::vector<std::string> coordinate_names(const CalibrationVariable& v) {
  switch (v.type) {
    case Type::kOffset2: return {"x", "y", "theta"};
    case Type::kOffset3: return {"x", "y", "z", "rx", "ry", "rz"};
    case Type::kOdomDifferential: return {"k_left", "k_right", "baseline"};
    case Type::kOdomLinear: return {"K11", "K12", "K13", "K21", "K22", "K23", "K31", "K32", "K33"};
  }
  return {};
}

std::shared_ptr<Factor> make_calibrated_factor(const GraphEdge& e, std::shared_ptr<const NoiseModel> noise,
                                               std::shared_ptr<const RobustKernel> kernel) {
  const CalibratedMeasurement& c = *e.calibrated;
  const Key i = vertex_key(e.from), j = vertex_key(e.to);
  switch (c.kind) {
    case CalibratedEdgeKind::kSensorOffset2:
      return std::make_shared<SensorOffsetFactor<SE2>>(i, j, vertex_key(c.param_a), c.sensor2, noise, kernel);
    case CalibratedEdgeKind::kOffsetParams2:
      if (c.param_a == c.param_b)
        return std::make_shared<SensorOffsetFactor<SE2>>(i, j, offset_parameter_key(c.param_a), c.sensor2, noise, kernel);
      return std::make_shared<SensorOffsetPairFactor<SE2>>(i, j, offset_parameter_key(c.param_a),
                                                           offset_parameter_key(c.param_b), c.sensor2, noise, kernel);
    case CalibratedEdgeKind::kOffsetParams3:
      if (c.param_a == c.param_b)
        return std::make_shared<SensorOffsetFactor<SE3>>(i, j, offset_parameter_key(c.param_a), c.sensor3, noise, kernel);
      return std::make_shared<SensorOffsetPairFactor<SE3>>(i, j, offset_parameter_key(c.param_a),
                                                           offset_parameter_key(c.param_b), c.sensor3, noise, kernel);
    case CalibratedEdgeKind::kOdomDifferential:
      return std::make_shared<DifferentialDriveOdometryFactor>(i, j, vertex_key(c.param_a), c.odometry, noise, kernel);
    case CalibratedEdgeKind::kOdomLinear:
      return std::make_shared<LinearOdometryFactor>(i, j, vertex_key(c.param_a), c.odometry, noise, kernel);
  }
  return nullptr;
}

void add_calibration_to_problem(const PoseGraph& g, const CalibrationOptions& options, Values& values,
                                FactorGraph& graph, std::vector<CalibrationVariable>& out) {
  for (const CalibrationVertex& cv : g.calibration.vertices) {
    CalibrationVariable v;
    v.key = vertex_key(cv.id);
    v.id = cv.id;
    if (g.index_of(cv.id))
      throw InputError(g.source, cv.line, "id", "calibration vertex " + std::to_string(cv.id) + " is also a pose vertex");
    switch (cv.kind) {
      case CalibrationKind::kOffset2:
        v.type = Type::kOffset2, v.name = "offset[" + std::to_string(cv.id) + "]";
        values.insert(v.key, to_se2(cv.value));
        v.estimated = cv.estimate && options.offsets;
        break;
      case CalibrationKind::kOdomDifferential:
        v.type = Type::kOdomDifferential, v.name = "odometry[" + std::to_string(cv.id) + "]";
        values.insert(v.key, Eigen::Vector3d(cv.value));
        v.estimated = cv.estimate && options.odometry;
        break;
      case CalibrationKind::kOdomLinear:
        v.type = Type::kOdomLinear, v.name = "odometry_linear[" + std::to_string(cv.id) + "]", v.dim = 9;
        values.insert(v.key, Vector9d(cv.value));
        v.estimated = cv.estimate && options.odometry;
        break;
    }
    out.push_back(v);
  }
  // g2o offset parameters used by offset edges.
  const bool estimate_params = options.offsets && (options.offset_parameters || g.calibration.estimate_offset_parameters);
  for (const GraphEdge& e : g.edges) {
    if (!e.calibrated) continue;
    const CalibratedMeasurement& c = *e.calibrated;
    const bool two_d = c.kind == CalibratedEdgeKind::kOffsetParams2;
    if (!two_d && c.kind != CalibratedEdgeKind::kOffsetParams3) continue;
    for (std::int64_t id : {c.param_a, c.param_b}) {
      const Key k = offset_parameter_key(id);
      if (values.exists(k)) continue;
      CalibrationVariable v;
      v.key = k, v.id = id, v.parameter = true, v.estimated = estimate_params;
      if (two_d) {
        v.type = Type::kOffset2, v.name = "params_se2offset[" + std::to_string(id) + "]";
        values.insert(k, offset2_of(g, e, id));
      } else {
        v.type = Type::kOffset3, v.name = "params_se3offset[" + std::to_string(id) + "]", v.dim = 6;
        values.insert(k, offset3_of(g, e, id));
      }
      out.push_back(v);
    }
  }
  for (const CalibrationVariable& v : out)
    if (!v.estimated) values.set_fixed(v.key);
  for (const CalibrationPrior& p : g.calibration.priors) {
    const CalibrationVertex* cv = g.calibration.find(p.id);
    if (!cv) throw InputError(g.source, p.line, "id", "prior on unknown calibration vertex " + std::to_string(p.id));
    std::shared_ptr<const NoiseModel> noise;
    try {
      noise = NoiseModel::information(p.information);
    } catch (const NumericalError&) {
      throw InputError(g.source, p.line, "information", "prior information is not positive definite");
    }
    const Key k = vertex_key(p.id);
    switch (cv->kind) {
      case CalibrationKind::kOffset2: graph.emplace<PriorFactor<SE2>>(k, to_se2(p.mean), noise); break;
      case CalibrationKind::kOdomDifferential:
        graph.emplace<PriorFactor<Eigen::Vector3d>>(k, Eigen::Vector3d(p.mean), noise);
        break;
      case CalibrationKind::kOdomLinear: graph.emplace<PriorFactor<Vector9d>>(k, Vector9d(p.mean), noise); break;
    }
  }
}

CalibrationOptions parse_calibrate_option(const std::string& value) {
  CalibrationOptions o;
  if (value == "auto") return o;
  o.offsets = o.odometry = false;
  if (value == "none") return o;
  std::istringstream in(value);
  std::string part;
  while (std::getline(in, part, ',')) {
    if (part == "offset") o.offsets = o.offset_parameters = true;
    else if (part == "odometry") o.odometry = true;
    else throw InputError("--calibrate", 0, part, "unknown calibration group (auto, none, offset, odometry)");
  }
  return o;
}

CalibrationReport analyze_calibration(const FactorGraph& graph, const Values& values,
                                      const std::vector<CalibrationVariable>& variables,
                                      const CalibrationOptions& options) {
  CalibrationReport report;
  std::vector<Key> keys;
  std::vector<const CalibrationVariable*> free;
  for (const CalibrationVariable& v : variables)
    if (v.estimated) keys.push_back(v.key), free.push_back(&v);
  if (keys.empty()) return report;
  const MarginalInformation mi = marginal_information(graph, values, keys);
  const int m = static_cast<int>(mi.schur.rows());
  std::vector<bool> observable(static_cast<std::size_t>(m), true);
  std::vector<std::string> why(static_cast<std::size_t>(m));
  // Rank: correlation-scaled Schur complement.
  Eigen::VectorXd d(m);
  for (int i = 0; i < m; ++i) {
    d[i] = mi.hessian_diag[i] > 0.0 ? std::sqrt(mi.hessian_diag[i]) : 1.0;
    if (!(mi.hessian_diag[i] > 0.0)) observable[i] = false, why[i] = "no measurement depends on it";
  }
  const Eigen::MatrixXd N = d.asDiagonal().inverse() * mi.schur * d.asDiagonal().inverse();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(N);

  for (int k = 0; k < m; ++k) {
    if (eig.eigenvalues()[k] >= 1e-9 * std::max(1.0, eig.eigenvalues().maxCoeff())) continue;
    for (int i = 0; i < m; ++i)
      if (std::abs(eig.eigenvectors()(i, k)) > 0.3 && observable[i])
        observable[i] = false, why[i] = "rank-deficient calibration block";
  }
  // Covariance on the observable part (pseudo-inverse over the rank-deficient directions).
  Eigen::VectorXd inv_eig(m);
  for (int k = 0; k < m; ++k)
    inv_eig[k] = eig.eigenvalues()[k] > 1e-9 * std::max(1.0, eig.eigenvalues().maxCoeff()) ? 1.0 / eig.eigenvalues()[k] : 0.0;
  const Eigen::MatrixXd cov_scaled = eig.eigenvectors() * inv_eig.asDiagonal() * eig.eigenvectors().transpose();
  const Eigen::MatrixXd cov = d.asDiagonal().inverse() * cov_scaled * d.asDiagonal().inverse();
  report.covariance = cov;
  int offset = 0;
  for (std::size_t s = 0; s < free.size(); ++s) {
    const CalibrationVariable& v = *free[s];
    const std::vector<std::string> names = coordinate_names(v);
    const Eigen::VectorXd value = coordinate_values(v, values);
    const int n = std::max(1, mi.factors_per_key[s]);
    for (int k = 0; k < v.dim; ++k) {
      const int i = offset + k;
      CalibrationParameterEstimate p;
      p.name = v.name + "." + names[static_cast<std::size_t>(k)];
      p.value = value[k];
      p.sigma = std::sqrt(std::max(0.0, cov(i, i)));
      const double scale = coordinate_scale(v, values, k);
      const double q = p.sigma > 0.0 ? scale * scale / (p.sigma * p.sigma) / n : 0.0;
      p.excitation = std::isfinite(q) ? q : 0.0;
      if (mi.hessian_diag[i] * scale * scale / n < 1e-12) {
        p.excitation = 0.0;
        if (observable[static_cast<std::size_t>(i)])
          observable[static_cast<std::size_t>(i)] = false, why[static_cast<std::size_t>(i)] = "no measurement depends on it";
      }
      if (observable[static_cast<std::size_t>(i)]) {
        if (!(q >= options.min_excitation)) {
          observable[static_cast<std::size_t>(i)] = false;
          why[static_cast<std::size_t>(i)] = "excited only at the noise level (information per measurement " +
                                             std::to_string(q) + " < " + std::to_string(options.min_excitation) + ")";
        }
      }
      p.observable = observable[static_cast<std::size_t>(i)];
      if (!p.observable) {
        p.sigma = std::numeric_limits<double>::quiet_NaN();
        p.reason = why[static_cast<std::size_t>(i)];
        report.warnings.push_back("calibration parameter " + p.name + " is unobservable: " + p.reason);
      }
      report.parameters.push_back(p);
    }
    offset += v.dim;
  }
  return report;
}

bool hold_calibration_parameter(const std::string& name, const std::vector<CalibrationVariable>& variables,
                                const Values& initial, FactorGraph& graph) {
  for (const CalibrationVariable& v : variables) {
    if (!v.estimated) continue;
    const std::vector<std::string> names = coordinate_names(v);
    for (int k = 0; k < v.dim; ++k) {
      if (v.name + "." + names[static_cast<std::size_t>(k)] != name) continue;
      const double sigma = 1e-6 * std::max(1e-3, coordinate_scale(v, initial, k));
      switch (v.type) {
        case Type::kOffset2: graph.emplace<ComponentPriorFactor<SE2>>(v.key, initial.at<SE2>(v.key), k, sigma); break;
        case Type::kOffset3: graph.emplace<ComponentPriorFactor<SE3>>(v.key, initial.at<SE3>(v.key), k, sigma); break;
        case Type::kOdomDifferential:
          graph.emplace<ComponentPriorFactor<Eigen::Vector3d>>(v.key, initial.at<Eigen::Vector3d>(v.key), k, sigma);
          break;
        case Type::kOdomLinear:
          graph.emplace<ComponentPriorFactor<Vector9d>>(v.key, initial.at<Vector9d>(v.key), k, sigma);
          break;
      }
      return true;
    }
  }
  return false;
}

void copy_calibration_estimates(const Values& values, PoseGraph& g) {
  for (CalibrationVertex& cv : g.calibration.vertices) {
    const Key k = vertex_key(cv.id);
    if (!values.exists(k)) continue;
    switch (cv.kind) {
      case CalibrationKind::kOffset2: {
        const SE2 s = values.at<SE2>(k);
        cv.value = Eigen::Vector3d(s.x(), s.y(), s.theta());
        break;
      }
      case CalibrationKind::kOdomDifferential: cv.value = values.at<Eigen::Vector3d>(k); break;
      case CalibrationKind::kOdomLinear: cv.value = values.at<Vector9d>(k); break;
    }
  }
  for (auto& [id, s] : g.calibration.offset_parameters2)
    if (values.exists(offset_parameter_key(id))) s = values.at<SE2>(offset_parameter_key(id));
  for (auto& [id, s] : g.sensor_offsets)
    if (values.exists(offset_parameter_key(id))) s = values.at<SE3>(offset_parameter_key(id));
  update_calibrated_measurements(g);
}

}  // namespace slamkit
