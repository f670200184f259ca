#include "slamkit/vio/sliding_window_estimator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "slamkit/core/error.h"
#include "slamkit/factors/inverse_depth_factor.h"
#include "slamkit/factors/marginalization_prior.h"
#include "slamkit/factors/prior_factor.h"
#include "slamkit/solvers/optimizer.h"
#include "slamkit/vio/marginalization.h"

namespace slamkit {
namespace {

using InvDepth = Eigen::Matrix<double, 1, 1>;

Key state_key(std::uint64_t id) { return symbol('x', id); }
Key feature_key(std::uint64_t i) { return symbol('l', i); }

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

SlidingWindowEstimator::SlidingWindowEstimator(SlidingWindowOptions options, std::shared_ptr<const CameraModel> camera,
                                               const SE3& T_imu_cam)
    : options_(std::move(options)),
      camera_(std::move(camera)),
      T_imu_cam_(T_imu_cam),
      pool_(options_.num_threads),
      pixel_noise_(NoiseModel::isotropic(2, options_.pixel_sigma)),
      kernel_(std::make_shared<CauchyKernel>(options_.cauchy_delta)),
      dense_(camera_, T_imu_cam_, options_.pixel_sigma, kernel_, &pool_),
      pending_(ImuBias{}, options_.imu_noise) {
  if (!camera_) throw std::invalid_argument("SlidingWindowEstimator: no camera model");
  if (options_.dvi.enabled && !options_.dense_solver)
    throw std::invalid_argument("SlidingWindowEstimator: DVI weights need the dense window solver");
  if (options_.window_size < 2) throw std::invalid_argument("SlidingWindowEstimator: window_size must be at least 2");
}

void SlidingWindowEstimator::initialize(double stamp, const ImuState& state) {
  keyframes_.clear(), imu_factors_.clear(), features_.clear();
  keyframes_.push_back({next_keyframe_id_++, stamp, state, {}});
  Eigen::Matrix<double, 15, 1> sigma;
  sigma << Eigen::Vector3d::Constant(options_.prior_rotation_sigma), Eigen::Vector3d::Constant(options_.prior_velocity_sigma),
      Eigen::Vector3d::Constant(options_.prior_position_sigma), Eigen::Vector3d::Constant(options_.prior_gyro_bias_sigma),
      Eigen::Vector3d::Constant(options_.prior_accel_bias_sigma);
  prior_ = std::make_shared<PriorFactor<ImuState>>(state_key(keyframes_.back().id), state, NoiseModel::diagonal(sigma));
  pending_ = ImuPreintegration(ImuBias{state.bg, state.ba}, options_.imu_noise);
  last_stamp_ = stamp;
  frames_since_keyframe_ = 0;
}

void SlidingWindowEstimator::add_imu(const ImuMeasurement& m) {
  if (!std::isfinite(m.stamp) || !m.gyro.allFinite() || !m.accel.allFinite())
    throw InputError("", 0, "imu", "IMU sample at " + std::to_string(m.stamp) + " is not finite");
  if (!imu_.empty() && !(m.stamp > imu_.back().stamp))
    throw InputError("", 0, "imu stamp", "IMU stamps must increase (" + std::to_string(m.stamp) + " after " +
                                             std::to_string(imu_.back().stamp) + ")");
  imu_.push_back(m);
}

const SlidingWindowEstimator::Keyframe* SlidingWindowEstimator::keyframe(std::uint64_t id) const {
  for (const Keyframe& k : keyframes_)
    if (k.id == id) return &k;
  return nullptr;
}

bool SlidingWindowEstimator::try_triangulate(Feature& f) const {
  // Midpoint of the anchor ray and the ray of the observation with the widest angle.
  const Keyframe* a = keyframe(f.anchor);
  if (!a || f.obs.empty()) return false;
  const SE3 T_wa = a->state.pose() * T_imu_cam_;
  const Eigen::Vector3d da = T_wa.rotation().act(f.bearing), ca = T_wa.translation();
  double best_angle = 0.0, best_depth = 0.0;
  for (const auto& [kid, px] : f.obs) {
    const Keyframe* k = keyframe(kid);
    Eigen::Vector3d b;
    if (!k || !camera_->unproject(px, &b)) continue;
    const SE3 T_wk = k->state.pose() * T_imu_cam_;
    const Eigen::Vector3d dk = T_wk.rotation().act(b), ck = T_wk.translation();
    const double angle = std::acos(std::clamp(da.dot(dk), -1.0, 1.0));
    if (angle <= best_angle) continue;
    Eigen::Matrix<double, 3, 2> A;
    A << da, -dk;
    const Eigen::Vector2d lm = A.colPivHouseholderQr().solve(ck - ca);
    if (lm(0) < options_.min_depth || lm(0) > options_.max_depth || lm(1) <= 0.0) continue;
    best_angle = angle, best_depth = lm(0);
  }
  if (best_angle < options_.min_triangulation_angle_deg * kPi / 180.0) return false;
  f.inv_depth = 1.0 / best_depth;
  f.triangulated = true;
  return true;
}

double SlidingWindowEstimator::mean_reprojection_error_px(const Feature& f) const {
  const Keyframe* a = keyframe(f.anchor);
  if (!a || !(f.inv_depth > 0.0)) return std::nan("");
  // P_w = R_a (T_ic (b / ρ)) + p_a, seen from keyframe k: P_c = (T_wk T_ic)⁻¹ P_w.
  const Eigen::Vector3d P_w = a->state.R.act(T_imu_cam_.act(f.bearing / f.inv_depth)) + a->state.p;
  double sum = 0.0;
  int n = 0;
  for (const auto& [kid, px] : f.obs) {
    const Keyframe* k = keyframe(kid);
    if (!k) continue;
    Eigen::Vector2d uv;
    const Eigen::Vector3d P_c = (k->state.pose() * T_imu_cam_).inverse().act(P_w);
    if (!camera_->project(P_c, &uv)) return std::numeric_limits<double>::infinity();  // behind / outside
    sum += (uv - px).norm(), ++n;
  }
  return n > 0 ? sum / n : std::nan("");
}

int SlidingWindowEstimator::reject_outliers() {
  int removed = 0;
  for (auto it = features_.begin(); it != features_.end();) {
    const Feature& f = it->second;
    const double e = f.triangulated ? mean_reprojection_error_px(f) : std::nan("");
    if (e > options_.outlier_reprojection_px) {  // NaN (untriangulated, no observation): kept
      it = features_.erase(it), ++removed;
    } else {
      ++it;
    }
  }
  outliers_rejected_ += removed;
  return removed;
}

void SlidingWindowEstimator::add_keyframe(const CameraFrame& frame, const ImuState& predicted, double visual_weight) {
  Keyframe kf{next_keyframe_id_++, frame.stamp, predicted, {}, visual_weight};
  imu_factors_.push_back(pending_);
  pending_ = ImuPreintegration(ImuBias{predicted.bg, predicted.ba}, options_.imu_noise);
  for (const FeatureObservation& o : frame.features) {
    if (!o.pixel.allFinite()) continue;
    kf.pixels[o.track_id] = o.pixel;
    if (!(visual_weight > 0.0)) continue;  // DVI dropped the frame's vision: parallax only
    auto it = features_.find(o.track_id);
    if (it != features_.end()) {
      it->second.obs.emplace_back(kf.id, o.pixel);
      continue;
    }
    Feature f;
    if (!camera_->unproject(o.pixel, &f.bearing)) continue;
    f.key_index = next_feature_key_++;
    f.anchor = kf.id;
    f.inv_depth = 1.0 / options_.initial_depth;
    features_.emplace(o.track_id, std::move(f));
  }
  keyframes_.push_back(std::move(kf));
  for (auto& [id, f] : features_)
    if (!f.triangulated) try_triangulate(f);
}

void SlidingWindowEstimator::build(FactorGraph& graph, Values& values, bool only_oldest,
                                   std::vector<Key>* oldest_features) const {
  for (const Keyframe& k : keyframes_) values.insert(state_key(k.id), k.state);
  const std::uint64_t oldest = keyframes_.front().id;
  if (prior_) graph.add(prior_);
  for (std::size_t k = 0; k + 1 < keyframes_.size(); ++k) {
    if (only_oldest && k > 0) break;
    graph.emplace<ImuFactor>(state_key(keyframes_[k].id), state_key(keyframes_[k + 1].id), imu_factors_[k],
                             options_.gravity);
  }
  for (const auto& [track, f] : features_) {
    if (!f.triangulated || f.obs.empty()) continue;
    if (only_oldest && f.anchor != oldest) continue;
    const Key l = feature_key(f.key_index);
    values.insert(l, InvDepth(f.inv_depth));
    if (oldest_features) oldest_features->push_back(l);
    for (const auto& [kid, px] : f.obs)
      graph.emplace<InverseDepthFactor>(state_key(f.anchor), state_key(kid), l, f.bearing, px, camera_, T_imu_cam_,
                                        pixel_noise_, kernel_);
  }
}

int SlidingWindowEstimator::solve() {
  if (options_.dense_solver) return solve_dense();
  FactorGraph graph;
  Values values;
  build(graph, values, false, nullptr);
  OptimizerOptions o;
  o.algorithm = Algorithm::kLevenbergMarquardt;
  o.max_iterations = options_.max_iterations;
  o.num_threads = options_.num_threads;
  o.function_tolerance = 1e-6;
  o.schur_eliminate = [](Key k) { return symbol_char(k) == 'l'; };
  o.schur.method = SchurMethod::kDense;
  const Summary s = Optimizer(o).optimize(graph, values);
  for (Keyframe& k : keyframes_) k.state = values.at<ImuState>(state_key(k.id));
  for (auto it = features_.begin(); it != features_.end();) {
    Feature& f = it->second;
    const Key l = feature_key(f.key_index);
    if (values.exists(l)) {
      f.inv_depth = values.at<InvDepth>(l)(0);
      if (!(f.inv_depth >= 1.0 / options_.max_depth && f.inv_depth <= 1.0 / options_.min_depth)) {
        it = features_.erase(it);  // diverged or behind the camera: drop it
        continue;
      }
    }
    ++it;
  }
  return s.iterations;
}

void SlidingWindowEstimator::marginalize_oldest() {
  if (options_.dense_solver) {
    marginalize_oldest_dense();
  } else {
    FactorGraph graph;
    Values values;
    std::vector<Key> oldest_features;
    build(graph, values, true, &oldest_features);
    const Key x0 = state_key(keyframes_.front().id);
    const MarginalSystem m = marginalize(graph, values, oldest_features, {x0}, pool_);
    std::vector<ImuState> x_bar;
    for (Key k : m.kept) x_bar.push_back(values.at<ImuState>(k));
    prior_ = MarginalizationPrior<ImuState>::from_hessian(m.kept, x_bar, m.H, m.g);
  }
  // Drop the keyframe and its IMU factor; a feature anchored in it moves to its next
  // observation (as VINS-Mono shifts the depth): the bearing of that pixel, the inverse
  // distance of the current point from that camera. Features seen nowhere else are dropped.
  const ImuState x_old = keyframes_.front().state;
  const std::uint64_t oldest = keyframes_.front().id;
  keyframes_.pop_front();
  imu_factors_.pop_front();
  for (auto it = features_.begin(); it != features_.end();) {
    Feature& f = it->second;
    if (f.anchor != oldest) {
      ++it;
      continue;
    }
    const Keyframe* next = f.obs.empty() ? nullptr : keyframe(f.obs.front().first);
    Eigen::Vector3d bearing;
    if (!next || !camera_->unproject(f.obs.front().second, &bearing)) {
      it = features_.erase(it);
      continue;
    }
    const Eigen::Vector3d P_w = x_old.R.act(T_imu_cam_.act(f.bearing / f.inv_depth)) + x_old.p;
    const Eigen::Vector3d P_c = (next->state.pose() * T_imu_cam_).inverse().act(P_w);
    f.anchor = next->id;
    f.bearing = bearing;
    f.obs.erase(f.obs.begin());
    if (f.triangulated) {
      if (P_c.z() <= 0.0 || !(P_c.norm() >= options_.min_depth && P_c.norm() <= options_.max_depth)) {
        it = features_.erase(it);
        continue;
      }
      f.inv_depth = 1.0 / P_c.norm();
    }
    f.key_index = next_feature_key_++;  // a new variable: the old one was marginalized
    ++it;
  }
}

FrameEstimate SlidingWindowEstimator::add_frame(const CameraFrame& frame) {
  if (!initialized()) throw std::logic_error("SlidingWindowEstimator::add_frame before initialize()");
  if (!(frame.stamp > last_stamp_))
    throw InputError("", 0, "frame stamp", "frame at " + std::to_string(frame.stamp) + " does not follow " +
                                               std::to_string(last_stamp_));
  if (imu_.empty() || imu_.front().stamp > last_stamp_ || imu_.back().stamp < frame.stamp)
    throw InputError("", 0, "imu", "the IMU does not cover the frames " + std::to_string(last_stamp_) + " to " +
                                       std::to_string(frame.stamp));
  pending_.integrate_between(imu_, last_stamp_, frame.stamp);
  last_stamp_ = frame.stamp;
  // Keep the IMU from just before this frame on.
  const auto keep = std::upper_bound(imu_.begin(), imu_.end(), frame.stamp,
                                     [](double t, const ImuMeasurement& m) { return t < m.stamp; });
  if (keep - imu_.begin() > 1) imu_.erase(imu_.begin(), keep - 1);

  FrameEstimate out;
  out.stamp = frame.stamp;
  out.features = static_cast<int>(frame.features.size());
  // DVI: M = static / all by the front end's flags (or static / classified, untested tracks out of
  // both counts); with dvi on the dynamic observations go, the frame's vision is weighted by α(M),
  // or dropped when M < θ.
  int n_static = 0, n_counted = 0;
  for (const FeatureObservation& o : frame.features) {
    if (options_.dvi.ratio_of_classified && !o.classified) continue;
    n_static += !o.dynamic, ++n_counted;
  }
  out.static_ratio = n_counted == 0 ? 1.0 : static_cast<double>(n_static) / n_counted;
  CameraFrame used;
  const CameraFrame* in = &frame;
  if (options_.dvi.enabled) {
    used.stamp = frame.stamp, used.dynamic_groups = frame.dynamic_groups;
    for (const FeatureObservation& o : frame.features)
      if (!o.dynamic) used.features.push_back(o);
    in = &used;
    out.visual_dropped = out.static_ratio < options_.dvi.theta_for(frame.dynamic_groups);
    out.visual_weight = out.visual_dropped ? 0.0 : options_.dvi.alpha_of(out.static_ratio);
  }
  const ImuState predicted = pending_.predict(keyframes_.back().state, options_.gravity);
  // Keyframe decision: mean pixel motion of the tracks shared with the last keyframe; with
  // rotation compensation, against the last keyframe's pixel rotated into this frame by the
  // IMU-predicted rotation (b' = R_cur_kf b, VINS-Mono's compensated parallax), so that turning
  // on the spot does not fill the window with keyframes that add no baseline.
  const SO3 R_bc = T_imu_cam_.rotation();
  const SO3 R_cur_kf = (predicted.R * R_bc).inverse() * (keyframes_.back().state.R * R_bc);
  double parallax = 0.0;
  int common = 0;
  for (const FeatureObservation& o : in->features) {
    const auto it = keyframes_.back().pixels.find(o.track_id);
    if (it == keyframes_.back().pixels.end()) continue;
    Eigen::Vector2d from = it->second;
    Eigen::Vector3d b;
    Eigen::Vector2d rotated;
    if (options_.rotation_compensated_parallax && camera_->unproject(from, &b) && camera_->project(R_cur_kf.act(b), &rotated))
      from = rotated;
    parallax += (o.pixel - from).norm(), ++common;
  }
  parallax = common > 0 ? parallax / common : 0.0;
  ++frames_since_keyframe_;
  const bool keyframe = frames_since_keyframe_ >= options_.max_frames_between_keyframes ||
                        parallax >= options_.keyframe_parallax_px ||
                        common < static_cast<int>(in->features.size()) / 2;
  if (!keyframe) {
    out.state = predicted;
    return out;
  }
  frames_since_keyframe_ = 0;
  out.keyframe = true;
  add_keyframe(*in, predicted, out.visual_weight);
  auto t0 = std::chrono::steady_clock::now();
  out.iterations = solve();
  if (options_.outlier_reprojection_px > 0.0) out.outliers_rejected = reject_outliers();
  out.solve_ms = ms_since(t0);
  if (static_cast<int>(keyframes_.size()) > options_.window_size) {
    t0 = std::chrono::steady_clock::now();
    marginalize_oldest();
    out.marginalization_ms = ms_since(t0);
  }
  pending_.reset(ImuBias{keyframes_.back().state.bg, keyframes_.back().state.ba});
  out.state = keyframes_.back().state;
  for (const auto& [id, f] : features_) out.features_in_problem += f.triangulated && !f.obs.empty();
  return out;
}

}  // namespace slamkit
