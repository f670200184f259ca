// The relaxers as initializers of the manifold solvers (`slamkit optimize --init sgd|toro|
// relax|mlr`): each runs from the graph's current estimates with its default options and a
// budget that suits a starting guess, then hands the poses to Gauss-Newton / LM.
#pragma once

#include <string>
#include <vector>

#include "slamkit/core/pose_graph.h"
#include "slamkit/solvers/pose_graph_init.h"
#include "slamkit/solvers/relaxer.h"

namespace slamkit {

bool is_relaxer_init(InitMethod m);
/// The stopping rule used by --init: 100 iterations (SGD, TORO, relax) or 10 (MLR).
RelaxerStop default_init_stop(InitMethod m);
/// Runs the relaxer named by m on g; returns one note saying how far it got.
std::vector<std::string> relaxer_initialize(PoseGraph& g, InitMethod m);
/// Runs the relaxer named by m ("sgd", "toro", "relax", "mlr") with the given stopping rule.
RelaxerSummary run_named_relaxer(PoseGraph& g, const std::string& method, const RelaxerStop& stop);

}  // namespace slamkit
