// libFuzzer target: the tum trajectory reader (see fuzz_trajectory.h for the properties checked).
#include "fuzz_trajectory.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return slamkit::fuzz::fuzz_trajectory(data, size, slamkit::TrajectoryFormat::kTum, "fuzz.tum");
}
