#include "slamkit/vio/visual_inertial_initializer.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>

namespace slamkit {
namespace {

// Two unit vectors spanning the tangent plane of the unit vector n.
Eigen::Matrix<double, 3, 2> tangent_basis(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d b1 = (a - n * n.dot(a)).normalized();
  Eigen::Matrix<double, 3, 2> B;
  B << b1, n.cross(b1);
  return B;
}

// Least squares over x = [v_0 .. v_n−1 (3n), gravity part (gdim), s]; gravity = g0 + Bg·w.
bool solve_alignment(const InitializerInput& in, const Eigen::Vector3d& bg, const Eigen::Vector3d& g0,
                     const Eigen::MatrixXd& Bg, Eigen::VectorXd* x, double* scale_sigma = nullptr) {
  const int n = static_cast<int>(in.R_c0_body.size());
  const int gdim = static_cast<int>(Bg.cols());
  const int dim = 3 * n + gdim + 1;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(dim, dim);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(dim);
  double zz = 0.0;  // zᵀz: the residual is zᵀz − xᵀb at the solution
  ImuBias bias;
  bias.gyro = bg;
  for (int k = 0; k + 1 < n; ++k) {
    const ImuPreintegration& p = in.imu[k];
    const double T = p.dt();
    const Eigen::Matrix3d Ri = in.R_c0_body[k].matrix(), Rj = in.R_c0_body[k + 1].matrix();
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6, dim);
    Eigen::Matrix<double, 6, 1> z;
    // Rows 0-2: s Δp̄ − v_k T − ½ (g0 + Bg w) T² = Ri Δp + (Rj − Ri) p_bc.
    A.block<3, 3>(0, 3 * k) = -T * Eigen::Matrix3d::Identity();
    A.block(0, 3 * n, 3, gdim) = -0.5 * T * T * Bg;
    A.block<3, 1>(0, dim - 1) = in.p_c0_cam[k + 1] - in.p_c0_cam[k];
    z.head<3>() = Ri * p.delta_p(bias) + (Rj - Ri) * in.p_imu_cam + 0.5 * T * T * g0;
    // Rows 3-5: v_k+1 − v_k − (g0 + Bg w) T = Ri Δv.
    A.block<3, 3>(3, 3 * k) = -Eigen::Matrix3d::Identity();
    A.block<3, 3>(3, 3 * (k + 1)) = Eigen::Matrix3d::Identity();
    A.block(3, 3 * n, 3, gdim) = -T * Bg;
    z.tail<3>() = Ri * p.delta_v(bias) + T * g0;
    H += A.transpose() * A;
    b += A.transpose() * z;
    zz += z.squaredNorm();
  }
  // Scale the system for conditioning: the scale column is often much smaller.
  const Eigen::VectorXd d = H.diagonal().cwiseMax(1e-12).cwiseSqrt().cwiseInverse();
  const Eigen::MatrixXd Hs = d.asDiagonal() * H * d.asDiagonal();
  Eigen::LDLT<Eigen::MatrixXd> ldlt(Hs);
  if (ldlt.info() != Eigen::Success) return false;
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Hs, Eigen::EigenvaluesOnly).eigenvalues();
  if (!(ev.minCoeff() > 1e-10 * ev.maxCoeff())) return false;
  *x = d.asDiagonal() * ldlt.solve(d.asDiagonal() * b);
  if (scale_sigma) {
    // σ_s = sqrt(σ̂² (H⁻¹)_ss), σ̂² = ‖A x − z‖² / (rows − dim).
    const int rows = 6 * (n - 1);
    const double rss = std::max(0.0, zz - x->dot(b));
    Eigen::VectorXd e = Eigen::VectorXd::Zero(dim);
    e(dim - 1) = d(dim - 1);
    const double h_ss = d(dim - 1) * ldlt.solve(e)(dim - 1);
    *scale_sigma = rows > dim ? std::sqrt(rss / (rows - dim) * h_ss) : std::numeric_limits<double>::infinity();
  }
  return x->allFinite();
}

}  // namespace

InitializerResult initialize_visual_inertial(const InitializerInput& in, const InitializerOptions& o) {
  InitializerResult res;
  const int n = static_cast<int>(in.R_c0_body.size());
  if (n < o.min_frames || static_cast<int>(in.p_c0_cam.size()) != n || static_cast<int>(in.imu.size()) != n - 1) {
    res.message = "initializer: need at least " + std::to_string(o.min_frames) +
                  " frames with a pose each and IMU between consecutive frames (got " + std::to_string(n) + ")";
    return res;
  }
  for (const auto& p : in.imu)
    if (!(p.dt() > 0.0)) {
      res.message = "initializer: an IMU interval between frames is empty";
      return res;
    }
  // Excitation: the spread of the mean specific force over the intervals (rotated into c0).
  {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    std::vector<Eigen::Vector3d> a;
    for (int k = 0; k + 1 < n; ++k) a.push_back(in.R_c0_body[k].act(in.imu[k].delta_v()) / in.imu[k].dt()), sum += a.back();
    const Eigen::Vector3d mean = sum / a.size();
    double var = 0.0;
    for (const auto& x : a) var += (x - mean).squaredNorm();
    const double sd = std::sqrt(var / std::max<std::size_t>(1, a.size() - 1));
    if (!(sd >= o.min_accel_excitation)) {
      res.message = "initializer: not enough excitation (accel std " + std::to_string(sd) + " m/s² < " +
                    std::to_string(o.min_accel_excitation) + ")";
      return res;
    }
  }
  // 1. Gyroscope bias. rotation_error(k, b_g) = Log(ΔR_k(b_g)ᵀ R_bkᵀ R_bk+1): gyroscope against SfM.
  auto rotation_error = [&](int k, const Eigen::Vector3d& bg) {
    ImuBias bias;
    bias.gyro = bg;
    return Eigen::Vector3d(in.imu[k].delta_R(bias).between(in.R_c0_body[k].between(in.R_c0_body[k + 1])).log());
  };
  Eigen::Vector3d bg = Eigen::Vector3d::Zero();
  for (int it = 0; it < 2; ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (int k = 0; k + 1 < n; ++k) {
      const Eigen::Vector3d e = rotation_error(k, bg);
      const Eigen::Matrix3d J = in.imu[k].bias_jacobian().block<3, 3>(0, 0);
      H += J.transpose() * J;
      b += J.transpose() * e;
    }
    const Eigen::Vector3d d = H.ldlt().solve(b);
    if (!d.allFinite()) {
      res.message = "initializer: the gyroscope bias is unobservable (no rotation in the window)";
      return res;
    }
    bg += d;
  }
  res.gyro_bias = bg;
  // The SfM's rotations against the gyroscope's at the fitted bias.
  {
    double sum = 0.0;
    for (int k = 0; k + 1 < n; ++k) sum += rotation_error(k, bg).squaredNorm();
    res.rotation_rms_deg = std::sqrt(sum / (n - 1)) * 180.0 / kPi;
    if (o.max_rotation_rms_deg > 0.0 && !(res.rotation_rms_deg <= o.max_rotation_rms_deg)) {
      res.message = "initializer: the SfM rotations disagree with the gyroscope (RMS " +
                    std::to_string(res.rotation_rms_deg) + " deg > " + std::to_string(o.max_rotation_rms_deg) + " deg)";
      return res;
    }
  }
  // 2. Velocities, gravity, scale.
  Eigen::VectorXd x;
  if (!solve_alignment(in, bg, Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), &x)) {
    res.message = "initializer: the linear alignment (velocities, gravity, scale) is singular";
    return res;
  }
  Eigen::Vector3d g = x.segment<3>(3 * n);
  double s = x(x.size() - 1);
  if (!(s > 0.0) || std::abs(g.norm() - o.gravity_magnitude) > o.max_gravity_error * o.gravity_magnitude) {
    res.message = "initializer: alignment gave scale " + std::to_string(s) + " and |g| " + std::to_string(g.norm()) +
                  " (expected " + std::to_string(o.gravity_magnitude) + ")";
    return res;
  }
  // 3. Gravity refinement on the sphere |g| = G.
  for (int it = 0; it < o.refinement_iterations; ++it) {
    const Eigen::Vector3d g0 = o.gravity_magnitude * g.normalized();
    const Eigen::Matrix<double, 3, 2> B = tangent_basis(g.normalized());
    if (!solve_alignment(in, bg, g0, B, &x, &res.scale_sigma)) {
      res.message = "initializer: the gravity refinement is singular";
      return res;
    }
    g = o.gravity_magnitude * (g0 + B * x.segment<2>(3 * n)).normalized();
    s = x(x.size() - 1);
  }
  if (!(s > 0.0) || !x.allFinite()) {
    res.message = "initializer: refinement gave scale " + std::to_string(s);
    return res;
  }
  if (o.max_scale_rel_sigma > 0.0 && !(res.scale_sigma <= o.max_scale_rel_sigma * s)) {
    res.message = "initializer: the scale is not determined by the window (scale " + std::to_string(s) + " ± " +
                  std::to_string(res.scale_sigma) + ", more than " + std::to_string(o.max_scale_rel_sigma) +
                  " relative)";
    return res;
  }
  res.scale = s;
  res.gravity_c0 = g;
  // World frame: z up (g ↦ (0, 0, −G)), with the yaw of the c0 frame kept.
  const Eigen::Vector3d down = g.normalized();
  res.R_world_c0 = SO3(Eigen::Quaterniond::FromTwoVectors(down, -Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d p0 = s * in.p_c0_cam[0] - in.R_c0_body[0].act(in.p_imu_cam);
  for (int k = 0; k < n; ++k) {
    ImuState st;
    st.R = res.R_world_c0 * in.R_c0_body[k];
    st.p = res.R_world_c0.act(s * in.p_c0_cam[k] - in.R_c0_body[k].act(in.p_imu_cam) - p0);
    st.v = res.R_world_c0.act(x.segment<3>(3 * k));
    st.bg = bg;
    res.velocities_c0.push_back(x.segment<3>(3 * k));
    res.states.push_back(st);
  }
  res.success = true;
  res.message = "initialized: scale " + std::to_string(s) + ", gyro bias |b_g| " + std::to_string(bg.norm()) +
                " rad/s, rotation RMS against the gyroscope " + std::to_string(res.rotation_rms_deg) + " deg, scale σ " +
                std::to_string(res.scale_sigma);
  return res;
}

InitializerResult initialize_from_frames(const std::vector<CameraFrame>& frames, const std::vector<ImuMeasurement>& imu,
                                         const CameraModel& camera, const SE3& T_imu_cam, const ImuNoise& noise,
                                         const VisualSfmOptions& sfm_options, const InitializerOptions& options,
                                         VisualSfmResult* sfm_out) {
  InitializerResult res;
  std::vector<std::vector<SfmObservation>> bearings(frames.size());
  for (std::size_t k = 0; k < frames.size(); ++k)
    for (const FeatureObservation& f : frames[k].features) {
      SfmObservation s;
      s.track_id = f.track_id;
      if (f.pixel.allFinite() && camera.unproject(f.pixel, &s.bearing)) bearings[k].push_back(s);
    }
  VisualSfmResult sfm = solve_visual_sfm(bearings, sfm_options);
  if (sfm_out) *sfm_out = sfm;
  if (!sfm.success) {
    res.message = sfm.message;
    return res;
  }
  if (imu.empty() || imu.front().stamp > frames.front().stamp || imu.back().stamp < frames.back().stamp) {
    res.message = "initializer: the IMU does not cover the start-up window";
    return res;
  }
  InitializerInput in;
  in.p_imu_cam = T_imu_cam.translation();
  const SO3 R_cam_imu = T_imu_cam.rotation().inverse();
  for (std::size_t k = 0; k < frames.size(); ++k) {
    in.R_c0_body.push_back(sfm.T_c0_cam[k].rotation() * R_cam_imu);
    in.p_c0_cam.push_back(sfm.T_c0_cam[k].translation());
    if (k + 1 < frames.size()) {
      ImuPreintegration p(ImuBias{}, noise);
      p.integrate_between(imu, frames[k].stamp, frames[k + 1].stamp);
      in.imu.push_back(p);
    }
  }
  res = initialize_visual_inertial(in, options);
  if (res.success) res.message = sfm.message + "; " + res.message;
  return res;
}

}  // namespace slamkit
