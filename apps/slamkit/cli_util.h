// Small helpers shared by the subcommands: JSON output files and timing.
#pragma once

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "slamkit/core/error.h"

namespace slamkit::cli {

/// Writes j (pretty-printed) to path; "-" writes to stdout. Throws InputError if it cannot.
inline void write_json(const std::string& path, const nlohmann::json& j) {
  if (path == "-") {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::ofstream out(path);
  if (!out) throw InputError(path, 0, "", "cannot write JSON output");
  out << j.dump(2) << "\n";
  if (!out) throw InputError(path, 0, "", "error while writing JSON output");
}

class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

}  // namespace slamkit::cli
