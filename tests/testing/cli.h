// Running the built `slamkit` binary from a test, as a user would: exit code, stdout, stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace slamkit::testing {

struct CliRun {
  int exit_code;
  std::string out, err;
};

/// A per-process scratch folder under the temp directory, "<prefix><pid>".
inline std::filesystem::path cli_scratch(const std::string& prefix) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs `build/bin/slamkit ARGS` with stdout and stderr captured in files of `scratch`.
inline CliRun run_slamkit(const std::string& args, const std::filesystem::path& scratch) {
  const std::string cmd = std::string(SLAMKIT_BINARY_DIR) + "/bin/slamkit " + args + " > " +
                          (scratch / "out").string() + " 2> " + (scratch / "err").string();
  const int status = std::system(cmd.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(scratch / "out"), slurp(scratch / "err")};
}

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

}  // namespace slamkit::testing
