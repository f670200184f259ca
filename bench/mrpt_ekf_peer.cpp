// slamkit EKF-SLAM against MRPT's mrpt::slam::CRangeBearingKFSLAM2D (issue 15): the SAME
// simulated run (generated world of N landmarks, seed 1, the Bailey vehicle and sensor) goes
// through both filters in one process, step by step, known association (MRPT gets the landmark
// ids in CObservationBearingRange::landmarkID). Every control step is one filter step for
// both: slamkit predicts with the bicycle model and the noisy (v, G) and updates when a scan
// arrives; MRPT gets the odometry increment f(0, u) of the same control as a Gaussian
// CActionRobotMovement2D, and the scan (or an empty sensory frame) in the same
// processActionObservation call. Timing: thread CPU time per step, mean over all steps and over
// the last 10% (map at its final size), and binned by map size. Built only when MRPT is found.
// With --survey 1 the first update is a survey scan of the whole world (sim/survey_scan) given to
// both filters, so the timed steps run at exactly N landmarks from the start.
//   mrpt_ekf_peer [--landmarks N] [--steps S (0: whole route)] [--survey 0|1] [--out FILE]
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationBearingRange.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/slam/CRangeBearingKFSLAM2D.h>
#include <mrpt/version.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "bench_data.h"
#include "slamkit/filters/filter_factory.h"
#include "slamkit/geometry/lie_math.h"
#include "slamkit/sim/landmark_sim.h"

using namespace slamkit;

namespace {


struct Timing {
  double total = 0, last = 0, max = 0, se_pos = 0;
  long last_steps = 0, scans = 0;
  std::map<int, std::pair<double, long>> bins;  // ⌊log10(map size)·4⌋ → (Σ ms, steps)
  void add(double ms, int map_size, bool in_last) {
    total += ms, max = std::max(max, ms);
    if (in_last) last += ms, ++last_steps;
    if (map_size > 0) {
      auto& b = bins[int(std::floor(std::log10(map_size) * 4))];
      b.first += ms, ++b.second;
    }
  }
  nlohmann::json json(long steps, int landmarks) const {
    nlohmann::json curve = nlohmann::json::array();
    for (const auto& [bin, v] : bins)
      curve.push_back({{"landmarks", std::pow(10.0, (bin + 0.5) / 4)}, {"ms", v.first / v.second}, {"steps", v.second}});
    return {{"time_per_step_ms", {{"mean", total / steps}, {"max", max}}},
            {"time_per_step_ms_last_10pct", last / std::max(1L, last_steps)},
            {"total_s", total / 1000}, {"final_landmarks", landmarks},
            {"rmse_position", std::sqrt(se_pos / std::max(1L, scans))}, {"by_map_size", curve}};
  }
};

// One MRPT sensory frame with a bearing-range observation of `z` (MRPT needs one in every
// frame: empty between scans), known ids in landmarkID.
mrpt::obs::CSensoryFrame::Ptr sensory_frame(const std::vector<RangeBearing>& z, const LandmarkSimOptions& sim,
                                             double max_range) {
  auto sf = mrpt::obs::CSensoryFrame::Create();
  auto obs = mrpt::obs::CObservationBearingRange::Create();
  obs->sensor_std_range = float(sim.sigma_range);
  obs->sensor_std_yaw = float(sim.sigma_bearing);
  obs->sensor_std_pitch = 0;
  obs->validCovariances = false;
  obs->maxSensorDistance = float(max_range);
  obs->fieldOfView_yaw = float(2 * kPi);
  for (const RangeBearing& o : z) {
    mrpt::obs::CObservationBearingRange::TMeasurement m;
    m.range = float(o.range);
    m.yaw = float(o.bearing);
    m.pitch = 0;
    m.landmarkID = o.id;
    obs->sensedData.push_back(m);
  }
  sf->insert(obs);
  return sf;
}

}  // namespace

int main(int argc, char** argv) {
  int n = 1000, max_steps = 0;
  bool survey = false;
  std::string out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/mrpt_ekf_peer.json";
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--landmarks")) n = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--steps")) max_steps = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--out")) out = argv[i + 1];
    if (!std::strcmp(argv[i], "--survey")) survey = std::atoi(argv[i + 1]) != 0;
  }
  char version[16];
  std::snprintf(version, sizeof version, "%d.%d.%d", MRPT_VERSION >> 8, (MRPT_VERSION >> 4) & 15, MRPT_VERSION & 15);
  const std::string mrpt_version = version;
  LandmarkSimOptions sim;
  sim.max_steps = max_steps;
  std::vector<Eigen::Vector2d> lm, wp;
  generate_landmark_world(n, 1, &lm, &wp);
  const LandmarkSimRun run = simulate_landmark_run(lm, wp, sim, 1);
  const auto bicycle = std::make_shared<BicycleModel>(sim.wheelbase, sim.sigma_v, sim.sigma_steer);

  LandmarkFilterOptions fo;
  fo.motion = bicycle;
  fo.sensor = RangeBearingModel(sim.sigma_range, sim.sigma_bearing);
  fo.expected_landmarks = n;
  auto ekf = make_landmark_filter("ekf", fo);

  mrpt::slam::CRangeBearingKFSLAM2D mrpt_ekf;
  mrpt_ekf.KF_options.method = mrpt::bayes::kfEKFNaive;
  mrpt_ekf.KF_options.use_analytic_observation_jacobian = true;
  mrpt_ekf.KF_options.use_analytic_transition_jacobian = true;
  mrpt_ekf.options.std_sensor_range = float(sim.sigma_range);
  mrpt_ekf.options.std_sensor_yaw = float(sim.sigma_bearing);
  mrpt::obs::CActionRobotMovement2D::TMotionModelOptions motion;
  motion.modelSelection = mrpt::obs::CActionRobotMovement2D::mmGaussian;
  // Per-step σ of the odometry increment comparable to the bicycle's: σ_v dt in x/y, and the
  // heading σ of a 3° steering error over one step.
  motion.gaussianModel = {0.05, 0.0, 0.0, 0.05, sim.sigma_v * sim.dt,
                          sim.speed * sim.dt * std::sin(sim.sigma_steer) / sim.wheelbase};

  const long steps = long(run.steps.size());
  int map_sk = 0;
  double survey_ms_sk = 0, survey_ms_mrpt = 0;
  if (survey) {
    // The whole world enters both maps in one first update from the start pose (untimed in the
    // step statistics), so every timed step runs at exactly n landmarks.
    const std::vector<RangeBearing> z = survey_scan(lm, Eigen::Vector3d::Zero(), sim, 1000 + n);
    double t0 = bench::thread_cpu_ms();
    ekf->update(z);
    survey_ms_sk = bench::thread_cpu_ms() - t0;
    map_sk = ekf->last_update().new_landmarks;
    auto act = mrpt::obs::CActionCollection::Create();
    mrpt::obs::CActionRobotMovement2D still;
    still.computeFromOdometry(mrpt::poses::CPose2D(0, 0, 0), motion);
    act->insert(still);
    t0 = bench::thread_cpu_ms();
    auto survey_frame = sensory_frame(z, sim, 1e9);
    mrpt_ekf.processActionObservation(act, survey_frame);
    survey_ms_mrpt = bench::thread_cpu_ms() - t0;
    std::printf("survey: %zu observations, slamkit %d landmarks in %.0f ms, MRPT %zu in %.0f ms\n", z.size(), map_sk,
                survey_ms_sk, mrpt_ekf.getNumberOfLandmarksInTheMap(), survey_ms_mrpt);
  }
  const long last_from = steps * 9 / 10;
  Timing t_sk, t_mrpt;
  std::printf("generated:%d, %ld control steps; slamkit EKF and MRPT %s CRangeBearingKFSLAM2D\n", n, steps, mrpt_version.c_str());
  for (long k = 0; k < steps; ++k) {
    const LandmarkSimStep& s = run.steps[k];
    const Control u{s.v, s.steer, sim.dt};
    double t0 = bench::thread_cpu_ms();
    ekf->predict(u);
    if (s.observed) ekf->update(s.observations);
    t_sk.add(bench::thread_cpu_ms() - t0, map_sk, k >= last_from);
    if (s.observed) map_sk += ekf->last_update().new_landmarks;

    // MRPT: the same control as an odometry increment, the same scan.
    const Eigen::Vector3d d = bicycle->predict(Eigen::Vector3d::Zero(), u);
    auto act = mrpt::obs::CActionCollection::Create();
    mrpt::obs::CActionRobotMovement2D move;
    move.computeFromOdometry(mrpt::poses::CPose2D(d.x(), d.y(), d.z()), motion);
    act->insert(move);
    auto sf = sensory_frame(s.observations, sim, sim.max_range);
    const int map_mrpt = int(mrpt_ekf.getNumberOfLandmarksInTheMap());
    t0 = bench::thread_cpu_ms();
    mrpt_ekf.processActionObservation(act, sf);
    t_mrpt.add(bench::thread_cpu_ms() - t0, map_mrpt, k >= last_from);

    if (s.observed) {
      mrpt::poses::CPosePDFGaussian p;
      mrpt_ekf.getCurrentRobotPose(p);
      t_mrpt.se_pos += (Eigen::Vector2d(p.mean.x(), p.mean.y()) - s.true_pose.head<2>()).squaredNorm();
      t_sk.se_pos += (ekf->pose().head<2>() - s.true_pose.head<2>()).squaredNorm();
      ++t_mrpt.scans, ++t_sk.scans;
    }
    if ((k + 1) % 2000 == 0 || k + 1 == steps)
      std::printf("  step %ld/%ld: slamkit %d landmarks %.3f ms/step, MRPT %zu landmarks %.3f ms/step\n", k + 1, steps,
                  map_sk, t_sk.total / (k + 1), mrpt_ekf.getNumberOfLandmarksInTheMap(), t_mrpt.total / (k + 1)),
          std::fflush(stdout);
  }
  const int mrpt_landmarks = int(mrpt_ekf.getNumberOfLandmarksInTheMap());
  nlohmann::json doc = {
      {"benchmark", "mrpt_ekf_peer"},
      {"command", "build/bench/mrpt_ekf_peer --landmarks " + std::to_string(n) + " --steps " + std::to_string(max_steps) +
                      (survey ? " --survey 1" : "")},
      {"survey", survey},
      {"survey_update_ms", {{"slamkit", survey_ms_sk}, {"mrpt", survey_ms_mrpt}}},
      {"what", "slamkit EKF-SLAM vs MRPT CRangeBearingKFSLAM2D on the same simulated run, known association, one process"},
      {"world", "generated:" + std::to_string(n)}, {"seed", 1}, {"steps", steps},
      {"timing", "thread CPU time per control step (predict + update when a scan arrives), Release, 1 thread"},
      {"mrpt_version", mrpt_version},
      {"slamkit", t_sk.json(steps, map_sk)}, {"mrpt", t_mrpt.json(steps, mrpt_landmarks)},
      {"ratio_slamkit_over_mrpt", t_sk.total / t_mrpt.total},
      {"ratio_slamkit_over_mrpt_last_10pct", t_sk.last / t_mrpt.last}};
  std::printf("slamkit %.4f ms/step (last 10%%: %.4f), MRPT %.4f ms/step (last 10%%: %.4f): slamkit/MRPT = %.3f (last 10%%: %.3f); "
              "position RMSE slamkit %.3f m, MRPT %.3f m; landmarks %d / %d\n",
              t_sk.total / steps, t_sk.last / std::max(1L, t_sk.last_steps), t_mrpt.total / steps,
              t_mrpt.last / std::max(1L, t_mrpt.last_steps), t_sk.total / t_mrpt.total, t_sk.last / t_mrpt.last,
              std::sqrt(t_sk.se_pos / t_sk.scans), std::sqrt(t_mrpt.se_pos / t_mrpt.scans), map_sk, mrpt_landmarks);
  std::ofstream(out) << doc.dump(2) << "\n";
  std::printf("wrote %s\n", out.c_str());
  return 0;
}
