// libFuzzer target: the `sim:` pose-graph specs (parse_sim_spec, parse_calibration_sim_spec).
//
// The bytes are a spec (prefixed with "sim:" when byte 0 is odd, so most inputs get past the
// prefix). A rejected spec must throw InputError naming the spec; an accepted one must print
// (to_sim_spec) as a spec that parses to the same options, and when it is small it must generate
// a finite graph that survives g2o write → read (to rounding once, then bit for bit). Calibration
// problems (sim:calib2d/3d, one lap) must, once read, write → read → write the same g2o text,
// calibration tags included.
#include <cstdint>
#include <string>

#include "fuzz_pose_graph.h"
#include "slamkit/sim/calibration_generator.h"
#include "slamkit/sim/pose_graph_generator.h"

namespace {

bool same_options(const slamkit::PoseGraphSimOptions& a, const slamkit::PoseGraphSimOptions& b) {
  return a.world == b.world && a.seed == b.seed && a.num_poses == b.num_poses && a.rings == b.rings &&
         a.poses_per_ring == b.poses_per_ring && a.translation_sigma == b.translation_sigma &&
         a.rotation_sigma == b.rotation_sigma;
}

bool same_options(const slamkit::CalibrationSimOptions& a, const slamkit::CalibrationSimOptions& b) {
  return a.world == b.world && a.seed == b.seed && a.laps == b.laps && a.bias == b.bias && a.path == b.path &&
         a.odometry == b.odometry;
}

int fuzz_calibration_spec(const std::string& spec) {
  using namespace slamkit;
  CalibrationSimOptions o;
  try {
    if (!parse_calibration_sim_spec(spec, &o)) return 0;
  } catch (const InputError& e) {
    if (e.file() != spec) fuzz::violation("an InputError that does not name the calibration spec");
    return 1;
  }
  const std::string printed = to_calibration_sim_spec(o);
  CalibrationSimOptions again;
  try {
    if (!parse_calibration_sim_spec(printed, &again)) fuzz::violation("a printed calibration spec is not one");
  } catch (const InputError& e) {
    std::fprintf(stderr, "re-reading '%s' failed: %s\n", printed.c_str(), e.what());
    fuzz::violation("print -> parse (calibration)");
  }
  if (!same_options(o, again)) fuzz::violation("print -> parse changed the calibration options");
  if (o.laps == 1) {
    // The first read makes the generator's quaternions exact-unit; from then on the text is a
    // fixed point of write -> read -> write.
    PoseGraphReadOptions read;
    read.format = PoseGraphFormat::kG2o;
    auto reread = [&](const std::string& text) {
      std::istringstream in(text);
      return pose_graph_to_string(read_pose_graph(in, "calib.g2o", read), PoseGraphFormat::kG2o);
    };
    const std::string second = reread(pose_graph_to_string(generate_calibration_problem(o), PoseGraphFormat::kG2o));
    if (reread(second) != second) fuzz::violation("calibration problem: g2o write -> read -> write differs");
  }
  return 1;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slamkit;
  if (size == 0) return 0;
  const std::string spec = std::string(data[0] & 1 ? "sim:" : "") + std::string(reinterpret_cast<const char*>(data + 1), size - 1);
  if (fuzz_calibration_spec(spec)) return 0;
  PoseGraphSimOptions o;
  try {
    if (!parse_sim_spec(spec, &o)) return 0;
  } catch (const InputError& e) {
    if (e.file() != spec) fuzz::violation("an InputError that does not name the spec");
    return 0;
  }
  const std::string printed = to_sim_spec(o);
  PoseGraphSimOptions again;
  try {
    if (!parse_sim_spec(printed, &again)) fuzz::violation("a printed spec is not a spec");
  } catch (const InputError& e) {
    std::fprintf(stderr, "re-reading '%s' failed: %s\n", printed.c_str(), e.what());
    fuzz::violation("print -> parse");
  }
  if (!same_options(o, again)) fuzz::violation("print -> parse changed the options");

  const long long poses = o.world == "sphere" ? static_cast<long long>(o.rings) * o.poses_per_ring : o.num_poses;
  if (poses > 120) return 0;  // keep the fuzzer fast (a 120-pose graph takes ~0.1 s under ASan)
  const PoseGraph g = generate_pose_graph(o);
  if (!std::isfinite(total_chi2(g))) fuzz::violation("generated graph has a non-finite chi2");
  // The reader hands out exact-unit quaternions (io docs), the generator need not: the first
  // round trip agrees to rounding, every later one bit for bit.
  PoseGraphReadOptions read;
  read.format = PoseGraphFormat::kG2o;
  std::istringstream first(pose_graph_to_string(g, PoseGraphFormat::kG2o));
  const PoseGraph h = read_pose_graph(first, "generated.g2o", read);
  fuzz::check_same(g, h, 1e-12);
  std::istringstream second(pose_graph_to_string(h, PoseGraphFormat::kG2o));
  fuzz::check_same(h, read_pose_graph(second, "generated.g2o", read), 0.0);
  return 0;
}
