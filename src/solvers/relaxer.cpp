#include "slamkit/solvers/relaxer.h"

#include <Eigen/Cholesky>
#include <chrono>
#include <cmath>
#include <deque>
#include <nlohmann/json.hpp>
#include <sstream>

#include "slamkit/core/error.h"
#include "slamkit/core/pose_graph_error.h"
#include "string_format.h"

namespace slamkit {
namespace {
using detail::format;

bool finite_pose(const GraphVertex& v) {
  if (v.kind == VertexKind::kPose2) return std::isfinite(v.pose2.x()) && std::isfinite(v.pose2.y()) && std::isfinite(v.pose2.theta());
  return v.pose3.translation().allFinite() && v.pose3.rotation().quaternion().coeffs().allFinite();
}
}  // namespace

RelaxerGraph make_relaxer_graph(const PoseGraph& g) {
  RelaxerGraph r;
  if (g.vertices().empty()) throw InputError(g.source, 0, "", "the graph has no poses");
  r.dimension = g.dimension();
  std::vector<int> pose_of(g.vertices().size(), -1);
  for (std::size_t i = 0; i < g.vertices().size(); ++i) {
    const GraphVertex& v = g.vertices()[i];
    if (v.kind != VertexKind::kPose2 && v.kind != VertexKind::kPose3)
      throw InputError(g.source, v.line, "vertex " + std::to_string(v.id),
                       "the relaxers optimize pose graphs only (this is a landmark); use --solver gn|lm");
    if (!finite_pose(v)) throw InputError(g.source, v.line, "vertex " + std::to_string(v.id), "estimate is not finite");
    pose_of[i] = static_cast<int>(r.vertex.size());
    r.vertex.push_back(i);
  }
  const std::size_t n = r.vertex.size();
  r.gauge.assign(n, 0);
  for (std::int64_t id : gauge_vertices(g)) r.gauge[pose_of[*g.index_of(id)]] = 1;
  // Union-find over the edges: connectivity and the number of edges closing a cycle.
  std::vector<int> root(n);
  for (std::size_t k = 0; k < n; ++k) root[k] = static_cast<int>(k);
  auto find = [&](int a) {
    while (root[a] != a) a = root[a] = root[root[a]];
    return a;
  };
  for (const GraphEdge& e : g.edges) {
    const std::string field = "edge " + std::to_string(e.from) + "-" + std::to_string(e.to);
    if (e.kind != EdgeKind::kPose2Pose2 && e.kind != EdgeKind::kPose3Pose3)
      throw InputError(g.source, e.line, field, "the relaxers optimize pose graphs only (pose-landmark edge)");
    const Eigen::MatrixXd& info = e.information;
    if (!info.allFinite()) throw InputError(g.source, e.line, field, "information matrix is not finite");
    Eigen::LDLT<Eigen::MatrixXd> ldlt(0.5 * (info + info.transpose()));
    const double scale = std::max(info.diagonal().cwiseAbs().maxCoeff(), 1e-300);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 1e-12 * scale))
      throw InputError(g.source, e.line, field,
                       "information matrix is singular or not positive definite (--repair-information projects it)");
    const int a = pose_of[*g.index_of(e.from)], b = pose_of[*g.index_of(e.to)];
    if (a == b) throw InputError(g.source, e.line, field, "edge joins a pose to itself");
    r.ends.emplace_back(a, b);
    const int ra = find(a), rb = find(b);
    if (ra == rb) ++r.num_loop_closures;
    else root[ra] = rb;
  }
  std::size_t components = 0;
  for (std::size_t k = 0; k < n; ++k) components += find(static_cast<int>(k)) == static_cast<int>(k);
  if (components > 1) {
    int lonely = 0;
    for (std::size_t k = 0; k < n; ++k)
      if (find(static_cast<int>(k)) != find(0)) { lonely = static_cast<int>(k); break; }
    const GraphVertex& v = g.vertices()[r.vertex[lonely]];
    throw InputError(g.source, v.line, "vertex " + std::to_string(v.id),
                     "the graph has " + std::to_string(components) +
                         " connected components (this vertex is not connected to vertex " +
                         std::to_string(g.vertices()[r.vertex[0]].id) +
                         "); the relaxers need a connected graph: optimize the components separately");
  }
  return r;
}

RelaxerSummary run_relaxer(PoseGraph& g, const std::string& method, const RelaxerStop& stop,
                           const std::function<double(int)>& step, const std::function<void()>& write_back) {
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  RelaxerSummary s;
  s.method = method;
  s.dimension = g.dimension();
  s.num_edges = static_cast<int>(g.edges.size());
  s.num_poses = static_cast<int>(g.num_poses());
  s.initial_chi2 = total_chi2(g);
  if (!std::isfinite(s.initial_chi2)) throw InputError(g.source, 0, "", "the initial chi2 is not finite");
  RelaxerIteration it0;
  it0.chi2 = s.initial_chi2;
  it0.time_s = elapsed();
  s.trace.push_back(it0);
  s.termination = "max iterations";
  bool go = !stop.callback || stop.callback(it0);
  if (!go) s.termination = "user callback";
  std::vector<GraphVertex> last = g.vertices();
  // SGD and TORO are not monotone (a constraint's update may raise the others' error): the
  // run returns the best iterate it visited, not the last.
  std::vector<GraphVertex> best = g.vertices();
  double best_chi2 = s.initial_chi2;
  int best_iteration = 0;
  int flat = 0;
  for (int k = 1; go && k <= stop.max_iterations; ++k) {
    RelaxerIteration it;
    it.iteration = k;
    it.step = step(k);
    const bool done = it.step < 0;  // the method has nothing left to do
    if (done) it.step = 0;
    write_back();
    it.chi2 = total_chi2(g);
    it.time_s = elapsed();
    if (!std::isfinite(it.chi2) || !std::isfinite(it.step)) {
      for (std::size_t i = 0; i < last.size(); ++i) g.vertex_at(i) = last[i];
      s.termination = "non-finite chi2";
      s.notes.push_back("iteration " + std::to_string(k) +
                        " produced a non-finite estimate; the estimates of the previous iteration were kept");
      break;
    }
    it.chi2_change = s.trace.back().chi2 - it.chi2;
    s.trace.push_back(it);
    s.iterations = k;
    for (std::size_t i = 0; i < last.size(); ++i) last[i] = g.vertices()[i];
    if (it.chi2 < best_chi2) best = last, best_chi2 = it.chi2, best_iteration = k;
    const double prev = s.trace[s.trace.size() - 2].chi2;
    flat = std::abs(prev - it.chi2) <= stop.relative_tolerance * std::max(it.chi2, 1e-300) ? flat + 1 : 0;
    if (stop.callback && !stop.callback(it)) {
      s.termination = "user callback";
      break;
    }
    if (it.chi2 <= 1e-300 * std::max(1.0, s.initial_chi2) || it.chi2 == 0.0) {
      s.termination = "converged";
      break;
    }
    if (done || flat >= stop.patience) {
      s.termination = "converged";
      break;
    }
    if (stop.time_budget_s > 0 && it.time_s >= stop.time_budget_s) {
      s.termination = "time budget";
      break;
    }
  }
  s.final_chi2 = s.trace.back().chi2;
  if (best_chi2 < s.final_chi2) {
    for (std::size_t i = 0; i < best.size(); ++i) g.vertex_at(i) = best[i];
    s.notes.push_back(format("returned the best iterate (iteration %d, chi2 %.10g; the last had %.10g)", best_iteration,
                             best_chi2, s.final_chi2));
    s.final_chi2 = best_chi2;
  }
  s.time_total_s = elapsed();
  return s;
}

std::string RelaxerSummary::progress_header() {
  return format("%4s %16s %11s %10s %10s", "iter", "chi2", "chi2_change", "|step|", "t_total[s]");
}

std::string RelaxerSummary::progress_line(const RelaxerIteration& it) {
  return format("%4d %16.9e %11.3e %10.3e %10.4f", it.iteration, it.chi2, it.chi2_change, it.step, it.time_s);
}

std::string RelaxerSummary::report() const {
  std::ostringstream os;
  os << "slamkit relaxer summary\n";
  os << format("  problem          %d poses (%dD), %d edges, %d loop closures\n", num_poses, dimension, num_edges,
               num_loop_closures);
  os << "  method           " << method << "\n";
  os << format("  cost (chi2)      initial %.10g -> final %.10g (%.3g%% of initial)\n", initial_chi2, final_chi2,
               initial_chi2 > 0 ? 100.0 * final_chi2 / initial_chi2 : 0.0);
  os << format("  iterations       %d in %.4f s\n", iterations, time_total_s);
  os << "  termination      " << termination << "\n";
  for (const std::string& n : notes) os << "  note             " << n << "\n";
  return os.str();
}

std::string RelaxerSummary::to_json() const {
  nlohmann::json j;
  j["kind"] = "optimize";
  j["solver"] = method;
  j["dimension"] = dimension;
  j["num_poses"] = num_poses;
  j["num_edges"] = num_edges;
  j["num_loop_closures"] = num_loop_closures;
  j["initial_chi2"] = initial_chi2;
  j["final_chi2"] = final_chi2;
  j["iterations"] = iterations;
  j["time_total_s"] = time_total_s;
  j["termination"] = termination;
  j["notes"] = notes;
  nlohmann::json t = nlohmann::json::array();
  for (const RelaxerIteration& it : trace)
    t.push_back({{"iteration", it.iteration}, {"cost", it.chi2}, {"time_s", it.time_s}, {"step", it.step}});
  j["trace"] = std::move(t);
  return j.dump(2);
}

}  // namespace slamkit
