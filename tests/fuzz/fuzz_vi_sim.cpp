// libFuzzer target: the visual-inertial simulation reader (read_visual_inertial_sim).
//
// Properties: a rejected input throws InputError naming the source; an accepted one has
// finite values, frames that point at IMU samples of the same time with the truth of that
// sample, labels that agree with the landmarks' groups; it writes, and the written text is a
// fixed point of read → write (T_cam_imu's quaternion is renormalized on every read, so its
// line is compared by value to 1e-15).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/io/visual_inertial_sim_io.h"

namespace {

[[noreturn]] void violation(const char* what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}

std::string without_line(const std::string& text, const std::string& prefix) {
  const auto at = text.find("\n" + prefix);
  if (at == std::string::npos) return text;
  const auto end = text.find('\n', at + 1);
  return text.substr(0, at) + text.substr(end);
}

std::string write(const slamkit::VisualInertialSim& sim) {
  std::ostringstream out;
  try {
    slamkit::write_visual_inertial_sim(out, sim);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    violation("an accepted run cannot be written");
  }
  return out.str();
}

slamkit::VisualInertialSim read_back(const std::string& text) {
  std::istringstream in(text);
  try {
    return slamkit::read_visual_inertial_sim(in, "written");
  } catch (const slamkit::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    violation("written text does not read back");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slamkit;
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  VisualInertialSim sim;
  try {
    sim = read_visual_inertial_sim(in, "fuzz.vis");
  } catch (const InputError& e) {
    if (e.file() != "fuzz.vis") violation("an InputError that does not name the source");
    return 0;
  }
  if (!sim.camera || sim.imu.size() != sim.imu_truth.size() || sim.frames.empty()) violation("incomplete run accepted");
  for (const SimFrame& f : sim.frames) {
    if (f.imu_index >= sim.imu.size() || sim.imu[f.imu_index].t != f.t) violation("frame not at its IMU sample");
    if (f.truth.p_world != sim.imu_truth[f.imu_index].p_world) violation("frame truth differs from the IMU truth");
    for (const SimObservation& o : f.observations) {
      if (!o.uv.allFinite()) violation("pixel not finite");
      if (o.dynamic != (sim.landmarks.at(static_cast<std::size_t>(o.landmark_id)).group >= 0)) violation("label");
    }
  }
  const std::string once = write(sim);
  const VisualInertialSim again = read_back(once);
  const std::string twice = write(again);
  if (without_line(once, "T_cam_imu") != without_line(twice, "T_cam_imu")) violation("read -> write is not a fixed point");
  if (!again.T_cam_imu.rotation().quaternion().coeffs().isApprox(sim.T_cam_imu.rotation().quaternion().coeffs(), 1e-15) ||
      again.T_cam_imu.translation() != sim.T_cam_imu.translation())
    violation("T_cam_imu changed in write -> read");
  return 0;
}
