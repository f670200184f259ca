// The phases of one slamkit BA iteration against one bare factorization of the same reduced
// system, in CPU time of the calling thread (1 thread: less sensitive to the load of a shared
// machine than wall time), medians of 11 at the start point with λ = 1e-4 (LM's first step):
//   linearize (residuals, Jacobians, C/W/B, g), cost (a candidate, no Jacobians),
//   factorize (plain factorize(H): C⁻¹, S formed, factorized; PCG: its preconditioner) = bare
//   (PCG: + one plain PCG solve), factorize with rhs (the LM's call: the reduced rhs formed
//   alongside S), solve (S⁻¹ or PCG, back-substitution), quadratic (δᵀHδ, PCG only), retract.
// "iteration" times one accepted LM iteration as a whole (the candidate's linearization, which
// gives its cost, damp, factorize with rhs, solve, predicted reduction, retract), warm, with the
// same solver object as the bare.
// Then (unless --lm 0) full LM runs with schur-pcg, 1 thread, under the old PCG stopping rule
// (relative residual 0.1 only) and the current one (Nash-Sofer quadratic-model test 0.1):
// outer iterations, linear solves, CG iterations, final cost, CPU seconds.
//   ba_peer_phases [--only SUBSTRING] [--lm 0|1] [--out bench/results/ba_peer_phases.json]
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "bench_data.h"
#include "slamkit/factors/bal_normal_equations.h"
#include "slamkit/factors/bundle_adjustment.h"
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

double median_cpu(const std::function<void()>& fn, int reps = 11) {
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
  std::string only, lm = "1", out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/ba_peer_phases.json";
  if (!bench::parse_options(argc, argv, "[--only SUBSTRING] [--lm 0|1] [--out FILE]",
                            {{"--only", &only}, {"--lm", &lm}, {"--out", &out}}))
    return 2;
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
  nlohmann::json results = nlohmann::json::array(), pcg_runs = nlohmann::json::array();
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
      // Bare: the plain factorize(H) (C⁻¹, S formed, factorized; PCG: its preconditioner) and
      // for PCG one plain solve; warm (median of 11 after the same calls), same solver object.
      const double t_fact = median_cpu([&] { solver.factorize(ne.hessian()); });
      const double t_factor_alone = solver.last_factor_time_s();
      const double t_solve_plain = median_cpu([&] { solver.solve(rhs.data(), step.data()); });
      const int pcg_iterations = solver.last_pcg_iterations();
      // The LM loop's calls: factorize with the reduced rhs formed alongside S, then S⁻¹ (or
      // PCG) and back-substitution.
      const double t_fact_rhs = median_cpu([&] { solver.factorize(ne.hessian(), rhs.data()); });
      const double t_solve = median_cpu([&] { solver.solve_factored_rhs(step.data()); });
      const double t_quad = median_cpu([&] { ne.quadratic(step); });
      const double t_retract = median_cpu([&] { ne.retract(x, step.data(), y); });
      ne.clear_damping();
      // One accepted LM iteration in a run of accepted ones, timed as a whole, as the LM loop does
      // it: the candidate's linearization (its cost comes with it; here the linearization at x
      // stands for the previous iteration's candidate, the same work), damp, factorize with the
      // rhs, solve, predicted reduction (−gᵀδ + λδᵀDδ + x_kᵀr_k, no pass over H), retract.
      // (Before: linearize, ..., δᵀHδ for PCG, retract, then a separate candidate cost pass.)
      const double iteration = median_cpu([&] {
        ne.linearize(x);
        ne.set_diagonal_damping(1e-4 * D);
        const Eigen::VectorXd r = -ne.gradient();
        solver.factorize(ne.hessian(), r.data());
        solver.solve_factored_rhs(step.data());
        volatile double predicted = r.dot(step) + 1e-4 * (D.array() * step.array().square()).sum() +
                                    solver.last_residual_dot_solution();
        (void)predicted;
        ne.retract(x, step.data(), y);
      });
      ne.clear_damping();
      // The bare system solve: the factorization (explicit S) or one PCG solve with its preconditioner.
      const double bare = m == SchurMethod::kPcg ? t_fact + t_solve_plain : t_fact;
      std::printf("  %-15s linearize %7.2f  cost %6.2f  factorize %7.2f (S alone, wall %6.2f; with rhs %7.2f)  solve %6.2f  "
                  "quadratic %5.2f  retract %5.2f  | iteration %7.2f  bare %7.2f  ratio %.2f\n",
                  to_string(m), 1e3 * t_lin, 1e3 * t_cost, 1e3 * t_fact, 1e3 * t_factor_alone, 1e3 * t_fact_rhs,
                  1e3 * t_solve, 1e3 * t_quad, 1e3 * t_retract, 1e3 * iteration, 1e3 * bare, iteration / bare);
      std::fflush(stdout);
      results.push_back({{"problem", name}, {"method", to_string(m)}, {"linearize_s", t_lin}, {"cost_s", t_cost},
                         {"factorize_s", t_fact}, {"factor_alone_wall_s", t_factor_alone},
                         {"factorize_with_rhs_s", t_fact_rhs}, {"solve_plain_s", t_solve_plain}, {"solve_s", t_solve}, {"quadratic_s", t_quad}, {"retract_s", t_retract},
                         {"iteration_s", iteration}, {"bare_s", bare}, {"ratio", iteration / bare},
                         {"pcg_iterations", pcg_iterations}});
    }
  }
  for (const auto& [name, make] : cases) {
    if (lm == "0" || (!only.empty() && name.find(only) == std::string::npos)) continue;
    for (const bool old_rule : {true, false}) {
      BalProblem p = make();
      BundleAdjustmentOptions o;
      o.optimizer.num_threads = 1;
      o.optimizer.function_tolerance = 1e-6;  // ba_peer's stopping rule
      o.optimizer.schur.method = SchurMethod::kPcg;
      if (old_rule) o.optimizer.schur.pcg_tolerance = 0.1, o.optimizer.schur.pcg_q_tolerance = 0.0;
      BundleAdjustmentResult r;
      const double cpu = median_cpu([&] { r = optimize_bundle_adjustment(p, o); }, 1);
      const Summary& sm = r.summary;
      const char* rule = old_rule ? "residual 0.1" : "Nash-Sofer 0.1";
      std::printf("  LM schur-pcg %-14s %-40s iterations %3d  solves %3d  CG %5ld (%.1f per solve)  final cost %.6f  "
                  "CPU %.2f s\n",
                  rule, name.c_str(), sm.iterations, sm.linear_solves, sm.pcg_iterations,
                  static_cast<double>(sm.pcg_iterations) / std::max(1, sm.linear_solves), r.final_cost, cpu);
      std::fflush(stdout);
      pcg_runs.push_back({{"problem", name}, {"pcg_stopping_rule", rule}, {"iterations", sm.iterations},
                          {"linear_solves", sm.linear_solves}, {"pcg_iterations", sm.pcg_iterations},
                          {"final_cost", r.final_cost}, {"cpu_s", cpu}, {"termination", to_string(sm.termination)}});
    }
  }
  std::ofstream(out) << nlohmann::json{{"clock", "thread CPU time, 1 thread, medians of 11"},
                                       {"phases", results},
                                       {"pcg_lm_runs", pcg_runs}}
                            .dump(2)
                     << "\n";
  std::printf("wrote %s\n", out.c_str());
}
