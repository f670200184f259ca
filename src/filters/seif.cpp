#include "slamkit/filters/seif.h"

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "filter_common.h"

namespace slamkit {

using namespace filters_detail;

struct Seif::Landmark {
  int id = -1;
  Eigen::Vector2d mu = Eigen::Vector2d::Zero(), xi = Eigen::Vector2d::Zero();
  Eigen::Matrix2d omega = Eigen::Matrix2d::Zero();                   // Ω_mm
  Eigen::Matrix<double, 3, 2> omega_pose = Eigen::Matrix<double, 3, 2>::Zero();  // Ω_xm
  std::vector<std::pair<int, Eigen::Matrix2d>> links;               // Ω_{m, other}
  bool active = false;
  long last_seen = -1;
  int seen_order = 0;  // position in the scan where it was last observed
  double entropy_prev = std::numeric_limits<double>::quiet_NaN();  // H(x_t | m), entropy rule
};

struct Seif::Factorization {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
};

namespace {
constexpr double kLog2PiE = 2.8378770664093453;  // ln(2πe)
double gaussian_entropy(const Eigen::Matrix3d& S) { return 0.5 * (3 * kLog2PiE + std::log(S.determinant())); }
}  // namespace

Seif::Seif(LandmarkFilterOptions options, SeifOptions seif) : o_(std::move(options)), s_(seif) {
  check_filter_options(o_, "seif");
  if (o_.active_landmarks < 1) throw InputError("seif", 0, "active", "the active bound must be >= 1");
  if (s_.recovery_sweeps < 0 || s_.recovery_extra < 0)
    throw InputError("seif", 0, "recovery", "sweeps and extra landmarks must be >= 0");
  mu_x_ = o_.initial_pose;
  omega_xx_ = o_.initial_sigma.cwiseAbs2().cwiseInverse().asDiagonal();
  xi_x_ = omega_xx_ * mu_x_;
  pose_entropy_prev_ = gaussian_entropy(omega_xx_.inverse());
}

Seif::~Seif() = default;

std::string Seif::name() const { return s_.rule == SparsificationRule::kEntropy ? "seif-entropy" : "seif"; }

Eigen::Vector3d Seif::pose() const {
  Eigen::Vector3d p = mu_x_;
  p.z() = wrap_angle(p.z());
  return p;
}

std::size_t Seif::size() const { return lm_.size(); }

int Seif::max_links() const {
  std::size_t m = 0;
  for (const auto& l : lm_) m = std::max(m, l.links.size());
  return int(m);
}

const Eigen::Matrix2d* Seif::find_link(int i, int j) const {
  for (const auto& [k, block] : lm_[i].links)
    if (k == j) return &block;
  return nullptr;
}

Eigen::Matrix2d& Seif::link(int i, int j) {
  for (auto& [k, block] : lm_[i].links)
    if (k == j) return block;
  lm_[i].links.emplace_back(j, Eigen::Matrix2d::Zero());
  return lm_[i].links.back().second;
}

// Dense (Ω, ξ, μ) over [pose; set...].
void Seif::assemble(const std::vector<int>& set, Eigen::MatrixXd* Om, Eigen::VectorXd* xi,
                    Eigen::VectorXd* mu) const {
  const int n = 3 + 2 * int(set.size());
  Om->setZero(n, n);
  xi->resize(n);
  if (mu) mu->resize(n);
  Om->topLeftCorner<3, 3>() = omega_xx_;
  xi->head<3>() = xi_x_;
  if (mu) mu->head<3>() = mu_x_;
  for (std::size_t a = 0; a < set.size(); ++a) {
    const Landmark& l = lm_[set[a]];
    const int r = 3 + 2 * int(a);
    Om->block<2, 2>(r, r) = l.omega;
    Om->block<3, 2>(0, r) = l.omega_pose;
    Om->block<2, 3>(r, 0) = l.omega_pose.transpose();
    xi->segment<2>(r) = l.xi;
    if (mu) mu->segment<2>(r) = l.mu;
    for (std::size_t b = a + 1; b < set.size(); ++b)
      if (const Eigen::Matrix2d* L = find_link(set[a], set[b])) {
        const int c = 3 + 2 * int(b);
        Om->block<2, 2>(r, c) = *L;
        Om->block<2, 2>(c, r) = L->transpose();
      }
  }
}

// Writes the blocks of a dense local (Ω, ξ) back; zero links are dropped.
void Seif::store(const std::vector<int>& set, const Eigen::MatrixXd& Om, const Eigen::VectorXd& xi) {
  omega_xx_ = 0.5 * (Om.topLeftCorner<3, 3>() + Om.topLeftCorner<3, 3>().transpose());
  xi_x_ = xi.head<3>();
  for (std::size_t a = 0; a < set.size(); ++a) {
    Landmark& l = lm_[set[a]];
    const int r = 3 + 2 * int(a);
    l.omega = 0.5 * (Om.block<2, 2>(r, r) + Om.block<2, 2>(r, r).transpose());
    l.omega_pose = Om.block<3, 2>(0, r);
    l.xi = xi.segment<2>(r);
    for (std::size_t b = 0; b < set.size(); ++b) {
      if (a == b) continue;
      const Eigen::Matrix2d block = Om.block<2, 2>(r, 3 + 2 * int(b));
      if (block.isZero(0.0)) {
        auto& links = l.links;
        links.erase(std::remove_if(links.begin(), links.end(), [&](const auto& p) { return p.first == set[b]; }),
                    links.end());
      } else {
        link(set[a], set[b]) = block;
      }
    }
  }
  factor_.reset();
}

void Seif::predict(const Control& u) {
  check_control(u, "seif");
  const auto m = linearize_motion(o_, mu_x_, u);
  Eigen::MatrixXd Om;
  Eigen::VectorXd xi;
  assemble(active_, &Om, &xi, nullptr);
  information_motion_update(m, mu_x_, &Om, &xi);
  store(active_, Om, xi);
  mu_x_ = m.next;
}

bool Seif::is_active(int id) const { return lm_.at(index_.at(id)).active; }

std::vector<int> Seif::linked_landmarks(int id) const {
  std::vector<int> out;
  for (const auto& l : lm_.at(index_.at(id)).links) out.push_back(lm_[l.first].id);
  return out;
}

Eigen::MatrixXd Seif::local_covariance(const std::vector<int>& ids, bool with_neighbours) const {
  std::vector<int> set = active_;
  std::vector<int> want;
  for (int id : ids) {
    const auto it = index_.find(id);
    if (it == index_.end()) throw InputError("seif", 0, "landmark", "no landmark with id " + std::to_string(id));
    want.push_back(it->second);
  }
  auto add = [&](int k) {
    if (std::find(set.begin(), set.end(), k) == set.end()) set.push_back(k);
  };
  for (int k : want) {
    add(k);
    if (with_neighbours)
      for (const auto& l : lm_[k].links) add(l.first);
  }
  Eigen::MatrixXd Om;
  Eigen::VectorXd xi;
  assemble(set, &Om, &xi, nullptr);
  const Eigen::MatrixXd Sigma = Om.llt().solve(Eigen::MatrixXd::Identity(Om.rows(), Om.cols()));
  std::vector<int> rows = {0, 1, 2};
  for (int k : want) {
    const int a = int(std::find(set.begin(), set.end(), k) - set.begin());
    rows.push_back(3 + 2 * a);
    rows.push_back(4 + 2 * a);
  }
  Eigen::MatrixXd C(rows.size(), rows.size());
  for (std::size_t a = 0; a < rows.size(); ++a)
    for (std::size_t b = 0; b < rows.size(); ++b) C(a, b) = Sigma(rows[a], rows[b]);
  return C;
}

void Seif::update(const std::vector<RangeBearing>& z) {
  check_observations(z, "seif");
  stats_ = UpdateStatistics{};
  stats_.observations = int(z.size());
  ++scan_;
  observed_now_.clear();
  if (z.empty()) return;
  // Candidates: under known association only the mapped landmarks this scan names (a step must
  // not touch all n landmarks); nn and JCBB consider the whole map.
  std::vector<int> ids;
  std::vector<Eigen::Vector2d> means;
  if (o_.association.method == AssociationMethod::kKnown) {
    for (const RangeBearing& o : z) {
      const auto it = index_.find(o.id);
      if (it != index_.end() && std::find(ids.begin(), ids.end(), o.id) == ids.end())
        ids.push_back(o.id), means.push_back(lm_[it->second].mu);
    }
  } else {
    for (const Landmark& l : lm_) ids.push_back(l.id), means.push_back(l.mu);
  }
  const std::vector<int> assoc = associate_landmarks(
      z, pose(), ids, means, [this](const std::vector<int>& q) { return local_covariance(q, true); }, o_.sensor,
      o_.association);

  std::vector<int> matched_ids;
  for (std::size_t i = 0; i < z.size(); ++i)
    if (assoc[i] >= 0) matched_ids.push_back(assoc[i]);
  if (!matched_ids.empty()) {  // NIS with the local covariance
    const Eigen::MatrixXd C = local_covariance(matched_ids, false);
    const int k = int(matched_ids.size());
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2 * k, 3 + 2 * k);
    Eigen::VectorXd nu(2 * k);
    int a = 0;
    for (std::size_t i = 0; i < z.size(); ++i) {
      if (assoc[i] < 0) continue;
      const Landmark& l = lm_[index_.at(assoc[i])];
      Eigen::Matrix<double, 2, 3> Hx;
      Eigen::Matrix2d Hm;
      o_.sensor.jacobians(mu_x_, l.mu, &Hx, &Hm);
      H.block<2, 3>(2 * a, 0) = Hx;
      H.block<2, 2>(2 * a, 3 + 2 * a) = Hm;
      nu.segment<2>(2 * a) = RangeBearingModel::innovation(z[i], o_.sensor.predict(mu_x_, l.mu));
      ++a;
    }
    Eigen::MatrixXd S = H * C * H.transpose();
    for (int b = 0; b < k; ++b) S.block<2, 2>(2 * b, 2 * b) += o_.sensor.noise();
    stats_.associated = k;
    stats_.nis = nu.dot(S.ldlt().solve(nu));
    stats_.nis_dof = 2 * k;
  }

  auto activate = [&](int k, int order) {
    Landmark& l = lm_[k];
    if (!l.active) {
      l.active = true;
      l.entropy_prev = std::numeric_limits<double>::quiet_NaN();  // no time-t value: competes as new
      active_.push_back(k);
    }
    l.last_seen = scan_;
    l.seen_order = order;
    observed_now_.push_back(k);
  };
  auto add_factor = [&](int k, const InformationFactor& f) {
    Landmark& l = lm_[k];
    omega_xx_ += f.A_x.transpose() * f.V * f.A_x;
    l.omega_pose += f.A_x.transpose() * f.V * f.A_m;
    l.omega += f.A_m.transpose() * f.V * f.A_m;
    xi_x_ += f.A_x.transpose() * f.V * f.y;
    l.xi += f.A_m.transpose() * f.V * f.y;
  };
  // Measurement factors, all linearized at the predicted mean (as EKF and EIF).
  std::vector<std::pair<int, InformationFactor>> factors;
  for (std::size_t i = 0; i < z.size(); ++i)
    if (assoc[i] >= 0) {
      const int k = index_.at(assoc[i]);
      factors.emplace_back(k, measurement_factor(o_.sensor, mu_x_, lm_[k].mu, z[i]));
    }
  for (std::size_t a = 0; a < factors.size(); ++a) {
    add_factor(factors[a].first, factors[a].second);
    activate(factors[a].first, int(a));
  }
  if (!factors.empty()) recover_mean(observed_now_);
  int order = int(factors.size());
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (assoc[i] == kRejectedObservation) ++stats_.rejected;
    if (assoc[i] != kNewLandmark) continue;
    Landmark l;
    l.id = o_.association.method == AssociationMethod::kKnown ? z[i].id : next_id_++;
    const InformationFactor f = new_landmark_factor(o_.sensor, mu_x_, z[i], &l.mu);
    const int k = int(lm_.size());
    index_[l.id] = k;
    lm_.push_back(std::move(l));
    add_factor(k, f);
    activate(k, order++);
    ++stats_.new_landmarks;
  }
  factor_.reset();
  if (int(active_.size()) > o_.active_landmarks) sparsify();
  recover_mean(observed_now_);
  if (s_.rule == SparsificationRule::kEntropy) remember_entropies();
}

// Which active landmarks (indices into active_) become passive.
std::vector<int> Seif::choose_passive(const Eigen::MatrixXd& Sigma) const {
  const int n_active = int(active_.size()), excess = n_active - o_.active_landmarks;
  std::vector<double> score(n_active);
  std::vector<char> eligible(n_active, 1);
  if (s_.rule == SparsificationRule::kStandard) {
    // Least recently observed first; within one scan, earlier in the scan first.
    for (int a = 0; a < n_active; ++a) {
      const Landmark& l = lm_[active_[a]];
      score[a] = -(double(l.last_seen) * 1e6 + l.seen_order);
    }
  } else {
    const Eigen::Matrix3d Sxx = Sigma.topLeftCorner<3, 3>();
    const double H_now = gaussian_entropy(Sxx);  // maximum of H(x_{t+1} | m): unconditional
    for (int a = 0; a < n_active; ++a) {
      const Landmark& l = lm_[active_[a]];
      double h_next = H_now;
      if (l.last_seen == scan_) {  // observed at t+1: H(x_{t+1} | m_i)
        const int r = 3 + 2 * a;
        const Eigen::Matrix3d cond =
            Sxx - Sigma.block<3, 2>(0, r) * Sigma.block<2, 2>(r, r).ldlt().solve(Sigma.block<2, 3>(r, 0));
        h_next = gaussian_entropy(cond);
      }
      const bool is_new = std::isnan(l.entropy_prev);
      double h_prev = l.entropy_prev;
      if (is_new) {
        switch (s_.entropy.new_landmarks) {
          case EntropyRuleOptions::NewLandmarkScore::kPoseEntropy: h_prev = pose_entropy_prev_; break;
          case EntropyRuleOptions::NewLandmarkScore::kCurrentTwice: h_prev = h_next; break;
          case EntropyRuleOptions::NewLandmarkScore::kKeepActive: eligible[a] = 0; h_prev = 0; break;
        }
      }
      score[a] = s_.entropy.use_previous_step ? h_prev + h_next : h_next;
    }
  }
  std::vector<int> order(n_active);
  for (int a = 0; a < n_active; ++a) order[a] = a;
  // Highest score first among the eligible; ties by active-set position (deterministic).
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (eligible[a] != eligible[b]) return eligible[a] > eligible[b];
    return score[a] > score[b];
  });
  order.resize(std::max(0, excess));
  return order;
}

void Seif::sparsify() {
  Eigen::MatrixXd Om;
  Eigen::VectorXd xi, mu;
  assemble(active_, &Om, &xi, &mu);
  Eigen::MatrixXd Sigma;
  if (s_.rule == SparsificationRule::kEntropy)
    Sigma = Om.llt().solve(Eigen::MatrixXd::Identity(Om.rows(), Om.cols()));
  const std::vector<int> passive = choose_passive(Sigma);
  std::vector<char> is_passive(active_.size(), 0);
  for (int a : passive) is_passive[a] = 1;
  // Index sets in the local matrix: X = pose, Z = m⁰ (to become passive).
  std::vector<int> X = {0, 1, 2}, Z, XZ = {0, 1, 2};
  for (std::size_t a = 0; a < active_.size(); ++a)
    if (is_passive[a]) {
      for (int r : {3 + 2 * int(a), 4 + 2 * int(a)}) Z.push_back(r), XZ.push_back(r);
    }
  const int n = int(Om.rows());
  // Ω − Ω_{·S} (Ω_SS)⁻¹ Ω_{S·}: marginalizes the index set S out of Om.
  auto marginalize = [&](const Eigen::MatrixXd& A, const std::vector<int>& S) {
    Eigen::MatrixXd A_S(n, S.size()), A_SS(S.size(), S.size());
    for (std::size_t j = 0; j < S.size(); ++j) A_S.col(j) = A.col(S[j]);
    for (std::size_t i = 0; i < S.size(); ++i) A_SS.row(i) = A_S.row(S[i]);
    Eigen::MatrixXd out = A - A_S * A_SS.ldlt().solve(A_S.transpose());
    for (int s : S) out.row(s).setZero(), out.col(s).setZero();  // exactly zero, not round-off
    return out;
  };
  const Eigen::MatrixXd O1 = marginalize(Om, Z);
  const Eigen::MatrixXd O2 = marginalize(Om, XZ);
  const Eigen::MatrixXd O3 = marginalize(Om, X);
  Eigen::MatrixXd Otilde = O1 - O2 + O3;
  for (int s : Z) Otilde.block(0, s, 3, 1).setZero(), Otilde.block(s, 0, 1, 3).setZero();  // x–m⁰ links gone
  Otilde = 0.5 * (Otilde + Otilde.transpose()).eval();
  xi += (Otilde - Om) * mu;
  store(active_, Otilde, xi);
  std::vector<int> still;
  for (std::size_t a = 0; a < active_.size(); ++a) {
    Landmark& l = lm_[active_[a]];
    if (is_passive[a]) {
      l.active = false;
      l.omega_pose.setZero();
    } else {
      still.push_back(active_[a]);
    }
  }
  active_ = still;
}

// The entropy rule's time-t values for the next scan: H(x_t) and H(x_t | m_i) of the active set.
void Seif::remember_entropies() {
  Eigen::MatrixXd Om;
  Eigen::VectorXd xi;
  assemble(active_, &Om, &xi, nullptr);
  const Eigen::MatrixXd S = Om.llt().solve(Eigen::MatrixXd::Identity(Om.rows(), Om.cols()));
  const Eigen::Matrix3d Sxx = S.topLeftCorner<3, 3>();
  pose_entropy_prev_ = gaussian_entropy(Sxx);
  for (std::size_t a = 0; a < active_.size(); ++a) {
    const int r = 3 + 2 * int(a);
    lm_[active_[a]].entropy_prev =
        gaussian_entropy(Sxx - S.block<3, 2>(0, r) * S.block<2, 2>(r, r).ldlt().solve(S.block<2, 3>(r, 0)));
  }
}

void Seif::gauss_seidel_pose() {
  Eigen::Vector3d r = xi_x_;
  for (int k : active_) r -= lm_[k].omega_pose * lm_[k].mu;
  mu_x_ = omega_xx_.ldlt().solve(r);
}

void Seif::gauss_seidel_landmark(int k) {
  Landmark& l = lm_[k];
  Eigen::Vector2d r = l.xi;
  if (l.active) r -= l.omega_pose.transpose() * mu_x_;
  for (const auto& [j, block] : l.links) r -= block * lm_[j].mu;
  l.mu = l.omega.ldlt().solve(r);
}

void Seif::recover_mean(const std::vector<int>& extra_first) {
  std::vector<int> set = active_;
  for (int k : extra_first)
    if (std::find(set.begin(), set.end(), k) == set.end()) set.push_back(k);
  const std::size_t n = lm_.size();
  const std::size_t extra = std::min<std::size_t>(s_.recovery_extra, n);
  for (std::size_t i = 0; i < extra; ++i) {
    const int k = int((round_robin_ + i) % n);
    if (std::find(set.begin(), set.end(), k) == set.end()) set.push_back(k);
  }
  if (n > 0) round_robin_ = (round_robin_ + extra) % n;
  for (int s = 0; s < s_.recovery_sweeps; ++s) {
    gauss_seidel_pose();
    for (int k : set) gauss_seidel_landmark(k);
  }
}

void Seif::recover_mean_fully(int sweeps) {
  for (int s = 0; s < sweeps; ++s) {
    gauss_seidel_pose();
    for (std::size_t k = 0; k < lm_.size(); ++k) gauss_seidel_landmark(int(k));
  }
}

const Seif::Factorization& Seif::factorization() const {
  if (factor_) return *factor_;
  const int n = 3 + 2 * int(lm_.size());
  std::vector<Eigen::Triplet<double>> t;
  auto put = [&](int r, int c, const auto& M) {
    for (int i = 0; i < M.rows(); ++i)
      for (int j = 0; j < M.cols(); ++j)
        if (M(i, j) != 0.0) t.emplace_back(r + i, c + j, M(i, j));
  };
  put(0, 0, omega_xx_);
  for (std::size_t k = 0; k < lm_.size(); ++k) {
    const int r = 3 + 2 * int(k);
    put(r, r, lm_[k].omega);
    if (lm_[k].active) put(0, r, lm_[k].omega_pose), put(r, 0, Eigen::Matrix<double, 2, 3>(lm_[k].omega_pose.transpose()));
    for (const auto& [j, block] : lm_[k].links) put(r, 3 + 2 * j, block);
  }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  auto f = std::make_unique<Factorization>();
  f->ldlt.compute(A);
  if (f->ldlt.info() != Eigen::Success) throw NumericalError("seif: information matrix is not positive definite");
  factor_ = std::move(f);
  return *factor_;
}

Eigen::MatrixXd Seif::joint_covariance(const std::vector<int>& ids) const {
  std::vector<int> rows = {0, 1, 2};
  for (int id : ids) {
    const auto it = index_.find(id);
    if (it == index_.end()) throw InputError("seif", 0, "landmark", "no landmark with id " + std::to_string(id));
    rows.push_back(3 + 2 * it->second);
    rows.push_back(4 + 2 * it->second);
  }
  const auto& f = factorization();
  const int n = 3 + 2 * int(lm_.size());
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, rows.size());
  for (std::size_t a = 0; a < rows.size(); ++a) E(rows[a], a) = 1;
  const Eigen::MatrixXd X = f.ldlt.solve(E);
  Eigen::MatrixXd C(rows.size(), rows.size());
  for (std::size_t a = 0; a < rows.size(); ++a) C.row(a) = X.row(rows[a]);
  return 0.5 * (C + C.transpose());
}

Eigen::Matrix3d Seif::pose_covariance() const { return joint_covariance({}).topLeftCorner<3, 3>(); }

std::vector<LandmarkEstimate> Seif::landmarks() const {
  std::vector<LandmarkEstimate> out;
  const bool exact = int(lm_.size()) <= s_.exact_marginals_limit;
  const int n = 3 + 2 * int(lm_.size());
  const int batch = 64;  // landmarks per multi-right-hand-side solve
  for (std::size_t k0 = 0; k0 < lm_.size(); k0 += batch) {
    const int m = int(std::min<std::size_t>(batch, lm_.size() - k0));
    Eigen::MatrixXd X;
    if (exact) {
      Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, 2 * m);
      for (int a = 0; a < m; ++a) E(3 + 2 * (k0 + a), 2 * a) = E(4 + 2 * (k0 + a), 2 * a + 1) = 1;
      X = factorization().ldlt.solve(E);
    }
    for (int a = 0; a < m; ++a) {
      const Landmark& l = lm_[k0 + a];
      const int r = 3 + 2 * int(k0 + a);
      Eigen::Matrix2d C = exact ? Eigen::Matrix2d(X.block<2, 2>(r, 2 * a)) : Eigen::Matrix2d(l.omega.inverse());
      out.push_back({l.id, l.mu, 0.5 * (C + C.transpose())});
    }
  }
  return out;
}

}  // namespace slamkit
