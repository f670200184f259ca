// Camera models: projection of a point in the camera frame to pixels and back.
//
// Camera frame: x right, y down, z forward (optical axis). Every model maps p = (X, Y, Z) to
// normalized coordinates, distorts them and applies the intrinsics u = fx·x_d + cx,
// v = fy·y_d + cy. Intrinsics vectors are [fx, fy, cx, cy, distortion...].
//   pinhole       x = X/Z, y = Y/Z (Z > 0), no distortion.
//   radtan        (Kalibr "radtan", OpenCV plumb-bob k1 k2 p1 p2, EuRoC): r² = x² + y²,
//                 x_d = x(1 + k1 r² + k2 r⁴) + 2 p1 x y + p2 (r² + 2x²),
//                 y_d = y(1 + k1 r² + k2 r⁴) + p1 (r² + 2y²) + 2 p2 x y   (Z > 0).
//   equidistant   (Kannala-Brandt k1..k4, Kalibr "equidistant", OpenCV fisheye, TUM-VI):
//                 θ = atan2(√(X²+Y²), Z), θ_d = θ(1 + k1θ² + k2θ⁴ + k3θ⁶ + k4θ⁸),
//                 (x_d, y_d) = θ_d · (X, Y)/√(X²+Y²); valid for θ < max_theta() (where θ_d
//                 still increases), so points slightly behind the image plane project too.
// unproject() inverts the distortion by Newton iterations and returns a unit bearing.
// Jacobians: J_uv_p (2×3) wrt the point, J_uv_intrinsics (2×N) wrt the intrinsics vector.
// Models are immutable value objects; all methods are const and thread-safe.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace slamkit {

class CameraModel {
 public:
  virtual ~CameraModel() = default;

  /// "pinhole", "radtan" or "equidistant" (the Kalibr distortion_model names; "none" for pinhole).
  virtual std::string model_name() const = 0;
  /// [fx, fy, cx, cy, distortion...]
  virtual Eigen::VectorXd intrinsics() const = 0;
  virtual std::shared_ptr<CameraModel> with_intrinsics(const Eigen::VectorXd& intrinsics) const = 0;

  /// Pixel of p (camera frame). False (outputs untouched) if p cannot be projected (behind the
  /// camera, beyond the model's field of view, not finite). Pixels may lie outside the image.
  virtual bool project(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J_uv_p = nullptr,
                       Eigen::Matrix<double, 2, Eigen::Dynamic>* J_uv_intrinsics = nullptr) const = 0;
  /// Unit bearing of a pixel. False if the Newton inversion does not converge or the pixel
  /// lies outside the model's valid range.
  virtual bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const = 0;

  int width() const { return width_; }
  int height() const { return height_; }
  /// True if uv lies inside [border, width − border) × [border, height − border).
  bool in_image(const Eigen::Vector2d& uv, double border = 0.0) const {
    return uv.x() >= border && uv.y() >= border && uv.x() < width_ - border && uv.y() < height_ - border;
  }

 protected:
  CameraModel(int width, int height);
  int width_, height_;
};

/// The undistorted model; the distorted ones derive from it for the shared intrinsics.
class PinholeCamera : public CameraModel {
 public:
  PinholeCamera(double fx, double fy, double cx, double cy, int width, int height);
  std::string model_name() const override { return "pinhole"; }
  Eigen::VectorXd intrinsics() const override;
  std::shared_ptr<CameraModel> with_intrinsics(const Eigen::VectorXd& k) const override;
  bool project(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J_uv_p = nullptr,
               Eigen::Matrix<double, 2, Eigen::Dynamic>* J_uv_intrinsics = nullptr) const override;
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const override;

  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }

 protected:
  double fx_, fy_, cx_, cy_;
};

class RadTanCamera : public PinholeCamera {
 public:
  RadTanCamera(double fx, double fy, double cx, double cy, double k1, double k2, double p1, double p2, int width,
               int height);
  std::string model_name() const override { return "radtan"; }
  Eigen::VectorXd intrinsics() const override;
  std::shared_ptr<CameraModel> with_intrinsics(const Eigen::VectorXd& k) const override;
  bool project(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J_uv_p = nullptr,
               Eigen::Matrix<double, 2, Eigen::Dynamic>* J_uv_intrinsics = nullptr) const override;
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const override;
  /// Distorted normalized coordinates of m = (x, y) and their 2×2 Jacobian wrt m.
  Eigen::Vector2d distort(const Eigen::Vector2d& m, Eigen::Matrix2d* J_d_m = nullptr) const;

 private:
  double k1_, k2_, p1_, p2_;
};

class EquidistantCamera : public PinholeCamera {
 public:
  EquidistantCamera(double fx, double fy, double cx, double cy, double k1, double k2, double k3, double k4,
                    int width, int height);
  std::string model_name() const override { return "equidistant"; }
  Eigen::VectorXd intrinsics() const override;
  std::shared_ptr<CameraModel> with_intrinsics(const Eigen::VectorXd& k) const override;
  bool project(const Eigen::Vector3d& p, Eigen::Vector2d* uv, Eigen::Matrix<double, 2, 3>* J_uv_p = nullptr,
               Eigen::Matrix<double, 2, Eigen::Dynamic>* J_uv_intrinsics = nullptr) const override;
  bool unproject(const Eigen::Vector2d& uv, Eigen::Vector3d* bearing) const override;
  /// Largest incidence angle θ the model maps one-to-one (θ_d increasing on [0, max_theta]), ≤ π.
  double max_theta() const { return max_theta_; }

 private:
  double theta_d(double theta, double* dthetad_dtheta = nullptr) const;
  double k1_, k2_, k3_, k4_;
  double max_theta_ = 0.0;
  double max_theta_d_ = 0.0;
};

/// A model from its Kalibr name ("pinhole"/"none", "radtan", "equidistant") and the intrinsics
/// [fx, fy, cx, cy, distortion...] (4, 8, 8 values). Throws std::invalid_argument on a wrong
/// name, count, a non-finite or non-positive focal length, or a non-positive resolution.
std::shared_ptr<CameraModel> make_camera_model(const std::string& model, const std::vector<double>& intrinsics,
                                               int width, int height);

}  // namespace slamkit
