// slamkit: the command-line front end. Exit codes: 0 success, 1 error in the input or the
// run (message on stderr), 2 usage error (CLI11), 3 unexpected internal error.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>

#include "commands.h"
#include "slamkit/core/error.h"
#include "slamkit/core/process_heap.h"
#include "slamkit/linear/blas_runtime.h"

int main(int argc, char** argv) {
  // OpenBLAS may not know this CPU and run generic kernels at half speed: restart with the
  // right ones (see slamkit/linear/blas_runtime.h; SLAMKIT_KEEP_BLAS_CORE=1 opts out).
  slamkit::reexec_with_better_blas_core(argv);
  // Freed memory stays in the heap, and the run's first 4 MiB of heap sit on transparent huge
  // pages: page faults were a quarter of a small pose graph's run (slamkit/core/process_heap.h).
  // SLAMKIT_HUGE_PAGES=0 keeps ordinary pages.
  slamkit::configure_process_heap();
  CLI::App app{"slamkit: SLAM back-end toolkit (graph optimization, filters, VIO, evaluation)"};
  app.set_version_flag("--version", std::string("slamkit ") + SLAMKIT_VERSION);
  app.require_subcommand(1);
  // pose-graph tools
  slamkit::cli::add_info_command(app);
  slamkit::cli::add_convert_command(app);
  // optimizer
  slamkit::cli::add_optimize_command(app);
  slamkit::cli::add_compare_command(app);
  // evaluation and reports
  slamkit::cli::add_eval_command(app);
  slamkit::cli::add_report_command(app);
  // visual-inertial simulation
  slamkit::cli::add_simulate_command(app);
  slamkit::cli::add_vio_command(app);
  slamkit::cli::add_frontend_command(app);
  // landmark-SLAM filters
  slamkit::cli::add_filter_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help and --version exit 0
  } catch (const slamkit::Error& e) {
    std::cerr << "slamkit: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "slamkit: internal error: " << e.what() << "\n";
    return 3;
  }
  return 0;
}
