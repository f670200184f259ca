#include "slamkit/solvers/toro.h"

#include <algorithm>
#include <numeric>
#include <random>

#include "tree_relaxation.h"

namespace slamkit {

RelaxerSummary optimize_toro(PoseGraph& g, const ToroOptions& options) {
  const RelaxerGraph rg = make_relaxer_graph(g);
  const int root = detail::tree_root(rg);
  detail::TreeRelaxation engine(g, rg, detail::bfs_tree(rg, root));
  // Short constraints first (TORO's order); ties in file order.
  std::vector<int> order(g.edges.size()), length(g.edges.size());
  std::iota(order.begin(), order.end(), 0);
  for (std::size_t e = 0; e < order.size(); ++e) length[e] = engine.path_length(static_cast<int>(e));
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return length[x] < length[y]; });
  detail::GradientPhaseSchedule phase(options.gradient_phase);
  std::mt19937_64 rng(options.seed);
  auto step = [&](int iteration) {
    const RelaxerGradientPhase p = phase.at(iteration);
    if (options.shuffle_in_gradient_phase && rg.dimension == 2 && p.start > 0 && iteration > p.start)
      // Fisher-Yates with our own draws: the same order on every platform
      for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng() % i]);
    engine.set_gradient_phase(p);
    return engine.iterate(iteration, order);
  };
  RelaxerSummary s = run_relaxer(g, "toro", phase.wrap(options.stop), step, [&] { engine.write_back(g); });
  s.num_loop_closures = rg.num_loop_closures;
  if (!phase.note().empty()) s.notes.push_back(phase.note());
  if (rg.num_loop_closures == 0) s.notes.push_back("no loop closure: every constraint can be met exactly");
  return s;
}

}  // namespace slamkit
