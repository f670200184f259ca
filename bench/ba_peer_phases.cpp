// The phases of one slamkit BA iteration against one bare factorization of the same reduced
// system, in CPU time of the calling thread (1 thread: immune to the load of a shared machine),
// medians of 5 at the start point with λ = 1e-4 (LM's first step):
//   linearize (residuals, Jacobians, C/W/B, g), cost (a candidate, no Jacobians),
//   factorize (C⁻¹, S formed, factorized; PCG: its preconditioner), solve (rhs, S⁻¹ or PCG,
//   back-substitution), quadratic (δᵀHδ for ρ, PCG only), retract.
// An LM iteration with an accepted step is linearize + factorize + solve (+ quadratic) + retract + cost.
//   ba_peer_phases [--only SUBSTRING] [--out bench/results/ba_peer_phases.json]
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "bench_data.h"
#include "slamkit/factors/bal_normal_equations.h"
#include "slamkit/io/bal_io.h"
#include "slamkit/linear/schur_complement.h"
#include "slamkit/sim/ba_generator.h"

using namespace slamkit;

namespace {

double thread_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

double median_cpu(const std::function<void()>& fn, int reps = 5) {
  std::vector<double> t;
  for (int r = 0; r < reps; ++r) {
    const double t0 = thread_cpu_s();
    fn();
    t.push_back(thread_cpu_s() - t0);
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string only, out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/ba_peer_phases.json";
  if (!bench::parse_options(argc, argv, "[--only SUBSTRING] [--out FILE]", {{"--only", &only}, {"--out", &out}})) return 2;
  const auto bal = bench::data_root() / "bal";
  auto sim = [](int cameras, int points) {
    BaSimOptions o;
    o.cameras = cameras, o.points = points, o.seed = 1;
    return generate_ba_problem(o);
  };
  const std::vector<std::pair<std::string, std::function<BalProblem()>>> cases = {
      {"problem-49-7776-pre", [&] { return read_bal((bal / "problem-49-7776-pre.txt").string()); }},
      {"problem-21-11315-pre", [&] { return read_bal((bal / "problem-21-11315-pre.txt").string()); }},
      {"sim:ba?cameras=200&points=40000&seed=1", [&] { return sim(200, 40000); }},
  };
  nlohmann::json results = nlohmann::json::array();
  for (const auto& [name, make] : cases) {
    if (!only.empty() && name.find(only) == std::string::npos) continue;
    const BalProblem p = make();
    std::printf("== %s: %d cameras, %d points, %d observations (CPU ms, 1 thread)\n", name.c_str(), p.num_cameras(),
                p.num_points(), p.num_observations());
    const ThreadPool pool(1);
    BalNormalEquations ne(p, nullptr, pool);
    const BalState x = make_bal_state(p);
    BalState y;
    const double t_lin = median_cpu([&] { ne.linearize(x); });
    const double t_cost = median_cpu([&] { ne.cost(x); });
    const Eigen::VectorXd D = ne.hessian_diagonal().cwiseMax(1e-6);
    for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg}) {
      if (m == SchurMethod::kDense && p.num_cameras() > 400) continue;
      SchurOptions so;
      so.method = m;
      SchurComplementSolver solver(ne.eliminate_flags(), pool, so);
      solver.analyze(ne.hessian());
      ne.set_diagonal_damping(1e-4 * D);
      const Eigen::VectorXd rhs = -ne.gradient();
      Eigen::VectorXd step(rhs.size());
      const double t_fact = median_cpu([&] { solver.factorize(ne.hessian()); });
      const double t_factor_alone = solver.last_factor_time_s();
      const double t_solve = median_cpu([&] { solver.solve(rhs.data(), step.data()); });
      const double t_quad = median_cpu([&] { ne.quadratic(step); });
      const double t_retract = median_cpu([&] { ne.retract(x, step.data(), y); });
      ne.clear_damping();
      // The LM loop needs δᵀHδ only for PCG (direct solves use δᵀHδ = −gᵀδ − λδᵀDδ).
      const double iteration = t_lin + t_fact + t_solve + (m == SchurMethod::kPcg ? t_quad : 0.0) + t_retract + t_cost;
      // The bare system solve: the factorization (explicit S) or one PCG solve with its preconditioner.
      const double bare = m == SchurMethod::kPcg ? t_fact + t_solve : t_fact;
      std::printf("  %-15s linearize %7.2f  cost %6.2f  factorize %7.2f (S alone, wall %6.2f)  solve %6.2f  quadratic %5.2f  "
                  "retract %5.2f  | iteration %7.2f  bare %7.2f  ratio %.2f\n",
                  to_string(m), 1e3 * t_lin, 1e3 * t_cost, 1e3 * t_fact, 1e3 * t_factor_alone, 1e3 * t_solve,
                  1e3 * t_quad, 1e3 * t_retract, 1e3 * iteration, 1e3 * bare, iteration / bare);
      std::fflush(stdout);
      results.push_back({{"problem", name}, {"method", to_string(m)}, {"linearize_s", t_lin}, {"cost_s", t_cost},
                         {"factorize_s", t_fact}, {"solve_s", t_solve}, {"quadratic_s", t_quad}, {"retract_s", t_retract},
                         {"iteration_s", iteration}, {"bare_s", bare}, {"ratio", iteration / bare},
                         {"pcg_iterations", solver.last_pcg_iterations()}});
    }
  }
  std::ofstream(out) << nlohmann::json{{"clock", "thread CPU time, 1 thread, medians of 5"}, {"phases", results}}.dump(2)
                     << "\n";
  std::printf("wrote %s\n", out.c_str());
}
