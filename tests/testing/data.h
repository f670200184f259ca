// Locating ../shared/datasets from tests. SLAMKIT_DATA overrides the default; a relative
// path is taken relative to the source tree (where the README's commands run).
// A missing folder skips the test with a visible message, except under CI=true, where it fails.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace slamkit::testing {

inline std::filesystem::path data_root() {
  const char* env = std::getenv("SLAMKIT_DATA");
  std::filesystem::path p = env && *env ? std::filesystem::path(env) : std::filesystem::path("../shared/datasets");
  if (p.is_relative()) p = std::filesystem::path(SLAMKIT_SOURCE_DIR) / p;
  return p.lexically_normal();
}

inline bool running_in_ci() {
  const char* ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}

}  // namespace slamkit::testing

/// Declares `var` = data_root()/relative, or skips (fails under CI=true) when it is missing.
/// (The parameter must not be called `path`: it would replace std::filesystem::path.)
#define SLAMKIT_REQUIRE_DATA(var, relative)                                                    \
  const std::filesystem::path var = ::slamkit::testing::data_root() / (relative);             \
  if (!std::filesystem::exists(var)) {                                                         \
    if (::slamkit::testing::running_in_ci()) FAIL() << "dataset missing under CI: " << var;    \
    GTEST_SKIP() << "SKIPPED: dataset not found: " << var << " (set SLAMKIT_DATA)";            \
  }
