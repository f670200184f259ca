// The options of `slamkit optimize` that a JSON config file (--config) can set, with the CLI's
// defaults. The run's JSON summary echoes them under "config" in the same form, so a summary's
// "config" object, saved as a file, reproduces the run: read → write → read gives the same
// values (what the config fuzz target checks).
//
// Every value is validated while reading (names must parse, counts are non-negative integers,
// tolerances finite and non-negative); errors are InputError "FILE:LINE: field 'KEY': message".
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace slamkit::cli {

struct OptimizeSettings {
  std::string solver = "gn";             // gn | lm | tr-lm | dogleg | hogman
  std::string init = "auto";             // none | odometry | spanning-tree | linear | chordal | auto | sgd | toro | relax | mlr
  std::string robust;                    // KERNEL:delta, empty for none
  bool robust_loop_closures_only = false;
  int max_iterations = 100;
  int threads = 0;       // 0: all cores
  int blas_threads = 1;  // 0: = threads
  double function_tolerance = 1e-5;
  double gradient_tolerance = 1e-10;
  double parameter_tolerance = 1e-8;
  std::string linear_solver = "auto";  // auto | cholmod | eigen
  std::string ordering = "auto";       // auto | amd | metis | nesdis | natural
  bool repair_information = false;
  std::string format = "auto";  // auto | g2o | toro | gtsam | bal
  std::string calibrate = "auto";  // auto | none | offset,odometry (calibration_cli.h)
  double keep_estimates_chi2_per_dof = 1.0;  // init auto: start from estimates this consistent (0: never)

  bool operator==(const OptimizeSettings& o) const;
};

/// Calls f(key, flag, member) for every setting, in a fixed order.
template <typename Settings, typename F>
void for_each_setting(Settings& s, F&& f) {
  f("solver", "--solver", s.solver);
  f("init", "--init", s.init);
  f("robust", "--robust", s.robust);
  f("robust_loop_closures_only", "--robust-loop-closures-only", s.robust_loop_closures_only);
  f("max_iterations", "--max-iterations", s.max_iterations);
  f("threads", "--threads", s.threads);
  f("blas_threads", "--blas-threads", s.blas_threads);
  f("function_tolerance", "--function-tolerance", s.function_tolerance);
  f("gradient_tolerance", "--gradient-tolerance", s.gradient_tolerance);
  f("parameter_tolerance", "--parameter-tolerance", s.parameter_tolerance);
  f("linear_solver", "--linear-solver", s.linear_solver);
  f("ordering", "--ordering", s.ordering);
  f("repair_information", "--repair-information", s.repair_information);
  f("format", "--format", s.format);
  f("calibrate", "--calibrate", s.calibrate);
  f("keep_estimates_chi2_per_dof", "--keep-estimates-chi2-per-dof", s.keep_estimates_chi2_per_dof);
}

/// Throws InputError(source, 0, key, ...) if a value is out of its domain (unknown name,
/// negative count, non-finite tolerance).
void validate(const OptimizeSettings& s, const std::string& source);

/// Parses a JSON object of settings into `s`: keys present overwrite `s`, except those whose
/// flag `given(flag)` says was set on the command line (flags win). Unknown keys, wrong types and
/// invalid values throw InputError naming `source`, the line and the key.
void parse_optimize_config(std::string_view text, const std::string& source, OptimizeSettings& s,
                           const std::function<bool(const char* flag)>& given = {});
/// Reads the file `path` (see parse_optimize_config).
void read_optimize_config(const std::string& path, OptimizeSettings& s,
                          const std::function<bool(const char* flag)>& given = {});
/// All settings as a JSON object (the inverse of parse_optimize_config).
std::string optimize_config_to_json(const OptimizeSettings& s);

}  // namespace slamkit::cli
