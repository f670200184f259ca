// libFuzzer target: the g2o pose-graph reader (see fuzz_pose_graph.h for the properties checked).
#include "fuzz_pose_graph.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return slamkit::fuzz::fuzz_pose_graph(data, size, slamkit::PoseGraphFormat::kG2o, "fuzz.g2o");
}
