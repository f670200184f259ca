// The front end on the images of a simulated run, its tracks as the run's observations (see the header).
#include "slamkit/vio/image_vio.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <deque>
#include <stdexcept>

#include "slamkit/core/error.h"
#include "slamkit/factors/imu_preintegration.h"
#include "slamkit/vio/image_io.h"

namespace slamkit {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

LabelImage to_label_image(const GrayImage& g) {
  LabelImage l(g.width, g.height);
  std::copy(g.pixels.begin(), g.pixels.end(), l.labels.begin());
  return l;
}

}  // namespace

std::vector<std::optional<Eigen::Matrix3d>> gyro_camera_rotations(const VisualInertialSim& sim, const Eigen::Vector3d& gyro_bias) {
  std::vector<std::optional<Eigen::Matrix3d>> out(sim.frames.size());
  const Eigen::Matrix3d R_ci = sim.T_cam_imu.rotation().matrix();
  const ImuNoise noise{sim.imu_noise.gyro_noise_density, sim.imu_noise.accel_noise_density, sim.imu_noise.gyro_random_walk,
                       sim.imu_noise.accel_random_walk};
  std::size_t first = 0;  // the last IMU sample at or before the previous frame
  for (std::size_t k = 1; k < sim.frames.size(); ++k) {
    const double t0 = sim.frames[k - 1].t, t1 = sim.frames[k].t;
    while (first + 1 < sim.imu.size() && sim.imu[first + 1].t <= t0) ++first;
    std::vector<ImuMeasurement> samples;
    for (std::size_t i = first; i < sim.imu.size(); ++i) {
      ImuMeasurement m;
      m.stamp = sim.imu[i].t, m.gyro = sim.imu[i].gyro, m.accel = sim.imu[i].accel;
      samples.push_back(m);
      if (sim.imu[i].t >= t1) break;
    }
    try {
      ImuPreintegration pim(ImuBias{gyro_bias, Eigen::Vector3d::Zero()}, noise);
      pim.integrate_between(samples, t0, t1);
      const Eigen::Matrix3d dR = pim.delta_R().matrix();  // R_{i_{k−1}}ᵀ R_{i_k}
      out[k] = R_ci * dR.transpose() * R_ci.transpose();
    } catch (const std::invalid_argument&) {
      // the IMU does not cover this interval: no rotation for frame k
    }
  }
  return out;
}

std::map<int, double> walker_speeds(const RenderedScene& scene) {
  std::map<int, double> speeds;
  for (const SceneWalker& w : scene.walkers) speeds[w.id] = w.speed;  // ids may repeat mod 255: last wins
  return speeds;
}

ObjectDistances walker_distances(const RenderedScene& scene, const VisualInertialSim& sim) {
  struct Walker {
    SimMovingGroup path;
    int id;
  };
  std::vector<Walker> walkers;
  for (const SceneWalker& w : scene.walkers) walkers.push_back({w.path, w.id});
  std::vector<std::pair<double, Eigen::Vector3d>> cameras;  // frame time, camera centre in the world
  for (const SimFrame& f : sim.frames) cameras.emplace_back(f.t, frame_camera_pose(sim, f).translation());
  const Eigen::Vector3d centre(0.0, 0.0, scene.person_half.z());  // box centre in the walker's frame (feet at 0)
  return [walkers = std::move(walkers), cameras = std::move(cameras), centre](std::size_t k) {
    std::map<int, double> d;
    const auto& [t, c] = cameras.at(k);
    for (const Walker& w : walkers) {
      if (!w.path.active(t)) continue;
      const double r = (w.path.pose(t).act(centre) - c).norm();
      const auto it = d.find(w.id);
      if (it == d.end() || r < it->second) d[w.id] = r;
    }
    return d;
  };
}

FrameImageSource rendered_frames(const VisualInertialSim& sim, const ImageRenderer& renderer, const ThreadPool* pool) {
  return [&sim, &renderer, pool](std::size_t k, GrayImage* image, GrayImage* labels) {
    const SimFrame& f = sim.frames.at(k);
    renderer.render(f.t, frame_camera_pose(sim, f), image, labels, pool);
  };
}

FrameImageSource folder_frames(const VisualInertialSim& sim, const std::string& dir) {
  auto seq = std::make_shared<ImageSequence>(read_image_sequence(dir));
  const std::string csv = dir + "/mav0/cam0/data.csv";
  if (seq->frames.size() != sim.frames.size())
    throw InputError(csv, 0, "frames", std::to_string(seq->frames.size()) + " images but the run " + sim.source + " has " +
                                           std::to_string(sim.frames.size()) + " frames (same --seed, --dynamic, --duration?)");
  for (std::size_t k = 0; k < sim.frames.size(); ++k)
    if (seq->frames[k].t_ns != stamp_ns(sim.frames[k].t))
      throw InputError(csv, static_cast<int>(k + 2), "timestamp",
                       "image stamp " + std::to_string(seq->frames[k].t_ns) + " ns is not the run's frame stamp " +
                           std::to_string(stamp_ns(sim.frames[k].t)) + " ns");
  return [seq](std::size_t k, GrayImage* image, GrayImage* labels) {
    const ImageSequenceFrame& f = seq->frames.at(k);
    *image = read_png(f.image_path);
    if (labels) *labels = f.label_path.empty() ? GrayImage{} : read_png(f.label_path);
  };
}

VisualInertialSim track_images(const VisualInertialSim& sim, const FrameImageSource& source,
                               const std::map<int, double>& label_speed_mps, const ImageVioOptions& options,
                               ImageVioReport* report, const std::function<void(std::size_t, std::size_t)>& progress) {
  return track_images(sim, source, label_speed_mps, ObjectDistances{}, options, report, progress);
}

VisualInertialSim track_images(const VisualInertialSim& sim, const FrameImageSource& source,
                               const std::map<int, double>& label_speed_mps, const ObjectDistances& object_distance_m,
                               const ImageVioOptions& options, ImageVioReport* report,
                               const std::function<void(std::size_t, std::size_t)>& progress) {
  if (!sim.camera) throw InputError(sim.source, 0, "camera", "the run has no camera");
  if (sim.frames.empty()) throw InputError(sim.source, 0, "frames", "the run has no frames");
  const Eigen::VectorXd K = sim.camera->intrinsics();
  ImageFrontend frontend(options.frontend, sim.camera,
                         circular_mask(sim.camera->width(), sim.camera->height(), K(2), K(3), sim.mask_radius_px,
                                       options.mask_margin_px));
  DetectionScoreOptions so;
  so.label_speed_mps = label_speed_mps;
  so.min_speed_mps = options.min_speed_mps;
  DetectionScoreOptions so_patch = so;
  so_patch.patch_half_size_px =
      options.score_patch_half_size_px >= 0 ? options.score_patch_half_size_px : options.frontend.tracker.klt_window / 2;
  if (!(options.score_min_distance_m >= 0.0 && options.score_min_distance_m <= options.score_max_distance_m))
    throw std::invalid_argument("track_images: the scored distance range must satisfy 0 <= min <= max");
  DetectionScoreOptions so_range = so_patch;  // the patch rule, objects in the distance range
  so_range.min_distance_m = options.score_min_distance_m, so_range.max_distance_m = options.score_max_distance_m;
  ImageVioReport r;
  r.distance_range_applied = static_cast<bool>(object_distance_m);
  r.score_patch_half_size_px = so_patch.patch_half_size_px;
  VisualInertialSim out = sim;
  out.landmarks.clear();  // the tracks are not the simulator's landmarks
  out.pixel_noise_sigma = options.pixel_sigma;
  std::vector<std::optional<Eigen::Matrix3d>> rotations;  // gyroscope: IMU-aided epipolar model, KLT seed
  if (options.frontend.filter.known_rotation || options.frontend.tracker.gyro_klt != GyroKlt::kOff)
    rotations = gyro_camera_rotations(sim);
  GrayImage image, labels;
  std::deque<LabelImage> label_history;  // front: frame k
  double m_sum = 0.0, features = 0.0;
  std::size_t m_frames = 0;
  for (std::size_t k = 0; k < sim.frames.size(); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    source(k, &image, &labels);
    r.image_s += ms_since(t0) * 1e-3;
    FrontendFrameResult f;
    const std::clock_t cpu0 = std::clock();
    try {
      f = frontend.process(image, k < rotations.size() && rotations[k] ? &*rotations[k] : nullptr);
      r.frontend_cpu_s += static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC;
    } catch (const std::invalid_argument& e) {
      throw InputError(sim.source, 0, "image", "frame " + std::to_string(k) + ": " + e.what());
    }
    r.frontend_s += (f.tracking_ms + f.classification_ms) * 1e-3;
    r.tracking_ms_per_frame += f.tracking_ms, r.classification_ms_per_frame += f.classification_ms;
    r.tracked_per_frame += f.tracking.tracked, r.lost_klt_per_frame += f.tracking.lost_klt;
    r.lost_forward_backward_per_frame += f.tracking.lost_forward_backward;
    std::vector<SimObservation>& obs = out.frames[k].observations;
    obs.clear();
    for (const FrontendFeature& x : f.features) {
      SimObservation o;
      o.track_id = x.id, o.landmark_id = -1, o.uv = x.uv;
      o.dynamic = x.motion == FeatureMotion::kDynamic;
      o.classified = x.motion != FeatureMotion::kUnknown;
      obs.push_back(o);
    }
    features += static_cast<double>(f.features.size());
    // Scoring of the classified features: the patch rule at both ends of the tested baseline
    // (frames t − b and t), and the centre rule at t (the figure reported before).
    const bool labelled = !labels.empty() && labels.width == image.width && labels.height == image.height;
    label_history.push_front(labelled ? to_label_image(labels) : LabelImage{});
    while (static_cast<int>(label_history.size()) > options.frontend.baseline_frames + 1) label_history.pop_back();
    if (labelled) {
      if (object_distance_m) so_range.label_distance_m = object_distance_m(k);
      for (const FrontendFeature& x : f.features) {
        if (x.motion == FeatureMotion::kUnknown || x.baseline <= 0) continue;
        const LabelImage& now = label_history.front();
        // An isolated flag claims no moving object: scored as "not dynamic" (a miss on a mover).
        const FeatureMotion claim = x.isolated ? FeatureMotion::kStatic : x.motion;
        add_to_score(label_truth(now, x.uv, 0), claim, so, &r.score_centre);
        const LabelImage& then = label_history.at(std::min<std::size_t>(x.baseline, label_history.size() - 1));
        const int truth_now = label_truth(now, x.uv, so_patch.patch_half_size_px);
        const int truth = then.labels.empty() || static_cast<std::size_t>(x.baseline) >= label_history.size()
                              ? truth_now
                              : track_truth(label_truth(then, x.uv_then, so_patch.patch_half_size_px), truth_now);
        add_to_score(truth, claim, so_patch, &r.score_all_distances);
        add_to_score(truth, claim, so_range, &r.score);
        if (options.on_scored) {
          const auto d = truth > 0 ? so_range.label_distance_m.find(truth) : so_range.label_distance_m.end();
          options.on_scored(k, x, truth, d != so_range.label_distance_m.end() ? d->second : std::nan(""));
        }
      }
    }
    if (k > 0) {  // the first frame has nothing to classify
      m_sum += f.static_ratio, ++m_frames;
      r.static_ratio_min = std::min(r.static_ratio_min, f.static_ratio);
      r.frames_gyro_seeded += f.tracking.gyro_seeded;
      r.frames_too_few_matches += f.status == ClassificationStatus::kTooFewMatches;
      r.realigned_affine += f.n_realigned_affine, r.unflagged_affine += f.n_unflagged_affine;
      r.refits_affine += f.n_refits_affine;
      r.isolated_flags += f.n_isolated;
      r.contests_lost += f.n_contests_lost;
      r.trust_undecided_frames += f.trust_undecided;
      r.graced_flags += f.n_graced;
      r.frames_no_fundamental += f.status == ClassificationStatus::kNoFundamental;
      r.frames_static_camera += f.status == ClassificationStatus::kStaticCamera;
      if (f.status == ClassificationStatus::kEpipolar) {
        r.frames_known_rotation += f.motion_model == MotionModel::kKnownRotation;
        r.frames_pure_rotation += f.motion_model == MotionModel::kPureRotation;
        r.frames_rotation_rejected += f.motion_model == MotionModel::kRotationRejected;
      }
    }
    if (progress) progress(k, sim.frames.size());
  }
  const double n = static_cast<double>(sim.frames.size());
  r.frames = sim.frames.size();
  r.static_ratio_mean = m_frames > 0 ? m_sum / m_frames : 1.0;
  r.features_per_frame = features / n;
  r.image_ms_per_frame = 1e3 * r.image_s / n;
  r.tracking_ms_per_frame /= n, r.classification_ms_per_frame /= n;
  r.tracked_per_frame /= n, r.lost_klt_per_frame /= n, r.lost_forward_backward_per_frame /= n;
  if (report) {
    r.image_source = report->image_source;
    *report = r;
  }
  return out;
}

}  // namespace slamkit
