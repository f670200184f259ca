#include "slamkit/filters/data_association.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <limits>
#include <unordered_map>

#include "slamkit/core/error.h"
#include "slamkit/filters/chi_square.h"

namespace slamkit {

AssociationMethod parse_association_method(const std::string& name) {
  if (name == "known") return AssociationMethod::kKnown;
  if (name == "nn") return AssociationMethod::kNearestNeighbour;
  if (name == "jcbb") return AssociationMethod::kJcbb;
  throw InputError("--association", 0, "association", "unknown method \"" + name + "\" (known, nn, jcbb)");
}

const char* association_method_name(AssociationMethod m) {
  switch (m) {
    case AssociationMethod::kKnown: return "known";
    case AssociationMethod::kNearestNeighbour: return "nn";
    case AssociationMethod::kJcbb: return "jcbb";
  }
  return "?";
}

namespace {

double mahalanobis2(const Eigen::Vector2d& nu, const Eigen::Matrix2d& S) {
  return nu.dot(S.ldlt().solve(nu));
}

struct Candidates {
  // d2[i][j]: observation i against predicted j (infinity when not computed).
  std::vector<std::vector<double>> d2;
  std::vector<double> min_d2;
};

Candidates distances(const std::vector<RangeBearing>& obs, const std::vector<PredictedMeasurement>& pred) {
  Candidates c;
  c.d2.assign(obs.size(), std::vector<double>(pred.size()));
  c.min_d2.assign(obs.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < obs.size(); ++i)
    for (std::size_t j = 0; j < pred.size(); ++j) {
      c.d2[i][j] = mahalanobis2(RangeBearingModel::innovation(obs[i], pred[j].z), pred[j].S);
      c.min_d2[i] = std::min(c.min_d2[i], c.d2[i][j]);
    }
  return c;
}

void mark_unpaired(const Candidates& c, const AssociationOptions& o, std::vector<int>* result) {
  for (std::size_t i = 0; i < result->size(); ++i)
    if ((*result)[i] == kRejectedObservation && c.min_d2[i] >= o.new_landmark_distance2)
      (*result)[i] = kNewLandmark;
}

std::vector<int> nearest_neighbour(const std::vector<RangeBearing>& obs, const std::vector<PredictedMeasurement>& pred,
                                   const AssociationOptions& o) {
  const Candidates c = distances(obs, pred);
  std::vector<std::vector<std::pair<int, double>>> candidates(obs.size());
  for (std::size_t i = 0; i < obs.size(); ++i)
    for (std::size_t j = 0; j < pred.size(); ++j) candidates[i].emplace_back(pred[j].landmark_id, c.d2[i][j]);
  return nearest_neighbour_from_distances(candidates, chi2_quantile(o.gate_probability, 2), o.new_landmark_distance2);
}

class Jcbb {
 public:
  Jcbb(const std::vector<RangeBearing>& obs, const std::vector<PredictedMeasurement>& pred,
       const AssociationOptions& o, const JointInnovationFn& joint)
      : obs_(obs), pred_(pred), o_(o), joint_(joint), c_(distances(obs, pred)) {
    const double gate = chi2_quantile(o.gate_probability, 2);
    compatible_.resize(obs.size());
    for (std::size_t i = 0; i < obs.size(); ++i) {
      for (std::size_t j = 0; j < pred.size(); ++j)
        if (c_.d2[i][j] <= gate) compatible_[i].push_back(int(j));
      std::sort(compatible_[i].begin(), compatible_[i].end(),
                [&](int a, int b) { return c_.d2[i][a] < c_.d2[i][b]; });
    }
    for (std::size_t k = 1; k <= obs.size(); ++k) joint_gate_.push_back(chi2_quantile(o.jcbb_probability, 2.0 * k));
  }

  std::vector<int> run() {
    std::vector<int> pairing(obs_.size(), -1);
    used_.assign(pred_.size(), 0);
    search(0, 0, &pairing);
    std::vector<int> result(obs_.size(), kRejectedObservation);
    for (std::size_t i = 0; i < obs_.size(); ++i)
      if (best_[i] >= 0) result[i] = pred_[best_[i]].landmark_id;
    mark_unpaired(c_, o_, &result);
    return result;
  }

 private:
  // Joint D² of the pairings of observations [0, upto].
  double joint_d2(const std::vector<int>& pairing, std::size_t upto) const {
    std::vector<int> obs_idx, pred_idx;
    for (std::size_t i = 0; i <= upto && i < pairing.size(); ++i)
      if (pairing[i] >= 0) obs_idx.push_back(int(i)), pred_idx.push_back(pairing[i]);
    const int k = int(obs_idx.size());
    if (k == 0) return 0;
    Eigen::VectorXd nu(2 * k);
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(2 * k, 2 * k);
    for (int a = 0; a < k; ++a) {
      nu.segment<2>(2 * a) = RangeBearingModel::innovation(obs_[obs_idx[a]], pred_[pred_idx[a]].z);
      S.block<2, 2>(2 * a, 2 * a) = pred_[pred_idx[a]].S;
    }
    if (joint_) S = joint_(pred_idx);
    return nu.dot(S.ldlt().solve(nu));
  }

  void search(std::size_t i, int count, std::vector<int>* pairing) {
    if (++nodes_ > o_.jcbb_max_nodes) return;
    if (i == obs_.size()) {
      const double d2 = joint_d2(*pairing, obs_.size());
      if (count > best_count_ || (count == best_count_ && d2 < best_d2_)) {
        best_count_ = count;
        best_d2_ = d2;
        best_ = *pairing;
      }
      return;
    }
    for (int j : compatible_[i]) {
      if (used_[j]) continue;
      (*pairing)[i] = j;
      if (joint_d2(*pairing, i) <= joint_gate_[count]) {
        used_[j] = 1;
        search(i + 1, count + 1, pairing);
        used_[j] = 0;
      }
      (*pairing)[i] = -1;
    }
    const int remaining = int(obs_.size() - i - 1);
    if (count + remaining >= best_count_) search(i + 1, count, pairing);
  }

  const std::vector<RangeBearing>& obs_;
  const std::vector<PredictedMeasurement>& pred_;
  const AssociationOptions& o_;
  const JointInnovationFn& joint_;
  Candidates c_;
  std::vector<std::vector<int>> compatible_;
  std::vector<double> joint_gate_;
  std::vector<char> used_;
  std::vector<int> best_;
  int best_count_ = -1;
  double best_d2_ = std::numeric_limits<double>::infinity();
  long nodes_ = 0;
};

}  // namespace

std::vector<int> nearest_neighbour_from_distances(const std::vector<std::vector<std::pair<int, double>>>& candidates,
                                                  double gate_distance2, double new_landmark_distance2) {
  struct Pair {
    double d2;
    int i, id;
  };
  std::vector<Pair> pairs;
  std::vector<double> min_d2(candidates.size(), std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < candidates.size(); ++i)
    for (const auto& [id, d2] : candidates[i]) {
      if (d2 <= gate_distance2) pairs.push_back({d2, int(i), id});
      min_d2[i] = std::min(min_d2[i], d2);
    }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) {
    return a.d2 != b.d2 ? a.d2 < b.d2 : (a.i != b.i ? a.i < b.i : a.id < b.id);
  });
  std::vector<int> result(candidates.size(), kRejectedObservation);
  std::vector<int> used;  // a scan matches few landmarks: a short list
  for (const Pair& p : pairs)
    if (result[p.i] == kRejectedObservation && std::find(used.begin(), used.end(), p.id) == used.end()) {
      result[p.i] = p.id;
      used.push_back(p.id);
    }
  // Unmatched: a new landmark when far from every candidate, else rejected (ambiguous).
  for (std::size_t i = 0; i < result.size(); ++i)
    if (result[i] == kRejectedObservation && min_d2[i] >= new_landmark_distance2) result[i] = kNewLandmark;
  return result;
}

std::vector<int> associate(const std::vector<RangeBearing>& obs, const std::vector<PredictedMeasurement>& pred,
                           const AssociationOptions& o, const JointInnovationFn& joint) {
  switch (o.method) {
    case AssociationMethod::kKnown: {
      std::unordered_map<int, int> in_map;
      for (const auto& p : pred) in_map[p.landmark_id] = 1;
      std::vector<int> result;
      for (const auto& z : obs) {
        if (z.id < 0)
          throw InputError("association", 0, "id", "known association needs landmark ids (got id " +
                                                        std::to_string(z.id) + "); use nn or jcbb");
        result.push_back(in_map.count(z.id) ? z.id : kNewLandmark);
      }
      // The same id twice in one scan: keep the first as given, the rest would start duplicates.
      for (std::size_t i = 0; i < obs.size(); ++i)
        for (std::size_t k = 0; k < i; ++k)
          if (obs[k].id == obs[i].id && result[i] == kNewLandmark) result[i] = kRejectedObservation;
      return result;
    }
    case AssociationMethod::kNearestNeighbour:
      return nearest_neighbour(obs, pred, o);
    case AssociationMethod::kJcbb:
      return Jcbb(obs, pred, o, joint).run();
  }
  return {};
}

std::vector<int> associate_landmarks(const std::vector<RangeBearing>& obs, const Eigen::Vector3d& pose,
                                     const std::vector<int>& ids, const std::vector<Eigen::Vector2d>& means,
                                     const JointCovarianceFn& covariance, const RangeBearingModel& sensor,
                                     const AssociationOptions& o) {
  std::vector<PredictedMeasurement> pred;
  std::vector<Eigen::Matrix<double, 2, 5>> jac;  // [H_x H_m] per prediction
  if (o.method == AssociationMethod::kKnown) {
    for (int id : ids) pred.push_back({id});  // z, S: the struct's defaults (unused by known association)
    std::vector<int> result = associate(obs, pred, o);
    if (o.known_gate_probability <= 0) return result;
    const double gate = chi2_quantile(o.known_gate_probability, 2);
    std::unordered_map<int, std::size_t> index;
    for (std::size_t k = 0; k < ids.size(); ++k) index[ids[k]] = k;
    for (std::size_t i = 0; i < obs.size(); ++i) {
      if (result[i] < 0) continue;
      const Eigen::Vector2d& m = means[index.at(result[i])];
      Eigen::Matrix<double, 2, 3> H_x;
      Eigen::Matrix2d H_m;
      sensor.jacobians(pose, m, &H_x, &H_m);
      Eigen::Matrix<double, 2, 5> H;
      H << H_x, H_m;
      const Eigen::Matrix2d S = H * covariance({result[i]}) * H.transpose() + sensor.noise();
      const Eigen::Vector2d nu = RangeBearingModel::innovation(obs[i], sensor.predict(pose, m));
      if (mahalanobis2(nu, S) > gate) result[i] = kRejectedObservation;
    }
    return result;
  }
  const Eigen::Matrix2d R = sensor.noise();
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const Eigen::Vector2d z = sensor.predict(pose, means[k]);
    if (o.candidate_range > 0 && z.x() > o.candidate_range) continue;
    if (!(z.x() > 1e-9)) continue;  // a landmark at the vehicle: no bearing
    Eigen::Matrix<double, 2, 3> H_x;
    Eigen::Matrix2d H_m;
    sensor.jacobians(pose, means[k], &H_x, &H_m);
    Eigen::Matrix<double, 2, 5> H;
    H << H_x, H_m;
    const Eigen::MatrixXd C = covariance({ids[k]});
    pred.push_back({ids[k], z, H * C * H.transpose() + R});
    jac.push_back(H);
  }
  JointInnovationFn joint = [&](const std::vector<int>& idx) {
    std::vector<int> lm;
    for (int j : idx) lm.push_back(pred[j].landmark_id);
    const Eigen::MatrixXd C = covariance(lm);
    const int k = int(idx.size());
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * k, 3 + 2 * k);
    for (int a = 0; a < k; ++a) {
      H.block<2, 3>(2 * a, 0) = jac[idx[a]].leftCols<3>();
      H.block<2, 2>(2 * a, 3 + 2 * a) = jac[idx[a]].rightCols<2>();
    }
    Eigen::MatrixXd S = H * C * H.transpose();
    for (int a = 0; a < k; ++a) S.block<2, 2>(2 * a, 2 * a) += R;
    return S;
  };
  return associate(obs, pred, o, joint);
}

}  // namespace slamkit
