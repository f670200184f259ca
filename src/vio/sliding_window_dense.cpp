// The sliding-window estimator's dense path (vio/dense_window_solver.h): the window handed to
// the DenseWindowSolver as window indices (keyframe ids are consecutive, oldest first), and
// its results written back.
#include <algorithm>
#include <memory>
#include <stdexcept>

#include "slamkit/factors/marginalization_prior.h"
#include "slamkit/vio/sliding_window_estimator.h"

namespace slamkit {

void SlidingWindowEstimator::dense_problem(bool only_oldest, std::vector<ImuState>& states,
                                           std::vector<WindowFeature>& features, std::vector<std::uint64_t>& tracks,
                                           std::vector<WindowStateFactor>& factors) const {
  const std::uint64_t first = keyframes_.front().id;
  if (keyframes_.back().id - first + 1 != keyframes_.size())
    throw std::logic_error("SlidingWindowEstimator: keyframe ids are not consecutive");
  const auto index_of = [first](std::uint64_t id) { return static_cast<int>(id - first); };
  states.clear(), features.clear(), tracks.clear(), factors.clear();
  for (const Keyframe& k : keyframes_) states.push_back(k.state);
  if (prior_) {
    WindowStateFactor p{prior_, {}};
    for (Key k : prior_->keys()) p.states.push_back(index_of(symbol_index(k)));
    factors.push_back(std::move(p));
  }
  for (std::size_t k = 0; k + 1 < keyframes_.size(); ++k) {
    if (only_oldest && k > 0) break;
    factors.push_back({std::make_shared<ImuFactor>(symbol('x', keyframes_[k].id), symbol('x', keyframes_[k + 1].id),
                                                   imu_factors_[k], options_.gravity),
                       {static_cast<int>(k), static_cast<int>(k + 1)}});
  }
  for (const auto& [track, f] : features_) {
    if (!f.triangulated || f.obs.empty()) continue;
    if (only_oldest && f.anchor != first) continue;
    WindowFeature wf;
    wf.anchor = index_of(f.anchor);
    wf.bearing = f.bearing;
    wf.inv_depth = f.inv_depth;
    for (const auto& [kid, px] : f.obs) {
      const int i = index_of(kid);
      wf.obs.push_back({i, px, keyframes_[i].visual_weight});
    }
    features.push_back(std::move(wf));
    tracks.push_back(track);
  }
}

int SlidingWindowEstimator::solve_dense() {
  std::vector<ImuState> states;
  std::vector<WindowFeature> features;
  std::vector<std::uint64_t> tracks;
  std::vector<WindowStateFactor> factors;
  dense_problem(false, states, features, tracks, factors);
  DenseWindowOptions o;
  o.max_iterations = options_.max_iterations;
  o.function_tolerance = 1e-6;
  const DenseWindowSummary s = dense_.optimize(states, features, factors, o);
  for (std::size_t i = 0; i < keyframes_.size(); ++i) keyframes_[i].state = states[i];
  for (std::size_t i = 0; i < features.size(); ++i) {
    const double rho = features[i].inv_depth;
    if (!(rho >= 1.0 / options_.max_depth && rho <= 1.0 / options_.min_depth))
      features_.erase(tracks[i]);  // diverged or behind the camera: drop it
    else
      features_.at(tracks[i]).inv_depth = rho;
  }
  return s.iterations;
}

void SlidingWindowEstimator::marginalize_oldest_dense() {
  std::vector<ImuState> states;
  std::vector<WindowFeature> features;
  std::vector<std::uint64_t> tracks;
  std::vector<WindowStateFactor> factors;
  dense_problem(true, states, features, tracks, factors);
  // The prior always acts on the oldest keyframe (it covers every keyframe the last
  // marginalization kept), so marginalize_first() takes it whole into the new prior.
  if (prior_ && (factors.empty() || factors.front().states.end() ==
                                        std::find(factors.front().states.begin(), factors.front().states.end(), 0)))
    throw std::logic_error("SlidingWindowEstimator: the prior does not act on the oldest keyframe");
  const DenseMarginal m = dense_.marginalize_first(states, features, factors);
  std::vector<Key> keys;
  std::vector<ImuState> x_bar;
  for (int i : m.kept) keys.push_back(symbol('x', keyframes_[i].id)), x_bar.push_back(states[i]);
  prior_ = MarginalizationPrior<ImuState>::from_hessian(keys, x_bar, m.H, m.g);
}

}  // namespace slamkit
