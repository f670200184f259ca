// libFuzzer target: the MRCLAM log reader (io/mrclam_odometry.h), both layouts (byte 0 picks
// odometry t v ω or ground truth t x y θ). InputError naming the input is the expected outcome of
// bad input; an accepted log holds finite, non-decreasing stamps and writes and reads back to the
// same values bit for bit.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/io/mrclam_odometry.h"

namespace {
[[noreturn]] void violation(const char* what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slamkit;
  if (size == 0) return 0;
  const int columns = data[0] & 1 ? 4 : 3;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::vector<MrclamSample> log;
  try {
    std::istringstream in(text);
    log = read_mrclam_samples(in, "fuzz.dat", columns);
  } catch (const InputError& e) {
    if (e.file() != "fuzz.dat") violation("an InputError that does not name the input");
    return 0;
  }
  for (std::size_t k = 0; k < log.size(); ++k)
    if (!std::isfinite(log[k].t) || (k > 0 && log[k].t < log[k - 1].t)) violation("stamps not finite or going back");
  std::ostringstream out;
  write_mrclam_samples(out, log, columns);
  std::vector<MrclamSample> again;
  try {
    std::istringstream in(out.str());
    again = read_mrclam_samples(in, "fuzz.dat", columns);
  } catch (const InputError& e) {
    std::fprintf(stderr, "re-reading failed: %s\n", e.what());
    violation("write -> read");
  }
  if (again.size() != log.size() || std::memcmp(again.data(), log.data(), log.size() * sizeof(MrclamSample)) != 0)
    violation("write -> read changed a sample");
  return 0;
}
