// libFuzzer target: the BAL bundle-adjustment reader. InputError is the expected outcome of
// bad input; anything else (another exception, a sanitizer report) is a bug. An accepted
// problem must survive the geometry check, the cost, normalization, and a write → read round
// trip that reproduces it bit for bit (read → write → read).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/io/bal_io.h"

namespace {

[[noreturn]] void violation(const char* what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slamkit;
  const std::string text(reinterpret_cast<const char*>(data), size);
  BalProblem p;
  try {
    std::istringstream in(text);
    BalReadReport report;
    p = read_bal(in, "fuzz.bal", &report);
  } catch (const InputError& e) {
    if (e.file() != "fuzz.bal") violation("an InputError that does not name the input");
    return 0;
  }
  for (const BalObservation& o : p.observations)
    if (o.camera < 0 || o.camera >= p.num_cameras() || o.point < 0 || o.point >= p.num_points())
      violation("an accepted observation indexes outside the problem");
  try {
    validate_bal_geometry(p);
  } catch (const InputError&) {
  }
  (void)bal_cost(p);
  const std::string written = bal_to_string(p);
  BalProblem q;
  try {
    std::istringstream in(written);
    q = read_bal(in, "fuzz.bal");
  } catch (const InputError& e) {
    std::fprintf(stderr, "re-reading the written problem failed: %s\n", e.what());
    violation("write -> read");
  }
  if (bal_to_string(q) != written) violation("read -> write -> read is not bit-identical");
  BalProblem n = p;
  (void)normalize_bal(n);
  return 0;
}
