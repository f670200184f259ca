// `slamkit optimize FILE --solver hogman`: the HOG-Man back end behind the optimize command,
// with the same progress lines, summary and JSON keys (kind "optimize", solver, final_chi2, …).
#pragma once

#include <string>

#include "slamkit/core/pose_graph.h"

namespace slamkit::cli {

struct HogmanCliOutput {
  std::string input, json, output, trajectory, label;
  bool quiet = false;
  int threads = 1;
};

void run_hogman_optimize(PoseGraph& g, const HogmanCliOutput& out);

}  // namespace slamkit::cli
