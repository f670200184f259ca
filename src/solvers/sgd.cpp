#include "slamkit/solvers/sgd.h"

#include <numeric>
#include <optional>
#include <random>

#include "sgd_chain_2d.h"
#include "tree_relaxation.h"

namespace slamkit {

RelaxerSummary optimize_sgd(PoseGraph& g, const SgdOptions& options) {
  const RelaxerGraph rg = make_relaxer_graph(g);
  const int root = detail::tree_root(rg);
  const std::vector<int> parent = detail::id_chain(g, rg, root);
  // The chain from the root in position order; it is a single run when the root has the
  // smallest id (the usual gauge), and then the O(log N) chain engine applies in 2D.
  std::vector<int> chain{root};
  std::vector<int> child(parent.size(), -1);
  for (std::size_t k = 0; k < parent.size(); ++k)
    if (parent[k] >= 0) child[parent[k]] = static_cast<int>(k);
  while (child[chain.back()] >= 0) chain.push_back(child[chain.back()]);
  const bool fast = rg.dimension == 2 && chain.size() == parent.size();
  std::optional<detail::ChainSgd2D> chain_engine;
  std::optional<detail::TreeRelaxation> tree_engine;
  if (fast) chain_engine.emplace(g, rg, chain);
  else tree_engine.emplace(g, rg, parent);
  detail::GradientPhaseSchedule phase(options.gradient_phase);
  std::vector<int> order(g.edges.size());
  std::iota(order.begin(), order.end(), 0);
  std::mt19937_64 rng(options.seed);
  auto step = [&](int iteration) {
    const RelaxerGradientPhase p = phase.at(iteration);
    const bool in_phase = p.start > 0 && iteration > p.start;
    if (options.shuffle && (in_phase || iteration > options.file_order_iterations))
      // Fisher-Yates with our own draws: the same order on every platform
      for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng() % i]);
    if (fast) chain_engine->set_gradient_phase(p);
    else tree_engine->set_gradient_phase(p);
    return fast ? chain_engine->iterate(iteration, order) : tree_engine->iterate(iteration, order);
  };
  auto write_back = [&] { fast ? chain_engine->write_back(g) : tree_engine->write_back(g); };
  RelaxerSummary s = run_relaxer(g, "sgd", phase.wrap(options.stop), step, write_back);
  s.num_loop_closures = rg.num_loop_closures;
  if (!phase.note().empty()) s.notes.push_back(phase.note());
  if (rg.num_loop_closures == 0) s.notes.push_back("no loop closure: every constraint can be met exactly");
  return s;
}

}  // namespace slamkit
