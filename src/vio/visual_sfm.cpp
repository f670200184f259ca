#include "slamkit/vio/visual_sfm.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "slamkit/core/factor_graph.h"
#include "slamkit/core/robust_kernel.h"
#include "slamkit/core/values.h"
#include "slamkit/geometry/lie_math.h"
#include "slamkit/solvers/optimizer.h"

namespace slamkit {

NormalizedReprojectionFactor::Residual NormalizedReprojectionFactor::error(const SE3& T, const Eigen::Vector3d& P,
                                                                           Jacobian<SE3>* J_T,
                                                                           Jacobian<Eigen::Vector3d>* J_P) const {
  const Eigen::Matrix3d Rt = T.rotation().matrix().transpose();
  const Eigen::Vector3d q = Rt * (P - T.translation());
  if (!(q.z() > 1e-6)) {
    if (J_T) J_T->setZero();
    if (J_P) J_P->setZero();
    return Residual::Constant(kOutOfView);
  }
  const double iz = 1.0 / q.z();
  Eigen::Matrix<double, 2, 3> J_r_q;
  J_r_q << iz, 0.0, -q.x() * iz * iz, 0.0, iz, -q.y() * iz * iz;
  if (J_T) {
    J_T->leftCols<3>() = -J_r_q;
    J_T->rightCols<3>() = J_r_q * skew(q);
  }
  if (J_P) *J_P = J_r_q * Rt;
  return Eigen::Vector2d(q.x() * iz, q.y() * iz) - measured_;
}

BaselineFactor::Residual BaselineFactor::error(const SE3& T, Jacobian<SE3>* J_T) const {
  const double n = T.translation().norm();
  if (J_T) {
    J_T->setZero();
    if (n > 1e-12) J_T->leftCols<3>() = (T.translation() / n).transpose() * T.rotation().matrix();
  }
  return Residual(n - 1.0);
}

namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

using TrackMap = std::unordered_map<std::uint64_t, Eigen::Vector3d>;  // track → bearing

struct View {
  const SE3* T_c0_cam;
  Eigen::Vector3d bearing;
};

// Linear triangulation from bearings: [b]× (Rᵀ (P − c)) = 0 for every view, least squares.
// False if the point is behind a camera or the largest parallax is below min_parallax.
bool triangulate(const std::vector<View>& views, double min_parallax, double min_bearing_z, Eigen::Vector3d* P) {
  if (views.size() < 2) return false;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  double best = 0.0;
  for (std::size_t a = 0; a < views.size(); ++a) {
    const Eigen::Matrix3d R = views[a].T_c0_cam->rotation().matrix();
    const Eigen::Matrix3d A = skew(views[a].bearing) * R.transpose();
    H += A.transpose() * A;
    g += A.transpose() * (A * views[a].T_c0_cam->translation());
    for (std::size_t b = a + 1; b < views.size(); ++b) {
      const Eigen::Vector3d da = R * views[a].bearing, db = views[b].T_c0_cam->rotation().act(views[b].bearing);
      best = std::max(best, std::acos(std::clamp(da.dot(db), -1.0, 1.0)));
    }
  }
  if (best < min_parallax) return false;
  *P = H.ldlt().solve(g);
  if (!P->allFinite()) return false;
  for (const View& v : views) {
    const Eigen::Vector3d q = v.T_c0_cam->inverse().act(*P);
    if (q.norm() < 1e-9 || q.z() / q.norm() < min_bearing_z || q.normalized().dot(v.bearing) < std::cos(5 * kDeg))
      return false;
  }
  return true;
}

cv::Point2d normalized(const Eigen::Vector3d& b) { return {b.x() / b.z(), b.y() / b.z()}; }

// Relative pose of frame j to frame 0 (T_c0_cj, |t| = 1) by the 5-point RANSAC; false if degenerate.
bool relative_pose(const TrackMap& f0, const TrackMap& fj, const VisualSfmOptions& o, SE3* T_c0_cj, int* inliers) {
  std::vector<cv::Point2d> p0, pj;
  for (const auto& [id, b0] : f0) {
    const auto it = fj.find(id);
    if (it == fj.end()) continue;
    p0.push_back(normalized(b0)), pj.push_back(normalized(it->second));
  }
  if (static_cast<int>(p0.size()) < o.min_common_tracks) return false;
  cv::Mat mask;
  const cv::Mat E = cv::findEssentialMat(p0, pj, 1.0, cv::Point2d(0, 0), cv::RANSAC, 0.999,
                                         o.ransac_threshold_px / o.focal_px, 1000, mask);
  if (E.rows != 3 || E.cols != 3) return false;  // no or several solutions
  cv::Mat R, t;
  *inliers = cv::recoverPose(E, p0, pj, R, t, 1.0, cv::Point2d(0, 0), mask);
  if (*inliers < o.min_inliers) return false;
  Eigen::Matrix3d Re;
  Eigen::Vector3d te;
  for (int r = 0; r < 3; ++r) {
    te(r) = t.at<double>(r);
    for (int c = 0; c < 3; ++c) Re(r, c) = R.at<double>(r, c);
  }
  // x_j = R x_0 + t: T_cj_c0 = (R, t).
  *T_c0_cj = SE3(SO3::from_matrix(Re), te.normalized()).inverse();
  return T_c0_cj->translation().allFinite();
}

double mean_raw_parallax(const TrackMap& a, const TrackMap& b, int* common) {
  double sum = 0.0;
  *common = 0;
  for (const auto& [id, ba] : a) {
    const auto it = b.find(id);
    if (it == b.end()) continue;
    sum += std::acos(std::clamp(ba.dot(it->second), -1.0, 1.0)), ++*common;
  }
  return *common > 0 ? sum / *common : 0.0;
}

}  // namespace

VisualSfmResult solve_visual_sfm(const std::vector<std::vector<SfmObservation>>& input, const VisualSfmOptions& o) {
  VisualSfmResult res;
  const int n = static_cast<int>(input.size());
  if (n < 3) {
    res.message = "visual SfM: need at least 3 frames (got " + std::to_string(n) + ")";
    return res;
  }
  std::vector<TrackMap> frames(n);
  for (int k = 0; k < n; ++k)
    for (const SfmObservation& s : input[k]) {
      const Eigen::Vector3d b = s.bearing.normalized();
      if (b.allFinite() && b.z() >= o.min_bearing_z) frames[k][s.track_id] = b;
    }
  // 1. Reference pair (0, j), j as late as possible.
  std::vector<SE3> T(n);
  std::vector<bool> posed(n, false);
  int ref = -1, inliers = 0;
  for (int j = n - 1; j >= 1 && ref < 0; --j) {
    int common = 0;
    if (mean_raw_parallax(frames[0], frames[j], &common) < o.min_pair_parallax_deg * kDeg ||
        common < o.min_common_tracks)
      continue;
    if (relative_pose(frames[0], frames[j], o, &T[j], &inliers)) ref = j;
  }
  if (ref < 0) {
    res.message = "visual SfM: no frame has " + std::to_string(o.min_common_tracks) + " tracks in common with the first at " +
                  std::to_string(o.min_pair_parallax_deg) + "° parallax and a consistent essential matrix";
    return res;
  }
  posed[0] = posed[ref] = true;
  res.reference_frame = ref;
  // 2.–3. Triangulate what the posed frames see; pose the others by PnP, in order.
  std::unordered_map<std::uint64_t, Eigen::Vector3d>& points = res.points;
  const auto triangulate_new = [&]() {
    std::map<std::uint64_t, std::vector<View>> views;
    for (int k = 0; k < n; ++k)
      if (posed[k])
        for (const auto& [id, b] : frames[k])
          if (!points.count(id)) views[id].push_back({&T[k], b});
    for (const auto& [id, v] : views) {
      Eigen::Vector3d P;
      if (triangulate(v, o.min_point_parallax_deg * kDeg, o.min_bearing_z, &P)) points[id] = P;
    }
  };
  triangulate_new();
  const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
  const auto pnp = [&](int k, const SE3& guess) -> bool {
    std::vector<cv::Point3d> obj;
    std::vector<cv::Point2d> img;
    for (const auto& [id, b] : frames[k]) {
      const auto it = points.find(id);
      if (it == points.end()) continue;
      obj.emplace_back(it->second.x(), it->second.y(), it->second.z());
      img.push_back(normalized(b));
    }
    if (static_cast<int>(obj.size()) < o.min_inliers) return false;
    const SE3 T_cam_c0 = guess.inverse();
    const Eigen::Vector3d r0 = T_cam_c0.rotation().log(), t0 = T_cam_c0.translation();
    cv::Mat rvec = (cv::Mat_<double>(3, 1) << r0.x(), r0.y(), r0.z());
    cv::Mat tvec = (cv::Mat_<double>(3, 1) << t0.x(), t0.y(), t0.z());
    std::vector<int> inl;
    if (!cv::solvePnPRansac(obj, img, K, cv::noArray(), rvec, tvec, true, 100, o.pnp_threshold_px / o.focal_px, 0.99, inl,
                            cv::SOLVEPNP_ITERATIVE) ||
        static_cast<int>(inl.size()) < o.min_inliers)
      return false;
    const SE3 T_k(SO3::exp(Eigen::Vector3d(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2))),
                  Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)));
    T[k] = T_k.inverse();
    return T[k].translation().allFinite();
  };
  for (int k = 1; k < n; ++k) {
    if (posed[k]) continue;
    if (!pnp(k, T[k - 1])) {
      res.message = "visual SfM: PnP failed for frame " + std::to_string(k) + " of " + std::to_string(n);
      return res;
    }
    posed[k] = true;
    triangulate_new();
  }
  // 4. Bundle adjustment (frame 0 fixed, |c_ref| = 1).
  FactorGraph graph;
  Values values;
  const auto pose_key = [](int k) { return symbol('c', static_cast<std::uint64_t>(k)); };
  std::unordered_map<std::uint64_t, Key> point_key;
  for (int k = 0; k < n; ++k) values.insert(pose_key(k), T[k]);
  values.set_fixed(pose_key(0));
  graph.emplace<BaselineFactor>(pose_key(ref), NoiseModel::isotropic(1, 1e-4));
  const auto kernel = std::make_shared<CauchyKernel>(o.cauchy_delta);
  std::uint64_t next = 0;
  for (int k = 0; k < n; ++k)
    for (const auto& [id, b] : frames[k]) {
      const auto it = points.find(id);
      if (it == points.end()) continue;
      auto [pk, fresh] = point_key.emplace(id, symbol('p', next));
      if (fresh) values.insert(symbol('p', next++), it->second);
      // 1 px at θ off the axis moves the normalized point by up to 1 / (f cos²θ) (fisheye).
      const auto sigma = NoiseModel::isotropic(2, o.pixel_sigma / (o.focal_px * b.z() * b.z()));
      graph.emplace<NormalizedReprojectionFactor>(pose_key(k), pk->second, Eigen::Vector2d(b.x() / b.z(), b.y() / b.z()),
                                                  sigma, kernel);
    }
  OptimizerOptions opt;
  opt.max_iterations = o.ba_iterations;
  opt.num_threads = 1;
  opt.schur_eliminate = [](Key k) { return symbol_char(k) == 'p'; };
  opt.schur.method = SchurMethod::kDense;
  const Summary s = Optimizer(opt).optimize(graph, values);
  if (!s.success()) {
    res.message = "visual SfM: bundle adjustment failed (" + s.message + ")";
    return res;
  }
  for (int k = 0; k < n; ++k) T[k] = values.at<SE3>(pose_key(k));
  for (auto& [id, P] : points) P = values.at<Eigen::Vector3d>(point_key.at(id));
  // Inlier RMSE in pixels (residuals under 3σ·cauchy).
  double sum = 0.0;
  int count = 0;
  for (int k = 0; k < n; ++k)
    for (const auto& [id, b] : frames[k]) {
      const auto it = points.find(id);
      if (it == points.end()) continue;
      const Eigen::Vector3d q = T[k].inverse().act(it->second);
      if (q.z() <= 0) continue;
      const double e = o.focal_px * b.z() * b.z() * (Eigen::Vector2d(q.x() / q.z(), q.y() / q.z()) - Eigen::Vector2d(b.x() / b.z(), b.y() / b.z())).norm();
      if (e < 3.0 * o.cauchy_delta * o.pixel_sigma) sum += e * e, ++count;
    }
  res.reprojection_rmse_px = count > 0 ? std::sqrt(sum / count) : 0.0;
  if (count < o.min_inliers) {
    res.message = "visual SfM: too few inlier observations after bundle adjustment";
    return res;
  }
  res.T_c0_cam = T;
  res.success = true;
  res.message = "visual SfM: " + std::to_string(n) + " frames, reference pair (0, " + std::to_string(ref) + ") with " +
                std::to_string(inliers) + " inliers, " + std::to_string(points.size()) + " points, BA RMSE " +
                std::to_string(res.reprojection_rmse_px) + " px";
  return res;
}

}  // namespace slamkit
