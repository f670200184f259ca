// libFuzzer target: the `slamkit optimize --config` JSON reader (apps/slamkit/optimize_config.h).
//
// A rejected config must throw InputError naming the file; an accepted one must hold only valid
// settings (validate) and survive write (optimize_config_to_json) → read with the same values.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "optimize_config.h"
#include "slamkit/core/error.h"

namespace {
[[noreturn]] void violation(const char* what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slamkit;
  const std::string text(reinterpret_cast<const char*>(data), size);
  cli::OptimizeSettings s;
  try {
    cli::parse_optimize_config(text, "fuzz.json", s);
  } catch (const InputError& e) {
    if (e.file() != "fuzz.json") violation("an InputError that does not name the input");
    return 0;
  }
  try {
    cli::validate(s, "fuzz.json");
  } catch (const InputError& e) {
    std::fprintf(stderr, "accepted but invalid: %s\n", e.what());
    violation("accepted an invalid setting");
  }
  const std::string written = cli::optimize_config_to_json(s);
  cli::OptimizeSettings again;
  try {
    cli::parse_optimize_config(written, "fuzz.json", again);
  } catch (const InputError& e) {
    std::fprintf(stderr, "re-reading the written config failed: %s\n%s\n", e.what(), written.c_str());
    violation("write -> read");
  }
  if (!(again == s)) violation("write -> read changed a setting");
  return 0;
}
