#include "slamkit/filters/fastslam.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>

#include "slamkit/core/error.h"
#include "slamkit/geometry/lie_math.h"

namespace slamkit {
namespace {

constexpr double kLog2Pi = 1.8378770664093453;

// log N(ν; 0, S) for a 2-vector; also returns the squared Mahalanobis distance.
double log_gaussian(const Eigen::Vector2d& nu, const Eigen::Matrix2d& S, double* d2 = nullptr) {
  const double det = S.determinant();
  const double m = nu.dot(S.inverse() * nu);
  if (d2) *d2 = m;
  return -0.5 * m - 0.5 * std::log(det) - kLog2Pi;
}

template <int N>
Eigen::Matrix<double, N, N> symmetric(const Eigen::Matrix<double, N, N>& A) {
  return 0.5 * (A + A.transpose());
}

std::int64_t cell_key(long ix, long iy) {
  return (static_cast<std::int64_t>(ix) << 32) ^ static_cast<std::int64_t>(static_cast<std::uint32_t>(iy));
}

void require_options(const FastSlamOptions& o) {
  auto bad = [](const char* field, const char* msg) { throw InputError("fastslam options", 0, field, msg); };
  if (o.version != 1 && o.version != 2) bad("version", "must be 1 or 2");
  if (o.particles < 1) bad("particles", "must be at least 1");
  if (!(o.resample_fraction > 0 && o.resample_fraction <= 1)) bad("resample_fraction", "must lie in (0, 1]");
  if (!(o.gate_distance2 > 0) || !(o.new_landmark_distance2 >= o.gate_distance2))
    bad("gate_distance2", "need 0 < gate_distance2 <= new_landmark_distance2");
  if (!(o.grid_cell > 0) || !(o.candidate_radius > 0)) bad("grid_cell", "grid cell and candidate radius must be positive");
  if (!o.initial_pose.allFinite() || !o.initial_covariance.allFinite()) bad("initial_pose", "must be finite");
}

}  // namespace

ResamplingScheme parse_resampling_scheme(const std::string& name) {
  if (name == "systematic") return ResamplingScheme::kSystematic;
  if (name == "stratified") return ResamplingScheme::kStratified;
  if (name == "multinomial") return ResamplingScheme::kMultinomial;
  throw InputError("", 0, "resampling", "unknown scheme '" + name + "' (systematic|stratified|multinomial)");
}

const char* resampling_scheme_name(ResamplingScheme s) {
  switch (s) {
    case ResamplingScheme::kSystematic: return "systematic";
    case ResamplingScheme::kStratified: return "stratified";
    case ResamplingScheme::kMultinomial: return "multinomial";
  }
  return "?";
}

std::vector<int> resample_indices(const std::vector<double>& w, ResamplingScheme scheme, std::mt19937_64& rng) {
  const int n = static_cast<int>(w.size());
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  // Sorted points u_k in [0, 1): systematic u_k = (k + u)/N, stratified u_k = (k + u_k)/N,
  // multinomial: N sorted independent uniforms. Particle i is picked once per u_k in its CDF step.
  std::vector<double> u(static_cast<std::size_t>(n));
  const double u0 = uniform(rng);
  for (int k = 0; k < n; ++k) {
    if (scheme == ResamplingScheme::kSystematic)
      u[k] = (k + u0) / n;
    else if (scheme == ResamplingScheme::kStratified)
      u[k] = (k + uniform(rng)) / n;
    else
      u[k] = uniform(rng);
  }
  if (scheme == ResamplingScheme::kMultinomial) std::sort(u.begin(), u.end());
  std::vector<int> out(static_cast<std::size_t>(n));
  double cdf = w.empty() ? 0 : w[0];
  int i = 0;
  for (int k = 0; k < n; ++k) {
    while (u[k] >= cdf && i + 1 < n) cdf += w[++i];
    out[k] = i;
  }
  return out;
}

std::vector<int> fastslam_associate(const std::vector<std::vector<std::pair<int, double>>>& candidates,
                                    double gate_distance2, double new_landmark_distance2) {
  static_assert(kFastSlamNew == kNewLandmark && kFastSlamRejected == kRejectedObservation, "same result codes");
  return nearest_neighbour_from_distances(candidates, gate_distance2, new_landmark_distance2);
}

FastSlam::FastSlam(std::shared_ptr<const MotionModel> motion, const RangeBearingModel& sensor,
                   const FastSlamOptions& options)
    : motion_(std::move(motion)), sensor_(sensor), options_(options), rng_(options.seed) {
  require_options(options_);
  if (!motion_) throw InputError("fastslam options", 0, "motion", "no motion model");
  particles_.resize(static_cast<std::size_t>(options_.particles));
  const bool spread = !options_.initial_covariance.isZero(0);
  for (FastSlamParticle& p : particles_) {
    p.pose = spread ? sample_gaussian(options_.initial_pose, options_.initial_covariance) : options_.initial_pose;
    p.pose.z() = wrap_angle(p.pose.z());
  }
}

Eigen::Vector3d FastSlam::sample_gaussian(const Eigen::Vector3d& mean, const Eigen::Matrix3d& cov) {
  // x = μ + V Λ^½ n through the eigen-decomposition: exact for positive semi-definite Σ.
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Vector3d n(normal(rng_), normal(rng_), normal(rng_));
  if (cov.isZero(0)) return mean;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(symmetric<3>(cov));
  const Eigen::Vector3d s = eig.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return mean + eig.eigenvectors() * s.cwiseProduct(n);
}

void FastSlam::predict(const Control& u) {
  if (!std::isfinite(u.v) || !std::isfinite(u.turn) || !std::isfinite(u.dt) || u.dt < 0)
    throw InputError("control", 0, "dt", "control must be finite with dt >= 0");
  if (u.dt == 0) return;
  const Eigen::Matrix2d Q = motion_->control_noise(u);
  if (options_.version == 1) {
    // Sample the control from N(u, Q) per particle.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(symmetric<2>(Q));
    const Eigen::Matrix2d root = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
    std::normal_distribution<double> normal(0.0, 1.0);
    for (FastSlamParticle& p : particles_) {
      const Eigen::Vector2d e = root * Eigen::Vector2d(normal(rng_), normal(rng_));
      p.pose = motion_->predict(p.pose, Control{u.v + e.x(), u.turn + e.y(), u.dt});
    }
    return;
  }
  Eigen::Matrix3d F_x;
  Eigen::Matrix<double, 3, 2> F_u;
  for (FastSlamParticle& p : particles_) {
    motion_->jacobians(p.pose, u, &F_x, &F_u);
    p.pose_covariance = symmetric<3>(F_x * p.pose_covariance * F_x.transpose() + F_u * Q * F_u.transpose());
    p.pose = motion_->predict(p.pose, u);
  }
}

void FastSlam::set_common_map(const PersistentLandmarkMap& map) {
  map.for_each([&](int id, const LandmarkGaussian& g) {
    if (id < 0 || !g.mean.allFinite() || !g.covariance.allFinite())
      throw InputError("fastslam", 0, "map", "landmark ids must be >= 0 with finite mean and covariance");
    if (options_.association == FastSlamAssociation::kNearestNeighbour) register_landmark(id, g.mean);
    next_id_ = std::max(next_id_, id + 1);
  });
  for (FastSlamParticle& p : particles_) p.map = map;
}

void FastSlam::register_landmark(int id, const Eigen::Vector2d& m) {
  if (!registered_.emplace(id, true).second) return;
  const long ix = static_cast<long>(std::floor(m.x() / options_.grid_cell));
  const long iy = static_cast<long>(std::floor(m.y() / options_.grid_cell));
  grid_[cell_key(ix, iy)].push_back(id);
}

std::vector<int> FastSlam::associate_particle(const FastSlamParticle& p, const std::vector<RangeBearing>& z,
                                              const Eigen::Matrix3d& pose_cov) const {
  std::vector<int> out(z.size(), kFastSlamNew);
  const Eigen::Matrix2d R = sensor_.noise();
  Eigen::Matrix<double, 2, 3> H_x;
  Eigen::Matrix2d H_m;
  auto distance2 = [&](const RangeBearing& zi, const LandmarkGaussian& lm) {
    sensor_.jacobians(p.pose, lm.mean, &H_x, &H_m);
    const Eigen::Matrix2d S = H_m * lm.covariance * H_m.transpose() + R + H_x * pose_cov * H_x.transpose();
    const Eigen::Vector2d nu = RangeBearingModel::innovation(zi, sensor_.predict(p.pose, lm.mean));
    return nu.dot(S.inverse() * nu);
  };
  if (options_.association == FastSlamAssociation::kKnown) {
    for (std::size_t i = 0; i < z.size(); ++i) {
      const LandmarkGaussian* lm = p.map.find(z[i].id);
      if (!lm || (lm->mean - p.pose.head<2>()).squaredNorm() < 1e-12) continue;
      out[i] = options_.known_gate_distance2 > 0 && distance2(z[i], *lm) > options_.known_gate_distance2
                   ? kFastSlamRejected : z[i].id;
    }
    return out;
  }
  const double c = options_.grid_cell, r = options_.candidate_radius;
  std::vector<std::vector<std::pair<int, double>>> candidates(z.size());
  for (std::size_t i = 0; i < z.size(); ++i) {
    const Eigen::Vector2d at = sensor_.inverse(p.pose, z[i]);
    for (long ix = static_cast<long>(std::floor((at.x() - r) / c)); ix <= static_cast<long>(std::floor((at.x() + r) / c)); ++ix)
      for (long iy = static_cast<long>(std::floor((at.y() - r) / c)); iy <= static_cast<long>(std::floor((at.y() + r) / c)); ++iy) {
        const auto cell = grid_.find(cell_key(ix, iy));
        if (cell == grid_.end()) continue;
        for (int id : cell->second) {
          const LandmarkGaussian* lm = p.map.find(id);
          if (!lm || (lm->mean - p.pose.head<2>()).squaredNorm() < 1e-12) continue;
          candidates[i].push_back({id, distance2(z[i], *lm)});
        }
      }
  }
  return fastslam_associate(candidates, options_.gate_distance2, options_.new_landmark_distance2);
}

void FastSlam::update_particle(FastSlamParticle& p, const std::vector<RangeBearing>& z,
                               const std::vector<int>& new_ids, UpdateStatistics* stats) {
  const Eigen::Matrix2d R = sensor_.noise();
  const std::vector<int> assoc = associate_particle(p, z, p.pose_covariance);
  Eigen::Matrix<double, 2, 3> H_x;
  Eigen::Matrix2d H_m;
  if (options_.version == 2) {
    // Proposal: refine N(μ, Σ) by each associated observation in turn; weight at the prediction.
    const Eigen::Vector3d mu0 = p.pose;
    const Eigen::Matrix3d sigma0 = p.pose_covariance;
    Eigen::Vector3d mu = mu0;
    Eigen::Matrix3d sigma = sigma0;
    for (std::size_t i = 0; i < z.size(); ++i) {
      if (assoc[i] < 0) continue;
      const LandmarkGaussian& lm = *p.map.find(assoc[i]);
      sensor_.jacobians(mu0, lm.mean, &H_x, &H_m);
      const Eigen::Matrix2d Sm = H_m * lm.covariance * H_m.transpose() + R;
      p.log_weight += log_gaussian(RangeBearingModel::innovation(z[i], sensor_.predict(mu0, lm.mean)),
                                   Sm + H_x * sigma0 * H_x.transpose());
      sensor_.jacobians(mu, lm.mean, &H_x, &H_m);
      const Eigen::Vector2d nu = RangeBearingModel::innovation(z[i], sensor_.predict(mu, lm.mean));
      const Eigen::Matrix2d S = H_x * sigma * H_x.transpose() + Sm;
      const Eigen::Matrix<double, 3, 2> K = sigma * H_x.transpose() * S.inverse();
      mu += K * nu;
      mu.z() = wrap_angle(mu.z());
      const Eigen::Matrix3d IKH = Eigen::Matrix3d::Identity() - K * H_x;
      sigma = symmetric<3>(IKH * sigma * IKH.transpose() + K * Sm * K.transpose());
    }
    p.pose = sample_gaussian(mu, sigma);
    p.pose.z() = wrap_angle(p.pose.z());
    p.pose_covariance.setZero();
  }
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (assoc[i] == kFastSlamRejected) {
      ++stats->rejected;
      continue;
    }
    const int id = assoc[i] >= 0 ? assoc[i] : new_ids[i];
    const LandmarkGaussian* found = p.map.find(id);
    if (found && (found->mean - p.pose.head<2>()).squaredNorm() > 1e-12) {
      // Landmark EKF update (Joseph form); FastSLAM 1.0 weights by the innovation here.
      LandmarkGaussian lm = *found;
      sensor_.jacobians(p.pose, lm.mean, &H_x, &H_m);
      const Eigen::Vector2d nu = RangeBearingModel::innovation(z[i], sensor_.predict(p.pose, lm.mean));
      const Eigen::Matrix2d S = H_m * lm.covariance * H_m.transpose() + R;
      double d2 = 0;
      const double lw = log_gaussian(nu, S, &d2);
      if (options_.version == 1) p.log_weight += lw;
      const Eigen::Matrix2d K = lm.covariance * H_m.transpose() * S.inverse();
      const Eigen::Matrix2d IKH = Eigen::Matrix2d::Identity() - K * H_m;
      lm.mean += K * nu;
      lm.covariance = symmetric<2>(IKH * lm.covariance * IKH.transpose() + K * R * K.transpose());
      p.map.set(id, lm);
      ++stats->associated;
      stats->nis += d2;
      stats->nis_dof += 2;
    } else if (!found) {
      Eigen::Matrix2d G_z;
      LandmarkGaussian lm;
      lm.mean = sensor_.inverse(p.pose, z[i], nullptr, &G_z);
      lm.covariance = symmetric<2>(G_z * R * G_z.transpose());
      p.map.set(id, lm);
      if (options_.association == FastSlamAssociation::kNearestNeighbour) register_landmark(id, lm.mean);
      ++stats->new_landmarks;
    }
  }
}

void FastSlam::update(const std::vector<RangeBearing>& z) {
  stats_ = UpdateStatistics{};
  stats_.observations = static_cast<int>(z.size());
  for (const RangeBearing& o : z) {
    if (!(o.range > 0) || !std::isfinite(o.range) || !std::isfinite(o.bearing))
      throw InputError("observation", 0, "range", "range must be positive and finite, bearing finite");
    if (options_.association == FastSlamAssociation::kKnown && o.id < 0)
      throw InputError("observation", 0, "id", "known association needs landmark ids >= 0");
  }
  if (z.empty()) return;
  std::vector<int> new_ids(z.size());
  for (std::size_t i = 0; i < z.size(); ++i)
    new_ids[i] = options_.association == FastSlamAssociation::kKnown ? z[i].id : next_id_ + static_cast<int>(i);
  if (options_.association == FastSlamAssociation::kNearestNeighbour) next_id_ += static_cast<int>(z.size());
  std::vector<UpdateStatistics> per(particles_.size());
  for (std::size_t k = 0; k < particles_.size(); ++k) update_particle(particles_[k], z, new_ids, &per[k]);
  const int best = best_particle();
  per[best].observations = stats_.observations;
  stats_ = per[best];
  const double top = particles_[best].log_weight;
  for (FastSlamParticle& p : particles_) {
    p.log_weight -= top;  // keep the largest at 0
    if (!std::isfinite(p.log_weight)) p.log_weight = -1e300;
  }
  resample_if_needed();
}

std::vector<double> FastSlam::weights() const {
  double top = -std::numeric_limits<double>::infinity();
  for (const FastSlamParticle& p : particles_) top = std::max(top, p.log_weight);
  std::vector<double> w(particles_.size());
  double sum = 0;
  for (std::size_t k = 0; k < w.size(); ++k) sum += w[k] = std::exp(particles_[k].log_weight - top);
  for (double& x : w) x /= sum;
  return w;
}

double FastSlam::effective_sample_size() const {
  double s = 0;
  for (double x : weights()) s += x * x;
  return 1.0 / s;
}

int FastSlam::best_particle() const {
  int best = 0;
  for (std::size_t k = 1; k < particles_.size(); ++k)
    if (particles_[k].log_weight > particles_[best].log_weight) best = static_cast<int>(k);
  return best;
}

void FastSlam::resample_if_needed() {
  const std::vector<double> w = weights();
  double s = 0;
  for (double x : w) s += x * x;
  if (1.0 / s >= options_.resample_fraction * options_.particles) return;
  const std::vector<int> idx = resample_indices(w, options_.resampling, rng_);
  std::vector<FastSlamParticle> next;
  next.reserve(particles_.size());
  for (int i : idx) {
    next.push_back(particles_[static_cast<std::size_t>(i)]);  // copies the map's root pointer only
    next.back().log_weight = 0;
  }
  particles_ = std::move(next);
  ++resamples_;
}

Eigen::Vector3d FastSlam::pose() const {
  const std::vector<double> w = weights();
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  double s = 0, c = 0;
  for (std::size_t k = 0; k < w.size(); ++k) {
    m.head<2>() += w[k] * particles_[k].pose.head<2>();
    s += w[k] * std::sin(particles_[k].pose.z());
    c += w[k] * std::cos(particles_[k].pose.z());
  }
  m.z() = std::atan2(s, c);
  return m;
}

Eigen::Matrix3d FastSlam::pose_covariance() const {
  const Eigen::MatrixXd C = joint_covariance({});
  return C;
}

std::vector<LandmarkEstimate> FastSlam::landmarks() const {
  std::vector<LandmarkEstimate> out;
  if (options_.summary == LandmarkSummary::kBest) {
    particles_[static_cast<std::size_t>(best_particle())].map.for_each([&](int id, const LandmarkGaussian& g) {
      out.push_back({id, g.mean, g.covariance});
    });
    return out;
  }
  // Mixture: Σ w (P + (m − m̄)(m − m̄)ᵀ) / Σ w over the particles that hold the landmark.
  struct Acc {
    double w = 0;
    Eigen::Vector2d m = Eigen::Vector2d::Zero();
    Eigen::Matrix2d P = Eigen::Matrix2d::Zero();
  };
  std::map<int, Acc> acc;
  const std::vector<double> w = weights();
  for (std::size_t k = 0; k < particles_.size(); ++k)
    particles_[k].map.for_each([&](int id, const LandmarkGaussian& g) {
      Acc& a = acc[id];
      a.w += w[k];
      a.m += w[k] * g.mean;
    });
  for (auto& [id, a] : acc) a.m /= a.w;
  for (std::size_t k = 0; k < particles_.size(); ++k)
    particles_[k].map.for_each([&](int id, const LandmarkGaussian& g) {
      Acc& a = acc[id];
      const Eigen::Vector2d d = g.mean - a.m;
      a.P += w[k] * (g.covariance + d * d.transpose());
    });
  for (const auto& [id, a] : acc) out.push_back({id, a.m, symmetric<2>(a.P / a.w)});
  return out;
}

Eigen::MatrixXd FastSlam::joint_covariance(const std::vector<int>& ids) const {
  // The particles as a Gaussian mixture of s = [x; m_1 … m_k]: C = Σ w (blockdiag(Σ, P…) + d dᵀ),
  // d = s − s̄ with the heading wrapped around the circular mean, over the particles holding
  // every requested landmark (weights renormalized).
  const std::size_t n = 3 + 2 * ids.size();
  const std::vector<double> w_all = weights();
  std::vector<double> w;
  std::vector<Eigen::VectorXd> s;
  std::vector<Eigen::MatrixXd> block;
  for (std::size_t k = 0; k < particles_.size(); ++k) {
    Eigen::VectorXd sk(n);
    Eigen::MatrixXd bk = Eigen::MatrixXd::Zero(n, n);
    sk.head<3>() = particles_[k].pose;
    bk.topLeftCorner<3, 3>() = particles_[k].pose_covariance;
    bool all = true;
    for (std::size_t j = 0; j < ids.size() && all; ++j) {
      const LandmarkGaussian* g = particles_[k].map.find(ids[j]);
      if (!g) {
        all = false;
        break;
      }
      sk.segment<2>(3 + 2 * j) = g->mean;
      bk.block<2, 2>(3 + 2 * j, 3 + 2 * j) = g->covariance;
    }
    if (!all) continue;
    w.push_back(w_all[k]);
    s.push_back(sk);
    block.push_back(bk);
  }
  if (w.empty()) throw InputError("fastslam", 0, "landmark_ids", "no particle holds every requested landmark");
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  Eigen::VectorXd mean = Eigen::VectorXd::Zero(n);
  double sn = 0, cs = 0;
  for (std::size_t k = 0; k < w.size(); ++k) {
    mean += (w[k] / total) * s[k];
    sn += w[k] * std::sin(s[k](2));
    cs += w[k] * std::cos(s[k](2));
  }
  mean(2) = std::atan2(sn, cs);
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t k = 0; k < w.size(); ++k) {
    Eigen::VectorXd d = s[k] - mean;
    d(2) = wrap_angle(d(2));
    C += (w[k] / total) * (block[k] + d * d.transpose());
  }
  return 0.5 * (C + C.transpose());
}

}  // namespace slamkit
