// The dense window solver against the generic engine on the same window (synthetic scene,
// perturbed states, IMU factors, a prior, Cauchy reprojections): same cost, same minimum, same
// marginal system as vio/marginalize(); observation weights scale the cost; DVI options parse.
#include <gtest/gtest.h>

#include <map>
#include <random>

#include "slamkit/core/error.h"
#include "slamkit/factors/inverse_depth_factor.h"
#include "slamkit/factors/marginalization_prior.h"
#include "slamkit/factors/prior_factor.h"
#include "slamkit/solvers/optimizer.h"
#include "slamkit/vio/dense_window_solver.h"
#include "slamkit/vio/marginalization.h"
#include "testing/vio_scene.h"

namespace slamkit {
namespace {

using InvDepth = Eigen::Matrix<double, 1, 1>;

struct Window {
  testing::VioScene scene{0.5, 1.6, 5, 300};
  std::vector<ImuState> states;
  std::vector<WindowFeature> features;
  std::vector<WindowStateFactor> factors;
  std::shared_ptr<const RobustKernel> kernel = std::make_shared<CauchyKernel>(2.0);

  explicit Window(int n = 6) {
    std::mt19937 rng(3);
    std::normal_distribution<double> g;
    std::vector<int> frame_of;  // scene frame of each state
    for (int i = 0; i < n; ++i) frame_of.push_back(3 * i + 1);
    for (int i = 0; i < n; ++i) {
      ImuState x = scene.motion.state(scene.frames[frame_of[i]].stamp);
      x.R = x.R.plus(0.01 * Eigen::Vector3d(g(rng), g(rng), g(rng)));
      x.p += 0.03 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      x.v += 0.03 * Eigen::Vector3d(g(rng), g(rng), g(rng));
      states.push_back(x);
    }
    Eigen::Matrix<double, 15, 1> sigma = Eigen::Matrix<double, 15, 1>::Constant(0.01);
    factors.push_back({std::make_shared<PriorFactor<ImuState>>(symbol('x', 0), scene.motion.state(scene.frames[frame_of[0]].stamp),
                                                               NoiseModel::diagonal(sigma)),
                       {0}});
    for (int i = 0; i + 1 < n; ++i) {
      ImuPreintegration pim(ImuBias{}, scene.noise);
      pim.integrate_between(scene.imu, scene.frames[frame_of[i]].stamp, scene.frames[frame_of[i + 1]].stamp);
      factors.push_back({std::make_shared<ImuFactor>(symbol('x', i), symbol('x', i + 1), pim, scene.motion.gravity), {i, i + 1}});
    }
    // Features: anchored in the first state that sees them, observed in the later ones.
    std::map<std::uint64_t, WindowFeature> by_track;
    for (int i = 0; i < n; ++i) {
      const SE3 T_wc = states[i].pose() * scene.T_imu_cam;
      for (const FeatureObservation& o : scene.frames[frame_of[i]].features) {
        auto it = by_track.find(o.track_id);
        if (it == by_track.end()) {
          WindowFeature f;
          f.anchor = i;
          scene.camera->unproject(o.pixel, &f.bearing);
          const double d = (T_wc.inverse().act(scene.landmarks[o.track_id])).norm();
          f.inv_depth = (1.0 + 0.05 * g(rng)) / d;
          by_track.emplace(o.track_id, f);
        } else {
          Eigen::Vector2d px = o.pixel;
          if (o.track_id % 37 == 0) px += Eigen::Vector2d(25.0, -15.0);  // outliers for the kernel
          it->second.obs.push_back({i, px, 1.0});
        }
      }
    }
    for (auto& [t, f] : by_track)
      if (!f.obs.empty()) features.push_back(f);
  }

  DenseWindowSolver solver(const ThreadPool* pool = nullptr) const {
    return DenseWindowSolver(scene.camera, scene.T_imu_cam, scene.pixel_sigma, kernel, pool);
  }

  // The same problem as a factor graph: x<i>, l<f>.
  void graph(FactorGraph& G, Values& V, bool only_first, std::vector<Key>* first_features) const {
    for (std::size_t i = 0; i < states.size(); ++i) V.insert(symbol('x', i), states[i]);
    for (const WindowStateFactor& f : factors)
      if (!only_first || f.states.front() == 0) G.add(f.factor);
    const auto noise = NoiseModel::isotropic(2, scene.pixel_sigma);
    for (std::size_t k = 0; k < features.size(); ++k) {
      const WindowFeature& f = features[k];
      if (only_first && f.anchor != 0) continue;
      V.insert(symbol('l', k), InvDepth(f.inv_depth));
      if (first_features) first_features->push_back(symbol('l', k));
      for (const WindowObservation& o : f.obs)
        G.emplace<InverseDepthFactor>(symbol('x', f.anchor), symbol('x', o.state), symbol('l', k), f.bearing, o.pixel,
                                      scene.camera, scene.T_imu_cam, noise, kernel);
    }
  }
};

TEST(DenseWindowSolver, CostMatchesTheFactorGraph) {
  const Window w;
  ASSERT_GT(w.features.size(), 50u);
  FactorGraph G;
  Values V;
  w.graph(G, V, false, nullptr);
  const double c = w.solver().cost(w.states, w.features, w.factors);
  EXPECT_NEAR(c, G.cost(V), 1e-9 * G.cost(V));
}

TEST(DenseWindowSolver, ReachesTheEnginesMinimum) {
  Window w;
  FactorGraph G;
  Values V;
  w.graph(G, V, false, nullptr);
  OptimizerOptions o;
  o.algorithm = Algorithm::kLevenbergMarquardt;
  o.max_iterations = 50;
  o.function_tolerance = 1e-14;
  o.num_threads = 1;
  o.schur_eliminate = [](Key k) { return symbol_char(k) == 'l'; };
  o.schur.method = SchurMethod::kDense;
  const Summary s = Optimizer(o).optimize(G, V);
  DenseWindowOptions d;
  d.max_iterations = 50;
  d.function_tolerance = 1e-14;
  const double initial = w.solver().cost(w.states, w.features, w.factors);
  const DenseWindowSummary r = w.solver().optimize(w.states, w.features, w.factors, d);
  EXPECT_NEAR(r.initial_cost, initial, 1e-9 * initial);
  EXPECT_LT(r.final_cost, 0.2 * initial);
  EXPECT_NEAR(r.final_cost, s.final_cost, 1e-6 * s.final_cost);
  EXPECT_NEAR(r.final_cost, w.solver().cost(w.states, w.features, w.factors), 1e-9 * r.final_cost);
  for (std::size_t i = 0; i < w.states.size(); ++i) {
    const ImuState& e = V.at<ImuState>(symbol('x', i));
    EXPECT_LT(w.states[i].minus(e).norm(), 1e-5) << "state " << i;
  }
  for (std::size_t k = 0; k < w.features.size(); ++k)
    EXPECT_NEAR(w.features[k].inv_depth, V.at<InvDepth>(symbol('l', k))(0), 1e-5) << "feature " << k;
}

TEST(DenseWindowSolver, MarginalMatchesTheSchurFacility) {
  const Window w;
  FactorGraph G;
  Values V;
  std::vector<Key> first;
  w.graph(G, V, true, &first);
  ASSERT_GT(first.size(), 20u);
  ThreadPool pool(1);
  const MarginalSystem ref = marginalize(G, V, first, {symbol('x', 0)}, pool);
  const DenseMarginal m = w.solver().marginalize_first(w.states, w.features, w.factors);
  ASSERT_EQ(m.kept.size(), ref.kept.size());
  // Map the reference's block order onto the dense one (increasing window index).
  std::vector<int> pos(ref.kept.size());
  for (std::size_t a = 0; a < ref.kept.size(); ++a) {
    const auto it = std::find(m.kept.begin(), m.kept.end(), static_cast<int>(symbol_index(ref.kept[a])));
    ASSERT_NE(it, m.kept.end());
    pos[a] = static_cast<int>(it - m.kept.begin());
  }
  const double scale = ref.H.cwiseAbs().maxCoeff();
  for (std::size_t a = 0; a < pos.size(); ++a) {
    EXPECT_LT((m.g.segment<15>(15 * pos[a]) - ref.g.segment<15>(15 * a)).norm(), 1e-8 * (1.0 + ref.g.norm()));
    for (std::size_t b = 0; b < pos.size(); ++b)
      EXPECT_LT((m.H.block<15, 15>(15 * pos[a], 15 * pos[b]) - ref.H.block<15, 15>(15 * a, 15 * b)).cwiseAbs().maxCoeff(),
                1e-8 * scale);
  }
}

// The window after marginalizing its first state: the MarginalizationPrior (cached JᵀJ path),
// the remaining IMU factors and features; the dense solver and the engine agree again.
TEST(DenseWindowSolver, ReachesTheEnginesMinimumWithAMarginalizationPrior) {
  const Window w;
  const DenseMarginal m = w.solver().marginalize_first(w.states, w.features, w.factors);
  Window v;  // same scene; rebuilt as the window of states 1..n−1
  v.states.assign(w.states.begin() + 1, w.states.end());
  std::vector<Key> keys;
  std::vector<ImuState> x_bar;
  std::vector<int> idx;
  for (int i : m.kept) keys.push_back(symbol('x', i - 1)), x_bar.push_back(w.states[i]), idx.push_back(i - 1);
  v.factors.clear();
  v.factors.push_back({MarginalizationPrior<ImuState>::from_hessian(keys, x_bar, m.H, m.g), idx});
  for (std::size_t k = 2; k < w.factors.size(); ++k) {  // IMU factors 1→2, ...: re-keyed
    const auto& f = static_cast<const ImuFactor&>(*w.factors[k].factor);
    const int i = w.factors[k].states[0] - 1;
    v.factors.push_back({std::make_shared<ImuFactor>(symbol('x', i), symbol('x', i + 1), f.preintegration(), f.gravity()),
                         {i, i + 1}});
  }
  v.features.clear();
  for (const WindowFeature& f : w.features) {
    if (f.anchor == 0) continue;
    WindowFeature g = f;
    g.anchor -= 1;
    for (WindowObservation& o : g.obs) o.state -= 1;
    v.features.push_back(g);
  }
  FactorGraph G;
  Values V;
  v.graph(G, V, false, nullptr);
  OptimizerOptions o;
  o.algorithm = Algorithm::kLevenbergMarquardt;
  o.max_iterations = 50;
  o.function_tolerance = 1e-14;
  o.num_threads = 1;
  o.schur_eliminate = [](Key k) { return symbol_char(k) == 'l'; };
  o.schur.method = SchurMethod::kDense;
  const Summary s = Optimizer(o).optimize(G, V);
  DenseWindowOptions d;
  d.max_iterations = 50;
  d.function_tolerance = 1e-14;
  const DenseWindowSolver solver = v.solver();
  EXPECT_NEAR(solver.cost(v.states, v.features, v.factors), s.initial_cost, 1e-9 * s.initial_cost);
  const DenseWindowSummary r = solver.optimize(v.states, v.features, v.factors, d);
  EXPECT_NEAR(r.final_cost, s.final_cost, 1e-6 * s.final_cost);
  for (std::size_t i = 0; i < v.states.size(); ++i)
    EXPECT_LT(v.states[i].minus(V.at<ImuState>(symbol('x', i))).norm(), 1e-5) << "state " << i;
}

TEST(DenseWindowSolver, ObservationWeightsScaleTheCost) {
  Window w;
  std::vector<WindowStateFactor> none;
  const DenseWindowSolver s = w.solver();
  const double c1 = s.cost(w.states, w.features, none);
  for (WindowFeature& f : w.features)
    for (WindowObservation& o : f.obs) o.weight = 0.3;
  EXPECT_NEAR(s.cost(w.states, w.features, none), 0.3 * c1, 1e-9 * c1);
  for (WindowFeature& f : w.features)
    for (WindowObservation& o : f.obs) o.weight = 0.0;
  EXPECT_EQ(s.cost(w.states, w.features, none), 0.0);
  // With every observation dropped the IMU and prior still give a solvable window.
  DenseWindowOptions d;
  const DenseWindowSummary r = s.optimize(w.states, w.features, w.factors, d);
  EXPECT_TRUE(std::isfinite(r.final_cost));
  EXPECT_LE(r.final_cost, r.initial_cost);
}

// The feature blocks are fixed by the features, and summed in block order: any thread count gives
// bit-identical states, inverse depths, costs and marginal systems (EXPECT_EQ, not NEAR).
TEST(DenseWindowSolver, ResultsAreBitIdenticalForAnyThreadCount) {
  const Window start;
  DenseWindowOptions d;
  d.max_iterations = 6;
  d.function_tolerance = 0.0;
  Window serial = start;
  const DenseWindowSummary r1 = serial.solver().optimize(serial.states, serial.features, serial.factors, d);
  const DenseMarginal m1 = serial.solver().marginalize_first(serial.states, serial.features, serial.factors);
  for (int threads : {1, 2, 3, 4}) {
    const ThreadPool pool(threads);
    Window w = start;
    const DenseWindowSolver solver = w.solver(&pool);
    const DenseWindowSummary r = solver.optimize(w.states, w.features, w.factors, d);
    EXPECT_EQ(r.iterations, r1.iterations) << threads << " threads";
    EXPECT_EQ(r.final_cost, r1.final_cost) << threads << " threads";
    EXPECT_EQ(solver.cost(w.states, w.features, w.factors), serial.solver().cost(serial.states, serial.features, serial.factors));
    for (std::size_t i = 0; i < w.states.size(); ++i) {
      EXPECT_EQ(w.states[i].p, serial.states[i].p) << threads << " threads, state " << i;
      EXPECT_EQ(w.states[i].v, serial.states[i].v) << threads << " threads, state " << i;
      EXPECT_EQ(w.states[i].R.matrix(), serial.states[i].R.matrix()) << threads << " threads, state " << i;
      EXPECT_EQ(w.states[i].ba, serial.states[i].ba) << threads << " threads, state " << i;
    }
    for (std::size_t k = 0; k < w.features.size(); ++k) EXPECT_EQ(w.features[k].inv_depth, serial.features[k].inv_depth);
    const DenseMarginal m = solver.marginalize_first(w.states, w.features, w.factors);
    EXPECT_EQ(m.kept, m1.kept);
    EXPECT_EQ(m.H, m1.H) << threads << " threads";
    EXPECT_EQ(m.g, m1.g) << threads << " threads";
  }
  EXPECT_LT(r1.final_cost, r1.initial_cost);
}

TEST(DenseWindowSolver, BadIndices) {
  Window w;
  w.features.front().obs.front().state = 99;
  DenseWindowOptions d;
  EXPECT_THROW(w.solver().optimize(w.states, w.features, w.factors, d), std::invalid_argument);
  w.features.front().obs.front().state = w.features.front().anchor;
  EXPECT_THROW(w.solver().cost(w.states, w.features, w.factors), std::invalid_argument);
}

TEST(DviOptions, ParseAndEvaluate) {
  DviOptions o;
  parse_dvi_alpha("M", &o);
  EXPECT_DOUBLE_EQ(o.alpha_of(0.6), 0.6);
  parse_dvi_alpha("M^2", &o);
  EXPECT_DOUBLE_EQ(o.alpha_of(0.5), 0.25);
  parse_dvi_alpha("1", &o);
  EXPECT_DOUBLE_EQ(o.alpha_of(0.1), 1.0);
  EXPECT_THROW(parse_dvi_alpha("M^-1", &o), InputError);
  EXPECT_THROW(parse_dvi_alpha("x", &o), InputError);
  parse_dvi_theta("0.4", &o);
  EXPECT_DOUBLE_EQ(o.theta_for(5), 0.4);
  parse_dvi_theta("adaptive:0.3,0.1,0.6", &o);
  EXPECT_DOUBLE_EQ(o.theta_for(-1), 0.3);
  EXPECT_DOUBLE_EQ(o.theta_for(2), 0.5);
  EXPECT_DOUBLE_EQ(o.theta_for(9), 0.6);
  EXPECT_THROW(parse_dvi_theta("1.5", &o), InputError);
  EXPECT_THROW(parse_dvi_theta("adaptive:0.3,0.1", &o), InputError);
  EXPECT_THROW(parse_dvi_theta("nan", &o), InputError);
}

}  // namespace
}  // namespace slamkit
