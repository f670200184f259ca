// Small helpers shared by the subcommands: JSON output files and timing.
#pragma once

#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <iostream>
#include <utility>
#include <nlohmann/json.hpp>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/core/output_file.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/io/pose_graph_source.h"  // load_pose_graph: a file or a sim: spec
#include "slamkit/sim/calibration_generator.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace slamkit::cli {

/// Writes j (pretty-printed) to path atomically; "-" writes to stdout. Throws InputError if it cannot.
inline void write_json(const std::string& path, const nlohmann::json& j) {
  write_file_atomically(path, j.dump(2) + "\n", "json");
}

/// Fails at once, before any work, if one of the output paths (empty: not requested) cannot be
/// written: a long run must not end in "cannot open for writing".
inline void check_outputs(std::initializer_list<std::pair<const std::string*, const char*>> outputs) {
  for (const auto& [path, option] : outputs)
    if (!path->empty()) check_writable(*path, option);
}

/// Option validators like CLI::NonNegativeNumber / CLI::PositiveNumber that also refuse NaN
/// (CLI11's accept it: its range test `x < 0` is false for NaN, so "nan" would silently pass).
inline CLI::Validator number_at_least(double low, bool strict, const char* name) {
  return CLI::Validator(
      [low, strict](std::string& text) -> std::string {
        double x = 0.0;
        if (!CLI::detail::lexical_cast(text, x) || !std::isfinite(x) || x < low || (strict && x == low))
          return "Value " + text + (strict ? " is not a finite number > " : " is not a finite number >= ") +
                 CLI::detail::to_string(low);
        return {};
      },
      name);
}
/// A finite number in [low, high] ((low, high] with strict_low); refuses NaN, as above.
inline CLI::Validator FiniteRange(double low, double high, bool strict_low = false) {
  return CLI::Validator(
      [low, high, strict_low](std::string& text) -> std::string {
        double x = 0.0;
        if (!CLI::detail::lexical_cast(text, x) || !std::isfinite(x) || x < low || x > high || (strict_low && x == low))
          return "Value " + text + " is not a finite number in " + (strict_low ? "(" : "[") + CLI::detail::to_string(low) +
                 ", " + CLI::detail::to_string(high) + "]";
        return {};
      },
      std::string("FINITE in ") + (strict_low ? "(" : "[") + CLI::detail::to_string(low) + ", " + CLI::detail::to_string(high) + "]");
}
inline const CLI::Validator NonNegativeNumber = number_at_least(0.0, false, "NONNEGATIVE");
inline const CLI::Validator PositiveNumber = number_at_least(0.0, true, "POSITIVE");

class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace slamkit::cli
