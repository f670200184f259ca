#include "slamkit/solvers/gauss_seidel_relaxation.h"

#include <Eigen/Cholesky>

#include "slamkit/solvers/relaxer_pose_traits.h"
#include "slamkit/core/error.h"

namespace slamkit {
namespace {

template <int D>
double sweep(PoseGraph& g, const RelaxerGraph& rg, const std::vector<std::vector<int>>& incident, double omega) {
  using T = detail::RelaxerPose<D>;
  using Mat = typename T::Mat;
  using Vec = typename T::Vec;
  double change = 0.0;
  for (std::size_t k = 0; k < rg.vertex.size(); ++k) {
    if (rg.gauge[k]) continue;
    Mat H = Mat::Zero();
    Vec b = Vec::Zero();
    for (int e : incident[k]) {
      const GraphEdge& edge = g.edges[e];
      const auto [from, to] = rg.ends[e];
      Mat Ja, Jb;
      const Vec err = T::error(T::measurement(edge), T::pose(g.vertices()[rg.vertex[from]]),
                               T::pose(g.vertices()[rg.vertex[to]]), &Ja, &Jb);
      const Mat& J = from == static_cast<int>(k) ? Ja : Jb;
      const Mat JtO = J.transpose() * edge.information;
      H += JtO * J;
      b += JtO * err;
    }
    const Eigen::LDLT<Mat> ldlt(H);
    const Vec delta = -omega * ldlt.solve(b);
    if (!delta.allFinite()) continue;  // cannot happen with positive definite information; keep the pose
    auto& x = T::pose(g.vertex_at(rg.vertex[k]));
    x = x.plus(delta);
    change = std::max(change, delta.cwiseAbs().maxCoeff());
  }
  return change;
}

}  // namespace

RelaxerSummary optimize_relaxation(PoseGraph& g, const RelaxationOptions& options) {
  if (!(options.over_relaxation > 0 && options.over_relaxation < 2))
    throw InputError("", 0, "over_relaxation", "must be in (0, 2)");
  const RelaxerGraph rg = make_relaxer_graph(g);
  std::vector<std::vector<int>> incident(rg.vertex.size());
  for (std::size_t e = 0; e < rg.ends.size(); ++e) {
    incident[rg.ends[e].first].push_back(static_cast<int>(e));
    incident[rg.ends[e].second].push_back(static_cast<int>(e));
  }
  auto step = [&](int) {
    return rg.dimension == 2 ? sweep<3>(g, rg, incident, options.over_relaxation)
                             : sweep<6>(g, rg, incident, options.over_relaxation);
  };
  RelaxerSummary s = run_relaxer(g, "relax", options.stop, step, [] {});
  s.num_loop_closures = rg.num_loop_closures;
  return s;
}

}  // namespace slamkit
