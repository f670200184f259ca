// `slamkit optimize` on bundle-adjustment problems (BAL files, sim:ba): routed from
// cmd_optimize.cpp when --format bal is given or the input looks like a BAL file.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace slamkit::cli {

/// The options shared with pose-graph optimization, as given on the command line.
struct BundleAdjustmentCommonArgs {
  std::string input, output, json, robust, label;
  std::string solver;  ///< empty: lm
  int max_iterations = 100, threads = 0, blas_threads = 1;
  double function_tolerance = 1e-6, gradient_tolerance = 1e-10, parameter_tolerance = 1e-8;
  bool quiet = false;
};

/// Options only BA has (--linear, --ply, --normalize, --perturb, ...), registered on `cmd`.
void add_bundle_adjustment_options(CLI::App* cmd);
/// True for --format bal, *.bal, problem-*.txt, *-pre.txt and sim:ba specs.
bool is_bundle_adjustment_input(const std::string& input, const std::string& format);
void run_bundle_adjustment(const BundleAdjustmentCommonArgs& args);

}  // namespace slamkit::cli
