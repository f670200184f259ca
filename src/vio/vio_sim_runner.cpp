#include "slamkit/vio/vio_sim_runner.h"

#include <chrono>

#include "slamkit/core/error.h"
#include "slamkit/vio/feature_classifier.h"

namespace slamkit {
namespace {

constexpr double excitation_window_s = 1.0, min_accel_excitation = 0.25;  // [s], [m/s²] (VINS-Mono's check)

TrajectorySample sample_of(double t, const ImuState& s) {
  TrajectorySample x;
  x.stamp = t;
  x.T_world_body = s.pose();
  x.v_world = s.v;
  x.bias = ImuBias{s.bg, s.ba};
  return x;
}

ImuState state_of(const SimState& s) {
  ImuState x;
  x.R = SO3(s.q_world_imu);
  x.p = s.p_world;
  x.v = s.v_world;
  return x;
}

}  // namespace

VioRunResult run_vio_on_sim(const VisualInertialSim& sim, SlidingWindowOptions options,
                            const std::function<void(std::size_t, std::size_t, const FrameEstimate&)>& progress) {
  if (sim.frames.size() < 2) throw InputError(sim.source, 0, "frames", "the run has fewer than two frames");
  if (sim.imu.empty() || sim.imu.front().t > sim.frames.front().t)
    throw InputError(sim.source, 0, "imu", "no IMU sample at or before the first frame");
  if (!sim.camera) throw InputError(sim.source, 0, "camera", "the run has no camera");
  options.gravity = sim.gravity_world;
  options.imu_noise = ImuNoise{sim.imu_noise.gyro_noise_density, sim.imu_noise.accel_noise_density,
                               sim.imu_noise.gyro_random_walk, sim.imu_noise.accel_random_walk};
  options.pixel_sigma = sim.pixel_noise_sigma;
  SlidingWindowEstimator est(options, sim.camera, sim.T_cam_imu.inverse());
  VioRunResult out;
  const auto t_wall = std::chrono::steady_clock::now();
  const std::clock_t t_cpu = std::clock();
  // Start at the first frame after which the IMU shows motion (as VINS-Mono waits for
  // excitation): a sensor at rest gives the window no parallax, and the accelerometer bias
  // then goes unobserved. Uses the IMU only.
  std::size_t start = 0;
  for (std::size_t i = 0; start == 0 && i + 1 < sim.imu.size(); ++i) {
    if (sim.imu[i].t < sim.frames.front().t + excitation_window_s) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    std::size_t n = 0;
    for (std::size_t j = i; j > 0 && sim.imu[j].t > sim.imu[i].t - excitation_window_s; --j) mean += sim.imu[j].accel, ++n;
    mean /= static_cast<double>(n);
    double var = 0.0;
    for (std::size_t j = i; j > 0 && sim.imu[j].t > sim.imu[i].t - excitation_window_s; --j)
      var += (sim.imu[j].accel - mean).squaredNorm();
    if (std::sqrt(var / n) < min_accel_excitation) continue;
    for (std::size_t k = 0; k < sim.frames.size(); ++k)
      if (sim.frames[k].t >= sim.imu[i].t - excitation_window_s) {
        start = std::max<std::size_t>(k, 0);
        break;
      }
    if (start == 0) break;  // moving from the first frame on
  }
  if (start + 2 > sim.frames.size()) throw InputError(sim.source, 0, "imu", "the run never moves: nothing to initialize on");
  const SimFrame& first = sim.frames[start];
  est.initialize(first.t, state_of(first.truth));
  out.initialized_at_s = first.t - sim.imu.front().t;
  out.estimate.push_back(sample_of(first.t, state_of(first.truth)));
  out.truth.push_back(sample_of(first.t, state_of(first.truth)));
  std::size_t next_imu = 0;
  while (next_imu < sim.imu.size() && sim.imu[next_imu].t < first.t - 0.05) ++next_imu;
  double features = 0.0;
  SimLabelClassifier classifier(sim);  // the front end's static/dynamic flags (DVI)
  for (std::size_t k = start; k < sim.frames.size(); ++k) {
    const SimFrame& f = sim.frames[k];
    // IMU up to and including the sample at the frame time (and one beyond, if any).
    while (next_imu < sim.imu.size() && sim.imu[next_imu].t <= f.t + 1e-9) {
      ImuMeasurement m;
      m.stamp = sim.imu[next_imu].t, m.gyro = sim.imu[next_imu].gyro, m.accel = sim.imu[next_imu].accel;
      est.add_imu(m);
      ++next_imu;
    }
    if (k == start) continue;
    CameraFrame cf;
    cf.stamp = f.t;
    for (const SimObservation& o : f.observations)
      cf.features.push_back({static_cast<std::uint64_t>(o.track_id), o.uv});
    classifier.classify(k, cf);
    const FrameEstimate e = est.add_frame(cf);
    if (!e.state.p.allFinite() || !e.state.v.allFinite())
      throw NumericalError("vio: the estimate at t = " + std::to_string(f.t) + " is not finite");
    out.frames.push_back(e);
    out.estimate.push_back(sample_of(f.t, e.state));
    ImuState truth = state_of(f.truth);
    truth.bg = f.truth.b_g, truth.ba = f.truth.b_a;
    out.truth.push_back(sample_of(f.t, truth));
    out.keyframes += e.keyframe;
    features += e.features;
    if (progress) progress(k, sim.frames.size(), e);
  }
  out.features_per_frame = features / std::max<std::size_t>(1, out.frames.size());
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_wall).count();
  out.cpu_time_s = static_cast<double>(std::clock() - t_cpu) / CLOCKS_PER_SEC;
  out.sequence_duration_s = sim.frames.back().t - first.t;
  return out;
}

}  // namespace slamkit
