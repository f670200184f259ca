#include "optimize_config.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>
#include <type_traits>

#include "calibration_cli.h"
#include "slamkit/core/error.h"
#include "slamkit/core/robust_kernel.h"
#include "slamkit/io/pose_graph_io.h"
#include "slamkit/linear/sparse_cholesky.h"
#include "slamkit/solvers/optimizer_options.h"
#include "slamkit/solvers/pose_graph_init.h"

namespace slamkit::cli {

namespace {

/// 1-based line of byte offset `pos` in `text`.
int line_at(std::string_view text, std::size_t pos) {
  pos = std::min(pos, text.size());
  int line = 1;
  for (std::size_t i = 0; i < pos; ++i) line += text[i] == '\n';
  return line;
}

/// Line of the first occurrence of "key" in the text (0 if not found): JSON keeps no positions.
int line_of_key(std::string_view text, const std::string& key) {
  const std::size_t at = text.find('"' + key + '"');
  return at == std::string_view::npos ? 0 : line_at(text, at);
}

/// The name-valued settings must parse; counts and tolerances must be in their domain.
void check_setting(const OptimizeSettings& s, const std::string& key, const std::string& source = "") {
  auto require = [&](bool ok, const char* what) {
    if (!ok) throw InputError(source, 0, key, what);
  };
  if (key == "solver" && s.solver != "hogman") (void)parse_algorithm(s.solver);
  else if (key == "init") (void)parse_init_method(s.init);
  else if (key == "robust" && !s.robust.empty()) (void)parse_robust_kernel(s.robust);
  else if (key == "linear_solver") (void)parse_sparse_backend(s.linear_solver);
  else if (key == "ordering") (void)parse_ordering(s.ordering);
  else if (key == "format" && s.format != "bal") (void)parse_pose_graph_format(s.format);
  else if (key == "calibrate") (void)parse_calibrate_option(s.calibrate);
  else if (key == "max_iterations") require(s.max_iterations >= 0, "must be a non-negative integer");
  else if (key == "threads") require(s.threads >= 0, "must be a non-negative integer (0: all cores)");
  else if (key == "blas_threads") require(s.blas_threads >= 0, "must be a non-negative integer (0: = threads)");
  else if (key == "function_tolerance") require(std::isfinite(s.function_tolerance) && s.function_tolerance >= 0, "must be finite and non-negative");
  else if (key == "gradient_tolerance") require(std::isfinite(s.gradient_tolerance) && s.gradient_tolerance >= 0, "must be finite and non-negative");
  else if (key == "parameter_tolerance") require(std::isfinite(s.parameter_tolerance) && s.parameter_tolerance >= 0, "must be finite and non-negative");
  else if (key == "keep_estimates_chi2_per_dof")
    require(std::isfinite(s.keep_estimates_chi2_per_dof) && s.keep_estimates_chi2_per_dof >= 0, "must be finite and non-negative");
}

/// Assigns a JSON value to a setting of type T; returns an error text on a type mismatch.
template <typename T>
const char* assign(const nlohmann::json& v, T& out) {
  if constexpr (std::is_same_v<T, std::string>) {
    if (!v.is_string()) return "must be a string";
    out = v.get<std::string>();
  } else if constexpr (std::is_same_v<T, bool>) {
    if (!v.is_boolean()) return "must be true or false";
    out = v.get<bool>();
  } else if constexpr (std::is_same_v<T, int>) {
    if (!v.is_number_integer()) return "must be an integer";
    if (v.is_number_unsigned() ? v.get<std::uint64_t>() > static_cast<std::uint64_t>(std::numeric_limits<int>::max())
                               : (v.get<std::int64_t>() > std::numeric_limits<int>::max() ||
                                  v.get<std::int64_t>() < std::numeric_limits<int>::min()))
      return "is out of range";
    out = static_cast<int>(v.is_number_unsigned() ? static_cast<std::int64_t>(v.get<std::uint64_t>()) : v.get<std::int64_t>());
  } else {
    static_assert(std::is_same_v<T, double>);
    if (!v.is_number()) return "must be a number";
    out = v.get<double>();
  }
  return nullptr;
}

}  // namespace

bool OptimizeSettings::operator==(const OptimizeSettings& o) const {
  auto fields = [](const OptimizeSettings& x) {
    return std::tie(x.solver, x.init, x.robust, x.robust_loop_closures_only, x.max_iterations, x.threads,
                    x.blas_threads, x.function_tolerance, x.gradient_tolerance, x.parameter_tolerance,
                    x.linear_solver, x.ordering, x.repair_information, x.format, x.calibrate,
                    x.keep_estimates_chi2_per_dof);
  };
  return fields(*this) == fields(o);
}

void validate(const OptimizeSettings& s, const std::string& source) {
  for_each_setting(s, [&](const char* key, const char*, auto&) { check_setting(s, key, source); });
}

void parse_optimize_config(std::string_view text, const std::string& source, OptimizeSettings& s,
                           const std::function<bool(const char* flag)>& given) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(source, line_at(text, e.byte > 0 ? e.byte - 1 : 0), "", std::string("not valid JSON: ") + e.what());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(source, 0, "", std::string("not valid JSON: ") + e.what());
  }
  if (!j.is_object()) throw InputError(source, 1, "", "a config file holds one JSON object of options");
  OptimizeSettings read = s;
  std::size_t known = 0;
  for_each_setting(read, [&](const char* key, const char* flag, auto& member) {
    const auto it = j.find(key);
    if (it == j.end()) return;
    ++known;
    if (given && given(flag)) return;  // the command line wins
    const int line = line_of_key(text, key);
    if (const char* problem = assign(*it, member)) throw InputError(source, line, key, problem);
    try {
      check_setting(read, key);
    } catch (const Error& e) {
      throw InputError(source, line, key, e.what());
    }
  });
  if (known != j.size()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      bool found = false;
      for_each_setting(read, [&](const char* key, const char*, auto&) { found = found || it.key() == key; });
      if (!found) throw InputError(source, line_of_key(text, it.key()), it.key(), "unknown option");
    }
  }
  s = read;
}

void read_optimize_config(const std::string& path, OptimizeSettings& s,
                          const std::function<bool(const char* flag)>& given) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open config file");
  std::ostringstream text;
  text << in.rdbuf();
  parse_optimize_config(text.str(), path, s, given);
}

std::string optimize_config_to_json(const OptimizeSettings& s) {
  nlohmann::json j = nlohmann::json::object();
  for_each_setting(s, [&](const char* key, const char*, auto& member) { j[key] = member; });
  return j.dump(2);
}

}  // namespace slamkit::cli
