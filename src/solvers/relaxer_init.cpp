#include "slamkit/solvers/relaxer_init.h"

#include <cstdio>

#include "slamkit/core/error.h"
#include "slamkit/solvers/gauss_seidel_relaxation.h"
#include "slamkit/solvers/multilevel_relaxation.h"
#include "slamkit/solvers/sgd.h"
#include "slamkit/solvers/toro.h"

namespace slamkit {

bool is_relaxer_init(InitMethod m) {
  return m == InitMethod::kSgd || m == InitMethod::kToro || m == InitMethod::kRelax || m == InitMethod::kMlr;
}

RelaxerStop default_init_stop(InitMethod m) {
  RelaxerStop s;
  s.max_iterations = m == InitMethod::kMlr ? 10 : 100;
  return s;
}

RelaxerSummary run_named_relaxer(PoseGraph& g, const std::string& method, const RelaxerStop& stop) {
  if (method == "sgd") {
    SgdOptions o;
    o.stop = stop;
    return optimize_sgd(g, o);
  }
  if (method == "toro") {
    ToroOptions o;
    o.stop = stop;
    return optimize_toro(g, o);
  }
  if (method == "relax") {
    RelaxationOptions o;
    o.stop = stop;
    return optimize_relaxation(g, o);
  }
  if (method == "mlr") {
    MultilevelOptions o;
    o.stop = stop;
    return optimize_multilevel(g, o);
  }
  throw InputError("", 0, "solver", "unknown relaxer '" + method + "' (sgd, toro, relax, mlr)");
}

std::vector<std::string> relaxer_initialize(PoseGraph& g, InitMethod m) {
  const RelaxerSummary s = run_named_relaxer(g, to_string(m), default_init_stop(m));
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%s: chi2 %.10g -> %.10g in %d iterations, %.4f s (%s)", s.method.c_str(),
                s.initial_chi2, s.final_chi2, s.iterations, s.time_total_s, s.termination.c_str());
  std::vector<std::string> notes{buf};
  notes.insert(notes.end(), s.notes.begin(), s.notes.end());
  return notes;
}

}  // namespace slamkit
