// libFuzzer target: the landmark-dataset readers (io/landmark_dataset.h). Byte 0 picks one of
// MRCLAM measurements / barcodes / landmark ground truth, Victoria Park odometry / trees / GPS.
// InputError naming the input is the expected outcome of bad input; whatever is accepted holds
// finite values, non-decreasing stamps, positive ranges and wrapped bearings, and the event
// merge of accepted odometry and scans conserves time (Σ dt = last − first command stamp).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "slamkit/core/error.h"
#include "slamkit/io/landmark_dataset.h"

namespace {
[[noreturn]] void violation(const char* what) {
  std::fprintf(stderr, "fuzz property violated: %s\n", what);
  std::abort();
}
void check_observation(const slamkit::RangeBearing& z) {
  if (!(z.range > 0) || !std::isfinite(z.range)) violation("range not positive and finite");
  if (!(z.bearing > -M_PI && z.bearing <= M_PI)) violation("bearing not wrapped");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace slamkit;
  if (size == 0) return 0;
  const int which = data[0] % 6;
  const std::string text(reinterpret_cast<const char*>(data + 1), size - 1);
  std::istringstream in(text);
  try {
    if (which == 0) {
      const auto s = read_mrclam_measurements(in, "fuzz.dat");
      for (std::size_t k = 0; k < s.size(); ++k) {
        check_observation(RangeBearing{s[k].barcode, s[k].range, s[k].bearing});
        if (!std::isfinite(s[k].time) || (k > 0 && s[k].time < s[k - 1].time)) violation("stamps");
      }
    } else if (which == 1) {
      const auto m = read_mrclam_barcodes(in, "fuzz.dat");
      if (m.empty()) violation("empty barcode map accepted");
    } else if (which == 2) {
      for (const auto& [id, p] : read_mrclam_landmarks(in, "fuzz.dat"))
        if (!p.allFinite()) violation("landmark not finite");
    } else if (which == 5) {
      std::vector<double> t;
      std::vector<Eigen::Vector2d> p;
      read_victoria_gps(in, "fuzz.dat", &t, &p);
      if (t.size() != p.size()) violation("gps sizes");
    } else {
      // Odometry and trees from the two halves of the input, then the merge.
      const std::size_t cut = text.find('|');
      std::istringstream odo_in(text.substr(0, cut)), tree_in(cut == std::string::npos ? "" : text.substr(cut + 1));
      const auto odo = read_victoria_odometry(odo_in, "fuzz.dat");
      const auto scans = read_victoria_trees(tree_in, "fuzz.dat");
      std::vector<std::pair<double, Eigen::Vector2d>> commands;
      for (const auto& o : odo) commands.push_back({o.time, Eigen::Vector2d(o.speed, o.steering)});
      std::vector<std::pair<double, std::vector<RangeBearing>>> sc;
      for (const auto& s : scans) {
        for (const auto& z : s.trees) check_observation(z);
        sc.push_back({s.time, s.trees});
      }
      int dropped = 0;
      const auto events = merge_landmark_events(commands, sc, &dropped);
      double total = 0;
      for (const auto& e : events) {
        if (!e.is_scan && !(e.control.dt > 0)) violation("control with dt <= 0");
        total += e.is_scan ? 0 : e.control.dt;
      }
      const double span = commands.back().first - commands.front().first;
      if (std::abs(total - span) > 1e-9 * std::max(1.0, std::abs(span))) violation("merge does not conserve time");
    }
  } catch (const InputError& e) {
    if (e.file() != "fuzz.dat" && e.file() != "") violation("an InputError that does not name the input");
  }
  return 0;
}
