// slamkit: the command-line front end. Exit codes: 0 success, 1 error in the input or the
// run (message on stderr), 2 usage error (CLI11), 3 unexpected internal error.
#include <CLI/CLI.hpp>
#include <exception>
#include <iostream>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "commands.h"
#include "slamkit/core/error.h"
#include "slamkit/linear/blas_runtime.h"

int main(int argc, char** argv) {
  // OpenBLAS may not know this CPU and run generic kernels at half speed: restart with the
  // right ones (see slamkit/linear/blas_runtime.h; SLAMKIT_KEEP_BLAS_CORE=1 opts out).
  slamkit::reexec_with_better_blas_core(argv);
#if defined(__GLIBC__)
  // glibc serves blocks above 128 KiB (its starting mmap threshold) by mmap and unmaps them on
  // free, and hands a free heap top above 128 KiB back to the OS: memory that one phase frees
  // (loading, the initialization) then comes back to the next as fresh pages, each a page fault
  // (1.5-2 us per 4 KiB on the 2-core VM; a third of the faults of a small pose graph's run,
  // docs/pose_graph_profile.md). Blocks below 4 MiB stay in the heap and up to 64 MiB of free
  // top is kept; larger blocks (big graphs) still map and unmap.
  mallopt(M_MMAP_THRESHOLD, 4 << 20);
  mallopt(M_TRIM_THRESHOLD, 64 << 20);
#endif
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
