#include "slamkit/vio/vio_sim_runner.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>

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

ImuState state_of(const SimState& s, bool with_biases = false) {
  ImuState x;
  x.R = SO3(s.q_world_imu);
  x.p = s.p_world;
  x.v = s.v_world;
  if (with_biases) x.bg = s.b_g, x.ba = s.b_a;
  return x;
}

double yaw_of(const SO3& R) {
  const Eigen::Matrix3d m = R.matrix();
  return std::atan2(m(1, 0), m(0, 0));
}

// The frame's observations; with a counter `left_out`, without the dynamic-flagged ones (counted there).
CameraFrame camera_frame(const SimFrame& f, int* left_out = nullptr) {
  CameraFrame cf;
  cf.stamp = f.t;
  for (const SimObservation& o : f.observations) {
    if (left_out && o.dynamic) {
      ++*left_out;
      continue;
    }
    FeatureObservation x;
    x.track_id = static_cast<std::uint64_t>(o.track_id), x.pixel = o.uv, x.classified = o.classified;
    cf.features.push_back(x);
  }
  return cf;
}

// Mean pixel motion of the tracks common to a and b (∞ when none are common).
double mean_track_motion(const SimFrame& a, const SimFrame& b) {
  std::unordered_map<std::int64_t, Eigen::Vector2d> pa;
  for (const SimObservation& o : a.observations) pa[o.track_id] = o.uv;
  double sum = 0.0;
  int n = 0;
  for (const SimObservation& o : b.observations)
    if (const auto it = pa.find(o.track_id); it != pa.end()) sum += (o.uv - it->second).norm(), ++n;
  return n > 0 ? sum / n : std::numeric_limits<double>::infinity();
}

// First frame after which the IMU shows motion (as VINS-Mono waits for excitation): a sensor
// at rest gives no parallax, and the accelerometer bias then goes unobserved. IMU only.
std::size_t first_moving_frame(const VisualInertialSim& sim) {
  for (std::size_t i = 0; i + 1 < sim.imu.size(); ++i) {
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
      if (sim.frames[k].t >= sim.imu[i].t - excitation_window_s) return k;
    return sim.frames.size();
  }
  return sim.frames.size();
}

std::vector<ImuMeasurement> imu_between(const VisualInertialSim& sim, double t0, double t1) {
  std::vector<ImuMeasurement> out;
  for (const SimImuSample& s : sim.imu) {
    if (s.t < t0 - 0.05 || s.t > t1 + 0.05) continue;
    ImuMeasurement m;
    m.stamp = s.t, m.gyro = s.gyro, m.accel = s.accel;
    out.push_back(m);
  }
  return out;
}

struct Startup {
  std::vector<std::size_t> frames;  // window frame indices
  std::vector<ImuState> states;     // gauge-aligned states of the window frames
};

// The start-up window and the initializer, retried by sliding the window (see the header).
Startup initialize_without_truth(const VisualInertialSim& sim, std::size_t start, const VioStartupOptions& o,
                                 bool skip_dynamic, VioStartupReport* report) {
  VisualSfmOptions sfm = o.sfm;
  sfm.focal_px = sim.camera->intrinsics()(0);
  sfm.pixel_sigma = sim.pixel_noise_sigma;
  const ImuNoise noise{sim.imu_noise.gyro_noise_density, sim.imu_noise.accel_noise_density,
                       sim.imu_noise.gyro_random_walk, sim.imu_noise.accel_random_walk};
  const SE3 T_imu_cam = sim.T_cam_imu.inverse();
  InitializerOptions alignment = o.alignment;
  alignment.gravity_magnitude = sim.gravity_world.norm();
  std::vector<std::size_t> w{start};
  std::string last = "no full window";
  for (std::size_t k = start + 1; k < sim.frames.size(); ++k) {
    if (mean_track_motion(sim.frames[w.back()], sim.frames[k]) < o.frame_parallax_px &&
        static_cast<int>(k - w.back()) < o.max_frame_gap)
      continue;
    w.push_back(k);
    if (static_cast<int>(w.size()) < o.window_frames) continue;
    std::vector<CameraFrame> frames;
    int left_out = 0;
    for (std::size_t i : w) frames.push_back(camera_frame(sim.frames[i], skip_dynamic ? &left_out : nullptr));
    ++report->attempts;
    const InitializerResult r = initialize_from_frames(frames, imu_between(sim, frames.front().stamp, frames.back().stamp),
                                                       *sim.camera, T_imu_cam, noise, sfm, alignment);
    if (!r.success) {
      last = r.message;
      w.erase(w.begin());
      continue;
    }
    // Gauge: yaw and position of the first window frame from its truth.
    const SimState& t0 = sim.frames[w.front()].truth;
    const SO3 dR = SO3::exp(Eigen::Vector3d(0, 0, yaw_of(SO3(t0.q_world_imu)) - yaw_of(r.states.front().R)));
    const Eigen::Vector3d dp = t0.p_world - dR.act(r.states.front().p);
    Startup s;
    s.frames = w;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero(), true_mean = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < w.size(); ++i) {
      ImuState x = r.states[i];
      x.R = dR * x.R, x.p = dR.act(x.p) + dp, x.v = dR.act(x.v);
      s.states.push_back(x);
      const SimState& t = sim.frames[w[i]].truth;
      report->velocity_error = std::max(report->velocity_error, (x.v - t.v_world).norm());
      mean += x.p / w.size(), true_mean += t.p_world / w.size();
    }
    // Scale error: the spread of the positions about their mean against the truth's.
    double spread = 0.0, true_spread = 0.0;
    for (std::size_t i = 0; i < w.size(); ++i)
      spread += (s.states[i].p - mean).squaredNorm(), true_spread += (sim.frames[w[i]].truth.p_world - true_mean).squaredNorm();
    report->scale_error = true_spread > 0 ? std::abs(std::sqrt(spread / true_spread) - 1.0) : 0.0;
    const Eigen::Vector3d up_est = s.states.front().R.inverse().act(Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d up_true = SO3(t0.q_world_imu).inverse().act(Eigen::Vector3d::UnitZ());
    report->gravity_error_deg = std::acos(std::clamp(up_est.dot(up_true), -1.0, 1.0)) * 180.0 / kPi;
    report->gyro_bias_error = (r.gyro_bias - sim.frames[w.back()].truth.b_g).norm();
    report->rotation_rms_deg = r.rotation_rms_deg;
    report->scale_rel_sigma = r.scale_sigma / r.scale;
    report->dynamic_left_out = left_out;
    report->message = r.message;
    return s;
  }
  throw InputError(sim.source, 0, "frames",
                   "sequence too short to initialize: " + std::to_string(report->attempts) +
                       " start-up windows tried after the motion starts at t = " +
                       std::to_string(sim.frames[start].t - sim.frames.front().t) + " s, last: " + last);
}

}  // namespace

VioRunResult run_vio_on_sim(const VisualInertialSim& sim, SlidingWindowOptions options,
                            const std::function<void(std::size_t, std::size_t, const FrameEstimate&)>& progress,
                            const VioStartupOptions& startup) {
  if (sim.frames.size() < 2) throw InputError(sim.source, 0, "frames", "the run has fewer than two frames");
  if (sim.imu.empty() || sim.imu.front().t > sim.frames.front().t)
    throw InputError(sim.source, 0, "imu", "no IMU sample at or before the first frame");
  if (!sim.camera) throw InputError(sim.source, 0, "camera", "the run has no camera");
  for (std::size_t i = 1; i < sim.imu.size(); ++i)
    if (!(sim.imu[i].t > sim.imu[i - 1].t))
      throw InputError(sim.source, 0, "imu", "IMU sample " + std::to_string(i) + " at t = " + std::to_string(sim.imu[i].t) +
                                                 " s does not follow the previous one at " + std::to_string(sim.imu[i - 1].t) + " s");
  for (std::size_t k = 1; k < sim.frames.size(); ++k)
    if (!(sim.frames[k].t > sim.frames[k - 1].t))
      throw InputError(sim.source, 0, "frames", "frame " + std::to_string(k) + " at t = " + std::to_string(sim.frames[k].t) +
                                                    " s does not follow the previous one");
  options.gravity = sim.gravity_world;
  options.imu_noise = ImuNoise{sim.imu_noise.gyro_noise_density, sim.imu_noise.accel_noise_density,
                               sim.imu_noise.gyro_random_walk, sim.imu_noise.accel_random_walk};
  options.pixel_sigma = sim.pixel_noise_sigma;
  VioRunResult out;
  const auto t_wall = std::chrono::steady_clock::now();
  const std::clock_t t_cpu = std::clock();
  const std::size_t moving = first_moving_frame(sim);
  if (moving + 2 > sim.frames.size())
    throw InputError(sim.source, 0, "imu", "sequence too short to initialize: the run never moves");
  // The estimator starts at frame `start` from `initial`.
  std::size_t start = moving;
  ImuState initial;
  if (startup.use_ground_truth) {
    initial = state_of(sim.frames[start].truth);
    out.startup.method = "ground truth";
    out.startup.message = "true state at the first moving frame (biases zero)";
    out.estimate.push_back(sample_of(sim.frames[start].t, initial));
    out.truth.push_back(sample_of(sim.frames[start].t, state_of(sim.frames[start].truth, true)));
  } else {
    out.startup.method = "visual-inertial initializer";
    const Startup s = initialize_without_truth(sim, moving, startup, startup.dvi_startup && options.dvi.enabled, &out.startup);
    start = s.frames.back();
    initial = s.states.back();
    out.startup.window_frames = static_cast<int>(s.frames.size());
    out.startup.window_start_s = sim.frames[s.frames.front()].t - sim.imu.front().t;
    out.startup.window_end_s = sim.frames[start].t - sim.imu.front().t;
    for (std::size_t i = 0; i < s.frames.size(); ++i) {
      const SimFrame& f = sim.frames[s.frames[i]];
      out.estimate.push_back(sample_of(f.t, s.states[i]));
      out.truth.push_back(sample_of(f.t, state_of(f.truth, true)));
    }
    options.prior_rotation_sigma = startup.prior_rotation_sigma;
    options.prior_velocity_sigma = startup.prior_velocity_sigma;
  }
  SlidingWindowEstimator est(options, sim.camera, sim.T_cam_imu.inverse());
  const SimFrame& first = sim.frames[start];
  est.initialize(first.t, initial);
  out.initialized_at_s = first.t - sim.imu.front().t;
  std::size_t next_imu = 0;
  while (next_imu < sim.imu.size() && sim.imu[next_imu].t < first.t - 0.05) ++next_imu;
  double features = 0.0;
  SimLabelClassifier classifier(sim);  // the front end's static/dynamic flags (DVI)
  for (std::size_t k = start; k < sim.frames.size(); ++k) {
    const SimFrame& f = sim.frames[k];
    // IMU up to and including the sample at the frame time.
    while (next_imu < sim.imu.size() && sim.imu[next_imu].t <= f.t + 1e-9) {
      ImuMeasurement m;
      m.stamp = sim.imu[next_imu].t, m.gyro = sim.imu[next_imu].gyro, m.accel = sim.imu[next_imu].accel;
      est.add_imu(m);
      ++next_imu;
    }
    if (k == start) continue;
    CameraFrame cf = camera_frame(f);
    classifier.classify(k, cf);
    const FrameEstimate e = est.add_frame(cf);
    if (!e.state.p.allFinite() || !e.state.v.allFinite())
      throw NumericalError("vio: the estimate at t = " + std::to_string(f.t) + " is not finite");
    out.frames.push_back(e);
    out.estimate.push_back(sample_of(f.t, e.state));
    out.truth.push_back(sample_of(f.t, state_of(f.truth, true)));
    out.keyframes += e.keyframe;
    features += e.features;
    if (progress) progress(k, sim.frames.size(), e);
  }
  out.features_per_frame = features / std::max<std::size_t>(1, out.frames.size());
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_wall).count();
  out.cpu_time_s = static_cast<double>(std::clock() - t_cpu) / CLOCKS_PER_SEC;
  out.sequence_duration_s = sim.frames.back().t - sim.frames[moving].t;
  return out;
}

}  // namespace slamkit
