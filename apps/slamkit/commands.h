// Subcommands of the slamkit CLI, one file each (cmd_<name>.cpp). Each add_*_command
// registers a CLI11 subcommand whose callback does the work and throws on failure
// (slamkit::Error for user-facing problems); main() turns exceptions into a message on
// stderr and a non-zero exit code.
#pragma once

#include <CLI/CLI.hpp>

namespace slamkit::cli {

// pose-graph tools (issue: foundation)
void add_info_command(CLI::App& app);     // cmd_info.cpp
void add_convert_command(CLI::App& app);  // cmd_convert.cpp
// optimizer (issue: graph optimization)
void add_optimize_command(CLI::App& app);  // cmd_optimize.cpp: optimize FILE
void add_compare_command(CLI::App& app);   // cmd_compare.cpp: compare FILE --solvers ...
// evaluation and reports (issue: trajectory evaluation)
void add_eval_command(CLI::App& app);    // cmd_eval.cpp: eval ate|rpe
void add_report_command(CLI::App& app);  // cmd_report.cpp: report RUN.json... -o report.html
// visual-inertial simulation (issue 12)
void add_simulate_command(CLI::App& app);  // cmd_simulate.cpp: simulate --vi room1 -o run.vis
void add_vio_command(CLI::App& app);       // cmd_vio.cpp: vio --sim run.vis
void add_frontend_command(CLI::App& app);  // cmd_frontend.cpp: frontend VIDEO_OR_IMAGES --out DIR (issue 13)
// landmark-SLAM filters (issue 15)
void add_filter_command(CLI::App& app);  // cmd_filter.cpp: filter --algorithm ekf|eif|seif|...

}  // namespace slamkit::cli
