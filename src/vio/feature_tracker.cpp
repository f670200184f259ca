// Shi-Tomasi detection + sub-pixel refinement + pyramidal KLT with a forward-backward check
// (see the header). OpenCV stays inside this file.
#include "slamkit/vio/feature_tracker.h"
#include "opencv_gray.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <opencv2/optflow/rlofflow.hpp>
#include <opencv2/video/tracking.hpp>
#include <stdexcept>
#include <string>

#include "slamkit/geometry/camera_models.h"

namespace slamkit {

namespace {

void check_image(const GrayImage& image, const char* what) {
  if (image.empty() || image.pixels.size() != std::size_t(image.width) * image.height)
    throw std::invalid_argument(std::string("feature tracker: ") + what + " is empty or its pixel count is not width x height");
}

bool is_rotation(const Eigen::Matrix3d& R) {
  return R.allFinite() && (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-6 && R.determinant() > 0.0;
}

// Robust local optical flow (RLOF) from prev3 to cur3, started at `to` (in place): cross-based
// support regions (they need three channels: the gray frames replicated) and the shrinked-Hampel
// M-estimator; one pyramid level above the image (the start is KLT's flow). ok[i] = 0 where RLOF
// gave no finite position. OpenCV 4.6 writes the result back only into a 1 × N matrix (it
// copies a 1 × N result into the caller's matrix, which an N × 1 one would not receive).
void rlof_refine(const cv::Mat& prev3, const cv::Mat& cur3, int window, const std::vector<cv::Point2f>& from,
                 std::vector<cv::Point2f>* to, std::vector<uchar>* ok) {
  auto param = cv::makePtr<cv::optflow::RLOFOpticalFlowParameter>();
  param->setSupportRegionType(cv::optflow::SR_CROSS);
  param->setUseMEstimator(true);
  param->setUseInitialFlow(true);
  param->setUseGlobalMotionPrior(false);
  param->setLargeWinSize(window);
  param->setSmallWinSize(std::min(9, window));
  param->setMaxLevel(1);
  const int n = static_cast<int>(from.size());
  cv::Mat from_m = cv::Mat(from, true).reshape(2, 1), to_m = cv::Mat(*to, true).reshape(2, 1);
  std::vector<float> err;
  cv::optflow::calcOpticalFlowSparseRLOF(prev3, cur3, from_m, to_m, *ok, err, param, 0.f);
  for (int i = 0; i < n; ++i) {
    const cv::Point2f q = to_m.at<cv::Point2f>(0, i);
    if (std::isfinite(q.x) && std::isfinite(q.y)) (*to)[i] = q; else (*ok)[i] = 0;
  }
}

}  // namespace

const char* rlof_refine_name(RlofRefine mode) {
  switch (mode) {
    case RlofRefine::kOff: return "off";
    case RlofRefine::kTrack: return "track";
    case RlofRefine::kTest: return "test";
  }
  return "?";
}

RlofRefine parse_rlof_refine(const std::string& name) {
  if (name == "off") return RlofRefine::kOff;
  if (name == "track" || name == "on") return RlofRefine::kTrack;
  if (name == "test") return RlofRefine::kTest;
  throw std::invalid_argument("rlof_refine: '" + name + "' is not off, track (on) or test");
}

const char* gyro_klt_name(GyroKlt mode) {
  switch (mode) {
    case GyroKlt::kSeed: return "seed";
    case GyroKlt::kCandidate: return "candidate";
    default: return "off";
  }
}

GyroKlt parse_gyro_klt(const std::string& name) {
  if (name == "off") return GyroKlt::kOff;
  if (name == "seed" || name == "on") return GyroKlt::kSeed;
  if (name == "candidate") return GyroKlt::kCandidate;
  throw std::invalid_argument("gyro_klt must be off, seed (on) or candidate, not '" + name + "'");
}

bool predict_by_rotation(const CameraModel& camera, const Eigen::Matrix3d& R_cur_prev, const Eigen::Vector2d& uv,
                         Eigen::Vector2d* out) {
  Eigen::Vector3d bearing;  // a point at infinity moves with the rotation only: p' = π(R π⁻¹(p))
  Eigen::Vector2d p;
  if (!camera.unproject(uv, &bearing) || !camera.project(R_cur_prev * bearing, &p) || !p.allFinite()) return false;
  *out = p;
  return true;
}

double patch_ncc(const GrayImage& a, const Eigen::Vector2d& pa, const GrayImage& b, const Eigen::Vector2d& pb, int half) {
  auto inside = [half](const GrayImage& g, const Eigen::Vector2d& p) {
    return p.allFinite() && p.x() - half >= 0.0 && p.y() - half >= 0.0 && p.x() + half + 1 < g.width &&
           p.y() + half + 1 < g.height;
  };
  if (half < 0 || !inside(a, pa) || !inside(b, pb)) return std::numeric_limits<double>::quiet_NaN();
  // Bilinear sample at p + (dx, dy); the weights are the same for every sample of one patch.
  auto sampler = [](const GrayImage& g, const Eigen::Vector2d& p) {
    const int x0 = int(std::floor(p.x())), y0 = int(std::floor(p.y()));
    const double fx = p.x() - x0, fy = p.y() - y0;
    return [&g, x0, y0, fx, fy](int dx, int dy) {
      const std::uint8_t* r0 = g.row(y0 + dy) + x0 + dx;
      const std::uint8_t* r1 = r0 + g.width;
      return (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
    };
  };
  const auto sa = sampler(a, pa), sb = sampler(b, pb);
  double s_a = 0, s_b = 0, s_aa = 0, s_bb = 0, s_ab = 0;
  for (int dy = -half; dy <= half; ++dy)
    for (int dx = -half; dx <= half; ++dx) {
      const double u = sa(dx, dy), v = sb(dx, dy);
      s_a += u, s_b += v, s_aa += u * u, s_bb += v * v, s_ab += u * v;
    }
  const double n = double(2 * half + 1) * (2 * half + 1);
  const double va = s_aa - s_a * s_a / n, vb = s_bb - s_b * s_b / n, cab = s_ab - s_a * s_b / n;
  const double flat = 1e-6 * n;  // variance of a constant patch, up to rounding
  if (va <= flat && vb <= flat) return 1.0;
  if (va <= flat || vb <= flat) return 0.0;
  return cab / std::sqrt(va * vb);
}

void TrackingResult::matches(std::vector<Eigen::Vector2d>* prev, std::vector<Eigen::Vector2d>* cur,
                             std::vector<std::int64_t>* ids) const {
  prev->clear(), cur->clear();
  if (ids) ids->clear();
  for (const TrackedFeature& f : features) {
    if (f.age == 0) continue;
    prev->push_back(f.prev_uv), cur->push_back(f.uv);
    if (ids) ids->push_back(f.id);
  }
}

struct FeatureTracker::State {
  GrayImage mask;
  cv::Mat prev_image;              // a deep copy of the last frame
  cv::Mat prev_image3;             // the last frame in three channels (RLOF), when rlof_refine is on
  std::vector<cv::Mat> prev_pyramid;
  GrayImage prev_frame;            // the last frame as a plain buffer (appearance check)
  std::vector<TrackedFeature> features;
  std::int64_t next_id = 0;
};

FeatureTracker::FeatureTracker(FeatureTrackerOptions o, GrayImage mask, std::shared_ptr<const CameraModel> camera)
    : options_(o), camera_(std::move(camera)), state_(std::make_unique<State>()) {
  if (o.max_features < 1) throw std::invalid_argument("feature tracker: max_features must be >= 1");
  if (!(o.min_distance_px >= 0.0)) throw std::invalid_argument("feature tracker: min_distance_px must be >= 0");
  if (!(o.quality_level > 0.0 && o.quality_level < 1.0)) throw std::invalid_argument("feature tracker: quality_level must be in (0, 1)");
  if (o.klt_window < 3 || o.klt_pyramid_levels < 0 || o.klt_max_iterations < 1 || o.block_size < 1)
    throw std::invalid_argument("feature tracker: klt_window >= 3, klt_pyramid_levels >= 0, klt_max_iterations >= 1, block_size >= 1");
  if (!(o.rlof_max_shift_px > 0.0)) throw std::invalid_argument("feature tracker: rlof_max_shift_px > 0");
  if (o.grid_cols < 0 || o.grid_rows < 0 || (o.grid_cols > 0) != (o.grid_rows > 0))
    throw std::invalid_argument("feature tracker: grid_cols and grid_rows must both be 0 or both > 0");
  if (o.patch_half_px < 1 || !(o.min_patch_ncc <= 1.0))
    throw std::invalid_argument("feature tracker: patch_half_px must be >= 1 and min_patch_ncc <= 1");
  if (!mask.empty()) check_image(mask, "the mask");
  state_->mask = std::move(mask);
}

FeatureTracker::~FeatureTracker() = default;
FeatureTracker::FeatureTracker(FeatureTracker&&) noexcept = default;
FeatureTracker& FeatureTracker::operator=(FeatureTracker&&) noexcept = default;

void FeatureTracker::drop(const std::vector<std::int64_t>& ids) {
  auto& f = state_->features;
  f.erase(std::remove_if(f.begin(), f.end(),
                         [&](const TrackedFeature& t) { return std::find(ids.begin(), ids.end(), t.id) != ids.end(); }),
          f.end());
}

void FeatureTracker::relocate(const std::vector<std::int64_t>& ids, const std::vector<Eigen::Vector2d>& uv) {
  if (ids.size() != uv.size()) throw std::invalid_argument("feature tracker: relocate needs one position per id");
  for (std::size_t k = 0; k < ids.size(); ++k)
    for (TrackedFeature& t : state_->features)
      if (t.id == ids[k]) t.uv = t.uv_test = uv[k];
}

TrackingResult FeatureTracker::track(const GrayImage& frame, const Eigen::Matrix3d* R_cur_prev) {
  check_image(frame, "the frame");
  State& s = *state_;
  const FeatureTrackerOptions& o = options_;
  if (!s.mask.empty() && (s.mask.width != frame.width || s.mask.height != frame.height))
    throw std::invalid_argument("feature tracker: the mask is " + std::to_string(s.mask.width) + "x" +
                                std::to_string(s.mask.height) + " but the frame is " + std::to_string(frame.width) +
                                "x" + std::to_string(frame.height));
  if (!s.prev_image.empty() && (s.prev_image.cols != frame.width || s.prev_image.rows != frame.height))
    throw std::invalid_argument("feature tracker: frame size changed from " + std::to_string(s.prev_image.cols) + "x" +
                                std::to_string(s.prev_image.rows) + " to " + std::to_string(frame.width) + "x" +
                                std::to_string(frame.height));
  const cv::Mat image = wrap(frame).clone();
  const cv::Size window(o.klt_window, o.klt_window);
  std::vector<cv::Mat> pyramid;
  cv::Mat image3;  // the frame in three channels, formed when RLOF runs (kept for the next frame)
  cv::buildOpticalFlowPyramid(image, pyramid, window, o.klt_pyramid_levels);
  TrackingResult r;

  // 1. KLT forward and backward.
  if (!s.features.empty() && !s.prev_pyramid.empty()) {
    std::vector<cv::Point2f> p0, p1, p0_back;
    for (const TrackedFeature& f : s.features) p0.emplace_back(float(f.uv.x()), float(f.uv.y()));
    // Gyro seed: the infinite-depth prediction of each feature (zero flow where it fails).
    std::vector<cv::Point2f> predicted = p0;
    r.gyro_seeded = o.gyro_klt != GyroKlt::kOff && camera_ && R_cur_prev && is_rotation(*R_cur_prev);
    if (r.gyro_seeded)
      for (std::size_t i = 0; i < p0.size(); ++i) {
        Eigen::Vector2d q;
        if (!predict_by_rotation(*camera_, *R_cur_prev, s.features[i].uv, &q)) continue;
        predicted[i] = cv::Point2f(float(q.x()), float(q.y()));
        ++r.predicted;
      }
    const bool seed = r.gyro_seeded && o.gyro_klt == GyroKlt::kSeed;
    std::vector<uchar> status, status_back;
    std::vector<float> err;
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, o.klt_max_iterations, o.klt_epsilon);
    // KLT from the initial positions q1 (in place); each feature keeps the better of its current
    // candidate (p1, status, err) and the new one, or is lost if both converge, lie more than
    // ambiguity_px apart and have residuals within ambiguity_ratio (two motifs of a repeated texture fit).
    const auto candidate = [&](std::vector<cv::Point2f> q1) {
      std::vector<uchar> status2;
      std::vector<float> err2;
      cv::calcOpticalFlowPyrLK(s.prev_pyramid, pyramid, p0, q1, status2, err2, window, o.klt_pyramid_levels, term,
                               cv::OPTFLOW_USE_INITIAL_FLOW);
      for (std::size_t i = 0; i < p0.size(); ++i) {
        const bool both = status[i] && status2[i];
        if (both && o.ambiguity_px > 0.0 && cv::norm(p1[i] - q1[i]) > o.ambiguity_px &&
            std::min(err[i], err2[i]) > float(o.ambiguity_ratio) * std::max(err[i], err2[i])) {
          status[i] = 0;  // ambiguous
          continue;
        }
        if (status2[i] && (!status[i] || err2[i] < err[i])) p1[i] = q1[i], status[i] = 1, err[i] = err2[i];
      }
    };
    p1 = seed ? predicted : p0;
    cv::calcOpticalFlowPyrLK(s.prev_pyramid, pyramid, p0, p1, status, err, window, o.klt_pyramid_levels, term,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    const std::vector<cv::Point2f>& start = seed ? predicted : p0;  // the first pass's seeds
    // Large motion: KLT started at zero flow (or at the prediction) may lock onto a repeated
    // texture motif. Track again from the median flow (relative to the start) as another candidate.
    if (o.median_flow_retry_px > 0.0) {
      std::vector<float> fx, fy;
      for (std::size_t i = 0; i < p0.size(); ++i)
        if (status[i]) fx.push_back(p1[i].x - start[i].x), fy.push_back(p1[i].y - start[i].y);
      if (!fx.empty()) {
        std::nth_element(fx.begin(), fx.begin() + fx.size() / 2, fx.end());
        std::nth_element(fy.begin(), fy.begin() + fy.size() / 2, fy.end());
        const cv::Point2f median(fx[fx.size() / 2], fy[fy.size() / 2]);
        if (cv::norm(median) > o.median_flow_retry_px) {
          std::vector<cv::Point2f> q1(p0.size());
          for (std::size_t i = 0; i < p0.size(); ++i) q1[i] = start[i] + median;
          candidate(std::move(q1));
        }
      }
    }
    if (r.gyro_seeded && o.gyro_klt == GyroKlt::kCandidate) candidate(predicted);
    // Robust refinement: RLOF from the previous position, started where KLT's flow puts it, taken
    // if it lands closer than the limit to that start. kTrack refines the track; kTest the test
    // chain (from its own previous position, moved by KLT's flow; restarted at KLT's position when
    // the refinement is not taken).
    std::vector<cv::Point2f> p1_test;
    if (o.rlof_refine != RlofRefine::kOff && !p0.empty()) {
      const bool test = o.rlof_refine == RlofRefine::kTest;
      std::vector<cv::Point2f> from = p0, q = p1;
      if (test)
        for (std::size_t i = 0; i < p0.size(); ++i) {
          const Eigen::Vector2d& t = s.features[i].uv_test;
          from[i] = cv::Point2f(float(t.x()), float(t.y()));
          q[i] = from[i] + (p1[i] - p0[i]);
        }
      const std::vector<cv::Point2f> start = q;
      std::vector<uchar> ok;
      if (s.prev_image3.empty()) cv::cvtColor(s.prev_image, s.prev_image3, cv::COLOR_GRAY2BGR);
      cv::cvtColor(image, image3, cv::COLOR_GRAY2BGR);
      rlof_refine(s.prev_image3, image3, o.klt_window, from, &q, &ok);
      if (test) p1_test = p1;
      for (std::size_t i = 0; i < p0.size(); ++i) {
        if (!status[i] || !ok[i] || !(cv::norm(q[i] - start[i]) < o.rlof_max_shift_px)) continue;
        (test ? p1_test : p1)[i] = q[i];
        ++r.rlof_refined;
      }
    }
    const bool fb = o.forward_backward_px > 0.0;
    if (fb) {
      p0_back = p0;  // initial guess: where the feature started
      cv::calcOpticalFlowPyrLK(pyramid, s.prev_pyramid, p1, p0_back, status_back, err, window, o.klt_pyramid_levels,
                               term, cv::OPTFLOW_USE_INITIAL_FLOW);
    }
    float err_limit = std::numeric_limits<float>::infinity();
    if (o.max_residual_ratio > 0.0) {  // photometric residual above ratio × the median ⇒ lost
      std::vector<float> e;
      for (std::size_t i = 0; i < p0.size(); ++i)
        if (status[i]) e.push_back(err[i]);
      if (!e.empty()) {
        std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
        err_limit = float(o.max_residual_ratio) * e[e.size() / 2];
      }
    }
    std::vector<TrackedFeature> kept;
    for (std::size_t i = 0; i < p0.size(); ++i) {
      if (!status[i] || err[i] > err_limit) { ++r.lost_klt; continue; }
      if (fb && (!status_back[i] || cv::norm(p0[i] - p0_back[i]) > o.forward_backward_px)) {
        ++r.lost_forward_backward;
        continue;
      }
      const double x = p1[i].x, y = p1[i].y, b = o.border_px;
      if (!(x >= b && y >= b && x < frame.width - b && y < frame.height - b)) { ++r.lost_border; continue; }
      if (o.min_patch_ncc > -1.0) {  // NaN (patch at the border): no verdict, kept
        const double ncc = patch_ncc(s.prev_frame, s.features[i].uv, frame, Eigen::Vector2d(x, y), o.patch_half_px);
        if (ncc < o.min_patch_ncc) { ++r.lost_appearance; continue; }
      }
      TrackedFeature t = s.features[i];
      t.prev_uv = t.uv;
      t.uv = Eigen::Vector2d(x, y);
      t.uv_test = p1_test.empty() ? t.uv : Eigen::Vector2d(p1_test[i].x, p1_test[i].y);
      ++t.age;
      kept.push_back(t);
    }
    s.features = std::move(kept);
  } else {
    s.features.clear();
  }
  r.tracked = int(s.features.size());

  // 2. Refill: detect where the mask allows and no tracked feature is within min_distance.
  const int missing = o.max_features - int(s.features.size());
  if (missing > 0) {
    cv::Mat free_mask = s.mask.empty() ? cv::Mat(image.size(), CV_8UC1, cv::Scalar(255)) : (wrap(s.mask) != 0);
    const int radius = int(std::lround(o.min_distance_px));
    for (const TrackedFeature& f : s.features)
      cv::circle(free_mask, cv::Point(int(std::lround(f.uv.x())), int(std::lround(f.uv.y()))), radius, cv::Scalar(0), -1);
    std::vector<cv::Point2f> corners;
    if (o.grid_cols > 0) {
      const int cells = o.grid_cols * o.grid_rows;
      const int per_cell = std::max(1, (missing + cells - 1) / cells);
      for (int gy = 0; gy < o.grid_rows; ++gy)
        for (int gx = 0; gx < o.grid_cols; ++gx) {
          const cv::Rect cell(gx * image.cols / o.grid_cols, gy * image.rows / o.grid_rows,
                              (gx + 1) * image.cols / o.grid_cols - gx * image.cols / o.grid_cols,
                              (gy + 1) * image.rows / o.grid_rows - gy * image.rows / o.grid_rows);
          std::vector<cv::Point2f> c;
          cv::goodFeaturesToTrack(image(cell), c, per_cell, o.quality_level, o.min_distance_px, free_mask(cell),
                                  o.block_size);
          for (cv::Point2f& p : c) corners.emplace_back(p.x + cell.x, p.y + cell.y);
        }
      if (int(corners.size()) > missing) corners.resize(missing);
    } else {
      cv::goodFeaturesToTrack(image, corners, missing, o.quality_level, o.min_distance_px, free_mask, o.block_size);
    }
    if (!corners.empty() && o.subpix_half_window > 0) {
      const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
      cv::cornerSubPix(image, corners, cv::Size(o.subpix_half_window, o.subpix_half_window), cv::Size(-1, -1), term);
    }
    for (const cv::Point2f& p : corners) {
      if (!(p.x >= o.border_px && p.y >= o.border_px && p.x < frame.width - o.border_px && p.y < frame.height - o.border_px))
        continue;
      TrackedFeature t;
      t.id = s.next_id++;
      t.uv = t.prev_uv = t.uv_test = Eigen::Vector2d(p.x, p.y);
      t.age = 0;
      s.features.push_back(t);
      ++r.detected;
    }
  }
  r.features = s.features;
  s.prev_image = image;
  s.prev_image3 = image3;  // empty unless RLOF ran: the next call converts the previous frame then
  if (o.min_patch_ncc > -1.0) s.prev_frame = frame;
  s.prev_pyramid = std::move(pyramid);
  return r;
}

}  // namespace slamkit
