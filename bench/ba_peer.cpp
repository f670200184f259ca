// Bundle adjustment side by side with Ceres 2.1 (Debian libceres-dev), every run in its own
// forked process (so peak memory is per run: ru_maxrss of the child), on the two real BAL
// problems and synthetic sim:ba problems of 200 and 2,000 cameras.
//   Ceres: LM (its defaults: radius 1e4, Nielsen update), DENSE_SCHUR / SPARSE_SCHUR
//          (SuiteSparse) / ITERATIVE_SCHUR + SCHUR_JACOBI, points eliminated first,
//          AutoDiff reprojection residual of the BAL model, 2 threads.
//   slamkit: LM with the Schur complement, schur-dense / schur-cholesky / schur-pcg / auto, 2 threads.
// Same stopping rule for both: function tolerance 1e-6, gradient 1e-10, parameter 1e-8,
// at most 100 iterations. Costs are ½ Σ‖r‖².
// Every solver runs once per round, rounds interleaved (--rounds, default 3); the JSON keeps
// each round and the medians (wall and CPU time of the child, its peak RSS = what
// /usr/bin/time -v calls "Maximum resident set size"). The machine is shared: read CPU times.
//   ba_peer [--only SUBSTRING] [--skip-large 1] [--ours a,b] [--ceres A,B] [--rounds N] [--bare 0|1]
//           [--out bench/results/ba_peer.json]
#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "bench_data.h"
#include "slamkit/factors/bal_normal_equations.h"
#include "slamkit/factors/bundle_adjustment.h"
#include "slamkit/io/bal_io.h"
#include "slamkit/linear/normal_equations.h"
#include "slamkit/linear/schur_complement.h"
#include "slamkit/linear/blas_runtime.h"
#include "slamkit/sim/ba_generator.h"

using namespace slamkit;

namespace {

struct BalResidual {
  explicit BalResidual(const Eigen::Vector2d& z) : z_(z) {}
  template <class T>
  bool operator()(const T* camera, const T* point, T* r) const {
    T P[3];
    ceres::AngleAxisRotatePoint(camera, point, P);
    for (int a = 0; a < 3; ++a) P[a] += camera[3 + a];
    const T px = -P[0] / P[2], py = -P[1] / P[2];
    const T n = px * px + py * py;
    const T d = T(1.0) + camera[7] * n + camera[8] * n * n;
    r[0] = camera[6] * d * px - T(z_.x());
    r[1] = camera[6] * d * py - T(z_.y());
    return true;
  }
  Eigen::Vector2d z_;
};

double load_average() {
  double l[1] = {0};
  return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

nlohmann::json run_ceres(BalProblem p, const std::string& solver) {
  const double t0 = now_s();
  ceres::Problem problem;
  for (const BalObservation& o : p.observations)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<BalResidual, 2, 9, 3>(new BalResidual(o.pixel)), nullptr,
                             p.cameras[o.camera].data(), p.points[o.point].data());
  ceres::Solver::Options options;
  options.linear_solver_type = solver == "DENSE_SCHUR"    ? ceres::DENSE_SCHUR
                               : solver == "SPARSE_SCHUR" ? ceres::SPARSE_SCHUR
                                                          : ceres::ITERATIVE_SCHUR;
  if (options.linear_solver_type == ceres::ITERATIVE_SCHUR) options.preconditioner_type = ceres::SCHUR_JACOBI;
  options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  auto* ordering = new ceres::ParameterBlockOrdering;
  for (auto& X : p.points) ordering->AddElementToGroup(X.data(), 0);
  for (auto& c : p.cameras) ordering->AddElementToGroup(c.data(), 1);
  options.linear_solver_ordering.reset(ordering);
  options.num_threads = 2;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-6;
  options.gradient_tolerance = 1e-10;
  options.parameter_tolerance = 1e-8;
  ceres::Solver::Summary s;
  ceres::Solve(options, &problem, &s);
  const double t = now_s() - t0;
  long cg_iterations = 0;  // ITERATIVE_SCHUR: CG iterations over all LM steps (direct solvers: 1 per step)
  for (const ceres::IterationSummary& it : s.iterations) cg_iterations += it.linear_solver_iterations;
  return {{"solver", "ceres " + solver},
          {"seconds", t},
          {"solve_seconds", s.total_time_in_seconds},
          {"initial_cost", s.initial_cost},
          {"final_cost", s.final_cost},
          {"iterations", static_cast<int>(s.iterations.size()) - 1},
          {"linear_solver_seconds", s.linear_solver_time_in_seconds},
          {"linear_solves", s.num_linear_solves},
          {"linear_solver_iterations", cg_iterations},
          {"termination", ceres::TerminationTypeToString(s.termination_type)}};
}

nlohmann::json run_slamkit(BalProblem p, const std::string& linear) {
  BundleAdjustmentOptions o;
  o.optimizer.num_threads = 2;
  o.optimizer.schur.method = parse_schur_method(linear);
  const BundleAdjustmentResult r = optimize_bundle_adjustment(p, o);
  const Summary& s = r.summary;
  const int iters = std::max(1, s.iterations);
  return {{"solver", "slamkit " + linear},
          {"schur", s.linear_solver},
          {"seconds", s.time_total_s + r.time_build_s},
          {"solve_seconds", s.time_total_s},
          {"initial_cost", r.initial_cost},
          {"final_cost", r.final_cost},
          {"iterations", s.iterations},
          {"linear_solver_seconds", s.time_linear_solver_s},
          {"seconds_per_iteration", s.time_total_s / iters},
          {"linearize_seconds", s.time_linearize_s},
          {"evaluate_seconds", s.time_evaluate_s},
          {"linear_solves", s.linear_solves},
          {"pcg_iterations", s.pcg_iterations},
          {"termination", to_string(s.termination)}};
}

// One bare factorization of the reduced camera system at the start point (H from
// BalNormalEquations, damped by λ = 1e-4 as LM's first step): Schur elimination (S formed)
// + factorization, and the factorization alone; for schur-pcg one preconditioner + one PCG
// solve. Medians of 3, to compare with slamkit's time per iteration.
nlohmann::json bare_factorization(const BalProblem& p, SchurMethod method) {
  const ThreadPool pool(2);
  BalNormalEquations ne(p, nullptr, pool);
  ne.linearize(make_bal_state(p));
  ne.set_diagonal_damping(1e-4 * ne.hessian_diagonal().cwiseMax(1e-6));
  SchurOptions so;
  so.method = method;
  SchurComplementSolver solver(ne.eliminate_flags(), pool, so);
  solver.analyze(ne.hessian());
  std::vector<double> total, factor;
  const Eigen::VectorXd rhs = -ne.gradient();
  Eigen::VectorXd x(rhs.size());
  for (int r = 0; r < 3; ++r) {
    const double t0 = now_s();
    solver.factorize(ne.hessian());
    if (method == SchurMethod::kPcg) solver.solve(rhs.data(), x.data());
    total.push_back(now_s() - t0);
    factor.push_back(method == SchurMethod::kPcg ? total.back() - solver.last_schur_time_s() : solver.last_factor_time_s());
  }
  std::sort(total.begin(), total.end());
  std::sort(factor.begin(), factor.end());
  return {{"method", to_string(method)}, {"schur_and_factorize_s", total[1]}, {"factorize_s", factor[1]},
          {"pcg_iterations", solver.last_pcg_iterations()}};
}

// Runs fn in a child process; returns its JSON with the child's peak RSS.
template <class F>
nlohmann::json in_child(F fn) {
  std::fflush(stdout);  // the child must not print the parent's buffered lines again
  int fd[2];
  if (pipe(fd) != 0) return {{"error", "pipe"}};
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    std::string out;
    try {
      out = fn().dump();
    } catch (const std::exception& e) {
      out = nlohmann::json{{"error", e.what()}}.dump();
    }
    const char* b = out.data();
    std::size_t left = out.size();
    while (left > 0) {
      const ssize_t w = write(fd[1], b, left);
      if (w <= 0) break;
      b += w, left -= static_cast<std::size_t>(w);
    }
    close(fd[1]);
    _exit(0);
  }
  close(fd[1]);
  std::string text;
  char buf[4096];
  ssize_t n;
  while ((n = read(fd[0], buf, sizeof buf)) > 0) text.append(buf, static_cast<std::size_t>(n));
  close(fd[0]);
  int status = 0;
  struct rusage ru {};
  wait4(pid, &status, 0, &ru);
  nlohmann::json j = text.empty() ? nlohmann::json{{"error", "child failed"}} : nlohmann::json::parse(text);
  j["peak_rss_mb"] = ru.ru_maxrss / 1024.0;
  // CPU time of the child (all threads): on a loaded machine a steadier measure of work than wall time.
  j["cpu_seconds"] = ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  return j;
}

}  // namespace

int main(int argc, char** argv) {
  reexec_with_better_blas_core(argv);
  const SerialOpenMpScope serial_openmp;  // CHOLMOD's OpenMP regions serial for both (1 BLAS thread)
  std::string only, out = std::string(SLAMKIT_SOURCE_DIR) + "/bench/results/ba_peer.json", skip_large = "0";
  std::string ours_only, ceres_only, bare_only = "1", rounds_s = "3";
  if (!bench::parse_options(argc, argv,
                            "[--only SUBSTRING] [--skip-large 1] [--ours a,b] [--ceres A,B] [--bare 0|1] [--rounds N] [--out FILE]",
                            {{"--only", &only}, {"--skip-large", &skip_large}, {"--ours", &ours_only},
                             {"--ceres", &ceres_only}, {"--bare", &bare_only}, {"--rounds", &rounds_s}, {"--out", &out}}))
    return 2;
  const int rounds = bench::int_option("--rounds", rounds_s, 1, 1000);
  auto wanted = [](const std::string& list, const std::string& name) {
    return list.empty() || ("," + list + ",").find("," + name + ",") != std::string::npos;
  };
  struct Case {
    std::string name;
    std::function<BalProblem()> make;
    std::vector<std::string> ours, ceres;
  };
  const auto bal = bench::data_root() / "bal";
  const std::vector<std::string> all_ours = {"schur-dense", "schur-cholesky", "schur-pcg", "auto"};
  const std::vector<std::string> all_ceres = {"DENSE_SCHUR", "SPARSE_SCHUR", "ITERATIVE_SCHUR"};
  std::vector<Case> cases = {
      {"problem-49-7776-pre", [&] { return read_bal((bal / "problem-49-7776-pre.txt").string()); }, all_ours, all_ceres},
      {"problem-21-11315-pre", [&] { return read_bal((bal / "problem-21-11315-pre.txt").string()); }, all_ours, all_ceres},
      {"sim:ba?cameras=200&points=40000&seed=1",
       [] {
         BaSimOptions o;
         o.cameras = 200, o.points = 40000, o.seed = 1;
         return generate_ba_problem(o);
       },
       all_ours, all_ceres},
  };
  if (skip_large != "1")
    cases.push_back({"sim:ba?cameras=2000&points=500000&seed=1",
                     [] {
                       BaSimOptions o;
                       o.cameras = 2000, o.points = 500000, o.seed = 1;
                       return generate_ba_problem(o);
                     },
                     {"schur-cholesky", "schur-pcg", "auto"},
                     {"SPARSE_SCHUR", "ITERATIVE_SCHUR"}});
  nlohmann::json results = nlohmann::json::array();
  for (const Case& c : cases) {
    if (!only.empty() && c.name.find(only) == std::string::npos) continue;
    const BalProblem p = c.make();
    std::printf("== %s: %d cameras, %d points, %d observations\n", c.name.c_str(), p.num_cameras(), p.num_points(),
                p.num_observations());
    // Interleaved rounds (every solver once per round, Ceres and slamkit alternating), then
    // medians per solver: the machine is shared, so wall and CPU times are both reported.
    std::vector<std::string> names;
    std::map<std::string, std::vector<nlohmann::json>> by_solver;
    for (const std::string& x : c.ceres)
      if (wanted(ceres_only, x)) names.push_back("ceres " + x);
    for (const std::string& x : c.ours)
      if (wanted(ours_only, x)) names.push_back("slamkit " + x);
    for (int round = 0; round < rounds; ++round) {
      for (const std::string& name : names) {
        const bool ceres = name.rfind("ceres ", 0) == 0;
        const std::string solver = name.substr(ceres ? 6 : 8);
        nlohmann::json j = ceres ? in_child([&] { return run_ceres(p, solver); })
                                 : in_child([&] { return run_slamkit(p, solver); });
        j["round"] = round;
        j["load_average"] = load_average();
        const long cg = j.value("linear_solver_iterations", j.value("pcg_iterations", 0L));
        std::printf("  [%d] %-24s %8.3f s (cpu %8.3f)  %3d it  cost %.6e -> %.6e  %7.0f MB  %s%s\n", round, name.c_str(),
                    j.value("seconds", 0.0), j.value("cpu_seconds", 0.0), j.value("iterations", 0),
                    j.value("initial_cost", 0.0), j.value("final_cost", 0.0), j.value("peak_rss_mb", 0.0),
                    j.value("error", "").c_str(),
                    solver.find("ITERATIVE") != std::string::npos || solver.find("pcg") != std::string::npos
                        ? ("  CG iterations " + std::to_string(cg)).c_str()
                        : "");
        std::fflush(stdout);
        by_solver[name].push_back(j);
      }
    }
    auto median = [](std::vector<double> v) {
      std::sort(v.begin(), v.end());
      return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
    };
    nlohmann::json runs = nlohmann::json::array();
    double best_ceres = 1e300, best_ceres_cost = 0, best_ceres_cpu = 1e300;
    for (const std::string& name : names) {
      const auto& rs = by_solver[name];
      std::vector<double> wall, cpu, per_it;
      double rss = 0.0;
      for (const auto& j : rs) {
        wall.push_back(j.value("seconds", 0.0)), cpu.push_back(j.value("cpu_seconds", 0.0));
        rss = std::max(rss, j.value("peak_rss_mb", 0.0));
        per_it.push_back(j.value("solve_seconds", 0.0) / std::max(1, j.value("iterations", 1)));
      }
      nlohmann::json m = rs.back();
      m.erase("round"), m.erase("load_average");
      m["median_seconds"] = median(wall), m["median_cpu_seconds"] = median(cpu), m["max_peak_rss_mb"] = rss;
      m["median_seconds_per_iteration"] = median(per_it);
      m["rounds"] = rs;
      if (name.rfind("ceres ", 0) == 0) {
        if (m["median_seconds"].get<double>() < best_ceres) best_ceres = m["median_seconds"], best_ceres_cost = m.value("final_cost", 0.0);
        best_ceres_cpu = std::min(best_ceres_cpu, m["median_cpu_seconds"].get<double>());
      }
      runs.push_back(m);
    }
    for (auto& m : runs) {
      if (m.value("solver", "").rfind("slamkit ", 0) != 0) continue;
      m["ratio_vs_fastest_ceres"] = m["median_seconds"].get<double>() / best_ceres;
      m["cpu_ratio_vs_least_cpu_ceres"] = m["median_cpu_seconds"].get<double>() / best_ceres_cpu;
      m["cost_vs_fastest_ceres"] = m.value("final_cost", 0.0) / best_ceres_cost - 1.0;
    }
    std::printf("  medians over %d rounds:\n", rounds);
    for (const auto& m : runs) {
      std::printf("  %-24s %8.3f s (cpu %8.3f)  %3d it  %.4f s/it  final %.8e  %7.0f MB", m.value("solver", "").c_str(),
                  m["median_seconds"].get<double>(), m["median_cpu_seconds"].get<double>(), m.value("iterations", 0),
                  m["median_seconds_per_iteration"].get<double>(), m.value("final_cost", 0.0), m["max_peak_rss_mb"].get<double>());
      if (m.contains("ratio_vs_fastest_ceres"))
        std::printf("  x%.3f of fastest Ceres (cpu x%.3f), cost %+.2e", m["ratio_vs_fastest_ceres"].get<double>(),
                    m["cpu_ratio_vs_least_cpu_ceres"].get<double>(), m["cost_vs_fastest_ceres"].get<double>());
      std::printf("\n");
    }
    std::fflush(stdout);
    nlohmann::json bare = nlohmann::json::array();
    for (SchurMethod m : {SchurMethod::kDense, SchurMethod::kCholesky, SchurMethod::kPcg}) {
      if ((m == SchurMethod::kDense && p.num_cameras() > 400) || bare_only != "1") continue;
      nlohmann::json b = in_child([&] { return bare_factorization(p, m); });
      std::printf("  bare %-19s Schur elimination + factorization %.4f s, factorization alone %.4f s\n",
                  b.value("method", "").c_str(), b.value("schur_and_factorize_s", 0.0), b.value("factorize_s", 0.0));
      bare.push_back(b);
    }
    results.push_back({{"problem", c.name},
                       {"bare_factorization", bare},
                       {"cameras", p.num_cameras()},
                       {"points", p.num_points()},
                       {"observations", p.num_observations()},
                       {"fastest_ceres_seconds", best_ceres},
                       {"least_ceres_cpu_seconds", best_ceres_cpu},
                       {"load_average_at_start", load_average()},
                       {"runs", runs}});
  }
  nlohmann::json doc = {{"ceres_version", CERES_VERSION_STRING}, {"threads", 2}, {"function_tolerance", 1e-6},
                        {"rounds", rounds}, {"note", "interleaved rounds, medians; shared 2-core machine: see cpu figures"},
                        {"problems", results}};
  std::ofstream(out) << doc.dump(2) << "\n";
  std::printf("wrote %s\n", out.c_str());
}
