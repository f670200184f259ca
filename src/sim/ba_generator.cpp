#include "slamkit/sim/ba_generator.h"

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <sstream>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

constexpr double kHalfWidth = 500.0, kHalfHeight = 375.0;

Eigen::Vector3d log_rotation(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

}  // namespace

BalProblem generate_ba_problem(const BaSimOptions& o, BalProblem* truth) {
  if (o.cameras < 2 || o.cameras > 100000) throw InputError("sim:ba", 0, "cameras", "must be in [2, 100000]");
  if (o.points < 1 || o.points > 10000000) throw InputError("sim:ba", 0, "points", "must be in [1, 10000000]");
  if (o.min_track < 2 || o.max_track < o.min_track || o.max_track > 50)
    throw InputError("sim:ba", 0, "max_track", "need 2 <= min_track <= max_track <= 50");
  if (!(o.noise >= 0.0) || !(o.spacing > 0.0)) throw InputError("sim:ba", 0, "noise", "noise >= 0 and spacing > 0 required");
  std::mt19937_64 rng(o.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);

  BalProblem p;
  p.source = "sim:ba";
  // Camera axes in the world: x → +x, y (up) → +z, looking down −z → +y (the facade).
  Eigen::Matrix3d R_wc_base;
  R_wc_base.col(0) = Eigen::Vector3d::UnitX();
  R_wc_base.col(1) = Eigen::Vector3d::UnitZ();
  R_wc_base.col(2) = -Eigen::Vector3d::UnitY();
  std::vector<Eigen::Matrix3d> R_cw(o.cameras);
  std::vector<Eigen::Vector3d> centre(o.cameras);
  p.cameras.resize(o.cameras);
  for (int i = 0; i < o.cameras; ++i) {
    const Eigen::Vector3d jitter(0.03 * n01(rng), 0.03 * n01(rng), 0.03 * n01(rng));
    const Eigen::Matrix3d R_wc = R_wc_base * Eigen::AngleAxisd(jitter.norm(), jitter.normalized()).toRotationMatrix();
    R_cw[i] = R_wc.transpose();
    centre[i] = Eigen::Vector3d(i * o.spacing, 0.3 * n01(rng), 1.5 + 0.1 * n01(rng));
    BalProblem::CameraParams& c = p.cameras[i];
    c.head<3>() = log_rotation(R_cw[i]);
    c.segment<3>(3) = -(R_cw[i] * centre[i]);
    c[6] = 500.0 + 20.0 * n01(rng);
    c[7] = 0.02 * n01(rng);
    c[8] = 0.002 * n01(rng);
  }
  p.points.reserve(o.points);
  p.observations.reserve(static_cast<std::size_t>(o.points) * (o.min_track + o.max_track) / 2);
  std::uniform_int_distribution<int> anchor_dist(0, o.cameras - 1), track_dist(o.min_track, o.max_track);
  for (int j = 0; j < o.points; ++j) {
    // A point in the anchor camera's view: pixel inside the central 80%, depth 4–20.
    for (int attempt = 0;; ++attempt) {
      const int a = anchor_dist(rng);
      const double depth = 4.0 + 16.0 * u01(rng);
      const Eigen::Vector2d pix((2 * u01(rng) - 1) * 0.8 * kHalfWidth, (2 * u01(rng) - 1) * 0.8 * kHalfHeight);
      const Eigen::Vector3d P(-pix.x() / 500.0 * depth, -pix.y() / 500.0 * depth, -depth);  // p = −P/P.z ≈ pix/f
      const Eigen::Vector3d X = R_cw[a].transpose() * P + centre[a];
      const int len = std::min(track_dist(rng), o.cameras);
      const int first = std::max(0, std::min(o.cameras - len, a - static_cast<int>(u01(rng) * len)));
      std::vector<BalObservation> obs;
      for (int i = first; i < first + len; ++i) {
        double pz = 0.0;
        const Eigen::Vector2d u = bal_project(p.cameras[i], X, &pz);
        if (pz < -0.5 && std::abs(u.x()) < kHalfWidth && std::abs(u.y()) < kHalfHeight)
          obs.push_back({i, j, u + o.noise * Eigen::Vector2d(n01(rng), n01(rng))});
      }
      if (obs.size() >= 2 || attempt > 20) {
        if (obs.size() < 2) {  // very rare: force the anchor and its neighbour
          obs.clear();
          const int b = a + 1 < o.cameras ? a + 1 : a - 1;
          for (int i : {std::min(a, b), std::max(a, b)})
            obs.push_back({i, j, bal_project(p.cameras[i], X) + o.noise * Eigen::Vector2d(n01(rng), n01(rng))});
        }
        p.points.push_back(X);
        p.observations.insert(p.observations.end(), obs.begin(), obs.end());
        break;
      }
    }
  }
  if (truth) *truth = p;
  // Perturbed start.
  for (BalProblem::CameraParams& c : p.cameras) {
    const Eigen::Vector3d C = bal_camera_center(c);
    const Eigen::Vector3d dr(o.rotation_start_sigma * n01(rng), o.rotation_start_sigma * n01(rng),
                             o.rotation_start_sigma * n01(rng));
    const Eigen::Matrix3d R = Eigen::AngleAxisd(c.head<3>().norm(), c.head<3>().normalized()).toRotationMatrix();
    const Eigen::Matrix3d Rp = (dr.norm() > 0 ? Eigen::AngleAxisd(dr.norm(), dr.normalized()).toRotationMatrix()
                                              : Eigen::Matrix3d::Identity()) * R;
    c.head<3>() = log_rotation(Rp);
    bal_set_camera_center(c, C + o.centre_start_sigma * Eigen::Vector3d(n01(rng), n01(rng), n01(rng)));
    c[6] += o.focal_start_sigma * n01(rng);
  }
  for (Eigen::Vector3d& X : p.points) X += o.point_start_sigma * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
  return p;
}

bool parse_ba_sim_spec(const std::string& spec, BaSimOptions* options) {
  if (spec != "sim:ba" && spec.rfind("sim:ba?", 0) != 0) return false;
  BaSimOptions o;
  if (spec.size() > 7) {
    std::stringstream ss(spec.substr(7));
    std::string kv;
    while (std::getline(ss, kv, '&')) {
      const auto eq = kv.find('=');
      if (eq == std::string::npos) throw InputError(spec, 0, kv, "expected key=value");
      const std::string k = kv.substr(0, eq), v = kv.substr(eq + 1);
      try {
        std::size_t used = 0;
        auto as_int = [&] {
          const long long x = std::stoll(v, &used);
          if (used != v.size()) throw std::invalid_argument(v);
          return x;
        };
        if (k == "cameras") o.cameras = static_cast<int>(std::max(-1LL, std::min<long long>(as_int(), 1LL << 30)));
        else if (k == "points") o.points = static_cast<int>(std::max(-1LL, std::min<long long>(as_int(), 1LL << 30)));
        else if (k == "seed") o.seed = static_cast<std::uint64_t>(as_int());
        else if (k == "min_track") o.min_track = static_cast<int>(as_int());
        else if (k == "max_track") o.max_track = static_cast<int>(as_int());
        else if (k == "noise") {
          o.noise = std::stod(v, &used);
          if (used != v.size()) throw std::invalid_argument(v);
        } else
          throw InputError(spec, 0, k, "unknown key (cameras, points, seed, noise, min_track, max_track)");
      } catch (const std::logic_error&) {
        throw InputError(spec, 0, k, "not a number: '" + v + "'");
      }
    }
  }
  if (options) *options = o;
  return true;
}

}  // namespace slamkit
