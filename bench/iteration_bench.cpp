// Micro benchmark: one optimizer iteration (assemble + factorize + solve + retract + evaluate)
// against one bare CHOLMOD factorize + solve of the very same Hessian, per dataset.
// The bound: iteration ≤ 1.3 × bare. Two bare references:
//   bare_cholmod           slamkit's CHOLMOD backend alone (its settings: relaxed supernodes)
//   bare_cholmod_defaults  CHOLMOD called directly with its default settings
// Google Benchmark; e.g.
//   iteration_bench --benchmark_out=bench/results/iteration.json --benchmark_out_format=json
#include <benchmark/benchmark.h>
#ifdef SLAMKIT_BENCH_CHOLMOD
#include <cholmod.h>

#include <cstring>
#endif

#include <chrono>
#include <map>
#include <utility>
#include <memory>

#include "bench_data.h"
#include "slamkit/factors/pose_graph_problem.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/linear/blas_runtime.h"
#include "slamkit/linear/normal_equations.h"
#include "slamkit/linear/sparse_cholesky.h"
#include "slamkit/solvers/pose_graph_init.h"

using namespace slamkit;

namespace {

// A dataset at its initialized state, with its linear system analyzed once.
struct Fixture {
  PoseGraphProblem problem;
  std::unique_ptr<NormalEquations> ne;
  std::unique_ptr<SparseCholesky> chol;
  Values candidate;
};

Fixture& fixture(const std::string& file) {
  static std::map<std::string, std::unique_ptr<Fixture>> cache;
  auto& f = cache[file];
  if (!f) {
    f = std::make_unique<Fixture>();
    PoseGraph g = read_pose_graph((bench::data_root() / "posegraph" / file).string());
    initialize_pose_graph(g, InitMethod::kAuto, gauge_vertices(g));
    f->problem = build_pose_graph_problem(g);
    f->ne = std::make_unique<NormalEquations>(f->problem.graph, f->problem.values);
    f->chol = make_sparse_cholesky(SparseBackend::kAuto, OrderingMethod::kAuto, 1);
    f->chol->analyze(f->ne->hessian());
    f->ne->linearize(f->problem.values, ThreadPool(1));
    f->candidate = f->problem.values;
  }
  return *f;
}

void bare_cholmod(benchmark::State& state, const std::string& file) {
  Fixture& f = fixture(file);
  std::vector<double> x(f.ne->dim());
  const Eigen::VectorXd b = -f.ne->gradient();
  using Clock = std::chrono::steady_clock;
  double t_factorize = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    f.chol->factorize(f.ne->hessian());
    t_factorize += std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    f.chol->solve(b.data(), x.data());
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["factorize_ms"] = t_factorize / static_cast<double>(state.iterations());
  state.counters["nnz_L"] = f.chol->stats().factor_nnz;
  for (const bench::Reference& r : bench::references())  // the figure, for the summary
    if (r.file == file) state.counters["issue_ms"] = r.cholmod_ms;
  state.SetLabel(f.chol->stats().ordering);
}

#ifdef SLAMKIT_BENCH_CHOLMOD
// CHOLMOD as it comes: default cholmod_common (supernodal switch, relaxation), the matrix
// factorized as stored (it is in elimination order), one thread as in bare_cholmod.
void bare_cholmod_defaults(benchmark::State& state, const std::string& file) {
  Fixture& f = fixture(file);
  const BlockSparseMatrix& H = f.ne->hessian();
  cholmod_common c;
  cholmod_start(&c);
  c.nmethods = 1;
  c.method[0].ordering = CHOLMOD_NATURAL;
  c.postorder = 0;
  c.final_ll = 1;
  cholmod_sparse A;
  std::memset(&A, 0, sizeof(A));
  A.nrow = A.ncol = static_cast<size_t>(H.rows());
  A.nzmax = H.row_index().size();
  A.p = const_cast<int*>(H.col_ptr().data());
  A.i = const_cast<int*>(H.row_index().data());
  A.x = const_cast<double*>(H.values().data());
  A.stype = -1;
  A.itype = CHOLMOD_INT;
  A.xtype = CHOLMOD_REAL;
  A.dtype = CHOLMOD_DOUBLE;
  A.sorted = A.packed = 1;
  cholmod_factor* L = cholmod_analyze(&A, &c);
  Eigen::VectorXd b = -f.ne->gradient();
  cholmod_dense B;
  std::memset(&B, 0, sizeof(B));
  B.nrow = B.d = B.nzmax = static_cast<size_t>(H.rows());
  B.ncol = 1;
  B.x = b.data();
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  const SerialOpenMpScope serial;  // as slamkit's backend does with 1 BLAS thread
  for (auto _ : state) {
    cholmod_factorize(&A, L, &c);
    cholmod_dense* X = cholmod_solve(CHOLMOD_A, L, &B, &c);
    benchmark::DoNotOptimize(X->x);
    cholmod_free_dense(&X, &c);
  }
  if (c.status != CHOLMOD_OK) state.SkipWithError("CHOLMOD failed");
  state.SetLabel(L->is_super ? "supernodal" : "simplicial");
  cholmod_free_factor(&L, &c);
  cholmod_finish(&c);
}
#endif

void iteration(benchmark::State& state, const std::string& file) {
  Fixture& f = fixture(file);
  const ThreadPool pool(static_cast<int>(state.range(0)));
  std::vector<double> x(f.ne->dim());
  Eigen::VectorXd b(f.ne->dim());
  // One accepted Gauss-Newton step as Optimizer runs it: assemble H, g from the point
  // evaluated last, factorize, solve, retract, evaluate the candidate (its cost, residuals
  // and Jacobians, which the optimizer's next iteration assembles; here the start point is
  // evaluated again, untimed, so that every repetition times the same step).
  // Per-phase wall time (ms per iteration) as counters: where an iteration's time goes.
  using Clock = std::chrono::steady_clock;
  double t_assemble = 0, t_factorize = 0, t_solve = 0, t_retract_evaluate = 0;
  const auto ms = [](Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
  };
  f.ne->evaluate(f.problem.values, pool);
  for (auto _ : state) {
    const auto t0 = Clock::now();
    f.ne->assemble(pool);
    const auto t1 = Clock::now();
    f.chol->factorize(f.ne->hessian());
    const auto t2 = Clock::now();
    b = -f.ne->gradient();
    f.chol->solve(b.data(), x.data());
    const auto t3 = Clock::now();
    f.ne->retract(f.problem.values, x.data(), f.candidate, pool);
    benchmark::DoNotOptimize(f.ne->evaluate(f.candidate, pool));
    const auto t4 = Clock::now();
    // Back to the start point, untimed: every timed iteration is the same first step (left to
    // run on, the steps would go on from the candidates' H and g but from the fixed start, and
    // diverge until a cost is not finite).
    state.PauseTiming();
    f.ne->evaluate(f.problem.values, pool);
    state.ResumeTiming();
    t_assemble += ms(t0, t1);
    t_factorize += ms(t1, t2);
    t_solve += ms(t2, t3);
    t_retract_evaluate += ms(t3, t4);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["assemble_ms"] = t_assemble / n;
  state.counters["factorize_ms"] = t_factorize / n;
  state.counters["solve_ms"] = t_solve / n;
  state.counters["retract_evaluate_ms"] = t_retract_evaluate / n;
  state.SetLabel(std::to_string(pool.threads()) + " threads");
}

// The parts of an iteration that are slamkit's own, alone: a whole linearization (evaluate:
// residuals and Jacobians; assemble: H and g), and retract + evaluate of a candidate.
void linearize(benchmark::State& state, const std::string& file) {
  Fixture& f = fixture(file);
  const ThreadPool pool(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(f.ne->linearize(f.problem.values, pool));
  state.SetLabel(std::to_string(pool.threads()) + " threads");
}

void retract_and_evaluate(benchmark::State& state, const std::string& file) {
  Fixture& f = fixture(file);
  const ThreadPool pool(static_cast<int>(state.range(0)));
  const std::vector<double> x(f.ne->dim(), 1e-6);
  for (auto _ : state) {
    f.ne->retract(f.problem.values, x.data(), f.candidate, pool);
    benchmark::DoNotOptimize(f.ne->evaluate(f.candidate, pool));
  }
  state.SetLabel(std::to_string(pool.threads()) + " threads");
}

const int kRegistered = [] {
  for (const bench::Reference& r : bench::references()) {
    if (!r.speed_goal) continue;
    if (!std::filesystem::exists(bench::data_root() / "posegraph" / r.file)) continue;
    benchmark::RegisterBenchmark(("bare_cholmod/" + r.file).c_str(), bare_cholmod, r.file)
        ->Unit(benchmark::kMillisecond)
        ->MinTime(1.0);
#ifdef SLAMKIT_BENCH_CHOLMOD
    benchmark::RegisterBenchmark(("bare_cholmod_defaults/" + r.file).c_str(), bare_cholmod_defaults, r.file)
        ->Unit(benchmark::kMillisecond)
        ->MinTime(1.0);
#endif
    benchmark::RegisterBenchmark(("iteration/" + r.file).c_str(), iteration, r.file)
        ->Arg(1)
        ->Arg(2)
        ->Unit(benchmark::kMillisecond)
        ->MinTime(1.0);
    const std::pair<const char*, void (*)(benchmark::State&, const std::string&)> parts[] = {
        {"linearize/", linearize}, {"retract_and_evaluate/", retract_and_evaluate}};
    for (const auto& [name, fn] : parts)
      benchmark::RegisterBenchmark((name + r.file).c_str(), fn, r.file)
          ->Arg(1)
          ->Arg(2)
          ->Unit(benchmark::kMillisecond)
          ->MinTime(0.5);
  }
  return 0;
}();

}  // namespace

int main(int argc, char** argv) {
  reexec_with_better_blas_core(argv);  // the kernels the CLI runs with
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  const BlasRuntime blas = blas_runtime();
  benchmark::AddCustomContext("blas", blas.vendor + " " + blas.core);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
