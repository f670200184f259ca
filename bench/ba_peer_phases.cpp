// The phases of one slamkit BA iteration against one bare factorization of the same reduced
// system, in CPU time of the calling thread (1 thread: less sensitive to the load of a shared
// machine than wall time; --threads N > 1: wall time on a pool of N threads, the setting of the
// Ceres comparison), at the start point with λ = 1e-4 (LM's first step).
//   Isolated phases (medians of --reps): linearize (residuals, Jacobians, C/W/B, g), cost (a
//   candidate, no Jacobians), factorize (plain factorize(H): C⁻¹, S formed, factorized; PCG:
//   its preconditioner), solve plain (PCG only: rhs, CG, back-substitution), factorize with rhs
//   (the LM's call: the reduced rhs formed alongside S), solve (S⁻¹ or PCG, back-substitution),
//   back-substitute (the points' rows alone), quadratic (δᵀHδ), retract. The "excess" line splits
//   iteration − bare into its phases, the fused pass beside its isolated parts.
//   Paired: bare (factorize(H), + one plain solve for PCG) and one accepted LM iteration timed as a
//   whole (damp, factorize with rhs, reduced solve, back-substitution + retract + the candidate's
//   linearization in one point pass, predicted reduction, the loop's checks and norms) alternate,
//   bare, iteration, bare, ... on the same solver object; per pair the ratio iteration / bare;
//   reported: the median of the ratios and the medians of each. Inside the iteration each phase is
//   timed too ("in context"): the phases cover the iteration ("unexplained" = iteration − Σ timed
//   phases, the time between the probes, ≈ 0), so an excess shows up in a named phase, and
//   in-context against isolated medians shows what the iteration's memory state costs each phase.
//   The untimed-in-the-pair relinearization at x after each pair is timed apart ("relinearize"):
//   fused pass − it, per pair, is the back-substitution's and retraction's share of the fused pass
//   at that moment. Every phase also reports its minor page faults (getrusage, this thread).
// Then (unless --lm 0) full LM runs, 1 thread: schur-dense, schur-cholesky, and schur-pcg under
// the old PCG stopping rule (relative residual 0.1 only) and the current one (Nash-Sofer 0.1):
// iterations, linear solves, CG iterations, final cost, CPU seconds.
//   ba_peer_phases [--only SUBSTRING] [--lm 0|1] [--reps 21] [--large 0|1] [--large-reps N] [--threads N]
//                  [--out FILE]
// --large 1 adds sim:ba 2,000 cameras / 500,000 points (schur-cholesky and schur-pcg; not in the LM runs).
#include <sys/resource.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>

#include "bench_data.h"
#include "slamkit/factors/bal_normal_equations.h"
#include "slamkit/factors/bundle_adjustment.h"
#include "slamkit/io/bal_io.h"
#include "slamkit/linear/schur_complement.h"
#include "slamkit/sim/ba_generator.h"

using namespace slamkit;

namespace {

struct Probe {
  double cpu_s;  // CPU seconds of the calling thread, or wall seconds with --threads > 1
  long minflt;
};

bool g_wall = false;  // --threads > 1: wall time (the workers' CPU time is not the caller's)

Probe probe() {
  timespec t{};
  clock_gettime(g_wall ? CLOCK_MONOTONIC : CLOCK_THREAD_CPUTIME_ID, &t);
  rusage u{};
  getrusage(RUSAGE_THREAD, &u);
  return {t.tv_sec + 1e-9 * t.tv_nsec, u.ru_minflt};
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// Samples of one phase: CPU seconds and minor faults per rep.
struct Phase {
  std::vector<double> s, faults;
  void add(const Probe& a, const Probe& b) {
    s.push_back(b.cpu_s - a.cpu_s);
    faults.push_back(static_cast<double>(b.minflt - a.minflt));
  }
  double med() const { return median(s); }
  double min() const { return s.empty() ? 0.0 : *std::min_element(s.begin(), s.end()); }
  nlohmann::json json() const {
    return {{"median_s", median(s)}, {"min_s", min()}, {"median_minor_faults", median(faults)}};
  }
};

Phase measure(const std::function<void()>& fn, int reps) {
  Phase p;
  for (int r = 0; r < reps; ++r) {
    const Probe a = probe();
    fn();
    p.add(a, probe());
  }
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  std::string only, lm = "1", reps_s = "21", large = "0", large_reps_s = "", threads_s = "1",
                    out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/ba_peer_phases.json";
  if (!bench::parse_options(argc, argv,
                            "[--only SUBSTRING] [--lm 0|1] [--reps N] [--large 0|1] [--large-reps N] [--threads N] [--out FILE]",
                            {{"--only", &only}, {"--lm", &lm}, {"--reps", &reps_s}, {"--large", &large},
                             {"--large-reps", &large_reps_s}, {"--threads", &threads_s}, {"--out", &out}}))
    return 2;
  const int threads = bench::int_option("--threads", threads_s, 1, 256);
  g_wall = threads > 1;
  const int base_reps = bench::int_option("--reps", reps_s, 1, 100000);
  const int large_reps = large_reps_s.empty() ? base_reps : bench::int_option("--large-reps", large_reps_s, 1, 100000);
  const auto bal = bench::data_root() / "bal";
  auto sim = [](int cameras, int points) {
    BaSimOptions o;
    o.cameras = cameras, o.points = points, o.seed = 1;
    return generate_ba_problem(o);
  };
  std::vector<std::pair<std::string, std::function<BalProblem()>>> cases = {
      {"problem-49-7776-pre", [&] { return read_bal((bal / "problem-49-7776-pre.txt").string()); }},
      {"problem-21-11315-pre", [&] { return read_bal((bal / "problem-21-11315-pre.txt").string()); }},
      {"sim:ba?cameras=200&points=40000&seed=1", [&] { return sim(200, 40000); }},
  };
  const std::string large_name = "sim:ba?cameras=2000&points=500000&seed=1";
  if (large == "1") cases.push_back({large_name, [&] { return sim(2000, 500000); }});
  nlohmann::json results = nlohmann::json::array(), lm_runs = nlohmann::json::array();
  for (const auto& [name, make] : cases) {
    if (!only.empty() && name.find(only) == std::string::npos) continue;
    const int reps = name == large_name ? large_reps : base_reps;
    const BalProblem p = make();
    std::printf("== %s: %d cameras, %d points, %d observations (%s ms, %d thread%s, %d reps)\n", name.c_str(),
                p.num_cameras(), p.num_points(), p.num_observations(), g_wall ? "wall" : "CPU", threads,
                threads > 1 ? "s" : "", reps);
    const ThreadPool pool(threads);
    BalNormalEquations ne(p, nullptr, pool);
    const BalState x = make_bal_state(p);
    BalState y;
    const Phase lin = measure([&] { ne.linearize(x); }, reps);
    const Phase cost = measure([&] { ne.cost(x); }, reps);
    const Eigen::VectorXd D = ne.hessian_diagonal().cwiseMax(1e-6);
    const double lambda = 1e-4;
    for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg}) {
      if (m == SchurMethod::kDense && p.num_cameras() > 400) continue;
      const bool pcg = m == SchurMethod::kPcg;
      SchurOptions so;
      so.method = m;
      SchurComplementSolver solver(ne.eliminate_flags(), pool, so);
      solver.analyze(ne.hessian());
      ne.set_diagonal_damping(lambda, D, false);  // as the LM loop: C_j's damping added by the solver
      const double* shift = ne.damping().data();
      Eigen::VectorXd rhs = -ne.gradient(), step(rhs.size());
      // Isolated phases, warm, same solver object.
      std::map<std::string, Phase> iso;
      iso["factorize"] = measure([&] { solver.factorize(ne.hessian(), nullptr, shift); }, reps);
      if (pcg) iso["solve_plain"] = measure([&] { solver.solve(rhs.data(), step.data()); }, reps);
      const int pcg_iterations = solver.last_pcg_iterations();
      iso["factorize_with_rhs"] = measure([&] { solver.factorize(ne.hessian(), rhs.data(), shift); }, reps);
      iso["solve"] = measure([&] { solver.solve_factored_rhs(step.data()); }, reps);
      // The back-substitution alone (all points; the fused pass runs it per sub-chunk).
      iso["back_substitute"] = measure([&] { solver.back_substitute(0, ne.num_points(), step.data()); }, reps);
      iso["quadratic"] = measure([&] { ne.quadratic(step); }, reps);
      iso["retract"] = measure([&] { ne.retract(x, step.data(), y); }, reps);
      // Paired: bare, iteration, bare, iteration, ... The iteration is the LM loop's (a run of
      // accepted steps): damp, factorize with the rhs, the reduced solve, then one pass over the
      // points that back-substitutes, retracts and linearizes the candidate (its cost comes with
      // it), the predicted reduction (−gᵀδ + λδᵀDδ + x_kᵀr_k, no pass over H); each phase timed
      // in context. After each pair H is re-linearized at x, untimed.
      Phase bare, iteration, relin;
      Eigen::VectorXd D_next(D.size());
      const int nk = ne.dim() - 3 * ne.num_points();
      std::vector<double> fused_minus_lin;
      std::map<std::string, Phase> ctx;
      std::vector<double> ratios, unexplained;
      for (int r = 0; r < reps; ++r) {
        const Probe b0 = probe();
        solver.factorize(ne.hessian(), nullptr, shift);
        if (pcg) solver.solve(rhs.data(), step.data());
        const Probe b1 = probe();
        bare.add(b0, b1);
        Probe t[7];
        t[0] = probe();
        ne.set_diagonal_damping(lambda, D, false);
        rhs = -ne.gradient();
        t[1] = probe();
        solver.factorize(ne.hessian(), rhs.data(), shift);
        t[2] = probe();
        solver.solve_factored_kept(step.data());
        t[3] = probe();
        ne.retract_and_linearize(x, step.data(), y, [&](int b, int e, double* d) { solver.back_substitute(b, e, d); });
        t[4] = probe();
        volatile double predicted = rhs.dot(step) + lambda * (D.array() * step.array().square()).sum() +
                                    solver.last_residual_dot_solution();
        (void)predicted;
        t[5] = probe();
        // The loop's checks and norms (optimize_bundle_adjustment's LM): the scaling D of the next
        // step, the step finite, its norm and x's (parameter tolerance), the gradient's max-norm.
        D_next = ne.hessian_diagonal().cwiseMax(1e-6).cwiseMin(1e32);
        volatile double checks = static_cast<double>(step.tail(nk).allFinite() && step.allFinite()) + step.norm() +
                                 BalNormalEquations::parameter_norm(x) + ne.gradient().lpNorm<Eigen::Infinity>();
        (void)checks;
        t[6] = probe();
        iteration.add(t[0], t[6]);
        const char* names[6] = {"damp", "factorize_with_rhs", "solve_kept", "backsub_retract_linearize", "predicted",
                                "checks"};
        double sum = 0.0;
        for (int k = 0; k < 6; ++k) {
          ctx[names[k]].add(t[k], t[k + 1]);
          sum += t[k + 1].cpu_s - t[k].cpu_s;
        }
        unexplained.push_back((t[6].cpu_s - t[0].cpu_s) - sum);
        ratios.push_back((t[6].cpu_s - t[0].cpu_s) / (b1.cpu_s - b0.cpu_s));
        // H, g back at x for the next pair: not part of the pair, but timed as "relinearize": a plain
        // linearization in the same memory state as the fused pass just before it, so
        // fused − relinearize (per pair) is what the back-substitution and retraction add to it.
        const Probe l0 = probe();
        ne.linearize(x);
        relin.add(l0, probe());
        fused_minus_lin.push_back((t[4].cpu_s - t[3].cpu_s) - relin.s.back());
      }
      ne.clear_damping();
      const double ratio = median(ratios);
      std::printf("  %-15s isolated: linearize %7.2f (%.0f ns/obs)  factorize %7.2f  with rhs %7.2f  solve %6.2f%s\n",
                  to_string(m), 1e3 * lin.med(), 1e9 * lin.med() / p.num_observations(), 1e3 * iso["factorize"].med(),
                  1e3 * iso["factorize_with_rhs"].med(), 1e3 * iso["solve"].med(),
                  pcg ? (" solve plain " + std::to_string(1e3 * iso["solve_plain"].med())).c_str() : "");
      std::printf("  %-15s in context: damp %5.2f  factorize with rhs %7.2f  solve kept %6.2f  back-sub+retract+"
                  "linearize %7.2f  predicted %5.2f  checks %5.2f  unexplained %5.2f  (faults: lin %.0f fact %.0f)\n",
                  "", 1e3 * ctx["damp"].med(), 1e3 * ctx["factorize_with_rhs"].med(), 1e3 * ctx["solve_kept"].med(),
                  1e3 * ctx["backsub_retract_linearize"].med(), 1e3 * ctx["predicted"].med(), 1e3 * ctx["checks"].med(),
                  1e3 * median(unexplained), median(ctx["backsub_retract_linearize"].faults),
                  median(ctx["factorize_with_rhs"].faults));
      // Where the iteration's time beyond bare goes (medians): the factorization with the rhs
      // against bare, the reduced solve, and the fused pass against its isolated parts.
      // (bare holds PCG's solve: the reduced system's share is factorize with rhs + solve kept − bare.)
      std::printf("  %-15s excess over bare %5.2f: reduced system (factorize with rhs + solve kept) - bare %5.2f  "
                  "fused pass %5.2f (isolated: linearize %5.2f  back-substitute %5.2f  retract %5.2f)  damp + predicted + checks %5.2f\n",
                  "", 1e3 * (iteration.med() - bare.med()),
                  1e3 * (ctx["factorize_with_rhs"].med() + ctx["solve_kept"].med() - bare.med()),
                  1e3 * ctx["backsub_retract_linearize"].med(), 1e3 * lin.med(),
                  1e3 * iso["back_substitute"].med(), 1e3 * iso["retract"].med(),
                  1e3 * (ctx["damp"].med() + ctx["predicted"].med() + ctx["checks"].med()));
      std::printf("  %-15s fused pass against a plain linearization right after it: relinearize %5.2f  "
                  "fused - relinearize (median of pairs) %5.2f\n",
                  "", 1e3 * relin.med(), 1e3 * median(fused_minus_lin));
      std::printf("  %-15s paired: iteration %7.2f  bare %7.2f  median ratio %.2f (ratio of medians %.2f, range %.2f-%.2f)\n",
                  "", 1e3 * iteration.med(), 1e3 * bare.med(), ratio, iteration.med() / bare.med(),
                  *std::min_element(ratios.begin(), ratios.end()), *std::max_element(ratios.begin(), ratios.end()));
      // Minima: the least disturbed samples (a loaded machine inflates CPU time, never deflates it).
      std::printf("  %-15s minima: linearize %7.2f  back-sub+retract+linearize %7.2f  factorize with rhs %7.2f  "
                  "iteration %7.2f  bare %7.2f  ratio of minima %.2f\n",
                  "", 1e3 * lin.min(), 1e3 * ctx["backsub_retract_linearize"].min(), 1e3 * ctx["factorize_with_rhs"].min(),
                  1e3 * iteration.min(), 1e3 * bare.min(), iteration.min() / bare.min());
      std::fflush(stdout);
      nlohmann::json isolated = {{"linearize", lin.json()}, {"cost", cost.json()}}, in_context;
      for (const auto& [k, v] : iso) isolated[k] = v.json();
      for (const auto& [k, v] : ctx) in_context[k] = v.json();
      results.push_back({{"problem", name}, {"method", to_string(m)}, {"reps", reps},
                         {"observations", p.num_observations()},
                         {"linearize_ns_per_obs", 1e9 * lin.med() / p.num_observations()},
                         {"isolated", isolated}, {"in_context", in_context},
                         {"unexplained_median_s", median(unexplained)}, {"relinearize", relin.json()},
                         {"fused_minus_relinearize_median_s", median(fused_minus_lin)},
                         {"iteration", iteration.json()}, {"bare", bare.json()}, {"ratio_median_of_pairs", ratio},
                         {"ratio_of_medians", iteration.med() / bare.med()},
                         {"ratio_of_minima", iteration.min() / bare.min()}, {"ratios", ratios},
                         {"pcg_iterations", pcg_iterations}});
    }
  }
  for (const auto& [name, make] : cases) {
    if (lm == "0" || name == large_name || (!only.empty() && name.find(only) == std::string::npos)) continue;
    // (method, PCG under the old rule): the direct methods, then PCG under both stopping rules.
    const std::vector<std::pair<SchurMethod, bool>> configs = {{SchurMethod::kDense, false}, {SchurMethod::kCholesky, false},
                                                               {SchurMethod::kPcg, true}, {SchurMethod::kPcg, false}};
    for (const auto& [method, old_rule] : configs) {
      BalProblem p = make();
      if (method == SchurMethod::kDense && p.num_cameras() > 400) continue;
      BundleAdjustmentOptions o;
      o.optimizer.num_threads = 1;
      o.optimizer.function_tolerance = 1e-6;  // ba_peer's stopping rule
      o.optimizer.schur.method = method;
      if (old_rule) o.optimizer.schur.pcg_tolerance = 0.1, o.optimizer.schur.pcg_q_tolerance = 0.0;
      BundleAdjustmentResult r;
      const double cpu = measure([&] { r = optimize_bundle_adjustment(p, o); }, 1).med();
      const Summary& sm = r.summary;
      const char* rule = method != SchurMethod::kPcg ? "-" : old_rule ? "residual 0.1" : "Nash-Sofer 0.1";
      std::printf("  LM %-15s %-14s %-40s iterations %3d  solves %3d  CG %5ld (%.1f per solve)  final cost %.6f  "
                  "CPU %.2f s\n",
                  to_string(method), rule, name.c_str(), sm.iterations, sm.linear_solves, sm.pcg_iterations,
                  static_cast<double>(sm.pcg_iterations) / std::max(1, sm.linear_solves), r.final_cost, cpu);
      std::fflush(stdout);
      lm_runs.push_back({{"problem", name}, {"method", to_string(method)}, {"pcg_stopping_rule", rule},
                         {"iterations", sm.iterations}, {"linear_solves", sm.linear_solves},
                         {"pcg_iterations", sm.pcg_iterations}, {"final_cost", r.final_cost}, {"cpu_s", cpu},
                         {"termination", to_string(sm.termination)}});
    }
  }
  const std::string clock = g_wall ? "wall time, " + std::to_string(threads) + " threads" : "thread CPU time, 1 thread";
  std::ofstream(out) << nlohmann::json{{"clock", clock + "; bare and iteration interleaved, medians of " +
                                                     std::to_string(base_reps) + " reps"},
                                       {"threads", threads},
                                       {"phases", results},
                                       {"lm_runs", lm_runs}}
                            .dump(2)
                     << "\n";
  std::printf("wrote %s\n", out.c_str());
}
