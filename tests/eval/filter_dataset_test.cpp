// The dataset replay loop: on a noise-free synthetic event stream every score has a known
// value; the GPS alignment is invariant to a rigid motion; bad specs name the field; the known-id
// gate rejects a gross outlier sighting.
#include "slamkit/eval/filter_dataset.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "slamkit/core/error.h"
#include "slamkit/filters/filter_factory.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {
namespace {

// A unicycle driving a circle among four landmarks, observed exactly every 10th step.
LandmarkDataset circle_dataset(const UnicycleModel& model) {
  LandmarkDataset ds;
  ds.name = "circle";
  const std::vector<Eigen::Vector2d> lm = {{5, 0}, {0, 8}, {-6, 2}, {1, -7}};
  for (int i = 0; i < 4; ++i) ds.true_landmarks.push_back({10 + i, lm[i]});
  const RangeBearingModel h(0.1, 0.01);
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  double t = 0;
  for (int k = 0; k < 600; ++k) {
    ds.truth_times.push_back(t), ds.truth_poses.push_back(x);
    if (k % 10 == 0) {
      LandmarkDatasetEvent scan;
      scan.time = t, scan.is_scan = true;
      for (int i = 0; i < 4; ++i) {
        const Eigen::Vector2d z = h.predict(x, lm[i]);
        scan.observations.push_back({10 + i, z.x(), z.y()});
      }
      ds.events.push_back(scan);
    }
    LandmarkDatasetEvent c;
    c.time = t, c.control = {1.0, 0.2, 0.05};
    ds.events.push_back(c);
    x = model.predict(x, c.control);
    t += 0.05;
  }
  ds.truth_times.push_back(t), ds.truth_poses.push_back(x);
  return ds;
}

TEST(FilterDataset, NoiseFreeStreamGivesZeroErrorsAndCountsEverything) {
  const auto model = std::make_shared<UnicycleModel>(0.05, 0.05, 0.1, 0.1);
  const LandmarkDataset ds = circle_dataset(*model);
  for (const std::string alg : {"ekf", "seif", "fastslam2"}) {
    LandmarkFilterOptions fo;
    fo.motion = model;
    fo.sensor = RangeBearingModel(0.1, 0.01);
    fo.particles = 20;
    auto f = make_landmark_filter(alg, fo);
    int progress_calls = 0;
    DatasetRunOptions ro;
    ro.progress_every = 20;
    ro.progress = [&](int, int total, int, double) { ++progress_calls;
      EXPECT_EQ(total, 60); };
    const DatasetRunResult r = run_filter_on_dataset(f.get(), *model, ds, ro);
    EXPECT_EQ(r.events, 660) << alg;
    EXPECT_EQ(r.scans, 60) << alg;
    EXPECT_EQ(progress_calls, 3) << alg;
    EXPECT_EQ(r.run.step_ms.size(), 660u);
    EXPECT_EQ(r.run.truth.size(), 60u);
    EXPECT_EQ(r.landmarks, 4) << alg;
    EXPECT_EQ(r.mapped_true_landmarks, 4) << alg;
    EXPECT_NEAR(r.dead_reckoning_rmse_position, 0, 1e-9) << alg;  // same model as the truth
    EXPECT_LT(r.rmse_position, 0.05) << alg;
    EXPECT_LT(r.map_rmse, 0.1) << alg;
    EXPECT_TRUE(r.run.finite);
    EXPECT_GE(r.time_per_step_max_ms, r.time_per_step_mean_ms);
    EXPECT_TRUE(std::isnan(r.gps_rms));
  }
}

TEST(FilterDataset, AlignedRmsIsInvariantToARigidMotion) {
  std::vector<Eigen::Vector2d> a = {{0, 0}, {1, 0}, {3, 2}, {-1, 4}}, b;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(0.7).toRotationMatrix();
  for (const auto& p : a) b.push_back(R * p + Eigen::Vector2d(5, -3));
  EXPECT_NEAR(aligned_rms(a, b), 0, 1e-12);
  b[0] += Eigen::Vector2d(0, 2);
  EXPECT_GT(aligned_rms(a, b), 0.1);
}

TEST(FilterDataset, BadSpecsNameTheField) {
  for (const std::string spec : {"x:y", "mrclam:dir", "mrclam:dir:0", "mrclam:dir:two", "victoria:"}) {
    try {
      load_landmark_dataset(spec);
      ADD_FAILURE() << spec << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "dataset") << spec;
    }
  }
  EXPECT_THROW(load_landmark_dataset("mrclam:/no/such/dir:1"), InputError);
}

TEST(FilterDataset, KnownGateRejectsAGrossOutlier) {
  const auto model = std::make_shared<UnicycleModel>(0.05, 0.05, 0.1, 0.1);
  for (double gate : {0.0, 0.999}) {
    LandmarkFilterOptions fo;
    fo.motion = model;
    fo.sensor = RangeBearingModel(0.1, 0.01);
    fo.association.known_gate_probability = gate;
    auto f = make_landmark_filter("ekf", fo);
    f->update({{1, 5.0, 0.0}, {2, 8.0, 1.0}});
    f->predict({1.0, 0.0, 0.1});
    f->update({{1, 4.9, 0.0}, {2, 2.0, -2.0}});  // landmark 2: 6 m and 3 rad off
    EXPECT_EQ(f->last_update().associated, gate > 0 ? 1 : 2);
    EXPECT_EQ(f->last_update().rejected, gate > 0 ? 1 : 0);
  }
}

}  // namespace
}  // namespace slamkit
