// Data association: gates, wrapped bearings, new/rejected decisions, JCBB against greedy NN,
// and nearest neighbour inside the EKF on a simulated run.
#include "slamkit/filters/data_association.h"

#include <gtest/gtest.h>

#include <cmath>
#include <Eigen/LU>
#include <random>
#include <set>

#include "filter_test_util.h"
#include "slamkit/core/error.h"
#include "slamkit/filters/chi_square.h"
#include "slamkit/filters/ekf_slam.h"
#include "slamkit/filters/fastslam.h"

namespace slamkit {
namespace {

constexpr double kPi = 3.14159265358979323846;

PredictedMeasurement predicted(int id, double r, double b, double sr = 0.1, double sb = 0.02) {
  PredictedMeasurement p;
  p.landmark_id = id;
  p.z << r, b;
  p.S = Eigen::Vector2d(sr * sr, sb * sb).asDiagonal();
  return p;
}

TEST(DataAssociation, NearestNeighbourGatesWrapsAndStartsNewLandmarks) {
  AssociationOptions o;
  o.method = AssociationMethod::kNearestNeighbour;
  const std::vector<PredictedMeasurement> pred = {predicted(7, 10, kPi - 0.01), predicted(9, 20, 0.5),
                                                  predicted(4, 5, -1.0)};
  const std::vector<RangeBearing> z = {
      {-1, 10.05, -kPi + 0.005},  // across ±π from landmark 7
      {-1, 20.0, 0.51},           // landmark 9
      {-1, 40.0, 2.0},            // far from everything: new
      {-1, 5.0, -1.0 + 0.07},     // 3.5σ in bearing from 4: d² = 12.25, outside the gate, below 25
  };
  const std::vector<int> a = associate(z, pred, o);
  EXPECT_EQ(a, (std::vector<int>{7, 9, kNewLandmark, kRejectedObservation}));
}

TEST(DataAssociation, EachLandmarkAtMostOnceAndKnownIds) {
  AssociationOptions o;
  o.method = AssociationMethod::kNearestNeighbour;
  const std::vector<PredictedMeasurement> pred = {predicted(1, 10, 0)};
  const std::vector<int> a = associate({{-1, 10.0, 0.001}, {-1, 10.02, 0.0}}, pred, o);
  EXPECT_EQ(a[0], 1);
  EXPECT_NE(a[1], 1);
  o.method = AssociationMethod::kKnown;
  EXPECT_EQ(associate({{1, 3, 0}, {5, 3, 0}}, pred, o), (std::vector<int>{1, kNewLandmark}));
  EXPECT_THROW(associate({{-1, 3, 0}}, pred, o), InputError);
  EXPECT_THROW(parse_association_method("nearest"), InputError);
}

// FastSLAM's per-particle association and the Gaussian filters' nn share one core: on random
// scenes associate() (nn) and fastslam_associate give the same answer as the core itself.
TEST(DataAssociation, FastSlamAndNearestNeighbourShareOneCore) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> r(1, 30), b(-kPi, kPi), off(-1.5, 1.5);
  AssociationOptions o;
  o.method = AssociationMethod::kNearestNeighbour;
  const double gate = chi2_quantile(o.gate_probability, 2);
  int matched = 0, fresh = 0, rejected = 0;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<PredictedMeasurement> pred;
    std::vector<RangeBearing> obs;
    for (int j = 0; j < 6; ++j) pred.push_back(predicted(100 + 3 * j, r(rng), b(rng), 0.3, 0.05));
    for (int i = 0; i < 5; ++i) {
      const auto& p = pred[(i * 5 + trial) % 4];  // some landmarks twice: one is left over
      obs.push_back({-1, p.z.x() + off(rng), p.z.y() + 0.2 * off(rng)});
    }
    std::vector<std::vector<std::pair<int, double>>> cand(obs.size());
    for (std::size_t i = 0; i < obs.size(); ++i)
      for (const auto& p : pred) {
        const Eigen::Vector2d nu = RangeBearingModel::innovation(obs[i], p.z);
        cand[i].emplace_back(p.landmark_id, nu.dot(p.S.inverse() * nu));
      }
    const std::vector<int> core = nearest_neighbour_from_distances(cand, gate, o.new_landmark_distance2);
    EXPECT_EQ(associate(obs, pred, o), core);
    EXPECT_EQ(fastslam_associate(cand, gate, o.new_landmark_distance2), core);
    for (int a : core) matched += a >= 0, fresh += a == kNewLandmark, rejected += a == kRejectedObservation;
  }
  EXPECT_GT(matched, 0);  // the scenes exercise every outcome
  EXPECT_GT(fresh + rejected, 0);
}

TEST(DataAssociation, JcbbUsesTheCorrelationGreedyNearestNeighbourIgnores) {
  // Two landmarks 0.1 rad apart; a common heading error rotates both observations by 0.15 rad.
  // Individually the first observation is closest to the wrong landmark; jointly (the heading
  // uncertainty is shared: bearing correlation 0.999) only the correct pairing fits.
  const std::vector<PredictedMeasurement> pred = {predicted(0, 10, 0.0, 0.1, 0.1), predicted(1, 10, 0.1, 0.1, 0.1)};
  const std::vector<RangeBearing> z = {{-1, 10.0, 0.15}, {-1, 10.0, 0.25}};
  AssociationOptions o;
  o.method = AssociationMethod::kNearestNeighbour;
  EXPECT_EQ(associate(z, pred, o), (std::vector<int>{1, 0}));
  JointInnovationFn joint = [&](const std::vector<int>& idx) {
    const int k = int(idx.size());
    Eigen::MatrixXd S = Eigen::MatrixXd::Zero(2 * k, 2 * k);
    for (int a = 0; a < k; ++a)
      for (int b = 0; b < k; ++b) {
        S(2 * a, 2 * b) = a == b ? 0.01 : 0.0;
        S(2 * a + 1, 2 * b + 1) = a == b ? 0.01 : 0.00999;
      }
    return S;
  };
  o.method = AssociationMethod::kJcbb;
  EXPECT_EQ(associate(z, pred, o, joint), (std::vector<int>{0, 1}));
}

TEST(DataAssociation, EkfWithNearestNeighbourMapsEveryLandmarkOnce) {
  auto w = testing::small_world(20, 2500, 5);
  const LandmarkSimRun run = simulate_landmark_run(w.landmarks, w.waypoints, w.sim, 3);
  std::set<int> seen;
  for (const auto& s : run.steps)
    for (const auto& z : s.observations) seen.insert(z.id);
  for (auto method : {AssociationMethod::kNearestNeighbour, AssociationMethod::kJcbb}) {
    w.filter.association.method = method;
    EkfSlam ekf(w.filter);
    LandmarkSimRun blind = run;  // the filter must not see the ids
    for (auto& s : blind.steps)
      for (auto& z : s.observations) z.id = -1;
    testing::run_filter(&ekf, blind, w.sim, [](std::size_t) {});
    const auto map = ekf.landmarks();
    EXPECT_EQ(map.size(), seen.size()) << association_method_name(method);
    // Every estimated landmark is near a distinct true one.
    std::set<int> matched;
    for (const auto& m : map) {
      int best = -1;
      double d = 1e9;
      for (std::size_t i = 0; i < w.landmarks.size(); ++i)
        if ((w.landmarks[i] - m.mean).norm() < d) d = (w.landmarks[i] - m.mean).norm(), best = int(i);
      EXPECT_LT(d, 3.0);
      matched.insert(best);
    }
    EXPECT_EQ(matched.size(), map.size()) << association_method_name(method);
  }
}

}  // namespace
}  // namespace slamkit
