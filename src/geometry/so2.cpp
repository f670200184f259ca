#include "slamkit/geometry/so2.h"

#include <cmath>

namespace slamkit {

namespace {
void set_if(SO2::Jacobian* J, double v) {
  if (J) (*J)(0, 0) = v;
}
}  // namespace

SO2 SO2::from_matrix(const Eigen::Matrix2d& R) { return SO2(std::atan2(R(1, 0), R(0, 0))); }

Eigen::Matrix2d SO2::matrix() const {
  const double c = std::cos(angle_), s = std::sin(angle_);
  Eigen::Matrix2d R;
  R << c, -s, s, c;
  return R;
}

SO2 SO2::exp(const Tangent& tau, Jacobian* J_out_tau) {
  set_if(J_out_tau, 1.0);
  return SO2(tau(0));
}

SO2::Tangent SO2::log(Jacobian* J_out_this) const {
  set_if(J_out_this, 1.0);
  return Tangent(angle_);
}

SO2 SO2::compose(const SO2& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  set_if(J_out_this, 1.0);
  set_if(J_out_other, 1.0);
  return SO2(angle_ + other.angle_);
}

SO2 SO2::inverse(Jacobian* J_out_this) const {
  set_if(J_out_this, -1.0);
  return SO2(-angle_);
}

SO2 SO2::between(const SO2& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  set_if(J_out_this, -1.0);
  set_if(J_out_other, 1.0);
  return SO2(other.angle_ - angle_);
}

Eigen::Vector2d SO2::act(const Eigen::Vector2d& p, Eigen::Matrix<double, 2, 1>* J_out_this,
                         Eigen::Matrix2d* J_out_p) const {
  const Eigen::Matrix2d R = matrix();
  const Eigen::Vector2d out = R * p;
  if (J_out_this) *J_out_this = Eigen::Vector2d(-out.y(), out.x());  // R [1]× p
  if (J_out_p) *J_out_p = R;
  return out;
}

SO2 SO2::plus(const Tangent& delta, Jacobian* J_out_this, Jacobian* J_out_delta) const {
  set_if(J_out_this, 1.0);
  set_if(J_out_delta, 1.0);
  return SO2(angle_ + delta(0));
}

SO2::Tangent SO2::minus(const SO2& other, Jacobian* J_out_this, Jacobian* J_out_other) const {
  set_if(J_out_this, 1.0);
  set_if(J_out_other, -1.0);
  return Tangent(wrap_angle(angle_ - other.angle_));
}

}  // namespace slamkit
